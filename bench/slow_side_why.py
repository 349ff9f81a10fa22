"""Why the Autoferry radar's turns are missed at its own rate (issue 15, goal 2a; session 27):
per scored GNSS turn (default: scenarios 13-22; ``--all``), found or missed by the detector
(defaults or ``--set``), and which single relief finds it: ``min_speed_kn=0`` (the speed
rule), ``slow_side=0.5``, ``noise_k=0`` (the noise floor), ``rest_radius_m=0`` (the at-rest
rule). Then, over the turn ±10 s at the first scale's p and at the fine scale's (5 s), per
plot: ``time:δ v_back/v_fwd (kn) n_back/n_fwd longest-step`` for the window pair ending and
starting there (n = fixes in the window, longest step in s of the slower window).

    python bench/slow_side_why.py [--all] [--set slow_side=0.5]

Radar only: the lidar is the blind check.
"""

import argparse
import os
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "bench"))
from radar_scan_rates import _params  # noqa: E402

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
from wakeline.core.maneuver import detect, maneuver_factor  # noqa: E402
from wakeline.core.schema import time_seconds  # noqa: E402
from wakeline.core.tracks import local_xy, track_seconds  # noqa: E402

REAL = Path(os.environ.get("WAKELINE_SHARED", REPO.parent / "shared")) / "data" / "real"


def found_near(res, turns: pd.DataFrame) -> np.ndarray:
    """Per scored turn: a detection on its track within 10 s of it."""
    tab = res.table()
    det = pd.DataFrame({"batch": _track_key(tab).to_numpy(), "t_s": time_seconds(tab["time"])})
    out = []
    for turn in turns.itertuples():
        d = det[det.batch == turn.batch]
        out.append(bool(d.t_s.between(turn.start_s - 10, turn.end_s + 10).any()))
    return np.array(out)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--all", action="store_true", help="every scenario, not 13-22 only")
    ap.add_argument("--set", nargs="*", default=[], metavar="FIELD=VALUE")
    a = ap.parse_args(argv)
    params = _params(a.set)
    pts, truth = real_sets.read_autoferry(REAL / "autoferry-fusion", exclusive=True)
    plots = in_content_order(pts.assign(sensor="radar"))
    match = match_to_truth(plots, truth)
    turns = _under_tracks(truth_turns(truth, params.threshold_deg, 1.0), match)
    faults = _under_tracks(gnss_faults(truth, 0.5), match)
    scored = sound_turns(
        covered_turns(turns, plots.assign(batch=_track_key(plots)), 10.0), faults, 2.0
    )
    scored = scored.sort_values(["batch", "start_s"]).reset_index(drop=True)
    if not a.all:
        scen = scored.batch.str.split("/").str[1].astype(int)
        scored = scored[scen >= 13].reset_index(drop=True)
    res = detect(plots, params)
    reliefs = {
        "min_speed_kn=0": replace(params, min_speed_kn=0.0),
        "slow_side=0.5": replace(params, slow_side=0.5),
        "noise_k=0": replace(params, noise_k=0.0),
        "rest_radius_m=0": replace(params, rest_radius_m=0.0),
    }
    hit = found_near(res, scored)
    hits = {k: found_near(detect(plots, p), scored) for k, p in reliefs.items()}
    print(f"{hit.sum()} of {len(scored)} scored turns found")
    idx = res.index
    x, y = local_xy(res.points, idx)
    t = track_seconds(res.points)
    row_of = {k: i for i, k in enumerate(_track_key(idx.keys).to_numpy())}
    for i, turn in scored.iterrows():
        k = row_of[turn.batch]
        s, e = idx.starts[k], idx.ends[k]
        t0 = t[s]
        by = [name for name, h in hits.items() if h[i]]
        print(
            f"\n{turn.batch} turn {turn.start_s - t0:.0f}-{turn.end_s - t0:.0f} s "
            f"({turn.change_deg:+.0f} deg) {'FOUND' if hit[i] else 'missed'}"
            + ("" if hit[i] else f"; found with: {', '.join(by) or 'none of these'}")
            + f"; track {e - s} plots, first plot {t0:.0f} s"
        )
        tt = t[s:e]
        rows = s + np.flatnonzero((tt >= turn.start_s - 10) & (tt <= turn.end_s + 10))
        for p in sorted({int(res.window_p[k]), 3}, reverse=True):
            f = maneuver_factor(x, y, idx, p)
            cells = []
            for r in rows:
                a_, b_ = r - p + 1, r + p - 1
                if a_ < s or b_ >= e:
                    cells.append(f"{t[r] - t0:.0f}:-")
                    continue
                vb = np.hypot(x[r] - x[a_], y[r] - y[a_]) / (t[r] - t[a_]) / geo.KN_MS
                vf = np.hypot(x[b_] - x[r], y[b_] - y[r]) / (t[b_] - t[r]) / geo.KN_MS
                slow = slice(a_, r + 1) if vb <= vf else slice(r, b_ + 1)
                step = np.diff(t[slow]).max()
                cells.append(f"{t[r] - t0:.0f}:{f[r]:.0f} {vb:.1f}/{vf:.1f} {step:.1f}")
            print(f"  p={p}: " + "  ".join(cells))


if __name__ == "__main__":
    main()
