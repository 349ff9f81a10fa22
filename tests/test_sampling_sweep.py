"""bench/sampling_sweep.py: the decimation it scores every set with (docs/evaluation.md,
"Sampling-rate sweep (session 19)")."""

import importlib.util

import numpy as np
import pandas as pd

from conftest import REPO
from wakeline.core.schema import time_seconds


def _sweep():
    spec = importlib.util.spec_from_file_location(
        "_bench_sweep", REPO / "bench" / "sampling_sweep.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _track(batch: str, seconds) -> pd.DataFrame:
    t = np.asarray(seconds, dtype="float64")
    return pd.DataFrame(
        {
            "sensor": "AIS",
            "batch": batch,
            "time": pd.to_datetime(t, unit="s", utc=True),
            "lon": 10.0,
            "lat": 55.0 + np.arange(len(t)) * 1e-4,
        }
    )


def test_decimate_keeps_the_first_fix_at_or_after_each_tick_per_track():
    pts = pd.concat(
        [_track("a", [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 30, 31, 32]), _track("b", [5, 7, 9, 11])]
    )
    out = _sweep().decimate(pts, 3.0)
    got = {b: time_seconds(g["time"]).tolist() for b, g in out.groupby("batch")}
    # a: ticks 0, 3, 6, 9, then 12 ... 30 all fall in the gap: the fix after it, once
    assert got["a"] == [0.0, 3.0, 6.0, 9.0, 30.0]
    # b: ticks from its own first fix (5, 8, 11)
    assert got["b"] == [5.0, 9.0, 11.0]


def test_jittered_decimation_keeps_intervals_within_its_bounds():
    pts = _track("a", np.arange(0, 3600, 1.0))
    out = _sweep().decimate(pts, 60.0, jitter=0.3, seed=1)
    dt = np.diff(time_seconds(out["time"]))
    assert dt.min() >= 42 - 1 and dt.max() <= 78 + 1  # 60 s ± 30 %, on a 1 s grid
    assert dt.std() > 5  # not the regular grid
