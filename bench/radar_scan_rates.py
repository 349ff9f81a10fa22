"""Turns of the Autoferry radar (and lidar) plots against their GNSS truth when the sensor
scans more slowly: the tracks decimated to one plot every 2–5 s, as a harbour or ship radar
turning at 12–30 rpm would give them (the set's radar scans every 1.68 s, its lidar every
0.5 s). Each rate is scored as ``wakeline evaluate maneuver --real FILE --gnss TRUTH``
scores a plain file (``core.evaluate_real``), with the defaults and with each ``--set`` row.

    python bench/radar_scan_rates.py [--sensor radar|lidar] [--rates 2 2.5 3 4 5]
        [--set window_p=4] [--set window_p=3 slow_side=0.5] ...

One line per rate: precision / recall (detections, scored turns) and F1 for every row, and
the F1 of each row as a ratio of the defaults' in the same run. Session 24's figures and the
rule they were held to: docs/evaluation.md "Radar at slower scans (session 24)".
"""

import argparse
import os
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "bench"))
from sampling_sweep import decimate  # noqa: E402

from wakeline.core import real_sets  # noqa: E402
from wakeline.core.evaluate_real import evaluate_real  # noqa: E402
from wakeline.core.io import write_points  # noqa: E402
from wakeline.core.maneuver import ManeuverParams  # noqa: E402

REAL = Path(os.environ.get("WAKELINE_SHARED", REPO.parent / "shared")) / "data" / "real"


def _params(pairs: list[str]) -> ManeuverParams:
    """``["window_p=4", "slow_side=0.5"]`` → the defaults with those fields changed."""
    base = ManeuverParams()
    changes = {}
    for pair in pairs:
        key, _, value = pair.partition("=")
        changes[key] = type(getattr(base, key))(float(value))
    return replace(base, **changes)


def score(points, truth_csv: Path, params: ManeuverParams, folder: Path) -> dict:
    """P, R, F1 and counts of ``params`` on ``points`` written as a plain file."""
    path = folder / "plots.csv"
    write_points(points.assign(sensor="radar"), path)
    r = evaluate_real(path, params=params, gnss=truth_csv, gnss_fault_m=0.5).rows
    r = r.set_index("method").loc["ours"]
    p, rec = float(r["precision"]), float(r["recall"])
    f1 = 2 * p * rec / (p + rec) if p + rec else 0.0
    return {"P": p, "R": rec, "F1": f1, "det": int(r["detections"]), "turns": int(r["turns"])}


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sensor", choices=("radar", "lidar"), default="radar")
    ap.add_argument("--rates", nargs="+", type=float, default=[2.0, 2.5, 3.0, 4.0, 5.0])
    ap.add_argument(
        "--set",
        nargs="+",
        action="append",
        default=[],
        metavar="FIELD=VALUE",
        help="one more row: the defaults with these ManeuverParams changes",
    )
    a = ap.parse_args(argv)
    folder = REAL / "autoferry-fusion"
    if not folder.is_dir():
        sys.exit(f"{folder} not found (set WAKELINE_SHARED)")
    rows = {"defaults": ManeuverParams()} | {" ".join(s): _params(s) for s in a.set}
    pts, truth = real_sets.read_autoferry(folder, exclusive=True, sensor=a.sensor)
    cpu0, wall0 = time.process_time(), time.time()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        write_points(truth, tmp / "gnss.csv")
        print(f"{a.sensor}: P/R (detections, turns) F1 [F1 / defaults' F1]")
        sums = dict.fromkeys(rows, 0.0)
        for rate in [None, *a.rates]:
            plots = pts if rate is None else decimate(pts, rate)
            cells, base = [], None
            for name, params in rows.items():
                s = score(plots, tmp / "gnss.csv", params, tmp)
                base = s["F1"] if base is None else base
                sums[name] += s["F1"]
                ratio = s["F1"] / base if base else float("nan")
                cells.append(
                    f"{name} {s['P']:.2f}/{s['R']:.2f} ({s['det']},{s['turns']}) "
                    f"F1 {s['F1']:.3f} [{ratio:.2f}]"
                )
            label = "own" if rate is None else f"{rate:g} s"
            print(f"{label:>6} ({len(plots):>5} plots) | " + " | ".join(cells), flush=True)
    print("F1 summed over the rates: " + ", ".join(f"{k} {v:.3f}" for k, v in sums.items()))
    print(f"CPU {time.process_time() - cpu0:.0f} s, wall {time.time() - wall0:.0f} s")


if __name__ == "__main__":
    main()
