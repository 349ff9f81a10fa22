"""Progress reporting: a plain callback ``progress(fraction, text)``.

Core functions call it now and then; a caller stops a job by raising from it
(conventionally :class:`wakeline.core.errors.Cancelled`). Sub-steps map onto a slice
of the range with :func:`sub_progress`.
"""

from collections.abc import Callable

Progress = Callable[[float, str], None]


def null_progress(fraction: float, text: str = "") -> None:
    """A progress callback that does nothing."""


def sub_progress(progress: Progress | None, start: float, end: float) -> Progress:
    """Map a sub-step's 0..1 onto ``start..end`` of ``progress``."""
    if progress is None:
        return null_progress
    span = end - start

    def _sub(fraction: float, text: str = "") -> None:
        progress(start + span * min(max(fraction, 0.0), 1.0), text)

    return _sub
