"""Association in a harbour with ships at rest (issue 15): ships at berths along three
quays (spacing drawn per case, GPS jitter 2–8 m, AIS every 3 min), ships swinging at anchor
(40–150 m, 500 m and more apart) and hard moving ships (10 s, 10 m), every track cut once
at a known gap (``cut_known_gaps``). Defaults beside ``rest_seen_s=0`` (no evidence from
the ends' scatter), ``rest_drift_s=0`` (the allowance whatever the gap) and both (session
11's rest model). Cases: "tuning" (seeds 0–2, berths 30–80 m apart, gaps 300–900 s) was
looked at while the rules were made; the "report" ones were run after (seeds 10–12,
berths 25–60 m apart, gaps 600–1,500 s; seeds 20–22, an anchorage on a 350 m grid whose
ships swing round once with the tide).

    python bench/moored_harbour.py [--seeds 3]
    python bench/moored_harbour.py --wander   # real ships at rest (Saronic, from ../shared)

``--wander``: how far real ships at rest (greece-ais-annotated, GPL, read from
``../shared``) lie g seconds after an end of 10 fixes at rest (spanning at most 30 min,
end to end slower than 0.25 m/s) from that end's mean position; the evidence for
``rest_drift_s``.
"""

import argparse
import os
from pathlib import Path

import numpy as np
import pandas as pd

from wakeline.core import geo, simulate
from wakeline.core.associate import LinkParams, associate_interrupted
from wakeline.core.evaluate_association import cut_known_gaps, score_association

#: name: (first seed, berth spacing m, known gaps s, anchorage on a 350 m grid whose ships
#: swing round with the tide (180° over 30 min, once))
CASES = {
    "tuning: berths 30-80 m, gaps 300-900 s": (0, (30.0, 80.0), (300.0, 900.0), False),
    "report: berths 25-60 m, gaps 600-1500 s": (10, (25.0, 60.0), (600.0, 1500.0), False),
    "report: + anchorage 350 m apart, tide swing": (20, (30.0, 80.0), (600.0, 1500.0), True),
}


def harbour(
    seed: int,
    spacing: tuple[float, float],
    tide: bool = False,
    n_berth: int = 39,
    n_anchor: int = 15,
    n_move: int = 20,
) -> pd.DataFrame:
    """Six hours of a harbour: berths, an anchorage and moving ships (truth b*, a*, m*).
    ``tide``: the anchorage is a 350 m grid and each ship there swings round once."""
    rng = np.random.default_rng(seed)
    dur, t0, rows = 6 * 3600.0, 1.7e9, []
    n = int(dur / 180)
    for q in range(3):  # three quays 250 m apart
        x = 0.0
        for k in range(n_berth // 3):
            x += rng.uniform(*spacing)
            t = t0 + np.cumsum(rng.uniform(170, 190, n))
            jitter = rng.uniform(2, 8)
            xy = np.array([x, q * 250.0]) + rng.normal(0, jitter, (n, 2))
            rows.append(pd.DataFrame({"truth": f"b{q}-{k}", "t": t, "x": xy[:, 0], "y": xy[:, 1]}))
    for k in range(n_anchor):
        centre = rng.uniform([-1500, 800], [1500, 2500])
        if tide:
            centre = np.array([(k % 5) * 350.0, 800.0 + (k // 5) * 350.0])
        radius = rng.uniform(40, 150)
        t = t0 + np.cumsum(rng.uniform(170, 190, n))
        ang = np.cumsum(rng.normal(0, 0.05, n)) + rng.uniform(0, 2 * np.pi)
        if tide:
            turn = rng.uniform(0, dur)
            ang = ang + np.pi * np.clip((t - t0 - turn) / 1800.0, 0.0, 1.0)
        x = centre[0] + radius * np.cos(ang) + rng.normal(0, 4, n)
        y = centre[1] + radius * np.sin(ang) + rng.normal(0, 4, n)
        rows.append(pd.DataFrame({"truth": f"a{k}", "t": t, "x": x, "y": y}))
    df = pd.concat(rows, ignore_index=True)
    lon, lat = geo.from_local(df["x"].to_numpy(), df["y"].to_numpy(), *simulate.SCENE_ORIGIN)
    still = pd.DataFrame(
        {
            "sensor": "AIS",
            "batch": df["truth"],
            "truth": df["truth"],
            "time": pd.to_datetime(df["t"], unit="s", utc=True),
            "lon": lon,
            "lat": lat,
        }
    )
    ships = simulate.hard_ships(rng, n_move, 6000.0, dur)
    spec = simulate.SensorSpec("AIS", period_s=10.0, sigma_m=10.0, coverage=1.0, interrupt=False)
    counter = simulate._BatchCounter(1000)
    moving = pd.concat(
        [f for s in ships for f in simulate._observe(rng, s, spec, counter, simulate.SCENE_ORIGIN)],
        ignore_index=True,
    )
    name = "m" + moving["truth"].astype(str)
    moving = moving.assign(batch=name, truth=name)
    return pd.concat([still, moving[still.columns]], ignore_index=True)


#: ../shared, or $WAKELINE_SHARED (as the tests read it)
SARONIC = (
    Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
    / "data/real/greece-ais-annotated/vessels.csv"
)


def wander(path: Path = SARONIC, n: int = 10) -> None:
    """Percentiles of the distance (m) from an at-rest end's mean to the fix g s later."""
    df = pd.read_csv(path, sep=" ", header=None, names=["id", "lon", "lat", "t"])
    out = []
    for _, g in df.groupby("id"):
        g = g.sort_values("t")
        x, y = geo.to_local(
            g["lon"].to_numpy(), g["lat"].to_numpy(), g["lon"].mean(), g["lat"].mean()
        )
        t = g["t"].to_numpy(dtype="float64")
        for k in range(n, len(t) - 1, 3):
            xs, ys, ts = x[k - n : k], y[k - n : k], t[k - n : k]
            if ts[-1] - ts[0] > 1800:
                continue
            if np.hypot(xs[-1] - xs[0], ys[-1] - ys[0]) / max(ts[-1] - ts[0], 1.0) > 0.25:
                continue
            for gap in (300, 900, 1800, 3600):
                m = np.searchsorted(t, ts[-1] + gap)
                if m < len(t) and t[m] - ts[-1] <= gap * 1.3:
                    sd = np.sqrt((np.var(xs) + np.var(ys)) / 2)  # the end's scatter per axis
                    out.append((gap, sd, np.hypot(x[m] - xs.mean(), y[m] - ys.mean())))
    o = pd.DataFrame(out, columns=["gap_s", "sd", "d"])
    o = o[o["d"] < 1000]  # a ship that sailed away
    q = o.groupby("gap_s")["d"].quantile([0.5, 0.9]).unstack()
    print("real ships at rest (Saronic): distance from the end's mean, m")
    for gap, row in q.iterrows():
        print(f"  after {gap:5d} s: median {row[0.5]:5.1f}, 90 % {row[0.9]:5.1f}")
    o["scatter"] = pd.cut(o["sd"], [-1.0, 2.0, 5.0, 20.0], labels=["<= 2 m", "2-5 m", "5-20 m"])
    by = o.groupby(["scatter", "gap_s"], observed=True)["d"]
    print("by the end's own scatter (per axis): 90 % of the distance, m; the same as a")
    print("per-axis wander (Rayleigh: 90 % / 2.146, less the scatter), in units of the scatter")
    for (band, gap), d90 in by.quantile(0.9).items():
        sd = o.loc[(o["scatter"] == band) & (o["gap_s"] == gap), "sd"].median()
        wander = np.sqrt(max((d90 / 2.146) ** 2 - sd**2, 0.0))
        print(
            f"  scatter {band:>6}, after {gap:5d} s: 90 % {d90:6.1f}; wander {wander / sd:4.1f} x"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--wander", action="store_true", help="real ships at rest (Saronic)")
    ap.add_argument("--set", action="append", default=[], help="one more row: NAME=VALUE")
    args = ap.parse_args()
    if args.wander:
        wander()
        return
    variants = {
        "defaults": LinkParams(),
        "rest_move=0.5": LinkParams(rest_move=0.5),
        "rest_drift_s=2700": LinkParams(rest_drift_s=2700.0),
        "session 11": LinkParams(rest_seen_s=0.0),
    }
    if args.set:
        variants[" ".join(args.set)] = LinkParams().replace(
            **dict(kv.split("=", 1) for kv in args.set)
        )
    for case, (first, spacing, gaps, tide) in CASES.items():
        print(case)
        for v, params in variants.items():
            got = []
            for seed in range(first, first + args.seeds):
                df = cut_known_gaps(harbour(seed, spacing, tide), *gaps, seed=seed)
                sc = score_association(associate_interrupted(df, params))
                got.append((sc["p_ca"], sc["p_fa"]))
            each = ", ".join(f"{a:.3f}/{b:.3f}" for a, b in got)
            mean = np.mean(got, axis=0)
            print(f"  {v:<16} P_CA/P_FA per seed {each}; mean {mean[0]:.3f}/{mean[1]:.3f}")


if __name__ == "__main__":
    main()
