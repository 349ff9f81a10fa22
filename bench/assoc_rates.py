"""Association at known gaps on decimated real sets, per set and rate (issue 15; the
sampling sweep's decimation and gaps): P_CA / P_FA (ours, optimal; mean over scenes), the
true pairs, and the wrong joins / misses by kind, summed (``error_breakdown``).

    python bench/assoc_rates.py --sets mtad-tune saronic --rates 180
    python bench/assoc_rates.py --sets mtad-held --rates 180 600 --set end_span_s=0

``own`` as a rate: the set as it is. ``--set NAME=VALUE``: a LinkParams change.
"""

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import sampling_sweep as sw  # noqa: E402

from wakeline.core.associate import LinkParams  # noqa: E402
from wakeline.core.evaluate_association import MTAD_SPLIT, real_files, scene_scores  # noqa: E402
from wakeline.core.io import read_points  # noqa: E402

KINDS = (
    "wrong_skip",
    "wrong_loose",
    "wrong_swap",
    "miss_not_candidate",
    "miss_taken",
    "miss_left_loose",
)


def scenes_of(name: str) -> tuple[list, tuple]:
    """(points, truth_sep) per scene and the set's (gaps, every); ``mtad-tune-cut``,
    ``mtad-held-cut``: MTAD cut at its own gaps over 120 s (gaps None)."""
    if name.startswith("mtad"):
        half = MTAD_SPLIT["tuning half" if name.startswith("mtad-tune") else "held-out half"]
        files = [f for f in real_files(sw.REAL / sw.SETS["mtad"][0]) if f.name in half]
        gaps = (None, None) if name.endswith("-cut") else sw.SETS["mtad"][1]
        return [(read_points(f).points, "-") for f in files], gaps
    return sw.read_set(name)[1], sw.SETS[name][1]


def run(name: str, rate, params: LinkParams, read=None) -> dict:
    """Mean scores of set ``name`` decimated to ``rate`` s (None: as it is); ``read``: the
    set's :func:`scenes_of`, read once for every rate."""
    scenes, (gaps, every) = read or scenes_of(name)
    rows = []
    for pts, sep in scenes:
        if rate is not None:
            pts = sw.decimate(pts, rate)
        r = scene_scores(pts, params=params, gaps=gaps, gaps_every=every, truth_sep=sep)[0]
        if r["true_pairs"] > 0:
            rows.append(r)
    out = {
        "p_ca": float(np.mean([r["p_ca"] for r in rows])),
        "p_fa": float(np.mean([r["p_fa"] for r in rows])),
        "pairs": sum(r["true_pairs"] for r in rows),
        "reach": sum(r["reachable"] for r in rows),
    }
    out.update({k: sum(r[k] for r in rows) for k in KINDS})
    return out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument(
        "--sets",
        nargs="+",
        default=["mtad-tune", "saronic"],
        help="mtad-tune, mtad-held (300-900 s known gaps), mtad-tune-cut, mtad-held-cut "
        "(own gaps over 120 s), saronic, dma, oresund",
    )
    ap.add_argument("--rates", nargs="+", default=["180"])
    ap.add_argument("--set", action="append", default=[], help="LinkParams NAME=VALUE")
    a = ap.parse_args(argv)
    params = LinkParams().replace(**dict(kv.split("=", 1) for kv in a.set))  # text converted
    cpu = time.process_time()
    print(f"{'set':<10}{'rate':>6}  P_CA  P_FA pairs reach  skip loose swap | notc taken loose")
    for name in a.sets:
        read = scenes_of(name)
        for r in a.rates:
            rate = None if r == "own" else float(r)
            o = run(name, rate, params, read)
            print(
                f"{name:<10}{r:>6} {o['p_ca']:.3f} {o['p_fa']:.3f} {o['pairs']:5d} {o['reach']:5d}"
                f"  {o['wrong_skip']:4d} {o['wrong_loose']:5d} {o['wrong_swap']:4d} |"
                f" {o['miss_not_candidate']:4d} {o['miss_taken']:5d} {o['miss_left_loose']:5d}",
                flush=True,
            )
    print(f"CPU {time.process_time() - cpu:.0f} s, load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
