"""Session 31 (h240): where, in a per-track noise ratio, do the slow-scan options' extra
detections sit — the Autoferry radar / lidar turns the *Slow radar scans* pair
(``radius_s`` 15 + ``edge_s`` 12) finds at 2.5–5 s, and the false turns ``radius_s`` /
``edge_s`` / the pair add on the long noisy bench's 5 s rows?

The ratio, per track, from what the detector measures itself: σ / (v · step), σ the track's
position noise (``position_noise_m``, lag 1, the noise floor's), step its median interval,
v its median speed over the first scale's windows (the chord over ``window_p`` − 1 steps
over its time, the median over the track's rows): the noise per distance run in one step.

    python bench/slow_scan_gate.py autoferry [--sensor radar lidar] [--rates 2.5 3 4 5]
    python bench/slow_scan_gate.py noisy [--seeds 0 1 2] [--dts 5] [--sigmas 5 10 20]

``autoferry``: per sensor and rate, every track with its ratio, then each detection a
variant adds or removes against the defaults (``radar_slow_extra.run``: right / wrong by
the GNSS, edge / inner, new scored turn) with its track's ratio. ``noisy``: per row of
``bench/long_noisy_tracks.py``, the track's ratio and the false / found turns of the
defaults and of each variant.
"""

import argparse
import contextlib
import io
import sys
from dataclasses import replace
from pathlib import Path

import pandas as pd

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "bench"))
import long_noisy_tracks as lnt  # noqa: E402
import radar_slow_extra as rse  # noqa: E402
from sampling_sweep import decimate  # noqa: E402

from wakeline.core import real_sets  # noqa: E402
from wakeline.core.evaluate_real import _track_key, in_content_order  # noqa: E402
from wakeline.core.maneuver import (  # noqa: E402
    ManeuverParams,
    median_window_speed_ms,
    position_noise_m,
)
from wakeline.core.tracks import (  # noqa: E402
    local_xy,
    median_interval_s,
    sorted_with_index,
    track_seconds,
)

VARIANTS = {
    "radius_s": {"radius_s": 15.0},
    "edge_s": {"edge_s": 12.0},
    "pair": {"radius_s": 15.0, "edge_s": 12.0},
}


def track_ratio(pts: pd.DataFrame, window_p: int = 5) -> pd.DataFrame:
    """Per track: points, median step (s), σ (m, lag 1), v (m/s, the median chord speed over
    ``window_p`` − 1 steps) and σ / (v · step)."""
    srt, index = sorted_with_index(pts)
    x, y = local_xy(srt, index)
    t = track_seconds(srt)
    med = median_interval_s(t, index)
    sigma = position_noise_m(x, y, t, index, 1)
    v = median_window_speed_ms(x, y, t, index, window_p)
    return pd.DataFrame(
        {
            "track": _track_key(index.keys).to_numpy(),
            "n": index.sizes,
            "step": med,
            "sigma": sigma,
            "v": v,
            "ratio": sigma / (v * med),
        }
    )


def autoferry(sensors, rates) -> None:
    base = ManeuverParams()
    for sensor in sensors:
        pts, _ = real_sets.read_autoferry(
            rse.REAL / "autoferry-fusion", exclusive=True, sensor=sensor
        )
        for rate in rates:
            plots = pts if rate <= 0 else decimate(pts, rate)
            plots = in_content_order(plots.assign(sensor="radar"))
            tr = track_ratio(plots).set_index("track")
            label = "own" if rate <= 0 else f"{rate:g} s"
            print(f"\n== {sensor} {label}: {len(tr)} tracks; ratio σ/(v·step) per track")
            print(
                "   "
                + "  ".join(
                    f"{k} {r.ratio:.3f}" for k, r in tr.sort_values("ratio").iterrows() if r.n >= 5
                )
            )
            for name, change in VARIANTS.items():
                with contextlib.redirect_stdout(io.StringIO()):
                    rows = rse.run(
                        sensor, None if rate <= 0 else rate, replace(base, **change), base
                    )
                for r in rows:
                    k = tr.loc[r["batch"]]
                    print(
                        f"   {name:8} {r['sign']} {r['batch']:<14} {r['kind']:5} "
                        f"{'RIGHT' if r['right'] else 'WRONG'}  track ratio {k.ratio:.3f} "
                        f"(σ {k.sigma:4.1f} m, v {k.v:4.2f} m/s, step {k.step:4.2f} s, "
                        f"n {k.n}); at the detection {r['ratio']:.3f}"
                    )


def noisy(seeds, dts, sigmas, hours) -> None:
    variants = {"default": ManeuverParams()} | {
        k: replace(ManeuverParams(), **v) for k, v in VARIANTS.items()
    }
    print(
        f"{'dt':>4} {'sigma':>5} {'seed':>4} {'σ est':>6} {'v':>5} {'ratio':>6}  "
        + "  ".join(f"{k:>16}" for k in variants)
        + "   (false / found of turns)"
    )
    tot = dict.fromkeys(variants, 0)
    for dt in dts:
        for sigma in sigmas:
            for seed in seeds:
                pts, spans, moor = lnt.make(seed, dt, sigma, hours)
                r = track_ratio(pts).iloc[0]
                cells = []
                for k, p in variants.items():
                    s = lnt.score(pts, spans, moor, p)
                    tot[k] += s["false"]
                    cells.append(f"{s['false']:>5} / {s['found']:>2} of {s['turns']:>2}")
                print(
                    f"{dt:>4g} {sigma:>5g} {seed:>4} {r.sigma:>6.2f} {r.v:>5.2f} "
                    f"{r.ratio:>6.3f}  " + "  ".join(f"{c:>16}" for c in cells),
                    flush=True,
                )
    print("false turns in total: " + ", ".join(f"{k} {v}" for k, v in tot.items()))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="what", required=True)
    a1 = sub.add_parser("autoferry")
    a1.add_argument("--sensor", nargs="+", default=["radar", "lidar"])
    a1.add_argument("--rates", nargs="+", type=float, default=[2.5, 3.0, 4.0, 5.0])
    a2 = sub.add_parser("noisy")
    a2.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2])
    a2.add_argument("--dts", nargs="+", type=float, default=[5.0])
    a2.add_argument("--sigmas", nargs="+", type=float, default=[5.0, 10.0, 20.0])
    a2.add_argument("--hours", type=float, default=4.0)
    a = ap.parse_args(argv)
    if a.what == "autoferry":
        autoferry(a.sensor, a.rates)
    else:
        noisy(a.seeds, a.dts, a.sigmas, a.hours)


if __name__ == "__main__":
    main()
