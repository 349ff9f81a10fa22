"""How often the issue-16 goals can be met at all: the clairvoyant bound over many draws.

For each random geometry (``bearing_eval.random_scenarios``, drawn as the held-out
evaluation draws them) at 1 s, 2 s and jittered sampling, ``detection_bound`` gives the most
any detector can find of a 50° turn at 3 % false alarms per run (σ 0.6°, 5 min). The
script prints the share of cells below 90 % (no detector reaches the worst-cell goal there)
and, over random report sets of ``--set-size`` geometries, how often the bound itself
admits the goals (mean ≥ 98 %, worst ≥ 90 %). A real detector finds less than the bound.

    python bench/bearing_bound.py [--seed 777] [--geometries 300] [--set-size 8]
"""

import argparse

import numpy as np

from wakeline.core.bearing_eval import detection_bound, random_scenarios


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=777)
    ap.add_argument("--geometries", type=int, default=300)
    ap.add_argument("--set-size", type=int, default=8)
    ap.add_argument("--draws", type=int, default=5000)
    a = ap.parse_args()
    scs = random_scenarios(a.seed, a.geometries)
    bound = np.array([detection_bound(sc) for sc in scs]).reshape(a.geometries, -1)
    print(
        f"{a.geometries} geometries x {bound.shape[1]} samplings (seed {a.seed}): "
        f"mean bound {bound.mean():.1%}; cells below 90 %: {(bound < 0.9).mean():.1%}; "
        f"below 98 %: {(bound < 0.98).mean():.1%}; geometries with a cell below 90 %: "
        f"{(bound.min(axis=1) < 0.9).mean():.1%}"
    )
    rng = np.random.default_rng(0)
    pick = np.array([rng.choice(a.geometries, a.set_size, replace=False) for _ in range(a.draws)])
    means = bound[pick].mean(axis=(1, 2))
    worst = bound[pick].min(axis=(1, 2))
    ok = (means >= 0.98) & (worst >= 0.9)
    print(
        f"report sets of {a.set_size} geometries ({a.draws} draws): the bound admits mean >= 98 % "
        f"in {(means >= 0.98).mean():.1%}, worst >= 90 % in {(worst >= 0.9).mean():.1%}, "
        f"both in {ok.mean():.1%}"
    )
    for name, seed, n in (("report set (seed 1)", 1, 8), ("tune set (seed 1001)", 1001, 6)):
        b = np.array([detection_bound(sc) for sc in random_scenarios(seed, n)])
        print(f"{name}: bound mean {b.mean():.1%}, worst {b.min():.1%}")


if __name__ == "__main__":
    main()
