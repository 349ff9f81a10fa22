"""False turns on long, dense, noisy tracks (issue 15 goal 2; session 27, h170).

Operator test 4 (D-man-1) saw a 1 s "radar" of one ship (6 h, white noise 15 m per axis)
give 1,388 maneuver points where the ship made ~6 turns. This bench simulates such tracks
with known turns: per track a stay at the berth (``moor_min`` minutes, the noise alone),
then a ship at 8-12 kn with a turn every 15-40 min (20-90 deg at 0.3-1.0 deg/s, so 20 s to
5 min long); plots every ``dt`` s with white Gaussian noise ``sigma`` m per axis.

Scores: a detection is true when it lies within ``TOL_S`` (30 s) of a turn span; a turn
is found when a detection lies there. False detections per track-hour (all the track's
time, berth included) and those at the berth apart.

Run: ``python bench/long_noisy_tracks.py [--dts 1 2 5] [--sigmas 5 10 20] [--seeds 0 1 2]
[--hours 4] [--set key=value ...]`` (``--set``: a second row with these ManeuverParams).
"""

import argparse
import time

import numpy as np
import pandas as pd

from wakeline.core import geo
from wakeline.core.maneuver import ManeuverParams, detect
from wakeline.core.schema import time_seconds

LON0, LAT0 = 11.0, 57.0
TOL_S = 30.0


def make(seed: int, dt: float, sigma: float, hours: float = 4.0, moor_min: float = 20.0):
    """One track: canonical table and its turn spans (start, end) in seconds from start."""
    rng = np.random.default_rng(seed)
    duration = hours * 3600.0
    t = np.arange(0.0, duration, dt)
    moor = moor_min * 60.0
    rate = np.zeros_like(t)  # deg/s
    spans = []
    s = moor + rng.uniform(600, 1200)
    while s < duration - 600:
        ang, r = rng.uniform(20, 90), rng.uniform(0.3, 1.0)
        d = ang / r
        rate[(t >= s) & (t < s + d)] = rng.choice([-1, 1]) * r
        spans.append((s, s + d))
        s += d + rng.uniform(900, 2400)
    v = np.where(t < moor, 0.0, rng.uniform(8, 12) * geo.KN_MS)
    c = np.radians(rng.uniform(0, 360) + np.cumsum(rate) * dt)
    x, y = np.cumsum(v * np.sin(c) * dt), np.cumsum(v * np.cos(c) * dt)
    x = x + rng.normal(0, sigma, len(t))
    y = y + rng.normal(0, sigma, len(t))
    lon, lat = geo.from_local(x, y, LON0, LAT0)
    pts = pd.DataFrame(
        {
            "sensor": "RADAR",
            "batch": f"s{seed}",
            "time": pd.to_datetime(1.6e9 + t, unit="s", utc=True),
            "lon": lon,
            "lat": lat,
        }
    )
    return pts, np.array(spans).reshape(-1, 2), moor


def score(pts, spans, moor, params: ManeuverParams) -> dict:
    tab = detect(pts, params).table()
    t0 = time_seconds(pts["time"]).min()
    td = time_seconds(tab["time"]) - t0
    near = (td[:, None] >= spans[:, 0] - TOL_S) & (td[:, None] <= spans[:, 1] + TOL_S)
    true = near.any(axis=1)
    hours = (time_seconds(pts["time"]).max() - t0) / 3600.0
    return {
        "detections": len(td),
        "turns": len(spans),
        "found": int(near.any(axis=0).sum()),
        "false": int((~true).sum()),
        "false_per_h": float((~true).sum() / hours),
        "false_moored": int((~true & (td < moor)).sum()),
    }


def _value(text: str):
    return text.lower() == "true" if text.lower() in ("true", "false") else float(text)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dts", type=float, nargs="+", default=[1.0, 2.0, 5.0])
    ap.add_argument("--sigmas", type=float, nargs="+", default=[5.0, 10.0, 20.0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    ap.add_argument("--hours", type=float, default=4.0)
    ap.add_argument("--set", nargs="*", metavar="KEY=VALUE", help="ManeuverParams changes")
    args = ap.parse_args()
    variants = {"default": ManeuverParams()}
    if args.set:
        changes = {k: _value(v) for k, v in (item.split("=", 1) for item in args.set)}
        variants[" ".join(args.set)] = ManeuverParams(**changes)
    print(
        f"{'dt':>4} {'sigma':>5} {'seed':>4} {'variant':28} {'det':>5} {'turns':>5} "
        f"{'found':>5} {'false':>5} {'false/h':>8} {'moored':>6} {'s':>5}"
    )
    totals = {name: np.zeros(4) for name in variants}
    for dt in args.dts:
        for sigma in args.sigmas:
            for seed in args.seeds:
                pts, spans, moor = make(seed, dt, sigma, args.hours)
                for name, p in variants.items():
                    t1 = time.perf_counter()
                    s = score(pts, spans, moor, p)
                    el = time.perf_counter() - t1
                    totals[name] += [s["turns"], s["found"], s["false"], args.hours]
                    print(
                        f"{dt:>4g} {sigma:>5g} {seed:>4} {name:28} {s['detections']:>5} "
                        f"{s['turns']:>5} {s['found']:>5} {s['false']:>5} "
                        f"{s['false_per_h']:>8.2f} {s['false_moored']:>6} {el:>5.1f}",
                        flush=True,
                    )
    for name, (turns, found, false, hours) in totals.items():
        print(
            f"total {name}: turns {turns:g} found {found:g} false {false:g} "
            f"({false / hours:.2f} per track-hour)"
        )


if __name__ == "__main__":
    main()
