"""An operator's help shows sources an operator can read (operator test 5, D-cli-3).

The parameter fields keep the team's history in their source (sessions, helper branches,
pre-registration files) for the maintainers; every command's --help and the parameter
panel's tooltips show the label and docs/evaluation.md instead.
"""

import contextlib
import io
import re

import pytest

from wakeline.app.cli import build_parser
from wakeline.core.params import shown_source

HISTORY = re.compile(r"session ?\d|session\d+_|\bh\d{2,3}\b|prereg")


def _commands() -> list[str]:
    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    return sorted(sub.choices)


@pytest.mark.parametrize("command", _commands())
def test_no_command_help_names_the_teams_history(command):
    out = io.StringIO()
    with contextlib.redirect_stdout(out), pytest.raises(SystemExit):
        build_parser().parse_args([command, "--help"])
    text = out.getvalue()
    assert text.strip()
    hits = [line for line in text.splitlines() if HISTORY.search(line)]
    assert not hits, hits[:5]


def test_shown_source_keeps_papers_and_labels_ours():
    assert shown_source("seed 001 §5") == "seed 001 §5"
    assert shown_source("ours") == "ours"
    assert shown_source("") == ""
    assert (
        shown_source("ours (session 22; default since session 27, docs/prereg/x.md)")
        == "ours (docs/evaluation.md)"
    )
    assert shown_source("ours (h162, docs/prereg/session27_radar_edges.md)") == (
        "ours (docs/evaluation.md)"
    )
    assert not HISTORY.search(shown_source("ours; 600 s until session 22: docs/evaluation.md"))
