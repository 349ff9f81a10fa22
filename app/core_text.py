"""The core's messages in the window's language (operator test 4, D-i18n-1).

The core speaks English and never translates (no Qt there): an open that failed
(:class:`~wakeline.core.errors.InputError`), a quarantined row's reason, an import's
warnings, a layout's name. The window shows each through :func:`shown`: first the
command-line advice in the window's words (:func:`~wakeline.app.window_words.window_words`:
``--encoding`` becomes the import dialog's Encoding field), then, in a language other than
English, through a catalog of patterns (``resources/translations/core_<language>.json``):
each entry a regular expression over the English, its named groups the numbers, names and
paths, and the template that says the same in the language with those groups. Entries apply
in the catalog's order, each to every place it matches, so a message made of several
clauses (a path, a missing column, the headers found, the advice) is translated clause by
clause; a text no entry matches stays English, whole and readable (never garbled).

In a template ``{name}`` is the group's text as found (a number keeps its thousands
separators, a file keeps its name); a group named ``t_…`` is itself shown through the
catalog (a quarantine reason quoted inside a sentence); ``{name?text}`` is ``text`` (with
its own ``{…}``) only where the group matched.
"""

import json
import re
from functools import lru_cache

from wakeline.app.window_words import window_words
from wakeline.resources import translations_dir

#: The window's language (set by :func:`wakeline.app.i18n.install`).
_language = "en"

_OPTIONAL = re.compile(r"\{(\w+)\?((?:[^{}]|\{\w+\})*)\}")
_FIELD = re.compile(r"\{(\w+)\}")


def set_language(code: str) -> None:
    """The language :func:`shown` speaks (``en``: the core's English as it is)."""
    global _language
    _language = code


def language() -> str:
    return _language


@lru_cache(maxsize=4)
def catalog(code: str) -> tuple[tuple[re.Pattern, str], ...]:
    """The patterns and templates of ``core_<code>.json`` (none for a language without one)."""
    path = translations_dir() / f"core_{code}.json"
    if not path.exists():
        return ()
    entries = json.loads(path.read_text(encoding="utf-8"))["entries"]
    return tuple((re.compile(e["en"]), e["zh"]) for e in entries)


def _fill(template: str, match: re.Match, code: str, depth: int) -> str:
    groups = match.groupdict()

    def optional(m: re.Match) -> str:
        return m.group(2) if groups.get(m.group(1)) is not None else ""

    def field(m: re.Match) -> str:
        name = m.group(1)
        if name not in groups:
            return m.group(0)
        value = groups[name] or ""
        if name.startswith("t_") and depth < 3:
            return translate(value, code, depth + 1)
        return value

    return _FIELD.sub(field, _OPTIONAL.sub(optional, template))


def translate(text: str, code: str, depth: int = 0) -> str:
    """``text`` (English) through the catalog of ``code``; what no entry matches is kept."""
    for pattern, template in catalog(code):
        if pattern.search(text):
            text = pattern.sub(lambda m, t=template: _fill(t, m, code, depth), text)
    return text


def shown(text) -> str:
    """A core message as the window shows it: the command line's flags as the import
    dialog's fields, in the window's language (:func:`translate`)."""
    return shown_cli(window_words(str(text)))


def shown_cli(text) -> str:
    """A core message as a window run says it on stderr (``wakeline gui … --screenshot``:
    read at the command line), in the window's language but with the command line's flags
    kept (``--map time=col4 --map lon=col2 …``, not the import dialog's Column mapping:
    operator test 11, F7)."""
    text = str(text)
    if _language == "en":
        return text
    return translate(text, _language)
