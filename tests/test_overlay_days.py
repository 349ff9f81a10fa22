"""bench/overlay_days.py: each (vessel, UTC day) is a ship of its own, moved onto the first
day by whole days and a time-of-day offset within ±offset; positions are kept; the control
(``alone``) gives the same ships the same cuts and true pairs."""

import importlib.util

import numpy as np

from conftest import REPO
from wakeline.core.schema import time_seconds


def _bench():
    spec = importlib.util.spec_from_file_location(
        "_overlay_days", REPO / "bench" / "overlay_days.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _saronic_like(folder):
    """Two vessels over three UTC days, a fix a minute for 3 h each day (id lon lat t)."""
    folder.mkdir(parents=True)
    day0 = 19_936 * 86_400
    rows = []
    for v in (1, 2):
        for d in range(3):
            for k in range(180):
                t = day0 + d * 86_400 + 36_000 + 60 * k
                rows.append(f"{v} {23.5 + 0.001 * k * v:.5f} {37.9 + 0.01 * d:.5f} {t}")
    (folder / "vessels.csv").write_text("\n".join(rows) + "\n")


def test_each_vessel_day_is_a_ship_on_one_day(tmp_path):
    bench = _bench()
    bench.REAL = tmp_path
    _saronic_like(tmp_path / "greece-ais-annotated")
    df = bench.overlay_saronic(offset_h=2.0, seed=0)
    assert sorted(df["batch"].unique()) == [f"v{v}d{d}" for v in (1, 2) for d in range(3)]
    t = time_seconds(df["time"])
    start = df.assign(t=t).groupby("batch")["t"].min()
    first_day = 19_936 * 86_400 + 36_000
    assert (np.abs(start - first_day) <= 2 * 3600).all()
    assert start.nunique() == 6  # each ship its own offset
    # positions kept, fix for fix (in each ship's own time order)
    raw = bench.real_sets.read_greece(tmp_path / "greece-ais-annotated")
    assert np.allclose(np.sort(df["lon"]), np.sort(raw["lon"]))
    # the control: the same cuts and the same true pairs, no ship near another in time
    alone = bench.overlay_saronic(offset_h=2.0, seed=0, alone=True)
    a = bench.cut(df, (300.0, 900.0), 3600.0, seed=1)
    b = bench.cut(alone, (300.0, 900.0), 3600.0, seed=1)
    assert len(a) == len(b) and a["batch"].nunique() == b["batch"].nunique()
    span = alone.assign(t=time_seconds(alone["time"])).groupby("batch")["t"].agg(["min", "max"])
    span = span.sort_values("min")
    assert (span["min"].to_numpy()[1:] - span["max"].to_numpy()[:-1] > 86_400).all()
    d, d_alone = bench.density(df), bench.density(alone)
    assert d["ships"] == d_alone["ships"] == 6
    assert d["present_max"] >= 3 and d_alone["present_max"] == 1
