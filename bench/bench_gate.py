"""Gating bearings on tracks (``wakeline bearing --tracks``, the Open bearings dialog's
gate): every track against every bearing (before h167, tests/gate_reference.py) against
the gate by time (core/bearing_read.py: bearings sorted by time once, each track's span
found by searchsorted). h157's probe: 65,000 bearings over 10 h in 18 series, tracks of
20 min at 1 Hz anywhere in the 10 h. Both give the same table (checked here too).

Run: ``python bench/bench_gate.py [--bearings 65000] [--tracks 100 400] [--repeat 3]``.
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import gate_reference as ref  # noqa: E402

from wakeline.core.bearing_read import gate_to_tracks  # noqa: E402


def make(n_bearings: int, n_tracks: int, seed: int = 0) -> tuple[pd.DataFrame, pd.DataFrame]:
    rng = np.random.default_rng(seed)
    t0 = pd.Timestamp("2024-01-01", tz="UTC")
    b = pd.DataFrame(
        {
            "batch": rng.choice([f"s{k}" for k in range(18)], n_bearings),
            "time": t0 + pd.to_timedelta(np.sort(rng.uniform(0, 36000, n_bearings)), unit="s"),
            "bearing": rng.uniform(0, 360, n_bearings),
            "obs_lon": 10.39,
            "obs_lat": 63.43,
        }
    )
    rows = []
    for k in range(n_tracks):
        s = rng.uniform(0, 36000 - 1200)
        tt = s + np.arange(1200.0)
        rows.append(
            pd.DataFrame(
                {
                    "batch": f"t{k}",
                    "time": t0 + pd.to_timedelta(tt, unit="s"),
                    "lon": 10.4 + 1e-5 * np.arange(1200),
                    "lat": 63.44,
                }
            )
        )
    return b, pd.concat(rows, ignore_index=True)


def best(fn, repeat: int) -> tuple[float, tuple]:
    out, times = None, []
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return min(times), out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bearings", type=int, default=65_000)
    ap.add_argument("--tracks", type=int, nargs="+", default=[100, 400])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    for n in args.tracks:
        b, tr = make(args.bearings, n)
        old_s, (old, old_rep) = best(lambda: ref.gate_to_tracks(b, tr), args.repeat)  # noqa: B023
        new_s, (new, new_rep) = best(lambda: gate_to_tracks(b, tr), args.repeat)  # noqa: B023
        pd.testing.assert_frame_equal(new, old, check_exact=True)
        assert new_rep == old_rep
        print(
            f"{n} tracks x {args.bearings:,} bearings: before {old_s:.3f} s "
            f"({old_s / n * 1000:.2f} ms a track), now {new_s:.3f} s "
            f"({new_s / n * 1000:.2f} ms a track): {old_s / new_s:.1f}x; "
            f"kept {new_rep['kept']:,}, same table"
        )


if __name__ == "__main__":
    main()
