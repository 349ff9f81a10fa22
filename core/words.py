"""Counted nouns in the summaries the window logs and the command line prints: one place
for "1 track" / "2 tracks" (zh_CN needs no plural: the window's translated strings take
the bare number)."""


def count(n: int, noun: str, plural: str | None = None) -> str:
    """``n`` (thousands separated) with its noun, singular for one: ``count(1, "track")``
    is '1 track', ``count(9427, "row")`` '9,427 rows'; ``plural`` for an irregular noun."""
    return f"{n:,} {noun if n == 1 else plural or noun + 's'}"


def import_counts(rep: dict, label: str | None = None) -> str:
    """What an import read, every line of the file accounted for as ``wakeline import``
    says it and the window's log repeats it: '384 rows in 1 track (CSV, utf-8); 18
    quarantined, 2 blank lines skipped' (``label``: the format's name, else the report's
    ``format``)."""
    blank = int(rep.get("blank_lines", 0) or 0)
    return (
        f"{count(rep.get('rows_imported', 0), 'row')} in {count(rep.get('tracks', 0), 'track')} "
        f"({label or rep.get('format')}, {rep.get('encoding')}); "
        f"{rep.get('rows_quarantined', 0):,} quarantined"
        + (f", {count(blank, 'blank line')} skipped" if blank else "")
    )
