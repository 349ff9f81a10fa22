"""What a slow-scan option changes, detection by detection: the Autoferry radar (or lidar)
decimated to one plot every ``--rates`` s, the detections of the defaults and of ``--set``
compared; each detection only one of them makes is printed with the track's own measures
and what the GNSS truth shows there.

    python bench/radar_slow_extra.py --sensor lidar --rates 4 5 --set radius_s=15 edge_s=12

Per changed detection (``--all``: every detection ``--set`` makes, ``=`` where the defaults
make it too): the track (sensor/scenario/target), the plot's number in it (``#``), its time
from the track's first plot, ``+`` (only with ``--set``) or ``-`` (only with the defaults),
the kind (``edge``: in a track's first or last p − 1 plots, where only ``edge_s`` gives a
heading; ``inner`` otherwise), δ, the speed v over the plots either side, the track's
measured noise σ (``position_noise_m``, lag 1), its median step, the noise per step
σ / (v · step), δ of 3-point windows against their noise floor (k σ_δ), ``z``: the
confirmation test's statistic (``confirm_z``'s) with legs of 6 and of 2p plots, and the
truth: right (a GNSS turn within 10 s) or wrong, the truth's course change over the
detection's ±10 s, the nearest GNSS turn, and the distance of the plots ±2 about it from
the GNSS position (in σ). Then the changed detections counted by sensor, sign, truth and
kind with their median measures. Session 30's diagnosis (docs/evaluation.md "Session 30:
slow scans").
"""

import argparse
import os
import sys
from pathlib import Path

import numpy as np
import pandas as pd

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "bench"))
from radar_scan_rates import _params  # noqa: E402
from sampling_sweep import decimate  # noqa: E402

from wakeline.core import geo, real_sets  # noqa: E402
from wakeline.core.evaluate_real import (  # noqa: E402
    _track_key,
    _under_tracks,
    covered_turns,
    gnss_faults,
    in_content_order,
    match_to_truth,
    sound_turns,
    truth_turns,
)
from wakeline.core.maneuver import (  # noqa: E402
    ManeuverParams,
    _heading_noise_deg,
    _leg_bounds,
    _leg_fits,
    detect,
    maneuver_factor,
    position_noise_m,
)
from wakeline.core.schema import time_seconds  # noqa: E402
from wakeline.core.tracks import (  # noqa: E402
    local_xy,
    median_interval_s,
    sorted_with_index,
    track_seconds,
)  # noqa: E402

ALL = [False]  # --all: the detections both make as well (sign =)
REAL = Path(os.environ.get("WAKELINE_SHARED", REPO.parent / "shared")) / "data" / "real"


def _truth_course(truth: pd.DataFrame):
    """Per truth batch: (t, course deg unwrapped) on a 1 s grid (the 2 s chord, as
    ``truth_turns`` takes it)."""
    pts, index = sorted_with_index(truth)
    x, y = local_xy(pts, index)
    t = track_seconds(pts)
    out = {}
    for k, (a, b) in enumerate(zip(index.starts, index.ends, strict=True)):
        grid = np.arange(t[a], t[b - 1], 1.0)
        gx, gy = np.interp(grid, t[a:b], x[a:b]), np.interp(grid, t[a:b], y[a:b])
        c = np.degrees(np.unwrap(np.arctan2(gx[2:] - gx[:-2], gy[2:] - gy[:-2])))
        out[str(index.keys.iloc[k]["batch"])] = (grid[1:-1], c)
    return out


def confirm_stat(x, y, t, idx, row: int, legs: int, sigma: np.ndarray, min_ms: float) -> float:
    """The confirmation test's statistic at ``row`` (``_confirmed``): the course change
    between lines fitted to the ``legs`` points before and after it, in standard errors."""
    rows = np.array([row])
    lo, hi = _leg_bounds(idx, rows, np.array([legs]), np.array([legs]), np.zeros(0, "int64"))
    first = np.array([lo[0], row])
    count = np.array([row - lo[0] + 1, hi[0] - row])
    s2 = np.repeat(sigma[idx.track_of_row[rows]], 2)
    course, se, fits = _leg_fits(x, y, t, first, count, np.repeat(rows, 2), s2, min_ms)
    if not fits.all():
        return float("nan")
    d = abs(np.angle(np.exp(1j * (course[1] - course[0]))))
    return float(d / np.hypot(se[0], se[1]))


def run(sensor: str, rate: float | None, cand: ManeuverParams, base: ManeuverParams) -> list:
    pts, truth = real_sets.read_autoferry(REAL / "autoferry-fusion", exclusive=True, sensor=sensor)
    plots = pts if rate is None else decimate(pts, rate)
    plots = in_content_order(plots.assign(sensor="radar"))
    match = match_to_truth(plots, truth)
    link = dict(zip(_track_key(match), match["truth_batch"], strict=True))
    turns = _under_tracks(truth_turns(truth, base.threshold_deg, 1.0), match)
    faults = _under_tracks(gnss_faults(truth, 0.5), match)
    scored = sound_turns(
        covered_turns(turns, plots.assign(batch=_track_key(plots)), 10.0), faults, 2.0
    )
    course = _truth_course(truth)
    truth_by = {str(b): g.sort_values("time") for b, g in truth.groupby("batch")}
    res = {}
    for name, prm in (("base", base), ("cand", cand)):
        r = detect(plots, prm)
        tab = r.table()
        res[name] = pd.DataFrame(
            {"batch": _track_key(tab).to_numpy(), "t_s": time_seconds(tab["time"])}
        )
        res[name]["f"] = tab["factor"].to_numpy()
    r = detect(plots, base)
    idx = r.index
    x, y = local_xy(r.points, idx)
    t = track_seconds(r.points)
    med = median_interval_s(t, idx)
    sigma = position_noise_m(x, y, t, idx, 1)
    keys = _track_key(idx.keys).to_numpy()
    row_of = {k: i for i, k in enumerate(keys)}
    f3 = maneuver_factor(x, y, idx, 3)
    p_first = r.window_p
    label = "own" if rate is None else f"{rate:g} s"
    print(f"\n== {sensor} {label}: detections base {len(res['base'])}, cand {len(res['cand'])}")
    b, c = res["base"], res["cand"]
    key_b = set(zip(b.batch, np.round(b.t_s, 3), strict=True))
    key_c = set(zip(c.batch, np.round(c.t_s, 3), strict=True))
    rows = []
    for sign, tab, other in (("+", c, key_b), ("-", b, key_c)):
        for d in tab.itertuples():
            both = (d.batch, round(d.t_s, 3)) in other
            if both and not (ALL[0] and sign == "+"):
                continue
            k = row_of[d.batch]
            s, e = idx.starts[k], idx.ends[k]
            i = s + int(np.argmin(np.abs(t[s:e] - d.t_s)))
            pos = i - s
            pf = int(p_first[k])
            kind = "edge" if (pos < pf - 1 or pos > e - s - pf) else "inner"
            lo, hi = max(i - 1, s), min(i + 1, e - 1)
            v = np.hypot(x[hi] - x[lo], y[hi] - y[lo]) / max(t[hi] - t[lo], 1e-9)
            ratio = sigma[k] / max(v * med[k], 1e-9)
            fl3 = (
                base.noise_k * _heading_noise_deg(x, y, idx, np.array([3]), sigma, np.array([i]))[0]
            )
            min_ms = base.min_speed_kn * geo.KN_MS
            z6 = confirm_stat(x, y, t, idx, i, 6, sigma, min_ms)
            zp = confirm_stat(x, y, t, idx, i, 2 * pf, sigma, min_ms)
            tb = turns[turns.batch == d.batch]
            right = bool(((tb.start_s - 10 <= d.t_s) & (d.t_s <= tb.end_s + 10)).any())
            near = ""
            if len(tb):
                gap = np.maximum(tb.start_s - d.t_s, d.t_s - tb.end_s).clip(lower=0)
                j = int(np.argmin(gap.to_numpy()))
                tj = tb.iloc[j]
                t0 = t[s]
                near = (
                    f"nearest GNSS turn {tj.start_s - t0:.0f}-{tj.end_s - t0:.0f} s "
                    f"({tj.change_deg:+.0f}°), {gap.iloc[j]:.0f} s away"
                )
            g = truth_by[link[d.batch]]
            w = np.arange(max(i - 2, s), min(i + 3, e))
            tt = time_seconds(g["time"])
            lat = np.interp(t[w], tt, g["lat"].to_numpy())
            lon = np.interp(t[w], tt, g["lon"].to_numpy())
            off = np.hypot(
                (r.points["lon"].to_numpy()[w] - lon) * 111320 * np.cos(np.radians(lat)),
                (r.points["lat"].to_numpy()[w] - lat) * 110540,
            )
            gnss = " ".join(f"{v / sigma[k]:.1f}" for v in off)
            tc, cc = course[link[d.batch]]
            c_lo = np.interp(d.t_s - 10, tc, cc)
            c_hi = np.interp(d.t_s + 10, tc, cc)
            sc = scored[scored.batch == d.batch]
            new_turn = ""
            if sign == "+" and right:
                inside = (sc.start_s - 10 <= d.t_s) & (d.t_s <= sc.end_s + 10)
                hit_b = [
                    ((b.batch == d.batch) & b.t_s.between(q.start_s - 10, q.end_s + 10)).any()
                    for q in sc[inside].itertuples()
                ]
                new_turn = " NEW scored turn" if hit_b and not all(hit_b) else " (turn found)"
            rows.append(
                {
                    "sensor": sensor,
                    "rate": label,
                    "sign": "=" if both else sign,
                    "batch": d.batch,
                    "kind": kind,
                    "right": right,
                    "ratio": ratio,
                    "med": med[k],
                    "sigma": sigma[k],
                    "v": v,
                    "delta": d.f,
                    "d3": f3[i],
                    "fl3": fl3,
                    "z6": z6,
                    "zp": zp,
                }
            )
            print(
                f"{'=' if both else sign} {d.batch:<16} #{pos:<2}  t {d.t_s - t[s]:5.0f} s of {t[e - 1] - t[s]:4.0f} {kind:5} "
                f"δ {d.f:5.1f}  v {v:4.1f} m/s  σ {sigma[k]:4.1f} m  step {med[k]:4.2f} s  "
                f"σ/(v·step) {ratio:5.3f}  δ3 {f3[i]:5.1f} / floor3 {fl3:5.1f}  "
                f"z(6) {z6:5.1f} z(2p) {zp:5.1f}  "
                f"{'RIGHT' if right else 'WRONG'}{new_turn}; truth Δcourse ±10 s "
                f"{c_hi - c_lo:+5.0f}°; {near}; plots ±2 from the GNSS in σ: {gnss}"
            )
    return rows


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sensor", nargs="+", default=["radar", "lidar"])
    ap.add_argument("--rates", nargs="+", type=float, default=[4.0, 5.0])
    ap.add_argument("--set", nargs="+", default=["radius_s=15", "edge_s=12"])
    ap.add_argument("--base", nargs="*", default=[], help="the base row's changes")
    ap.add_argument("--all", action="store_true", help="the detections both make too (=)")
    a = ap.parse_args(argv)
    ALL[0] = a.all
    cand, base = _params(a.set), _params(a.base)
    rows = []
    for sensor in a.sensor:
        for rate in a.rates:
            rows += run(sensor, None if rate <= 0 else rate, cand, base)
    if rows:
        df = pd.DataFrame(rows)
        print("\nchanged detections by sensor, sign and truth:")
        print(
            df.groupby(["sensor", "sign", "right", "kind"])
            .agg(
                n=("ratio", "size"),
                ratio=("ratio", "median"),
                step=("med", "median"),
                sigma=("sigma", "median"),
                v=("v", "median"),
            )
            .round(2)
            .to_string()
        )


if __name__ == "__main__":
    main()
