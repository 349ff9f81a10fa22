"""Every ``wakeline evaluate maneuver ...`` command shown in docs/ and README.md, parsed by
today's parser: the detector parameters each gives (the fields off the default), so that a
change to the flags can be checked against the commands the documents show.

    python bench/doc_evaluate_commands.py [--json OUT.json]

Placeholders are filled (S, Z, N, OUT, FILE, DIR, a bare ``--real``); ``[--flag V]`` is read
as given, ``a|b`` as ``a``; a command cut by a line end or written with alternatives
("--seed 1 2") is listed as not parsed. ``--json`` writes command -> ManeuverParams (as a
dict) for a before/after comparison. docs/evaluation.md "Session 29's leftovers".
"""

import argparse
import contextlib
import dataclasses
import io
import json
import re
import shlex
from pathlib import Path

from wakeline.app.cli import build_parser
from wakeline.app.cli_evaluate import _maneuver_params
from wakeline.core.maneuver import ManeuverParams

REPO = Path(__file__).resolve().parents[1]
PLACEHOLDERS = {"S": "1", "Z": "4", "N": "2", "OUT": "o.csv", "FILE": "f.csv", "DIR": "d"}


def shown_commands() -> list[tuple[str, list[str]]]:
    files = sorted((REPO / "docs").rglob("*.md")) + [REPO / "README.md"]
    out, seen = [], set()
    for f in files:
        for m in re.finditer(r"evaluate maneuver([^`\n]*)", f.read_text(encoding="utf-8")):
            tail = re.sub(r"\[([^\]]*)\]", lambda x: x.group(1).split("|")[0], m.group(1))
            tail = tail.replace("|", " ").replace("...", "X").replace("…", "X")
            try:
                toks = shlex.split(tail)
            except ValueError:
                toks = tail.split()
            cut = []
            for t in toks:
                if t.endswith((":", ")", ",", ";", ".")) and not t.startswith("-"):
                    break
                cut.append(t.rstrip(",;:"))
            cut = [PLACEHOLDERS.get(t.strip("[]"), t.strip("[]")) for t in cut]
            if "#" in cut:
                cut = cut[: cut.index("#")]
            if cut and cut[-1] == "--real":
                cut.append("X")
            key = " ".join(cut)
            if key not in seen:
                seen.add(key)
                out.append((str(f.relative_to(REPO)), cut))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", type=Path)
    args = ap.parse_args()
    default = dataclasses.asdict(ManeuverParams())
    parsed, failed = {}, []
    for where, cmd in shown_commands():
        try:
            with contextlib.redirect_stderr(io.StringIO()):
                ns = build_parser().parse_args(["evaluate", "maneuver", *cmd])
            params = dataclasses.asdict(_maneuver_params(ns))
        except SystemExit:
            failed.append((where, " ".join(cmd)))
            continue
        parsed[" ".join(cmd)] = params
        off = {k: v for k, v in params.items() if v != default[k]}
        print(f"{' '.join(cmd) or '(no flags)'}: {off or 'defaults'}")
    print(f"{len(parsed)} commands parsed; {len(failed)} not parsed:")
    for where, cmd in failed:
        print(f"  {where}: {cmd}")
    if args.json:
        args.json.write_text(json.dumps(parsed, indent=1, sort_keys=True, default=str))


if __name__ == "__main__":
    main()
