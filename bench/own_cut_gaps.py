"""Association at a real set's own cuts, by the length of the gap a true pair spans.

``wakeline evaluate associate --real PATH --cut-s S`` gives one P_CA over every true pair;
on multi-day AIS most misses are gaps of many hours (a ferry silent overnight in port),
far beyond what any gate can bridge. This prints, for the defaults ("ours, optimal"), how
many true pairs each gap band holds and how many were joined, and the wrong joins by band.

    python bench/own_cut_gaps.py [PATH] [--cut-s 600] [--truth-sep -]

PATH: a recognised folder of ../shared/data/real (default the Saronic AIS) or a track file.
"""

import argparse
import os
from pathlib import Path

import numpy as np
import pandas as pd

from wakeline.core import real_sets
from wakeline.core.evaluate_association import (
    _known_set,
    _truth,
    consecutive_true_pairs,
    cut_at_gaps,
    run_method,
)
from wakeline.core.io import read_points

SHARED = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
BANDS_MIN = [0, 12, 20, 30, 60, 120, 360, np.inf]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("path", nargs="?", default=str(SHARED / "data/real/greece-ais-annotated"))
    ap.add_argument("--cut-s", type=float, default=600.0)
    ap.add_argument("--truth-sep", default="")
    a = ap.parse_args()
    known = _known_set(a.path)
    df = (
        real_sets.association_tracks(known.folder)
        if known is not None
        else read_points(a.path).points
    )
    if "truth" not in df.columns:
        ship = df["batch"].astype(str)
        df = df.assign(
            truth=_truth(
                df.assign(batch=ship.str.split(a.truth_sep).str[0] if a.truth_sep else ship)
            )
        )
    assoc = run_method(cut_at_gaps(df, a.cut_s), "ours, optimal")
    seg = assoc.segments
    truth = seg.column("truth").astype(str).to_numpy()[seg.index.starts]
    chosen = set(
        zip(assoc.pairs.i[assoc.chosen].tolist(), assoc.pairs.j[assoc.chosen].tolist(), strict=True)
    )
    true = consecutive_true_pairs(truth, seg.t0)
    rows = [
        {"gap_min": (seg.t0[j] - seg.t1[i]) / 60, "joined": (i, j) in chosen, "true": True}
        for i, j in true
    ] + [
        {"gap_min": (seg.t0[j] - seg.t1[i]) / 60, "joined": True, "true": False}
        for i, j in chosen - true
    ]
    r = pd.DataFrame(rows, columns=["gap_min", "joined", "true"])
    r["band (min)"] = pd.cut(r["gap_min"], BANDS_MIN, right=True)
    tab = r.groupby("band (min)", observed=False).apply(
        lambda g: pd.Series(
            {
                "true pairs": int(g["true"].sum()),
                "joined": int((g["true"] & g["joined"]).sum()),
                "wrong joins": int((~g["true"]).sum()),
            }
        ),
        include_groups=False,
    )
    print(f"{a.path}, cut at gaps > {a.cut_s:g} s: {len(true)} true pairs")
    print(tab.to_string())
    within = r["true"] & (r["gap_min"] <= 60)
    print(
        f"within 1 h (the second look's reach, long_gap_s): {int((within & r['joined']).sum())}"
        f" of {int(within.sum())} joined; all: {int((r['true'] & r['joined']).sum())} of "
        f"{len(true)}, {int((~r['true']).sum())} wrong"
    )


if __name__ == "__main__":
    main()
