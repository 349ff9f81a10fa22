"""Shared pieces of the console subcommands: the epilog, number parsers, --set NAME=VALUE."""

import argparse

from wakeline.core.errors import InputError

EPILOG = "Exit status: 0 success, 2 bad input (one message on stderr), 1 internal error."


def positive_int(text: str) -> int:
    """argparse type: a whole number of at least 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def positive_float(text: str) -> float:
    """argparse type: a number above 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be positive, got {value}")
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
