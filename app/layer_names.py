"""A layer's name in the window's language (operator test 6, D-i18n-2).

The session stores a step's layer under an English name built from its input's name and
the step's word ("scene.csv · cleaned · compressed", "a.csv + b.csv · fused",
"… · maneuvers (compress)"): the name is data (projects, exports' suggested file names,
the command line) and stays as it is, so a project saved in one language opens in the
other. The window shows it through :func:`shown_name`: the words after the first
" · " that are a step's word are said in the window's language; the input's own name
(a file's) is never touched, nor a piece that is not a step's word.
"""

import re

from PySide6 import QtCore

SEP = " · "
CONTEXT = "LayerName"

_MORE = re.compile(r"^(?P<names>.+) and (?P<n>[\d,]+) more$")
_PAREN = re.compile(r"^(?P<word>.+?) \((?P<inner>[a-z]+)\)$")


def _words() -> dict[str, str]:
    return {
        # the steps' layer words (core.pipeline NewLayer suffixes)
        "cleaned": QtCore.QCoreApplication.translate("LayerName", "cleaned"),
        "maneuvers": QtCore.QCoreApplication.translate("LayerName", "maneuvers"),
        "compressed": QtCore.QCoreApplication.translate("LayerName", "compressed"),
        "associated": QtCore.QCoreApplication.translate("LayerName", "associated"),
        "stitched": QtCore.QCoreApplication.translate("LayerName", "stitched"),
        "fused": QtCore.QCoreApplication.translate("LayerName", "fused"),
        # a second layer of one step on one input: "… · maneuvers (compress)"
        "clean": QtCore.QCoreApplication.translate("LayerName", "clean"),
        "compress": QtCore.QCoreApplication.translate("LayerName", "compress"),
        "associate": QtCore.QCoreApplication.translate("LayerName", "associate"),
        "fuse": QtCore.QCoreApplication.translate("LayerName", "fuse"),
        "pipeline": QtCore.QCoreApplication.translate("LayerName", "pipeline"),
        # an export of a reviewed layer: "… · fused (reviewed)"
        "reviewed": QtCore.QCoreApplication.translate("LayerName", "reviewed"),
    }


def _piece(text: str, words: dict[str, str]) -> str:
    if text in words:
        return words[text]
    m = _PAREN.match(text)
    if m and m.group("inner") in words:
        word, inner = m.group("word"), m.group("inner")
        if word in words or inner == "reviewed":
            return QtCore.QCoreApplication.translate("LayerName", "{0} ({1})").format(
                words.get(word, word), words[inner]
            )
    return text


def _first(text: str) -> str:
    m = _MORE.match(text)
    if not m:
        return text
    return QtCore.QCoreApplication.translate("LayerName", "{0} and {1} more").format(
        m.group("names"), m.group("n")
    )


def shown_name(name: str) -> str:
    """``name`` (a layer's stored name) as the window shows it: its step words in the
    window's language ("scene.csv · 已清洗 · 已压缩"); the same text in English."""
    if not name:
        return name
    if "\n" in str(name):  # a legend entry's lines (a layer coloured by track): each alone
        return "\n".join(shown_name(line) for line in str(name).split("\n"))
    pieces = str(name).split(SEP)
    words = _words()
    out = [_first(pieces[0])] + [_piece(p, words) for p in pieces[1:]]
    if len(pieces) == 1:  # a name with no step words: "scene.csv (reviewed)"
        out[0] = _piece(out[0], {"reviewed": words["reviewed"]})
    return SEP.join(out)
