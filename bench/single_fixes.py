"""Association of ships seen as single fixes (issue 15): a sensor that sees some ships only
every few minutes (MTAD's sparse tracks, AIS far off, a radar's faint targets), so each fix
is a piece of its own, with no motion at either end of a pair between two of them. Every
track is cut where its step exceeds 120 s, as `wakeline evaluate associate --real` cuts
real sets. Defaults beside ``blind_order=0`` (every such pair alike: the solver's order
decides) and ``chain_passes`` 2 and 3.

Cases (straight ships, uniform speed 3–12 m/s and course; each case's seeds):
"tuning: mixed" (40 ships in 20 km, 300 m noise, half of them single fixes every
150–210 s, the other half every 5–15 s with a few 150–400 s gaps) and "tuning: dense
singles" (12 ships in 8 km, 100 m noise, all single fixes) were used to choose
``blind_order``'s form among the gap, ln(distance × gap), the implied speed and gap +
speed; the "report" ones were run after, once.

    python bench/single_fixes.py [--seeds 8]
"""

import argparse

import numpy as np
import pandas as pd

from wakeline.core import geo, simulate
from wakeline.core.associate import LinkParams, associate_interrupted
from wakeline.core.evaluate_association import score_association

#: name: (first seed, ships, side km, noise m, single-fix interval s, share seen as single
#: fixes, hours)
CASES = {
    "tuning: mixed": (0, 40, 20.0, 300.0, (150.0, 210.0), 0.5, 1.0),
    "tuning: dense singles": (100, 12, 8.0, 100.0, (150.0, 210.0), 1.0, 0.5),
    "report: radar-like singles": (200, 20, 6.0, 50.0, (100.0, 140.0), 1.0, 0.5),
    "report: MTAD-like": (300, 60, 30.0, 500.0, (150.0, 330.0), 0.3, 2.0),
}


def scene(
    seed: int,
    ships: int,
    side_km: float,
    noise_m: float,
    single_s: tuple[float, float],
    share_single: float,
    hours: float,
) -> pd.DataFrame:
    """Straight ships; a share of them seen as single fixes, the rest every 5–15 s with a
    3 % chance of a 150–400 s gap after each fix; cut where a step exceeds 120 s, pieces
    renumbered at random (truth: the ship)."""
    rng = np.random.default_rng(seed)
    dur, rows = hours * 3600.0, []
    for s in range(ships):
        x0, y0 = rng.uniform(0, side_km * 1000.0, 2)
        v, h = rng.uniform(3, 12), rng.uniform(0, 2 * np.pi)
        single = rng.random() < share_single
        t = rng.uniform(0, 300)
        while t < dur:
            xy = np.array([x0 + v * np.sin(h) * t, y0 + v * np.cos(h) * t])
            rows.append((s, t, *(xy + rng.normal(0, noise_m, 2))))
            if single:
                t += rng.uniform(*single_s)
            else:
                t += rng.uniform(5, 15) + (rng.uniform(150, 400) if rng.random() < 0.03 else 0)
    df = pd.DataFrame(rows, columns=["ship", "t", "x", "y"]).sort_values(["ship", "t"])
    new = (df["ship"].diff() != 0) | (df["t"].diff() > 120)
    piece = np.cumsum(new.to_numpy()) - 1
    perm = rng.permutation(piece.max() + 1)
    lon, lat = geo.from_local(df["x"].to_numpy(), df["y"].to_numpy(), *simulate.SCENE_ORIGIN)
    return pd.DataFrame(
        {
            "sensor": "R1",
            "batch": perm[piece].astype(str),
            "truth": df["ship"].astype(str).to_numpy(),
            "time": pd.to_datetime(1.7e9 + df["t"].to_numpy(), unit="s", utc=True),
            "lon": lon,
            "lat": lat,
        }
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=8)
    args = ap.parse_args()
    variants = {
        "defaults": LinkParams(),
        "blind_order=0": LinkParams(blind_order=0.0),
        "chain_passes=2": LinkParams(chain_passes=2),
        "chain_passes=3": LinkParams(chain_passes=3),
    }
    for case, (first, *spec) in CASES.items():
        print(case)
        scenes = [scene(seed, *spec) for seed in range(first, first + args.seeds)]
        base = None
        for v, params in variants.items():
            got = np.array(
                [
                    [sc["p_ca"], sc["p_fa"]]
                    for sc in (
                        score_association(associate_interrupted(df, params)) for df in scenes
                    )
                ]
            )
            line = f"  {v:<15} P_CA/P_FA mean {got[:, 0].mean():.3f}/{got[:, 1].mean():.3f}"
            if base is None:
                base = got
            else:
                up = int((base[:, 0] > got[:, 0]).sum())
                down = int((base[:, 0] < got[:, 0]).sum())
                line += f"; the defaults' P_CA higher in {up}, lower in {down} of {len(got)} seeds"
            print(line)


if __name__ == "__main__":
    main()
