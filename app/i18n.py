"""Translations: Qt Linguist ``.ts`` files read at run time.

``resources/translations/wakeline_<locale>.ts`` is the standard XML that Qt Linguist edits;
:class:`TsTranslator` loads it directly, so no compiled ``.qm`` (and no ``lrelease`` at
build time) is needed.
"""

import xml.etree.ElementTree as ET
from pathlib import Path

from PySide6 import QtCore

from wakeline.app import core_text
from wakeline.resources import translations_dir

LANGUAGES = {"en": "English", "zh_CN": "简体中文"}


class TsTranslator(QtCore.QTranslator):
    """A QTranslator over one ``.ts`` file (finished and unfinished entries)."""

    def __init__(self, path: Path, parent: QtCore.QObject | None = None) -> None:
        super().__init__(parent)
        self._table: dict[tuple[str, str], str] = {}
        root = ET.parse(path).getroot()
        for ctx in root.iter("context"):
            name = ctx.findtext("name", "")
            for msg in ctx.iter("message"):
                src = msg.findtext("source", "")
                tr = msg.find("translation")
                if tr is not None and tr.text:
                    self._table[(name, src)] = tr.text

    def translate(self, context, source, disambiguation=None, n=-1):  # noqa: D102 - Qt API
        # None becomes a null QString, which tells Qt "not here, ask the next translator /
        # keep the source"; an empty string would blank Qt's own texts (OK, Cancel, ...).
        return self._table.get((context, source))

    def isEmpty(self) -> bool:  # noqa: N802 - Qt API
        return not self._table

    def __len__(self) -> int:
        return len(self._table)


def system_language() -> str:
    """``zh_CN`` for a Chinese system locale, else ``en``."""
    name = QtCore.QLocale.system().name()
    return "zh_CN" if name.startswith("zh") else "en"


def install(app: QtCore.QCoreApplication, language: str, current: TsTranslator | None):
    """Swap the installed translator for ``language``; returns the new one (or None)."""
    if current is not None:
        app.removeTranslator(current)
        qt_own = getattr(current, "qt_own", None)
        if qt_own is not None:
            app.removeTranslator(qt_own)
    core_text.set_language(language)  # the core's messages too (app/core_text.py)
    if language == "en":
        return None
    path = translations_dir() / f"wakeline_{language}.ts"
    if not path.exists():
        return None
    translator = TsTranslator(path, app)
    # Qt's own texts (the dialog buttons' OK, Cancel, Yes, No; the context menus): Qt's
    # catalog for the language, installed first so that ours is asked before it
    qt_own = QtCore.QTranslator(app)
    where = QtCore.QLibraryInfo.path(QtCore.QLibraryInfo.LibraryPath.TranslationsPath)
    if qt_own.load(f"qtbase_{language}", where):
        app.installTranslator(qt_own)
        translator.qt_own = qt_own
    app.installTranslator(translator)
    return translator
