"""Association on real AIS encounters with gaps cut in (issue 15): the Øresund set
(GPL, read from ../shared) has 10 encounters of two ships each, the give-way ship
manoeuvring while the stand-on ship holds on. Every track loses one window of fixes
(random length in [lo, hi] s, at a random place at least 2 min from either end), the
pieces are renumbered at random and associated with the defaults; the old ids are the
truth. Nothing here was tuned: the defaults were chosen on MTAD (docs/evaluation.md).

    python bench/oresund_association.py [--seeds 4] [--gap 60 240]
"""

import argparse
import os
from pathlib import Path

import numpy as np

from wakeline.core.evaluate_association import run_method, score_association
from wakeline.core.real_sets import oresund_cut, read_oresund

#: ../shared, or $WAKELINE_SHARED (as the tests read it)
SHARED = (
    Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
    / "data"
    / "real"
    / "oresund-encounters"
)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=SHARED)
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--gap", type=float, nargs=2, default=(60.0, 240.0), metavar=("LO", "HI"))
    args = ap.parse_args()
    if not (args.data / "encounters.csv").exists():
        raise SystemExit(f"{args.data}: encounters.csv not found (see ../shared/data/real)")
    pts = read_oresund(args.data)
    methods = ("ours, optimal", "seed 003 (min-max, greedy)")
    rows = []
    for seed in range(args.seeds):
        df = oresund_cut(pts, seed, *args.gap)
        scores = [score_association(run_method(df, m)) for m in methods]
        rows.append([(s["p_ca"], s["p_fa"]) for s in scores])
        line = "; ".join(
            f"{m}: P_CA {s['p_ca']:.3f}, P_FA {s['p_fa']:.3f}"
            for m, s in zip(methods, scores, strict=True)
        )
        print(f"seed {seed} ({df['batch'].nunique()} pieces): {line}")
    r = np.array(rows)  # seed, method, (p_ca, p_fa)
    for k, m in enumerate(methods):
        print(
            f"mean over {len(rows)} seeds, {m}: P_CA {r[:, k, 0].mean():.3f}, "
            f"P_FA {r[:, k, 1].mean():.3f}"
        )


if __name__ == "__main__":
    main()
