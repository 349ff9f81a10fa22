"""Gating bearings on tracks by time (h157: every track was compared with every bearing):
the same table and report as before, exactly (tests/gate_reference.py, the frozen
former code), on the Autoferry detections with their ground truth and on a simulated
case with clutter, unsorted and repeated times, gaps and no observer."""

import gate_reference
import numpy as np
import pandas as pd
import pytest

from conftest import DATA, real_file
from wakeline.core import geo
from wakeline.core.bearing_read import gate_to_tracks, read_bearing_file
from wakeline.core.io import read_points

PIREN = "63.4389029083,10.39908278"


def _same(bearings: pd.DataFrame, tracks: pd.DataFrame, gate_deg: float = 3.0) -> dict:
    new, new_rep = gate_to_tracks(bearings, tracks, gate_deg)
    old, old_rep = gate_reference.gate_to_tracks(bearings, tracks, gate_deg)
    pd.testing.assert_frame_equal(new, old, check_exact=True)
    assert new_rep == old_rep
    return new_rep


def test_the_autoferry_sample_gates_as_before():
    got = read_bearing_file(DATA / "autoferry_detections_sample.csv")
    truth = read_points(DATA / "autoferry_truth_sample.csv", origin=PIREN).points
    rep = _same(got.bearings, truth)
    assert rep["kept"] > 0


@pytest.mark.real
def test_the_real_autoferry_detections_gate_as_before():
    folder = real_file("autoferry-fusion", "detections.csv.gz").parent
    got = read_bearing_file(folder / "detections.csv.gz")
    truth = read_points(folder / "ground_truth.csv.gz", origin=PIREN).points
    rep = _same(got.bearings, truth)
    assert rep["kept"] > 6_000


def _simulated(seed: int) -> tuple[pd.DataFrame, pd.DataFrame]:
    rng = np.random.default_rng(seed)
    t0 = pd.Timestamp("2024-01-01", tz="UTC")
    olon, olat = 10.39, 63.43
    tracks, bearings = [], []
    for k in range(30):
        start = rng.uniform(0, 3000)
        tt = start + np.cumsum(rng.choice([1.0, 1.0, 2.0, 0.0, 15.0], 300))  # repeats, gaps
        lon = olon + 0.01 + 1e-5 * k + 2e-5 * np.arange(300)
        lat = olat + 0.005 * np.sin(k + 1e-2 * np.arange(300))
        tracks.append(
            pd.DataFrame(
                {
                    "batch": f"t{k}",
                    "time": t0 + pd.to_timedelta(tt, unit="s"),
                    "lon": lon,
                    "lat": lat,
                }
            )
        )
        pick = rng.choice(300, 120)
        true_b = geo.initial_bearing_deg(
            np.full(120, olon), np.full(120, olat), lon[pick], lat[pick]
        )
        bearings.append(
            pd.DataFrame(
                {
                    "batch": rng.choice(["eo", "ir"], 120),
                    "time": t0 + pd.to_timedelta(tt[pick], unit="s"),
                    "bearing": (true_b + rng.normal(0, 2.0, 120)) % 360.0,
                }
            )
        )
    clutter = pd.DataFrame(
        {
            "batch": rng.choice(["eo", "ir"], 3000),
            "time": t0 + pd.to_timedelta(rng.uniform(-100, 4000, 3000), unit="s"),
            "bearing": rng.uniform(0, 360, 3000),
        }
    )
    b = pd.concat([*bearings, clutter], ignore_index=True).sample(frac=1.0, random_state=seed)
    b = b.reset_index(drop=True).assign(obs_lon=olon, obs_lat=olat)
    b.loc[b.index[::97], "obs_lon"] = np.nan  # no observer position: never gated
    return b, pd.concat(tracks, ignore_index=True).sample(frac=1.0, random_state=seed)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_simulated_case_gates_as_before(seed):
    b, tracks = _simulated(seed)
    for gate in (1.0, 3.0, 20.0):
        rep = _same(b, tracks, gate)
        assert rep["kept"] > 100 and rep["no_track"] > 0
    assert _same(b.iloc[:0], tracks)["kept"] == 0


def test_each_track_is_compared_with_the_bearings_of_its_span_only(monkeypatch):
    """The cost: a track's bearings from the observer are worked out only at the bearings
    within its time span (before: at every bearing, for every track)."""
    b, tracks = _simulated(0)
    sizes = []
    real = geo.initial_bearing_deg

    def counted(*args):
        sizes.append(len(args[0]))
        return real(*args)

    monkeypatch.setattr(geo, "initial_bearing_deg", counted)
    gate_to_tracks(b, tracks)
    t = b["time"].to_numpy()
    spans = tracks.groupby("batch")["time"].agg(["min", "max"])
    within = [int(((t >= lo) & (t <= hi)).sum()) for lo, hi in spans.to_numpy()]
    assert sorted(sizes) == sorted(within) and sum(sizes) < len(b) * len(spans) / 2
