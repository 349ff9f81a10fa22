"""The time rules of the importer on the real files (../shared/data/real): rows each rule
quarantines, the count check (every row a point or a quarantine row), and how close the
real tracks' first and last rows come to the edge-row rule (a mistyped date in a track's
first or last row, ``_edge_times`` in core/io/reader.py).

    python bench/edge_rows_real.py [--floor-h 1]

``--floor-h``: also run the edge-row rule with its one-day floor lowered to this many
hours, to see what its two other conditions (100 x the track's median step, no other
track at that time) keep on their own."""

import argparse
import glob
import os
import time
from pathlib import Path

import numpy as np
import pandas as pd

import wakeline.core.io.reader as R
from wakeline.core.io import read_points

REAL = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
REAL = REAL / "data" / "real"
RULES = {"decades": "time decades", "lone": "time days away", "edge": "time days from the rest"}


def real_files() -> list[str]:
    names = glob.glob(str(REAL / "**" / "*"), recursive=True)
    keep = [p for p in names if p.endswith((".csv", ".txt", ".csv.gz"))]
    return sorted(p for p in keep if Path(p).stat().st_size > 1000)


def edge_gaps(points) -> np.ndarray:
    """Per track of >= 3 points (file order): the gap (s) of its first and of its last
    point to its one neighbour, and the track's median step (s), as rows."""
    out = []
    t = pd.DatetimeIndex(points["time"]).asi8 / 1e9
    for _, idx in points.groupby(["sensor", "batch"], observed=True, sort=False).indices.items():
        if len(idx) < 3:
            continue
        tt = t[np.sort(idx)]
        med = float(np.median(np.abs(np.diff(tt))))
        out += [(abs(tt[0] - tt[1]), med), (abs(tt[-1] - tt[-2]), med)]
    return np.asarray(out).reshape(-1, 2)


def run(files: list[str]) -> tuple[dict, int, int, list]:
    counts = dict.fromkeys(RULES, 0)
    rows = mismatches = 0
    gaps = []
    for f in files:
        try:
            r = read_points(f)
        except Exception:  # noqa: BLE001 - files the importer refuses are not counted
            continue
        rep, q = r.report, r.quarantine
        if rep["rows_imported"] + rep["rows_quarantined"] != rep["rows_read"]:
            mismatches += 1
            print("COUNT MISMATCH", f)
        for k, prefix in RULES.items():
            hit = int(q["reason"].str.startswith(prefix).sum()) if len(q) else 0
            counts[k] += hit
            if hit and k != "decades":
                print(f"  {k}: {hit} rows quarantined in {f}")
        rows += rep["rows_read"]
        gaps.append((f, edge_gaps(r.points)))
    return counts, rows, mismatches, gaps


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--floor-h", type=float, default=None)
    args = ap.parse_args()
    files = real_files()
    cpu = time.process_time()
    counts, rows, mismatches, gaps = run(files)
    print(f"{len(files)} files, {rows:,} rows read, count mismatches: {mismatches}")
    print("quarantined by rule:", counts, f"(cpu {time.process_time() - cpu:.1f} s)")
    g = np.concatenate([x for _, x in gaps if len(x)])
    in_files = sum(1 for _, x in gaps if len(x) and (x[:, 0] > 3600).any())
    print(
        f"edge rows more than 1 h from their neighbour: {(g[:, 0] > 3600).sum()} "
        f"({in_files} files); more than 12 h: {(g[:, 0] > 43_200).sum()}; "
        f"more than a day: {(g[:, 0] > 86_400).sum()}; largest {g[:, 0].max() / 86_400:.2f} d"
    )
    if args.floor_h is not None:
        R.LONE_MIN_S = args.floor_h * 3600.0  # both time rules read it at call time
        counts, *_ = run(files)
        print(f"with a floor of {args.floor_h:g} h instead of a day:", counts)


if __name__ == "__main__":
    main()
