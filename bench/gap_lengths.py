"""Association at other sampling rates and gap lengths than the tuning sets (issue 15):
hard simulated ships (speed changes, turns, missed scans, a dropped piece on 30 % of the
ships) seen by a fast harbour radar (1.3 s, 5 m, gaps 5–30 s, 60 ships in 4 km, clutter)
and by AIS-like reports (30 s, 10 m, gaps 60–600 s or 300–1,200 s, 60 ships in 8 km, no
clutter), three seeds each, ours with the defaults beside ``long_rivals=False``. None of
these was used to choose a default.

    python bench/gap_lengths.py [--seeds 3]
"""

import argparse
from contextlib import contextmanager

import numpy as np

from wakeline.core import simulate
from wakeline.core.associate import LinkParams, associate_interrupted
from wakeline.core.evaluate_association import score_association

#: name: (period s, noise m, gaps s, ships, area km, duration s, clutter per ship)
CASES = {
    "harbour radar 1.3 s, gaps 5-30 s": (1.3, 5.0, (5.0, 30.0), 60, 4.0, 1800.0, 0.3),
    "AIS 30 s, gaps 60-600 s": (30.0, 10.0, (60.0, 600.0), 60, 8.0, 3 * 3600.0, 0.0),
    "AIS 30 s, gaps 300-1200 s": (30.0, 10.0, (300.0, 1200.0), 60, 8.0, 3 * 3600.0, 0.0),
}


@contextmanager
def hard_as(gap_s: tuple[float, float], clutter: float):
    """The hard simulator with other gaps and clutter, restored afterwards."""
    saved = dict(simulate.HARD)
    simulate.HARD.update(gap_s=gap_s, clutter_per_ship=clutter)
    try:
        yield
    finally:
        simulate.HARD.clear()
        simulate.HARD.update(saved)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=3)
    args = ap.parse_args()
    variants = {"defaults": LinkParams(), "long_rivals=False": LinkParams(long_rivals=False)}
    for name, (period, sigma, gaps, ships, area, duration, clutter) in CASES.items():
        scores = {v: [] for v in variants}
        with hard_as(gaps, clutter):
            for seed in range(40, 40 + args.seeds):
                df = simulate.segments_scene(
                    seed=seed,
                    n_ships=ships,
                    area_km=area,
                    duration_s=duration,
                    period_s=period,
                    sigma_m=sigma,
                    hard=True,
                )
                for v, params in variants.items():
                    sc = score_association(associate_interrupted(df, params))
                    scores[v].append((sc["p_ca"], sc["p_fa"]))
        line = "; ".join(
            f"{v} P_CA {np.mean(s, axis=0)[0]:.3f} P_FA {np.mean(s, axis=0)[1]:.3f}"
            for v, s in scores.items()
        )
        print(f"{name:<28} {line}")


if __name__ == "__main__":
    main()
