"""Light commands start fast: building the parser loads no scipy (issue 17)."""

import subprocess
import sys


def test_parser_imports_no_scipy():
    code = (
        "import sys; from wakeline.app.cli import build_parser; build_parser(); "
        "print(sorted(m for m in sys.modules if m == 'scipy' or m.startswith('scipy.')))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
