"""Counted nouns in the summaries the window logs and the command line prints: one place
for "1 track" / "2 tracks" (zh_CN needs no plural: the window's translated strings take
the bare number).

A summary is a :class:`Text`: the English sentence (a ``str``, as the command line
prints it) that also keeps its :class:`Phrase` s, each a message id — its English
template, a ``str.format`` string — and the named values it is filled with. The core
never translates (no Qt here); the window looks each template up in its translation
(context :data:`CONTEXT`) and fills the translated one with the same values
(:func:`render`). In a template ``{n:#track}`` is ``count(n, "track")`` ('1 track',
'2 tracks'; ``{n:#foot|feet}`` an irregular plural), any other spec is ``format``'s; a
value that is a :class:`Text` is rendered (translated) the same way.
"""

import string
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any

#: The translation context of the summaries' templates (the window's .ts file).
CONTEXT = "Summary"


def count(n: int, noun: str, plural: str | None = None) -> str:
    """``n`` (thousands separated) with its noun, singular for one: ``count(1, "track")``
    is '1 track', ``count(9427, "row")`` '9,427 rows'; ``plural`` for an irregular noun."""
    return f"{n:,} {noun if n == 1 else plural or noun + 's'}"


def import_counts(rep: dict, label: str | None = None) -> "Text":
    """What an import read, every line of the file accounted for as ``wakeline import``
    says it and the window's log repeats it: '384 rows in 1 track (CSV, utf-8); 18
    quarantined, 2 blank lines skipped' (``label``: the format's name, else the report's
    ``format``)."""
    blank = int(rep.get("blank_lines", 0) or 0)
    return Text(
        [
            phrase(
                "{rows:#row} in {tracks:#track} ({label}, {encoding}); {quarantined:,} quarantined",
                rows=rep.get("rows_imported", 0),
                tracks=rep.get("tracks", 0),
                label=label or rep.get("format"),
                encoding=rep.get("encoding"),
                quarantined=rep.get("rows_quarantined", 0),
            ),
            phrase(", {blank:#blank line} skipped", blank=blank) if blank else None,
        ]
    )


@dataclass(frozen=True)
class Phrase:
    """A piece of a summary: its message id (the English template) and named values."""

    template: str
    values: tuple[tuple[str, Any], ...] = ()


def phrase(template: str, **values: Any) -> Phrase:
    """A :class:`Phrase` of ``template`` filled with ``values`` (found in core by the
    translation test: the first argument is a literal)."""
    return Phrase(template, tuple(values.items()))


class _Words(string.Formatter):
    """``str.format`` with ``{n:#noun}`` (counted nouns) and values that are Texts."""

    def __init__(self, translate: Callable[[str], str] | None) -> None:
        self.translate = translate

    def format_field(self, value: Any, format_spec: str) -> str:
        if isinstance(value, Text):
            return render(value, self.translate)
        if format_spec.startswith("#"):
            noun, _, plural = format_spec[1:].partition("|")
            return count(value, noun, plural or None)
        return super().format_field(value, format_spec)


def render(text: "Text | str", translate: Callable[[str], str] | None = None) -> str:
    """``text`` in words: each phrase's template through ``translate`` (the window's
    translation of a template, or None/the template itself: English) filled with its
    values. A plain ``str`` is returned as it is. A translated template that its values
    cannot fill (a translation with a wrong name) falls back to the English one."""
    if not isinstance(text, Text):
        return str(text)
    words = _Words(translate)
    out = []
    for p in text.phrases:
        values = dict(p.values)
        template = p.template
        if translate is not None:
            template = translate(p.template) or p.template
        try:
            out.append(words.format(template, **values))
        except (KeyError, IndexError, ValueError, TypeError):
            out.append(words.format(p.template, **values))
    return "".join(out)


class Text(str):
    """A summary in English (this ``str``, as the command line prints it) made of
    :class:`Phrase` s a translator can render in another language (:func:`render`)."""

    phrases: tuple[Phrase, ...]

    def __new__(cls, phrases: Iterable[Phrase | None]) -> "Text":
        kept = tuple(p for p in phrases if p is not None)
        words = _Words(None)
        english = "".join(words.format(p.template, **dict(p.values)) for p in kept)
        obj = super().__new__(cls, english)
        obj.phrases = kept
        return obj

    def __reduce__(self):
        return (Text, (self.phrases,))


def joined(parts: list[Phrase]) -> list[Phrase]:
    """``parts`` with a "; " phrase between each two."""
    out: list[Phrase] = []
    for k, part in enumerate(parts):
        if k:
            out.append(phrase("; "))
        out.append(part)
    return out


#: Names :func:`joined_names` shows before it counts the rest.
JOINED_SHOWN = 2


def joined_names(names, shown: int = JOINED_SHOWN) -> str:
    """Names joined by " + ", the first ``shown`` and how many more when there are more
    than one past them: "a.csv + b.csv + c.csv", "f000.csv + f001.csv and 198 more" (a
    fuse of 200 layers was named by all 200, 2,205 characters)."""
    names = [str(n) for n in names]
    if len(names) <= shown + 1:
        return " + ".join(names)
    return f"{' + '.join(names[:shown])} and {len(names) - shown:,} more"
