"""The engine never imports Qt; the package layout is as documented."""

import pkgutil
import subprocess
import sys
from pathlib import Path

import wakeline.core


def test_core_never_imports_qt():
    modules = [m.name for m in pkgutil.walk_packages(wakeline.core.__path__, "wakeline.core.")]
    assert "wakeline.core.io.reader" in modules
    assert not any(m.endswith(".cli") for m in modules), "the console command lives in app/"
    code = (
        "import importlib, sys\n"
        f"for name in {modules!r}:\n"
        "    importlib.import_module(name)\n"
        "from wakeline.app.cli import build_parser\n"
        "build_parser()\n"
        "bad = sorted(m for m in sys.modules if m.split('.')[0] in ('PySide6', 'PyQt5', 'PyQt6', 'pyqtgraph', 'shiboken6'))\n"
        "print(','.join(bad))\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "", f"wakeline.core pulled in Qt: {proc.stdout}"


def test_packages_install_under_wakeline():
    import wakeline.app
    import wakeline.resources

    assert wakeline.resources.demo_path().is_file()
    assert wakeline.app.__name__ == "wakeline.app"


LINT = """
import sys
sys.meta_path[:] = [f for f in sys.meta_path if "editable" not in repr(f).lower()]
sys.path.insert(0, sys.argv[1])
from importlinter.cli import lint_imports
sys.exit(lint_imports(config_filename=sys.argv[2]))
"""


def _lint(tmp_path, tree: dict[str, Path], config: Path) -> subprocess.CompletedProcess:
    """Run import-linter on a ``wakeline`` package made of links to the given folders
    (the repository maps core/ and app/ onto wakeline.core and wakeline.app)."""
    root = tmp_path / "tree"
    (root / "wakeline").mkdir(parents=True)
    (root / "wakeline" / "__init__.py").write_text("")
    for name, target in tree.items():
        (root / "wakeline" / name).symlink_to(target, target_is_directory=True)
    return subprocess.run(
        [sys.executable, "-c", LINT, str(root), str(config)],
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_import_linter_contracts_hold(tmp_path):
    """pyproject.toml's import-linter contract: no module of wakeline.core imports
    wakeline.app, PySide6 or pyqtgraph — at module level or inside a function."""
    pytest = __import__("pytest")
    pytest.importorskip("importlinter")
    repo = Path(__file__).resolve().parents[1]
    tree = {"core": repo / "core", "app": repo / "app", "resources": repo / "resources"}
    proc = _lint(tmp_path, tree, repo / "pyproject.toml")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "1 kept, 0 broken" in proc.stdout or "kept" in proc.stdout

    # The same contract catches a lazy import inside a function.
    fake = tmp_path / "fake"
    (fake / "core").mkdir(parents=True)
    (fake / "app").mkdir()
    (fake / "core" / "__init__.py").write_text("")
    (fake / "app" / "__init__.py").write_text("")
    (fake / "core" / "bad.py").write_text("def f():\n    import wakeline.app\n")
    bad = _lint(
        tmp_path / "b", {"core": fake / "core", "app": fake / "app"}, repo / "pyproject.toml"
    )
    assert bad.returncode != 0 and "broken" in bad.stdout.lower()
