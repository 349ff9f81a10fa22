"""The bearing detector on the real camera bearings (Autoferry EO, gated to each boat by
its GNSS truth bearing), scored against the GNSS truth, for a window rule.

    python bench/bearing_real.py [--rule fixed|fit|fit:A,B|X,Y] [--split tune|report|all]
                                 [--truth-noise SIGMA] [--seeds N]

A truth maneuver: the boat's GNSS velocity changes by >= ``--dv`` (1 m/s) within 10 s (a
20 deg turn at 3 m/s, or a speed change), speed >= 0.5 m/s. Per sequence, over the span the windows
test (first boundary to last boundary + Y): a detection is right when a maneuver starts in
the Y + 10 s before it; a maneuver is found when a detection follows within Y + 10 s; a
sequence with no maneuver in its tested span and a detection is a false alarm. Split:
tune = scenarios 2-6 (4 May 2021), report = 13-22 (5 May: another boat, a docked ferry).
``--truth-noise``: the bearings replaced by the truth bearing plus Gaussian noise of SIGMA
deg (what the detector does when the camera is ideal and the boat's motion is real).
``--synthetic``: the fit windows on simulated 100 s runs (constant-velocity targets).
"""

import argparse
import os
from pathlib import Path

import numpy as np
import pandas as pd

from wakeline.core import bearing
from wakeline.core.bearing import BearingParams, detect_with_report, observer_xy, statistic
from wakeline.core.real_sets import autoferry_bearings

REAL = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
FOLDER = REAL / "data" / "real" / "autoferry-fusion"
TUNE = {2, 3, 4, 5, 6}


def maneuver_times(tr: pd.DataFrame, dv_ms: float = 1.0, lag_s: float = 10.0) -> np.ndarray:
    """Times (s, 1 s grid) where the GNSS velocity changed by >= dv_ms over lag_s."""
    grid = np.arange(tr["time"].min(), tr["time"].max(), 1.0)
    n = np.interp(grid, tr["time"], tr["north"])
    e = np.interp(grid, tr["time"], tr["east"])
    # velocity over 2 s (GNSS noise), then its change over lag_s
    vn, ve = (n[2:] - n[:-2]) / 2.0, (e[2:] - e[:-2]) / 2.0
    g = grid[1:-1]
    lag = int(lag_s)
    dv = np.hypot(vn[lag:] - vn[:-lag], ve[lag:] - ve[:-lag])
    moving = np.hypot(vn[lag:], ve[lag:]) >= 0.5
    return g[lag:][(dv >= dv_ms) & moving] - lag_s / 2.0  # the middle of the change


def params_for(rule: str) -> BearingParams:
    """fixed (the defaults), fit (windows="fit"), fit:A,B (fit with X, Y = A, B of the
    duration) or X,Y (those windows in s, X_min = X)."""
    if rule == "fixed":
        return BearingParams()
    if rule.startswith("fit"):
        if ":" in rule:
            bearing.FIT_X, bearing.FIT_Y = (float(v) for v in rule.split(":")[1].split(","))
        return BearingParams(windows="fit")
    x, y = (float(v) for v in rule.split(","))
    return BearingParams(window_x_s=x, min_window_x_s=x, window_y_s=y)


def score(rule: str, split: str, truth_noise: float | None, seed: int, dv: float = 1.0) -> dict:
    bearings, truth = autoferry_bearings(FOLDER)
    rng = np.random.default_rng(seed)
    rows = []
    for batch, g in bearings.groupby("batch", sort=False):
        scenario, target = (int(v) for v in batch.split("-"))
        if (split == "tune") != (scenario in TUNE) and split != "all":
            continue
        g = g.copy()
        if truth_noise is not None:
            g["bearing"] = (g["truth_bearing"] + rng.normal(0, truth_noise, len(g))) % 360.0
        t = g["time"].astype("int64").to_numpy() / 1e9
        params = bearing.windows_for(params_for(rule), t)
        table, report = detect_with_report(g.drop(columns="truth_bearing"), params)
        r = report[0]
        tr = truth[(truth.scenario == scenario) & (truth.target_id == target)]
        mt = maneuver_times(tr, dv)
        det = table["detect_time"].astype("int64").to_numpy() / 1e9
        y = float(r["y_spans_s"][-1]) if r["y_spans_s"] else 0.0
        # tested span: first tested boundary - its X .. last tested boundary + Y
        st = statistic(
            t,
            g["bearing"].to_numpy(float),
            params,
            observer=observer_xy(g["obs_lon"].to_numpy(float), g["obs_lat"].to_numpy(float)),
        )
        if len(st.boundary_t):
            lo, hi = float(st.boundary_t.min()), float(st.boundary_t.max()) + y
            mt_in = mt[(mt >= lo) & (mt <= hi)]
        else:
            mt_in = np.zeros(0)
        right = sum(((mt_in <= d) & (mt_in >= d - y - 10.0)).any() for d in det)
        # maneuvers as events: group times closer than 10 s
        events = np.split(mt_in, np.flatnonzero(np.diff(mt_in) > 10.0) + 1) if len(mt_in) else []
        ev_found = sum(bool(((det >= e[0]) & (det <= e[-1] + y + 10.0)).any()) for e in events)
        rows.append(
            {
                "batch": batch,
                "dur": round(t[-1] - t[0]),
                "n": len(t),
                "tested": r["tested"],
                "why": r["too_short"] or "",
                "noise": r.get("noise_deg"),
                "events": len(events),
                "found": ev_found,
                "dets": len(det),
                "right": right,
            }
        )
    return pd.DataFrame(rows)


def synthetic(runs: int = 200) -> None:
    """windows="fit" on simulated constant-velocity targets of 100 s (the model exact):
    runs with a detection without a turn, and after a 20 or 60 deg turn at 55 s."""
    from wakeline.core.bearing import detect_sequence
    from wakeline.core.bearing_eval import Scenario, simulate_bearings

    fit = BearingParams(windows="fit")
    cases = {
        "harbour: 400 m, 6 kn, 100 s at 5 Hz": Scenario(
            "h", 400.0, 40.0, 6.0, 120.0, duration_s=100.0, period_s=0.2
        ),
        "seed 002 scenario 1: 20 km, 18 kn, 100 s at 1 Hz": Scenario("p", duration_s=100.0),
    }
    for name, sc in cases.items():
        for turn in (0.0, 20.0, 60.0):
            hits = 0
            for seed in range(runs):
                t, b, _, _ = simulate_bearings(np.random.default_rng(seed), sc, turn, 55.0, 0.6)
                found = detect_sequence(t, b, fit)
                hits += any(d.detect_time_s >= 55.0 or not turn for d in found)
            print(f"{name}, turn {turn:g} deg: {hits}/{runs} runs with a detection")


def summary(df: pd.DataFrame) -> str:
    tested = df[df.tested > 0]
    with_m = tested[tested.events > 0]
    without = tested[tested.events == 0]
    prec = tested.right.sum() / max(tested.dets.sum(), 1)
    return (
        f"{len(tested)}/{len(df)} sequences tested; maneuver events found "
        f"{with_m.found.sum()}/{with_m.events.sum()}; detections right "
        f"{tested.right.sum()}/{tested.dets.sum()} ({prec:.2f}); sequences without a "
        f"maneuver: {len(without)}, with a false alarm {(without.dets > 0).sum()}"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rule", default="fit")
    ap.add_argument("--split", default="tune", choices=["tune", "report", "all"])
    ap.add_argument("--truth-noise", type=float, default=None)
    ap.add_argument("--seeds", type=int, default=1)
    ap.add_argument("--dv", type=float, default=1.0, help="maneuver: velocity change, m/s")
    ap.add_argument("-v", action="store_true")
    ap.add_argument("--synthetic", action="store_true", help="simulated 100 s runs instead")
    args = ap.parse_args()
    if args.synthetic:
        synthetic()
        return
    for seed in range(args.seeds):
        df = score(args.rule, args.split, args.truth_noise, seed, args.dv)
        if args.v:
            print(df.to_string(index=False))
        noise = "" if args.truth_noise is None else f", truth + {args.truth_noise:g} deg noise"
        print(f"rule {args.rule}, {args.split}{noise}, dv {args.dv:g}, seed {seed}: {summary(df)}")


if __name__ == "__main__":
    main()
