"""What ``slow_side`` adds on a real AIS file (issue 15; session 27): the maneuver points
found with ``--set slow_side=0.5 ...`` and not by the defaults (or ``--base``), each with
the two windows' chord speeds (kn), the slower window's span and longest step (s), the
track's median interval, and whether the goal counts it slow (chord over the legs either
side < 1 kn). ATD's example file by default (the tuning file; dataset1 is held out).

    python bench/slow_side_atd.py [FILE] [--set slow_side=0.5 slow_side_step_s=180]
"""

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "bench"))
from radar_scan_rates import _params  # noqa: E402
from slow_maneuvers import DEFAULT  # noqa: E402

from wakeline.core import geo  # noqa: E402
from wakeline.core.evaluate_real import _speed_either_side_kn, _track_files, slow_share  # noqa: E402
from wakeline.core.maneuver import detect  # noqa: E402
from wakeline.core.tracks import local_xy, median_interval_s, track_seconds  # noqa: E402


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("file", nargs="?", default=str(DEFAULT))
    ap.add_argument("--set", nargs="*", default=["slow_side=0.5"], metavar="FIELD=VALUE")
    ap.add_argument("--base", nargs="*", default=[], metavar="FIELD=VALUE")
    a = ap.parse_args(argv)
    pts = _track_files(Path(a.file), None)
    base, alt = detect(pts, _params(a.base)), detect(pts, _params(a.set))
    print(
        f"base {int(base.is_maneuver.sum())} maneuvers, slow share {slow_share(base):.4f}; "
        f"{' '.join(a.set)}: {int(alt.is_maneuver.sum())}, {slow_share(alt):.4f}"
    )
    p, idx = alt.points, alt.index
    x, y = local_xy(p, idx)
    t = track_seconds(p)
    med = median_interval_s(t, idx)
    chord = _speed_either_side_kn(p, idx)
    added = np.flatnonzero(alt.is_maneuver & ~base.is_maneuver)
    gone = np.flatnonzero(base.is_maneuver & ~alt.is_maneuver)
    print(
        f"added {len(added)} (slow {(chord[added] < 1).sum()}), gone {len(gone)} "
        f"(slow {(chord[gone] < 1).sum()})"
    )
    rows = []
    for r in added:  # a few dozen rows: a report, not a hot path
        k = idx.track_of_row[r]
        pk = alt.window_p[k]
        a_, b_ = max(r - pk + 1, idx.starts[k]), min(r + pk - 1, idx.ends[k] - 1)
        vb = np.hypot(x[r] - x[a_], y[r] - y[a_]) / (t[r] - t[a_]) / geo.KN_MS
        vf = np.hypot(x[b_] - x[r], y[b_] - y[r]) / (t[b_] - t[r]) / geo.KN_MS
        win = slice(a_, r + 1) if vb <= vf else slice(r, b_ + 1)
        steps = np.diff(t[win])
        rows.append(
            (chord[r] < 1, min(vb, vf), max(vb, vf), t[win][-1] - t[win][0], steps.max(), med[k])
        )
    d = pd.DataFrame(rows, columns=["slow", "v_lo_kn", "v_hi_kn", "span_s", "max_step_s", "med_s"])
    if len(d):
        print(d.describe().round(2).to_string())
        print(
            "slower window: longest step <= 180 s",
            int((d.max_step_s <= 180).sum()),
            "; span <= 180 s",
            int((d.span_s <= 180).sum()),
        )


if __name__ == "__main__":
    main()
