"""Whether the machine has a font for Chinese text (operator test 7, D4).

With no font covering Simplified Chinese, Qt draws every Chinese character as a box: the
Chinese window's menus, docks and log, and in either language a file's Chinese headers,
track ids or file name. The window asks :func:`has_cjk_font` once, the first time it
needs Chinese glyphs (a zh_CN start or switch, a log line or loaded data holding Chinese
text), and says once, in the log and the status bar, which package to install.

The message is English in either language: without the font a Chinese one is boxes.
"""

import re

from PySide6 import QtGui

#: The font database asked (a test puts a stand-in here).
FONT_DATABASE = QtGui.QFontDatabase
#: Han ideographs, CJK punctuation and full-width forms: text that needs a CJK font.
CJK = re.compile(r"[\u3000-\u303f\u3400-\u4dbf\u4e00-\u9fff\uf900-\ufaff\uff00-\uffef]")
#: The packages that bring a font for Chinese, by distribution.
PACKAGES = (("Debian/Ubuntu", "fonts-noto-cjk"), ("Fedora", "google-noto-sans-cjk-fonts"))
#: Languages of the window whose texts need a CJK font.
CJK_LANGUAGES = frozenset({"zh_CN"})


def cjk_families() -> list[str]:
    """The font families that cover Simplified Chinese."""
    return list(FONT_DATABASE.families(QtGui.QFontDatabase.WritingSystem.SimplifiedChinese))


def has_cjk_font() -> bool:
    return bool(cjk_families())


def needs_cjk(*texts) -> bool:
    """Whether any of ``texts`` (strings, or iterables of them) holds Chinese text."""
    for text in texts:
        if isinstance(text, str):
            if CJK.search(text):
                return True
        elif text is not None and any(CJK.search(str(t)) for t in text):
            return True
    return False


def missing_font_text() -> str:
    """The warning: what the operator sees and what to install."""
    pkgs = "; ".join(f"{where}: {name}" for where, name in PACKAGES)
    return (
        "no font for Chinese text on this machine (no family covers Simplified Chinese), "
        f"so Chinese is drawn as boxes; install one ({pkgs}) and start Wakeline again"
    )
