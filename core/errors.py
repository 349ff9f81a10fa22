"""Error types shared by the engine, the command line and the GUI."""


class InputError(Exception):
    """Bad input the user can fix (missing column, empty file, bad parameter).

    The message is written for the operator: one sentence, no traceback. The command
    line prints it and exits with status 2; the GUI shows it in a dialog.
    """


class Cancelled(Exception):
    """Raised by a progress callback to stop a running job."""


class NotTrackData(InputError):
    """An :class:`InputError` for a file that is not track data at all: binary, no
    table, a header that names no known column (and no ``--map`` column). ``wakeline
    batch`` skips such a file among several inputs with a note (a README.txt among the
    exports); any other refusal of a file fails the batch."""


class StaleResult(InputError):
    """A re-run of a reviewed step (Associate, Fuse) whose result the decisions made on
    the layer it replaces while it ran have put out of date: they change the pairs the
    run keeps out (a pair rejected or split, or a reject taken back, meanwhile). Nothing
    was applied; the step runs again on the decisions as they are now (the window does
    so by itself). Decisions of any other kind made meanwhile are carried, not stale."""


class ProjectMoved(InputError):
    """A write to a project file that was moved, renamed or removed while open (the
    path no longer names the file that was opened): nothing is written there; the work
    is saved with Save as. The window reports it once, not once per queued write."""
