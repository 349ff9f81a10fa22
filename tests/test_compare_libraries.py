"""bench/compare_libraries.py: its synthetic tracks are what its docstring says (stops the
ship holds still, gaps the ship sails through), and our side of the stop comparison finds
the stops (the other libraries are not installed here; they run in .venv-cmp)."""

import importlib.util

import numpy as np

from conftest import REPO
from wakeline.core.clean import at_rest
from wakeline.core.tracks import local_xy, sorted_with_index, track_seconds


def _load():
    spec = importlib.util.spec_from_file_location(
        "_bench_compare_libraries", REPO / "bench" / "compare_libraries.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_synthetic_tracks_have_stops_and_gaps():
    mod = _load()
    df = mod.synthetic(5000)
    pts, index = sorted_with_index(df)
    assert pts is df and index.n_tracks == 5 and (index.sizes == 1000).all()
    assert (df["row"].to_numpy() == np.arange(len(df))).all()
    truth = df["true_stop"].to_numpy()
    assert 0.05 < truth.mean() < 0.4
    t = track_seconds(pts)
    step = np.diff(t)[np.diff(index.track_of_row) == 0]
    assert (step >= 10.0).all() and (step > mod.GAP_S).sum() >= 3
    x, y = local_xy(pts, index)
    rest = at_rest(x, y, t, index, mod.RADIUS_M, mod.WINDOW_S)
    # measured 99.5 % at 10 k points (docs/benchmarks.md, Against MovingPandas and Stone Soup)
    assert np.mean(rest == truth) > 0.98
