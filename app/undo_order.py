"""One order for Edit ▸ Undo / Redo over the window's undo stacks (operator test 11, F1).

The review's decisions and the point restores sit on per-layer stacks (the review dock's
``QUndoGroup``), the layer edits (colour, order, removal) on a stack of the window's own.
Every command is stamped with a process-wide sequence number when it is made (right before
its push): Ctrl+Z undoes the newer of the candidates' tops, Ctrl+Shift+Z redoes the one
undone last. A command undone before a newer command was made is not redone (one stack
would have dropped it), whichever stack holds it.
"""

import itertools

_counter = itertools.count(1)
_latest = 0


def stamp(cmd) -> None:
    """Give ``cmd`` (a ``QUndoCommand`` about to be pushed) the next sequence number."""
    global _latest
    _latest = next(_counter)
    cmd.seq = _latest


def undone(cmd) -> None:
    """``cmd`` was undone now (its redo stays valid until a newer command is made)."""
    cmd.undone_at = _latest


def top(stack):
    """The command ``stack``'s undo would undo (None: nothing)."""
    if stack is None or not stack.canUndo():
        return None
    return stack.command(stack.index() - 1)


def following(stack):
    """The command ``stack``'s redo would redo, while it still may (None: nothing)."""
    if stack is None or not stack.canRedo():
        return None
    cmd = stack.command(stack.index())
    if cmd is None or getattr(cmd, "undone_at", -1) < _latest:
        return None  # a newer command was made since it was undone
    return cmd


def pick_undo(stacks):
    """``(stack, command)`` of the newest command to undo among ``stacks`` (or Nones)."""
    best = (None, None)
    for stack in stacks:
        cmd = top(stack)
        if cmd is not None and (best[1] is None or seq(cmd) > seq(best[1])):
            best = (stack, cmd)
    return best


def pick_redo(stacks):
    """``(stack, command)`` of the command undone last among ``stacks`` (or Nones)."""
    best = (None, None)
    for stack in stacks:
        cmd = following(stack)
        if cmd is not None and (best[1] is None or seq(cmd) < seq(best[1])):
            best = (stack, cmd)
    return best


def seq(cmd) -> int:
    return getattr(cmd, "seq", 0)
