"""The engine never imports Qt; the package layout is as documented."""

import pkgutil
import subprocess
import sys

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
