"""Counted nouns in the summaries the window logs and the command line prints: one place
for "1 track" / "2 tracks" (zh_CN needs no plural: the window's translated strings take
the bare number)."""


def count(n: int, noun: str, plural: str | None = None) -> str:
    """``n`` (thousands separated) with its noun, singular for one: ``count(1, "track")``
    is '1 track', ``count(9427, "row")`` '9,427 rows'; ``plural`` for an irregular noun."""
    return f"{n:,} {noun if n == 1 else plural or noun + 's'}"
