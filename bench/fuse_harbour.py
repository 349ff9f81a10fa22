"""Multi-sensor pairing in a harbour: ships in parallel lanes, AIS (30 s) sees every ship
whole, a radar (4 s, 40 m noise) sees 70-80 % of them, each broken into 2-3 pieces.

Prints P_CA / P_FA of `associate_sensors` with seed 003's gates (raw point counts, no
best-distance bound) and with the defaults, on the case the change was made for (500 m
lanes, seeds 0-7) and on held-out cases (other lane spacings, fleet sizes and seeds).

    python bench/fuse_harbour.py
"""

import numpy as np
import pandas as pd

from wakeline.core import geo
from wakeline.core.evaluate_association import sensor_pair_scores
from wakeline.core.fuse import FuseParams, associate_sensors


def harbour(seed: int, n: int = 60, spacing: float = 500.0, radar_share: float = 0.8):
    """The scene as a canonical table with a truth column (ship id)."""
    rng = np.random.default_rng(seed)
    parts = []
    for k in range(n):
        y0 = (k % 12) * spacing
        x0 = (k // 12) * 3000.0 + rng.uniform(-200, 200)
        v, hd = rng.uniform(4, 8), np.radians(rng.normal(90, 3))
        t_start = rng.uniform(0, 600)

        def pos(t, x0=x0, y0=y0, v=v, hd=hd, t_start=t_start, k=k):
            x = x0 + v * np.sin(hd) * (t - t_start)
            y = y0 + v * np.cos(hd) * (t - t_start) + 30 * np.sin(t / 400.0 + k)
            return x, y

        def seen(sensor, batch, t, sigma, k=k):
            x, y = pos(t)
            lon, lat = geo.from_local(
                x + rng.normal(0, sigma, len(t)), y + rng.normal(0, sigma, len(t)), 122.0, 30.0
            )
            return pd.DataFrame(
                {"sensor": sensor, "batch": batch, "t": t, "lon": lon, "lat": lat, "truth": f"S{k}"}
            )

        ta = np.arange(t_start, t_start + 3600.0, 30.0) + rng.uniform(0, 2)
        parts.append(seen("AIS", f"A{k}", ta, 8.0))
        if rng.random() < radar_share:
            tr = np.arange(t_start, t_start + 3600.0, 4.0)
            cuts = np.sort(rng.uniform(tr[0] + 300, tr[-1] - 300, rng.integers(1, 3)))
            piece = np.searchsorted(cuts, tr)
            keep = np.ones(len(tr), dtype=bool)
            for c in cuts:
                keep &= np.abs(tr - c) > rng.uniform(20, 120)
            for p in np.unique(piece):
                sel = keep & (piece == p)
                parts.append(seen("R1", f"R{k}_{p}", tr[sel], 40.0))
    df = pd.concat(parts, ignore_index=True)
    df["time"] = pd.to_datetime(1.7e9 + df.pop("t"), unit="s", utc=True)
    return df


CASES = {
    "tuning: 60 ships, lanes 500 m, seeds 0-7": (60, 500.0, 0.8, range(8)),
    "held out: 60 ships, lanes 250 m": (60, 250.0, 0.7, range(200, 206)),
    "held out: 40 ships, lanes 1 km": (40, 1000.0, 0.7, range(200, 206)),
    "held out: 30 ships, lanes 150 m": (30, 150.0, 0.7, range(200, 206)),
}
VARIANTS = {
    "seed 003 gates": FuseParams(best_factor=0.0, count_at_rates=False),
    "counts at rates": FuseParams(best_factor=0.0),
    "defaults": FuseParams(),
}


def main() -> None:
    print(f"{'case':44s} " + "  ".join(f"{v:>17s}" for v in VARIANTS))
    for case, (n, spacing, share, seeds) in CASES.items():
        scenes = [harbour(s, n, spacing, share) for s in seeds]
        cells = []
        for params in VARIANTS.values():
            r = [sensor_pair_scores(associate_sensors(df, params)) for df in scenes]
            ca = np.mean([x["p_ca"] for x in r])
            fa = np.mean([x["p_fa"] for x in r])
            cells.append(f"{ca:.3f} / {fa:.3f}")
        print(f"{case:44s} " + "  ".join(f"{c:>17s}" for c in cells))


if __name__ == "__main__":
    main()
