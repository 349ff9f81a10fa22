"""A rule tried and not adopted (issue 15, 2026-12-03): windows shrunk at a track's ends.

At a track's first and last p - 1 points our p-point window (p = round(10 s / median
interval): 6 at the radar's 1.68 s) does not fit, so a turn there cannot be seen however
clear. Held-out Autoferry track 17/2 begins 10 s before a -95/+44 deg zig-zag with one plot
and four more before the turn; the paper's 5 points fit there. Emulated here without
touching the detector: the default detector's maneuvers, plus the maneuvers of the
first-scale detector at p = ``window_p`` (5; noise floor, speed and at-rest rules as
default, no longer, gapped or shorter windows) at rows where the p-point window leaves the
track on one side, on tracks where p > 5, with no default maneuver within 5 rows. Scored on
the real Autoferry radar (both splits) and the synthetic radar set of
``bench/radar_turns_synthetic.py``.

Run: ``python bench/radar_track_ends.py [--seeds 1 2 3 4] [--tracks 150] [--hard 5]`` (reads
$WAKELINE_SHARED/data/real/autoferry-fusion, default ../shared; ``--hard N``: also the hard
maneuver table over N scenes, ``evaluate maneuver --hard``'s, with the rule in ours).
"""

import argparse
import os
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
from radar_turns_synthetic import make

from wakeline.core import evaluate_real as er
from wakeline.core import real_sets
from wakeline.core.maneuver import ManeuverParams, detect
from wakeline.core.schema import time_seconds

REAL = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
FIRST_SCALE_P5 = ManeuverParams(window_s=0.0, max_window_s=0.0, gap_s=0.0, min_window_s=0.0)


def with_track_ends(points: pd.DataFrame) -> tuple[pd.DataFrame, int]:
    """Detections (batch, t_s) of the default detector plus the track-end rule above, and
    how many the rule added."""
    res, added = track_ends_result(points)
    tab = res.table()
    return pd.DataFrame(
        {"batch": tab["batch"].astype(str), "t_s": time_seconds(tab["time"])}
    ), added


def track_ends_result(points: pd.DataFrame, params: ManeuverParams | None = None):
    """The default detector's result (``params``: another one's) with the track-end rule's
    maneuvers added, and how many it added."""
    res = detect(points, params or ManeuverParams())
    short = detect(points, FIRST_SCALE_P5)
    pts, index = res.points, res.index
    tr = index.track_of_row
    rows = np.arange(len(pts))
    p = np.asarray(res.window_p)[tr]
    at_end = ((rows - index.starts[tr]) < p - 1) | ((index.ends[tr] - 1 - rows) < p - 1)
    found = res.is_maneuver.copy()
    f = np.flatnonzero(found)
    extra = np.flatnonzero(short.is_maneuver & at_end & (p > FIRST_SCALE_P5.window_p))
    # a handful of candidates: one search each in the sorted list of default maneuvers
    lo = np.searchsorted(f, extra - FIRST_SCALE_P5.window_p)
    hi = np.searchsorted(f, extra + FIRST_SCALE_P5.window_p, side="right")
    alone = np.array(
        [not (tr[f[a:b]] == tr[r]).any() for r, a, b in zip(extra, lo, hi, strict=True)], bool
    )
    found[extra[alone]] = True
    return replace(res, is_maneuver=found), int(alone.sum())


def _split(batch: pd.Series, tuning: bool | None) -> np.ndarray:
    if tuning is None:
        return np.ones(len(batch), dtype=bool)
    scen = batch.astype(str).str.split("/").str[0].astype(int)
    return (scen.isin(er.AUTOFERRY_TUNING) == tuning).to_numpy()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3, 4])
    ap.add_argument("--tracks", type=int, default=150)
    ap.add_argument("--hard", type=int, default=0, metavar="N", help="hard scenes (0: none)")
    args = ap.parse_args()
    pts, truth = real_sets.read_autoferry(REAL / "data/real/autoferry-fusion", exclusive=True)
    turns = er.truth_turns(truth, 15.0, 1.0)
    scored = er.sound_turns(er.covered_turns(turns, pts, 10.0), er.gnss_faults(truth), 2.0)
    det, added = with_track_ends(pts)
    print(f"real Autoferry radar: {added} detections added at track ends")
    for label, tuning in (("all", None), ("scenarios 2-6", True), ("scenarios 13-22", False)):
        s = er.score_turns(
            det[_split(det["batch"], tuning)],
            turns[_split(turns["batch"], tuning)],
            10.0,
            scored[_split(scored["batch"], tuning)],
        )
        print(f"  {label}: {s}")
    for seed in args.seeds:
        p_, gnss = make(seed, args.tracks)
        tu = er.truth_turns(gnss, 15.0, 1.0)
        sc = er.covered_turns(tu, p_, 10.0)
        base = detect(p_, ManeuverParams()).table()
        base = pd.DataFrame({"batch": base["batch"], "t_s": time_seconds(base["time"])})
        det, added = with_track_ends(p_)
        s0, s1 = er.score_turns(base, tu, 10.0, sc), er.score_turns(det, tu, 10.0, sc)
        print(
            f"synthetic seed {seed}: default P {s0['precision']:.3f} R {s0['recall']:.3f}; "
            f"with track ends (+{added}) P {s1['precision']:.3f} R {s1['recall']:.3f}"
        )

    if args.hard:
        from wakeline.core import evaluate

        plain = evaluate.detect

        def patched(points, params=None, *a, **k):
            if params is not None and params.window_s > 0:  # ours, not the paper's
                return track_ends_result(points, params)[0]
            return plain(points, params, *a, **k)

        evaluate.detect = patched
        print(evaluate.evaluate_maneuver_hard(100, 0, args.hard, ManeuverParams()).format())


if __name__ == "__main__":
    main()
