"""Why the radar's turns are missed at slower scans: per scored GNSS turn of the Autoferry
radar decimated to one plot every ``--rate`` s, whether the detector (defaults, or ``--set``)
finds it, the track's median step and noise, and δ over the turn ±10 s at windows of 3, 4
and 5 points: ``time:δ/floor`` (floor = noise_k × the heading noise of those windows;
``s`` = a window slower than min_speed_kn, ``-`` = no δ, a window leaves the track). Then
per track the detections and the scored turns, in seconds from the track's first plot.

    python bench/radar_scan_why.py --rate 5 [--set window_max_s=20]

Session h131's diagnosis (docs/evaluation.md "Radar at slower scans (h131)"). Radar only:
the lidar is the blind check.
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
    score_turns,
    sound_turns,
    truth_turns,
)
from wakeline.core.maneuver import (  # noqa: E402
    _heading_noise_deg,
    _window_speeds_ms,
    detect,
    maneuver_factor,
    position_noise_m,
)
from wakeline.core.schema import time_seconds  # noqa: E402
from wakeline.core.tracks import local_xy, median_interval_s, track_seconds  # noqa: E402

REAL = Path(os.environ.get("WAKELINE_SHARED", REPO.parent / "shared")) / "data" / "real"


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rate", type=float, default=None, help="s (default: the radar's own)")
    ap.add_argument("--set", nargs="*", default=[], metavar="FIELD=VALUE")
    a = ap.parse_args(argv)
    params = _params(a.set)
    pts, truth = real_sets.read_autoferry(REAL / "autoferry-fusion", exclusive=True)
    plots = pts if a.rate is None else decimate(pts, a.rate)
    plots = in_content_order(plots.assign(sensor="radar"))
    match = match_to_truth(plots, truth)
    turns = _under_tracks(truth_turns(truth, params.threshold_deg, 1.0), match)
    faults = _under_tracks(gnss_faults(truth, 0.5), match)
    scored = sound_turns(
        covered_turns(turns, plots.assign(batch=_track_key(plots)), 10.0), faults, 2.0
    )
    res = detect(plots, params)
    tab = res.table()
    det = pd.DataFrame(
        {"batch": _track_key(tab).to_numpy(), "t_s": time_seconds(tab["time"]), "f": tab["factor"]}
    )
    print(score_turns(det[["batch", "t_s"]], turns, 10.0, scored))
    idx = res.index
    x, y = local_xy(res.points, idx)
    t = track_seconds(res.points)
    med = median_interval_s(t, idx)
    sigma = position_noise_m(x, y, t, idx, 1)
    row_of = {k: i for i, k in enumerate(_track_key(idx.keys).to_numpy())}
    fac = {p: maneuver_factor(x, y, idx, p) for p in (3, 4, 5)}
    slow = params.min_speed_kn * geo.KN_MS
    for _, turn in scored.sort_values(["batch", "start_s"]).iterrows():
        k = row_of[turn.batch]
        s, e = idx.starts[k], idx.ends[k]
        t0 = t[s]
        near = (det.batch == turn.batch) & det.t_s.between(turn.start_s - 10, turn.end_s + 10)
        print(
            f"\n{turn.batch} turn {turn.start_s - t0:.0f}-{turn.end_s - t0:.0f} s "
            f"({turn.change_deg:+.0f} deg) {'FOUND' if near.any() else 'missed'}; track "
            f"{e - s} plots over {t[e - 1] - t0:.0f} s, median step {med[k]:.2f} s, "
            f"sigma {sigma[k]:.1f} m, first-scale p {res.window_p[k]}"
        )
        tt = t[s:e]
        rows = s + np.flatnonzero((tt >= turn.start_s - 10) & (tt <= turn.end_s + 10))
        for p, f in fac.items():
            prow = np.full(len(rows), p)
            floor = params.noise_k * _heading_noise_deg(x, y, idx, prow, sigma, rows)
            lo, _ = _window_speeds_ms(x, y, t, idx, prow, rows)
            cells = [
                f"{t[r] - t0:.0f}:-"
                if not np.isfinite(f[r])
                else f"{t[r] - t0:.0f}:{f[r]:.0f}/{fl:.0f}{'' if v >= slow else 's'}"
                for r, fl, v in zip(rows, floor, lo, strict=True)
            ]
            print(f"  p={p} ({p * med[k]:.0f} s): " + " ".join(cells))
    print("\nper track (s from its first plot): scored turns | detections (δ)")
    for b in sorted(set(scored.batch)):
        t0 = t[idx.starts[row_of[b]]]
        tr = scored[scored.batch == b]
        d = det[det.batch == b]
        print(
            f"{b}: "
            + ", ".join(f"{r.start_s - t0:.0f}-{r.end_s - t0:.0f}" for r in tr.itertuples())
            + " | "
            + ", ".join(f"{v - t0:.0f} ({f:.0f})" for v, f in zip(d.t_s, d.f, strict=True))
        )


if __name__ == "__main__":
    main()
