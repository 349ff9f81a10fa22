"""Shared fixtures. GUI tests run offscreen; real data is read from ../shared when present."""

import os
from pathlib import Path

import pytest

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

REPO = Path(__file__).resolve().parents[1]
DATA = Path(__file__).resolve().parent / "data"
SHARED_REAL = Path(os.environ.get("WAKELINE_SHARED", REPO.parent / "shared")) / "data" / "real"


def real_file(*parts: str) -> Path:
    """A file of ../shared/data/real; the test is skipped when it is absent."""
    path = SHARED_REAL.joinpath(*parts)
    if not path.exists():
        pytest.skip(f"real data not available: {path}")
    return path


@pytest.fixture
def write(tmp_path):
    """Write bytes or text to a file in tmp_path and return its path."""

    def _write(name: str, content: str | bytes, encoding: str = "utf-8") -> Path:
        path = tmp_path / name
        if isinstance(content, str):
            content = content.encode(encoding)
        path.write_bytes(content)
        return path

    return _write


@pytest.fixture(autouse=True)
def _no_blocking_dialogs(monkeypatch):
    """A modal message box would wait forever offscreen: record instead (tests that check
    dialogs patch QMessageBox themselves)."""
    try:
        from PySide6 import QtWidgets
    except ImportError:
        return
    for name in ("warning", "information", "critical", "question"):
        monkeypatch.setattr(QtWidgets.QMessageBox, name, lambda *a, **k: None)
