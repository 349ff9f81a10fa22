"""Shared pieces of the console subcommands: the epilog, number parsers, --set NAME=VALUE."""

import argparse
import math

from wakeline.core.errors import InputError

EPILOG = "Exit status: 0 success, 2 bad input (one message on stderr), 1 internal error."


#: the largest seed numpy's generators take from the command line (2**32 - 1, as the
#: legacy ``RandomState`` and most tools): a seed is a whole number in [0, SEED_MAX]
SEED_MAX = 2**32 - 1


def _whole(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None


def _finite(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return value


def positive_int(text: str) -> int:
    """argparse type: a whole number of at least 1."""
    value = _whole(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def whole_int(text: str) -> int:
    """argparse type: a whole number, its range checked where it is used (the line counts
    ``--skip-rows`` / ``--like-skip-rows``: the reader's refusal names the flag and the
    file's length)."""
    return _whole(text)


def seed_int(text: str) -> int:
    """argparse type: a random seed, a whole number in [0, 2**32 - 1] (numpy refuses a
    negative one: it was an internal error, exit 1)."""
    value = _whole(text)
    if not 0 <= value <= SEED_MAX:
        raise argparse.ArgumentTypeError(f"a seed is a whole number 0-{SEED_MAX}, got {value}")
    return value


def positive_float(text: str) -> float:
    """argparse type: a finite number above 0."""
    value = _finite(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be positive, got {value:g}")
    return value


def settings_dict(settings: list[str] | None) -> dict[str, str]:
    """``--set NAME=VALUE`` texts as a dict; InputError on a malformed one."""
    changes = {}
    for text in settings or []:
        name, sep, value = text.partition("=")
        if not sep or not name.strip():
            raise InputError(f"--set expects NAME=VALUE, got {text!r}")
        changes[name.strip()] = value.strip()
    return changes


def link_params(settings: list[str] | None):
    """LinkParams with the ``--set`` changes applied and checked."""
    from wakeline.core.associate import LinkParams

    return LinkParams().replace(**settings_dict(settings)).checked()


def fuse_params(settings: list[str] | None):
    """FuseParams with the ``--set`` changes applied and checked."""
    from wakeline.core.fuse import FuseParams

    return FuseParams().replace(**settings_dict(settings)).checked()
