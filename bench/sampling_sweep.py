"""Sampling-rate sweep of issue 15's defaults on real data (docs/evaluation.md, "Sampling-rate
sweep (session 19)").

    python bench/sampling_sweep.py                      # every set, every rate, both variants
    python bench/sampling_sweep.py --quick              # fewer rates, regular only
    python bench/sampling_sweep.py --sets saronic dma --rates 60 180 600 --jitter 0
    python bench/sampling_sweep.py --max-step-windows 0   # headings across any step (before)

Each real set's tracks are decimated to one fix every R seconds per track: at ticks
t0, t0 + R, t0 + 2R, ... from the track's first fix, the first fix at or after each tick is
kept (no interpolation; a tick inside a gap takes the fix after the gap, once). The
jittered variant draws each tick interval from R × U(0.7, 1.3) (seed 0). A rate below the
set's median interval is skipped (the set is not that dense); ``own`` is the set as it is.

Per set × rate × variant (columns): points, tracks, the median of the tracks' median
intervals (med dt, s); the maneuvers of the default detector (man) and those per moving
track-hour (/mov h: the source's legs of at least 1 kn and at most 600 s, summed per set at
its own rate, so every rate shares one denominator); issue 15's slow share
(``evaluate_real.slow_share``, as ``wakeline evaluate maneuver --real`` counts it); the share
of points in at-rest spans (rest; the detector's at-rest rule) and of track time between
at-rest fixes (rest t: AIS reports faster under way, so the point share moves with
decimation where the time share should not); the compressor's kept points against
Douglas–Peucker's at the same Dis_e (``compression_against_dp``; o/DP their ratio); the
points default cleaning's speed and turn rules remove (``clean``); for the AIS sets the
association at known gaps (``evaluate_association.scene_scores``, ours, optimal; mean P_CA /
P_FA over the scenes, the true pairs and those within T_gap) as ``wakeline evaluate
associate --real ... --gaps`` runs it; for Autoferry the GNSS turns (``truth_turns`` of the
full-rate GNSS, covered by the decimated track) found within max(10 s, 2 periods), and the
precision.

Sets (read from $WAKELINE_SHARED/data/real, else ../shared/data/real): autoferry (the GNSS
truth of two boats, 5-25 Hz; ``real_sets.read_autoferry``), saronic (greece-ais-annotated,
GPL), dma (one ship), oresund (encounters), mtad (mtad-dtwcm/original, 10 scenes).
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np
import pandas as pd

from wakeline.core import geo, real_sets
from wakeline.core.associate import LinkParams
from wakeline.core.clean import clean
from wakeline.core.evaluate_association import real_files, scene_scores
from wakeline.core.evaluate_real import (
    _track_files,
    compression_against_dp,
    covered_turns,
    score_turns,
    slow_share,
    truth_turns,
)
from wakeline.core.io import read_points
from wakeline.core.maneuver import ManeuverParams, detect, median_interval_s
from wakeline.core.schema import time_seconds
from wakeline.core.tracks import local_xy, sorted_with_index, track_seconds

#: ../shared, or $WAKELINE_SHARED (as the tests read it)
SHARED = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
REAL = SHARED / "data" / "real"

RATES = (1.0, 2.0, 5.0, 10.0, 30.0, 60.0, 180.0, 600.0)
QUICK_RATES = (2.0, 10.0, 60.0, 600.0)

#: set -> (folder, known gaps (lo, hi) s and one window every S s (None: once per track), as
#: docs/evaluation.md scores each set; None: no association)
SETS = {
    "autoferry": ("autoferry-fusion", None),
    "saronic": ("greece-ais-annotated", ((300.0, 900.0), 7200.0)),
    "dma": ("dma-single-ship", ((300.0, 900.0), 3600.0)),
    "oresund": ("oresund-encounters", ((60.0, 600.0), None)),
    "mtad": ("mtad-dtwcm/original", ((300.0, 900.0), None)),
}


def decimate(points: pd.DataFrame, rate_s: float, jitter: float = 0.0, seed: int = 0):
    """One fix every ``rate_s`` s per track: ticks from each track's first fix, each tick
    interval ``rate_s`` × U(1 − ``jitter``, 1 + ``jitter``); the first fix at or after a
    tick is kept (once). Returns the kept rows, sorted by track and time."""
    pts, index = sorted_with_index(points)
    t = track_seconds(pts)
    first, last = t[index.starts], t[index.ends - 1]
    span = last - first
    n_ticks = (np.floor(span / (rate_s * (1 - jitter))) + 1).astype("int64")
    group = np.repeat(np.arange(index.n_tracks), n_ticks)
    step = np.full(len(group), float(rate_s))
    if jitter > 0:
        step *= np.random.default_rng(seed).uniform(1 - jitter, 1 + jitter, len(group))
    cs = np.cumsum(step)
    g0 = np.concatenate([[0], np.cumsum(n_ticks)[:-1]])
    tick = cs - cs[g0][group] + step[g0][group] - step  # 0 at each track's first tick
    inside = tick <= span[group]
    group, tick = group[inside], tick[inside]
    scale = float(span.max()) * (1 + 1e-9) + 1.0
    along = index.track_of_row + (t - first[index.track_of_row]) / scale  # sorted
    row = np.searchsorted(along, group + (tick - 1e-6) / scale)
    row = np.unique(row[row < index.ends[group]])
    return pts.iloc[row].reset_index(drop=True)


def moving_hours(points: pd.DataFrame, max_leg_s: float = 600.0, min_kn: float = 1.0) -> float:
    """Track-hours under way: the legs of at least ``min_kn`` knots and at most
    ``max_leg_s`` s (a longer leg is a gap, not time seen under way)."""
    pts, index = sorted_with_index(points)
    x, y = local_xy(pts, index)
    t = track_seconds(pts)
    same = index.track_of_row[1:] == index.track_of_row[:-1]
    dt = np.diff(t)
    with np.errstate(invalid="ignore", divide="ignore"):
        v = np.hypot(np.diff(x), np.diff(y)) / dt / geo.KN_MS
    leg = same & (dt > 0) & (dt <= max_leg_s) & (v >= min_kn)
    return float(dt[leg].sum() / 3600.0)


def read_set(name: str) -> tuple[pd.DataFrame, list]:
    """The set's points for the maneuver figures, and its association scenes (a list of
    (points, truth_sep)): one per file for MTAD, the recognised set's tracks otherwise."""
    folder = REAL / SETS[name][0]
    if name == "autoferry":
        return real_sets.read_autoferry(folder)[1], []
    if name == "mtad":
        scenes = [(read_points(f).points, "-") for f in real_files(folder)]
        return _track_files(folder, None), scenes
    points = {
        "saronic": real_sets.read_greece,
        "dma": real_sets.read_dma,
        "oresund": real_sets.read_oresund,
    }[name](folder)
    return points, [(real_sets.association_tracks(folder), "")]


def association(
    scenes: list, rate_s: float | None, jitter: float, gaps, every, link: LinkParams | None = None
) -> tuple:
    """Mean P_CA, P_FA (ours, optimal) over the scenes with a true pair, decimated alike;
    the true pairs and those within T_gap (``max_gap_s``), summed. ``link``: the
    association's parameters (None: the defaults)."""
    rows = []
    for pts, sep in scenes:  # a handful of scenes
        if rate_s is not None:
            pts = decimate(pts, rate_s, jitter)
        r = scene_scores(pts, params=link, gaps=gaps, gaps_every=every, truth_sep=sep)[0]
        if r["true_pairs"] > 0:
            rows.append((r["p_ca"], r["p_fa"], r["true_pairs"], r["reachable"]))
    if not rows:
        return np.nan, np.nan, 0, 0
    a = np.array(rows)
    return float(a[:, 0].mean()), float(a[:, 1].mean()), int(a[:, 2].sum()), int(a[:, 3].sum())


def rest_time_share(res, max_leg_s: float = 3600.0) -> float:
    """Share of the track time (legs of at most ``max_leg_s`` s) between two at-rest fixes:
    unlike the share of points, it does not depend on AIS reporting faster under way."""
    t = track_seconds(res.points)
    tr = res.index.track_of_row
    dt = np.diff(t)
    leg = (tr[1:] == tr[:-1]) & (dt <= max_leg_s)
    both = res.at_rest[1:] & res.at_rest[:-1]
    return float(dt[leg & both].sum() / max(dt[leg].sum(), 1e-9))


def one_row(
    pts: pd.DataFrame,
    hours: float,
    turns: pd.DataFrame | None,
    rate_s,
    params: ManeuverParams | None = None,
) -> dict:
    """The maneuver, at-rest, compression and cleaning figures of one decimated set (the
    detector's ``params``, default its defaults); with GNSS ``turns``, the turns found (match
    within max(10 s, 2 sampling periods))."""
    res = detect(pts, params or ManeuverParams())
    comp = compression_against_dp(res)
    n_m = int(res.is_maneuver.sum())
    med = median_interval_s(track_seconds(res.points), res.index)
    rules = clean(pts).report["rules"]
    row = {
        "points": len(res.points),
        "tracks": res.index.n_tracks,
        "med_dt": float(np.nanmedian(med)) if np.isfinite(med).any() else np.nan,
        "maneuvers": n_m,
        "per_h": n_m / hours if hours > 0 else np.nan,
        "slow": slow_share(res),
        "rest": float(res.at_rest.mean()) if len(pts) else 0.0,
        "rest_t": rest_time_share(res),
        "ours": comp["ours_kept"],
        "dp": comp["dp_kept"],
        "speed_rm": rules["speed"]["removed"],
        "turn_rm": rules["turn"]["removed"],
    }
    if turns is not None:
        tab = res.table()
        det = pd.DataFrame({"batch": tab["batch"], "t_s": time_seconds(tab["time"])})
        match = max(10.0, 2.0 * (rate_s or 0.0))
        sc = score_turns(det, turns, match, covered_turns(turns, res.points, match))
        row["turns"] = f"{sc['recall'] * sc['turns']:.0f}/{sc['turns']} P{sc['precision']:.2f}"
    return row


def main(argv: list[str] | None = None) -> pd.DataFrame:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sets", nargs="+", default=list(SETS), choices=list(SETS))
    ap.add_argument("--rates", nargs="+", type=float, default=None, help="seconds")
    ap.add_argument("--jitter", type=float, default=0.3, help="±share of R; 0 = regular only")
    ap.add_argument("--quick", action="store_true", help=f"rates {QUICK_RATES}, regular only")
    ap.add_argument("--no-assoc", action="store_true", help="skip the association columns")
    ap.add_argument("--csv", help="write the table here too")
    ap.add_argument(
        "--max-step-windows",
        type=float,
        default=ManeuverParams().max_step_windows,
        help="the detector's max_step_windows (0 = headings across any step, as before)",
    )
    ap.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="the association's LinkParams changed (as evaluate associate --set)",
    )
    ap.add_argument(
        "--maneuver-set",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="the detector's ManeuverParams changed (e.g. radius_s=15), for a candidate "
        "against the defaults",
    )
    a = ap.parse_args(argv)
    params = ManeuverParams(max_step_windows=a.max_step_windows)
    if a.maneuver_set:
        changes = dict(kv.split("=", 1) for kv in a.maneuver_set)
        params = params.replace(
            **{k: type(getattr(params, k))(float(v)) for k, v in changes.items()}
        ).checked()
    link = LinkParams().replace(**dict(kv.split("=", 1) for kv in a.set)) if a.set else None
    rates = a.rates or (QUICK_RATES if a.quick else RATES)
    variants = [0.0] if a.quick or a.jitter <= 0 else [0.0, a.jitter]
    cpu0, wall0 = time.process_time(), time.time()
    rows = []
    for name in a.sets:
        points, scenes = read_set(name)
        gaps = SETS[name][1]
        hours = moving_hours(points)
        turns = truth_turns(points) if name == "autoferry" else None
        t = track_seconds(sorted_with_index(points)[0])
        own_med = float(np.nanmedian(median_interval_s(t, sorted_with_index(points)[1])))
        cases = [("own", None, 0.0)]
        for r in rates:
            if r < own_med * 0.9:
                continue  # the set is not that dense
            cases += [(f"{r:g}" + (f"±{j:.0%}" if j else ""), r, j) for j in variants]
        for label, r, j in cases:
            pts = points if r is None else decimate(points, r, j)
            row = {"set": name, "rate": label, **one_row(pts, hours, turns, r, params)}
            if gaps is not None and scenes and not a.no_assoc:
                row["P_CA"], row["P_FA"], row["pairs"], row["reach"] = association(
                    scenes, r, j, *gaps, link
                )
            rows.append(row)
            print(_line(row), flush=True)
    table = pd.DataFrame(rows)
    load = os.getloadavg()
    print(
        f"CPU {time.process_time() - cpu0:.0f} s, wall {time.time() - wall0:.0f} s, "
        f"load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}"
    )
    if a.csv:
        table.to_csv(a.csv, index=False)
    return table


HEADER = (
    f"{'set':<10}{'rate s':>9}{'points':>7}{'tracks':>7}{'med dt':>7}{'man':>6}{'/mov h':>7}"
    f"{'slow':>6}{'rest':>6}{'rest t':>7}{'ours':>6}{'DP':>6}{'o/DP':>5}{'speed':>6}{'turn':>5}"
    f"  {'P_CA':>5} {'P_FA':>5} {'pairs':>5} {'reach':>5}  turns (GNSS)"
)


def _line(r: dict) -> str:
    if not hasattr(_line, "done"):
        print(HEADER)
        _line.done = True
    assoc = (
        f"  {r['P_CA']:5.3f} {r['P_FA']:5.3f} {r['pairs']:5d} {r['reach']:5d}"
        if "P_CA" in r and not np.isnan(r["P_CA"])
        else f"  {'':5} {'':5} {'':5} {'':5}"
    )
    return (
        f"{r['set']:<10}{r['rate']:>9}{r['points']:7d}{r['tracks']:7d}{r['med_dt']:7.1f}"
        f"{r['maneuvers']:6d}{r['per_h']:7.1f}{r['slow']:6.3f}{r['rest']:6.3f}{r['rest_t']:7.3f}"
        f"{r['ours']:6d}{r['dp']:6d}{r['ours'] / max(r['dp'], 1):5.2f}{r['speed_rm']:6d}"
        f"{r['turn_rm']:5d}" + assoc + (f"  {r['turns']}" if "turns" in r else "")
    ).rstrip()


if __name__ == "__main__":
    main()
