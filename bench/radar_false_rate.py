"""False turns per track-hour and plot noise: real Autoferry radar against the hard scene's.

Question (issue 15, session 18): is the hard maneuver scene's radar harsher than real radar,
or would long real radar tracks suffer the same false-turn rate?

False-turn rate: the default detector (or ``--set key=value`` overrides of
``ManeuverParams``) on radar tracks; a detection is false when it lies more than ``tol``
(10 s, both evaluations' tolerance) from every truth turn span (real: GNSS turns of at
least 15 deg, ``evaluate_real.truth_turns``; hard scene: its true turns, any size, as
``evaluate_maneuver_hard`` scores). Exposure: track time from ``window_s`` after the
first plot to ``window_s`` before the last, less the time within ``tol`` of a turn span,
on a 1 s grid; split by the truth speed over ground at each grid second (and at each false
detection): course and speed from truth positions 2 s apart, as ``truth_turns`` does.

Plot noise: residual = plot − truth at the plot's time (real: GNSS interpolated; hard:
the true path), away from turns (as above), split along and across the truth course. The
docs' measure: the residual less its centred 10 s running median per axis (the slowly
wandering offset) — median / 90 / 97 % radial, share beyond 3 m. A model fit: the
structure function 0.5·E[(e(t+τ) − e(t))²] per component, binned by lag τ within a track,
fitted with s_w² + s_o² (1 − exp(−τ / T)): s_w the white part (outliers included), s_o the
wandering offset's sd per axis and T its time constant. Robust white sd: 1.4826 · MAD of
the first differences of that residual / √2, and the outlier share: plots whose
offset-free residual exceeds 3 robust sd in either component (for the simulated mixture,
0.7 m white with 10 % at 2.5 m, that share is ≈ 0.07).

Run: ``python bench/radar_false_rate.py [--seeds 0 1 2 3 4] [--set key=value ...]``
"""

import argparse
import os
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.optimize import curve_fit

from wakeline.core import evaluate_real as er
from wakeline.core import geo, real_sets, simulate
from wakeline.core.maneuver import ManeuverParams, detect
from wakeline.core.schema import time_seconds

#: ../shared, or $WAKELINE_SHARED (as the tests read it)
REAL = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
SPEED_BINS = (0.0, 1.0, 5.0, 10.0, np.inf)
SPEED_LABELS = ("<1 kn", "1-5 kn", "5-10 kn", ">10 kn")
#: 1 kn bins for the speed-standardised comparison (the false rate falls steeply with speed)
FINE_BINS = np.r_[np.arange(0.0, 13.0, 1.0), np.inf]
LAG_BINS = np.array([0.5, 2.5, 4.5, 7.5, 12.5, 17.5, 25.0, 35.0, 50.0, 70.0])
TOL_S = 10.0
#: the structure function is fitted up to this lag (s): the real tracks are 1-2.5 min long,
#: few straight pairs lie further apart
FIT_MAX_LAG_S = 35.0


def _xy(lon: np.ndarray, lat: np.ndarray, lon0: float, lat0: float):
    return geo.to_local(lon, lat, lon0, lat0)


def _truth_motion(t: np.ndarray, x: np.ndarray, y: np.ndarray, grid: np.ndarray):
    """Speed (kn) and course (rad) on ``grid`` from positions 2 s apart (1 s resampling)."""
    dt = 1.0
    xa, ya = np.interp(grid - dt, t, x), np.interp(grid - dt, t, y)
    xb, yb = np.interp(grid + dt, t, x), np.interp(grid + dt, t, y)
    return np.hypot(xb - xa, yb - ya) / (2 * dt) / geo.KN_MS, np.arctan2(xb - xa, yb - ya)


def _near_turn(t: np.ndarray, spans: np.ndarray, tol: float) -> np.ndarray:
    if not len(spans):
        return np.zeros(len(t), dtype=bool)
    return ((t[:, None] >= spans[None, :, 0] - tol) & (t[:, None] <= spans[None, :, 1] + tol)).any(
        axis=1
    )


def track_tables(radar: pd.DataFrame, truth_of, turns: pd.DataFrame, window_s: float):
    """Per track: exposure seconds by speed bin, and per plot the residual (along, across),
    the time, the batch and whether it lies away from turns."""
    exposure = np.zeros(len(SPEED_LABELS))
    fine = np.zeros(len(FINE_BINS) - 1)
    plots = []
    radar = radar.assign(t_s=time_seconds(radar["time"]))
    lon0, lat0 = float(radar["lon"].mean()), float(radar["lat"].mean())
    for batch, r in radar.groupby("batch", sort=False):  # a few hundred tracks
        t = r["t_s"].to_numpy()
        tt, tlon, tlat = truth_of(batch, r)
        tx, ty = _xy(tlon, tlat, lon0, lat0)
        spans = turns.loc[turns["batch"] == batch, ["start_s", "end_s"]].to_numpy(float)
        grid = np.arange(t[0] + window_s, t[-1] - window_s, 1.0)
        if len(grid):
            v, _ = _truth_motion(tt, tx, ty, grid)
            ok = ~_near_turn(grid, spans, TOL_S)
            exposure += np.histogram(v[ok], bins=SPEED_BINS)[0]
            fine += np.histogram(v[ok], bins=FINE_BINS)[0]
        px, py = _xy(r["lon"].to_numpy(), r["lat"].to_numpy(), lon0, lat0)
        gx, gy = np.interp(t, tt, tx), np.interp(t, tt, ty)
        v, c = _truth_motion(tt, tx, ty, t)
        ex, ey = px - gx, py - gy
        along = ex * np.sin(c) + ey * np.cos(c)
        across = ex * np.cos(c) - ey * np.sin(c)
        plots.append(
            pd.DataFrame(
                {
                    "batch": batch,
                    "t": t,
                    "ex": ex,
                    "ey": ey,
                    "along": along,
                    "across": across,
                    "speed_kn": v,
                    "straight": ~_near_turn(t, spans, TOL_S) & (v >= 1.0),
                }
            )
        )
    return exposure / 3600.0, fine / 3600.0, pd.concat(plots, ignore_index=True)


def false_detections(radar, truth_of, turns, params: ManeuverParams) -> np.ndarray:
    """Counts of false detections by speed bin (truth speed at the detection)."""
    tab = detect(radar, params).table()
    det = pd.DataFrame({"batch": tab["batch"].astype(str), "t_s": time_seconds(tab["time"])})
    counts = np.zeros(len(SPEED_LABELS), dtype=int)
    fine = np.zeros(len(FINE_BINS) - 1, dtype=int)
    lon0, lat0 = float(radar["lon"].mean()), float(radar["lat"].mean())
    radar = radar.assign(batch=radar["batch"].astype(str))
    groups = dict(tuple(radar.groupby("batch", sort=False)))
    for batch, d in det.groupby("batch"):
        spans = turns.loc[turns["batch"] == batch, ["start_s", "end_s"]].to_numpy(float)
        t = d["t_s"].to_numpy()
        false = ~_near_turn(t, spans, TOL_S)
        if not false.any():
            continue
        tt, tlon, tlat = truth_of(batch, groups[batch])
        tx, ty = _xy(tlon, tlat, lon0, lat0)
        v, _ = _truth_motion(tt, tx, ty, t[false])
        counts += np.histogram(v, bins=SPEED_BINS)[0]
        fine += np.histogram(v, bins=FINE_BINS)[0]
    return counts, fine, len(det)


def _running_median(p: pd.DataFrame, col: str, w: float) -> np.ndarray:
    out = np.empty(len(p))
    for _, g in p.groupby("batch", sort=False):  # per track
        s = pd.Series(g[col].to_numpy(), index=pd.to_datetime(g["t"].to_numpy(), unit="s"))
        out[g.index] = s.rolling(f"{int(w * 1000)}ms", center=True, min_periods=1).median()
    return out


def noise_stats(p: pd.DataFrame) -> dict:
    """The docs' offset-free residual figures and the structure-function fit (see module)."""
    p = p.reset_index(drop=True)
    out = {}
    for c in ("ex", "ey", "along", "across"):
        p[c + "_w"] = p[c] - _running_median(p, c, 10.0)
    s = p[p["straight"]]
    rad = np.hypot(s["ex_w"], s["ey_w"])
    out["plots"] = len(s)
    out["median_m"], out["p90_m"], out["p97_m"] = np.percentile(rad, [50, 90, 97])
    out["beyond_3m"] = float((rad > 3.0).mean())
    for c in ("along", "across"):
        # white sd from first differences within a track (robust: MAD)
        d = p[c].diff()[(p["batch"] == p["batch"].shift()) & p["straight"]]
        out[f"white_sd_{c}"] = 1.4826 * np.median(np.abs(d - d.median())) / np.sqrt(2)
        w = s[c + "_w"]
        robust = 1.4826 * np.median(np.abs(w - w.median()))
        out[f"mad_sd_{c}"] = robust
        out[f"outliers_{c}"] = float((np.abs(w) > 3 * robust).mean())
        lags, gam = structure_function(p, c)
        out[f"gamma_{c}"] = dict(zip(np.round(lags, 1), np.round(gam, 2), strict=True))
        try:
            (sw, so, tau), _ = curve_fit(
                lambda x, a, b, T: a * a + b * b * (1 - np.exp(-x / T)),
                lags[lags <= FIT_MAX_LAG_S],
                gam[lags <= FIT_MAX_LAG_S],
                p0=(1.0, 1.5, 10.0),
                bounds=([0, 0, 0.5], [20, 20, 500]),
            )
        except RuntimeError:
            sw = so = tau = np.nan
        out[f"fit_{c}"] = (round(sw, 2), round(so, 2), round(tau, 1))
    return out


def structure_function(p: pd.DataFrame, col: str):
    """0.5·mean((e_j − e_i)²) over plot pairs of one straight piece of a track, by lag bin."""
    num = np.zeros(len(LAG_BINS) - 1)
    cnt = np.zeros(len(LAG_BINS) - 1)
    seg = (~p["straight"]).cumsum()  # a turn (or a slow spell) ends a straight piece
    for _, g in p[p["straight"]].groupby([p["batch"], seg], sort=False):  # per piece
        t, e = g["t"].to_numpy(), g[col].to_numpy()
        for k in range(1, 60):  # pairs k plots apart (≤ 60 plots: lags up to ~70 s)
            if k >= len(t):
                break
            lag = t[k:] - t[:-k]
            b = np.digitize(lag, LAG_BINS) - 1
            ok = (b >= 0) & (b < len(num))
            np.add.at(num, b[ok], 0.5 * (e[k:] - e[:-k])[ok] ** 2)
            np.add.at(cnt, b[ok], 1)
    has = cnt > 30
    mids = 0.5 * (LAG_BINS[1:] + LAG_BINS[:-1])
    return mids[has], num[has] / cnt[has]


def real_set(folder: Path):
    radar, truth = real_sets.read_autoferry(folder, exclusive=True)
    truth = truth.assign(t_s=time_seconds(truth["time"]))
    by = {b: g for b, g in truth.groupby("batch")}

    def truth_of(batch, _r):
        g = by[batch]
        return g["t_s"].to_numpy(), g["lon"].to_numpy(), g["lat"].to_numpy()

    turns = er.truth_turns(truth.drop(columns="t_s"), 15.0, 1.0)
    return radar, truth_of, turns


def hard_set(seed: int, hp: simulate.HardManeuverParams):
    sc = simulate.hard_maneuver_scene(seed, hp)
    radar = sc.points[sc.points["rate"] == "radar"].copy()
    radar["batch"] = radar["batch"].astype(str)
    t0 = (simulate.T0 - pd.Timestamp(0, tz="UTC")).total_seconds()
    turns = sc.turns.assign(start_s=sc.turns["start_s"] + t0, end_s=sc.turns["end_s"] + t0)

    def truth_of(_batch, r):
        return time_seconds(r["time"]), r["true_lon"].to_numpy(), r["true_lat"].to_numpy()

    return radar, truth_of, turns


def _rate_line(label, counts, hours, n_det):
    cells = []
    for k, name in enumerate(SPEED_LABELS):
        h = hours[k]
        rate = counts[k] / h if h > 0 else np.nan
        cells.append(f"{name}: {counts[k]} / {h:.3f} h = {rate:.1f}/h")
        if h > 0:
            from scipy.stats import chi2

            lo = chi2.ppf(0.025, 2 * counts[k]) / 2 / h if counts[k] else 0.0
            hi = chi2.ppf(0.975, 2 * (counts[k] + 1)) / 2 / h
            cells[-1] += f" [{lo:.1f}-{hi:.1f}]"
    moving = slice(1, None)
    tot = counts[moving].sum() / max(hours[moving].sum(), 1e-9)
    return (
        f"{label}: detections {n_det}; false by truth speed — "
        + "; ".join(cells)
        + f"; moving (>=1 kn) {counts[moving].sum()} / {hours[moving].sum():.3f} h = {tot:.1f}/h"
    )


def _parse_set(items):
    out = {}
    for item in items or []:
        k, v = item.split("=", 1)
        out[k] = float(v)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2, 3, 4])
    ap.add_argument("--real", default=str(REAL / "data/real/autoferry-fusion"), help="folder")
    ap.add_argument("--set", nargs="*", help="ManeuverParams overrides key=value")
    ap.add_argument("--scene-set", nargs="*", help="HardManeuverParams overrides key=value")
    ap.add_argument("--no-noise", action="store_true", help="false rates only")
    args = ap.parse_args()
    params = ManeuverParams().replace(**_parse_set(args.set)).checked()
    hp = simulate.HardManeuverParams().replace(**_parse_set(args.scene_set)).checked()
    sets = {"real autoferry": real_set(Path(args.real))}
    for s in args.seeds:
        sets[f"hard seed {s}"] = hard_set(s, hp)
    total_c = np.zeros(len(SPEED_LABELS), dtype=int)
    total_h = np.zeros(len(SPEED_LABELS))
    fine_c = np.zeros(len(FINE_BINS) - 1)
    fine_h = np.zeros(len(FINE_BINS) - 1)
    total_n = 0
    plots_hard = []
    real_fine = None
    for name, (radar, truth_of, turns) in sets.items():
        hours, hours_fine, plots = track_tables(radar, truth_of, turns, params.window_s)
        counts, counts_fine, n_det = false_detections(radar, truth_of, turns, params)
        print(_rate_line(name, counts, hours, n_det), flush=True)
        if name.startswith("hard"):
            total_c += counts
            total_h += hours
            total_n += n_det
            fine_c += counts_fine
            fine_h += hours_fine
            plots_hard.append(plots.assign(batch=f"{name}:" + plots["batch"]))
        else:
            real_fine = (counts_fine, hours_fine)
            if not args.no_noise:
                print(f"  noise {name}: {noise_stats(plots)}", flush=True)
    if len(args.seeds) > 1:
        print(_rate_line("hard, all seeds", total_c, total_h, total_n))
    if real_fine is not None and fine_h.sum() > 0:
        # the hard scene's false rate per 1 kn bin, applied to the real exposure by speed
        with np.errstate(invalid="ignore", divide="ignore"):
            rate = np.where(fine_h > 0, fine_c / fine_h, np.nan)
        moving = FINE_BINS[:-1] >= 1.0
        expect = np.nansum((rate * real_fine[1])[moving])
        seen = int(real_fine[0][moving].sum())
        from scipy.stats import poisson

        print(
            "real exposure by 1 kn bin (h): "
            + ", ".join(f"{FINE_BINS[i]:g}: {h:.3f}" for i, h in enumerate(real_fine[1]) if h)
        )
        print(
            "hard false rate by 1 kn bin (/h): "
            + ", ".join(f"{FINE_BINS[i]:g}: {r:.0f}" for i, r in enumerate(rate) if r == r)
        )
        print(
            f"real moving tracks: {seen} false seen; at the hard scene's rate for the same "
            f"speeds {expect:.1f} expected; P(X <= {seen} | Poisson {expect:.1f}) = "
            f"{poisson.cdf(seen, expect):.2g}"
        )
    if plots_hard and not args.no_noise:
        allp = pd.concat(plots_hard, ignore_index=True)
        print(f"  noise hard (seeds {args.seeds}): {noise_stats(allp)}")


if __name__ == "__main__":
    main()
