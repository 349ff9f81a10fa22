"""bench/radar_turns_synthetic.py: its radar plots carry the radar noise measured on Autoferry
(the hard scene's ``HardManeuverParams``), drawn along and across the true course."""

import importlib.util
import sys

import numpy as np

from conftest import REPO
from wakeline.core import geo
from wakeline.core.schema import time_seconds
from wakeline.core.simulate import HardManeuverParams


def _bench():
    spec = importlib.util.spec_from_file_location(
        "radar_turns_synthetic", REPO / "bench" / "radar_turns_synthetic.py"
    )
    mod = importlib.util.module_from_spec(spec)
    sys.modules["radar_turns_synthetic"] = mod
    spec.loader.exec_module(mod)
    return mod


def test_the_synthetic_radar_has_the_measured_noise_along_and_across_the_course():
    bench = _bench()
    radar, gnss = bench.make(seed=5, n_tracks=40)
    along, across = [], []
    for batch, r in radar.groupby("batch"):
        g = gnss[gnss["batch"] == batch]
        gx, gy = geo.to_local(g["lon"].to_numpy(), g["lat"].to_numpy(), bench.LON0, bench.LAT0)
        rx, ry = geo.to_local(r["lon"].to_numpy(), r["lat"].to_numpy(), bench.LON0, bench.LAT0)
        tg, tr = time_seconds(g["time"]), time_seconds(r["time"])
        ex, ey = rx - np.interp(tr, tg, gx), ry - np.interp(tr, tg, gy)
        # the true course at each plot: GNSS positions 1 s either side (5 Hz, 5 cm noise)
        dx = np.interp(tr + 1, tg, gx) - np.interp(tr - 1, tg, gx)
        dy = np.interp(tr + 1, tg, gy) - np.interp(tr - 1, tg, gy)
        c = np.arctan2(dx, dy)
        along.append(ex * np.sin(c) + ey * np.cos(c))
        across.append(ex * np.cos(c) - ey * np.sin(c))
    along, across = np.concatenate(along), np.concatenate(across)
    hp = HardManeuverParams()
    white = np.sqrt(0.9 * hp.radar_sigma_m**2 + 0.1 * hp.radar_outlier_m**2)
    want_across = np.hypot(white, hp.radar_offset_m)  # 1.41 m
    want_along = np.hypot(white, hp.radar_offset_along_m)  # 2.35 m
    # the bench's earlier noise was 1.82 m in every direction
    assert abs(across.std() - want_across) < 0.15
    assert abs(along.std() - want_along) < 0.4
    assert along.std() > 1.4 * across.std()
