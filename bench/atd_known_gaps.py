"""Where the joins on sparse AIS (ATD 2025, ~30-min posits) at known 30–60 min gaps come
from: right and wrong joins by the band of their gap as the time limits count it (``first``
≤ ``max_gap_s`` < ``soft`` ≤ ``soft_gap_s`` < ``long``), with raw gaps and piece sizes.

    python bench/atd_known_gaps.py [FILE] [--set NAME=VALUE ...]

FILE defaults to ../shared/data/real/atd2025-noaa/example_truth.csv.gz (MIT; read from
../shared, or WAKELINE_SHARED). Session 21: with each end's 30-min step counted as T_gap,
1,143 of 1,346 wrong joins were in the first band (gaps of about one report).
"""

import argparse
import os
from pathlib import Path

import numpy as np

from wakeline.core.associate import LinkParams, counted_gap
from wakeline.core.evaluate_association import _truth, cut_known_gaps, run_method
from wakeline.core.io import read_points

#: ../shared, or $WAKELINE_SHARED (as the tests read it)
SHARED = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
ATD = SHARED / "data/real/atd2025-noaa/example_truth.csv.gz"


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file", nargs="?", default=ATD)
    ap.add_argument("--set", action="append", default=[], help="LinkParams NAME=VALUE")
    ap.add_argument("--gaps", nargs=2, type=float, default=(1800.0, 3600.0))
    a = ap.parse_args(argv)
    params = LinkParams().replace(**dict(kv.split("=", 1) for kv in a.set))
    pts = read_points(a.file, mapping=["batch=track_id"]).points
    cut = cut_known_gaps(pts.assign(truth=_truth(pts)), *a.gaps, seed=0)
    res = run_method(cut, "ours, optimal", params)
    seg = res.segments
    truth = seg.column("truth").astype(str).to_numpy()[seg.index.starts]
    ch = res.chosen
    i, j = res.pairs.i[ch], res.pairs.j[ch]
    right = truth[i] == truth[j]
    counted = counted_gap(res.pairs)[ch]
    band = np.where(
        counted <= params.max_gap_s,
        "first",
        np.where(counted <= max(params.soft_gap_s, params.max_gap_s), "soft", "long"),
    )
    print(f"{Path(a.file).name}, known gaps {a.gaps[0]:g}-{a.gaps[1]:g} s")
    print(f"joins {len(ch)}: right {int(right.sum())}, wrong {int((~right).sum())}")
    for b in ("first", "soft", "long"):
        m = band == b
        print(f"  {b:<5} right {int((right & m).sum()):5d}  wrong {int((~right & m).sum()):5d}")
    for name, m in (("right", right), ("wrong", ~right)):
        if m.any():
            q = np.percentile(res.pairs.gap_s[ch][m], [10, 50, 90])
            print(f"  {name}: raw gap 10/50/90 % {q[0]:.0f} / {q[1]:.0f} / {q[2]:.0f} s")
    single = (seg.n[i] == 1) | (seg.n[j] == 1)
    print(f"  wrong joins with a single-fix piece: {int((~right & single).sum())}")


if __name__ == "__main__":
    main()
