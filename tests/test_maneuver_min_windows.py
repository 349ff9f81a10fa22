"""``noise_min_windows`` (session 28, h178; D-man-1): h170's ``noise_min_span`` and
``noise_k_windows`` only on tracks that offer at least this many first-scale windows.

A short track offers few windows, so few chances for a false turn; there both h170 options
had failed a guard by one detection (docs/prereg/session27_false_turns.md). With the gate a
long dense noisy track gets the options (its false turns go) and a short one is tested as
without them, bit for bit. The gate stays off (docs/prereg/session28_false_turns.md: both
candidates failed guard (7) on the DMA sample ship, a 9 h AIS track of 3,300 points).
"""

import numpy as np
import pandas as pd
import pytest
from test_maneuver_long_noisy import _false_and_found, long_noisy_track

from wakeline.core import maneuver as m
from wakeline.core.errors import InputError
from wakeline.core.maneuver import ManeuverParams, detect

A = {"noise_min_span": 8.0, "noise_k_windows": True}  # h170's A


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_long_track_gets_the_options(seed):
    # 1.5 h at 1 Hz: 5,400 points / 10-point windows = 540 windows >= 500
    pts, spans = long_noisy_track(seed)
    gated = detect(pts, ManeuverParams(noise_min_windows=500.0, **A)).is_maneuver
    assert np.array_equal(gated, detect(pts, ManeuverParams(**A)).is_maneuver)
    false_default, found_default = _false_and_found(pts, spans, ManeuverParams())
    false, found = _false_and_found(pts, spans, ManeuverParams(noise_min_windows=500.0, **A))
    assert false_default > 50
    assert false <= 3 and found >= found_default - 1


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_short_track_is_bit_identical(seed):
    # 0.4 h at 1 Hz: 1,440 points = 144 windows < 500: as without the options
    pts, _ = long_noisy_track(seed, hours=0.4)
    base = detect(pts, ManeuverParams())
    gated = detect(pts, ManeuverParams(noise_min_windows=500.0, **A))
    assert np.array_equal(gated.is_maneuver, base.is_maneuver)
    assert np.array_equal(gated.factor, base.factor, equal_nan=True)
    # the gate is what keeps it: the options alone change this track
    ungated = detect(pts, ManeuverParams(**A)).is_maneuver
    assert not np.array_equal(ungated, base.is_maneuver)


def test_gate_is_per_track():
    # one table, a long and a short track: each as it is alone
    long_pts, _ = long_noisy_track(5)
    short_pts, _ = long_noisy_track(6, hours=0.4)
    both = pd.concat([long_pts, short_pts], ignore_index=True)
    params = ManeuverParams(noise_min_windows=500.0, **A)
    res = detect(both, params)
    n = len(long_pts)
    on_long = detect(long_pts, ManeuverParams(**A)).is_maneuver
    on_short = detect(short_pts, ManeuverParams()).is_maneuver
    got = res.is_maneuver
    batch = res.points["batch"].to_numpy()
    assert np.array_equal(got[batch == "s5"], on_long)
    assert np.array_equal(got[batch == "s6"], on_short)
    assert (batch == "s5").sum() == n


def test_enough_windows_values():
    points = np.array([5000, 4999, 100, 100])
    p = np.array([10, 10, 0, 1])
    assert m._enough_windows(points, p, 500.0).tolist() == [True, False, False, False]
    assert m._enough_windows(points, p, 100.0).tolist() == [True, True, True, True]


def test_off_by_default_and_validated():
    assert ManeuverParams().noise_min_windows == 0.0
    ManeuverParams(noise_min_windows=500.0, **A).checked()
    for bad in (-1.0, 2e9, float("nan")):
        with pytest.raises(InputError, match="noise_min_windows"):
            ManeuverParams(noise_min_windows=bad).checked()


def test_gate_equals_the_straightforward_detector():
    import maneuver_reference as reference

    long_pts, _ = long_noisy_track(7, hours=0.5)  # 180 windows
    short_pts, _ = long_noisy_track(8, hours=0.2)  # 72 windows
    pts = pd.concat([long_pts, short_pts], ignore_index=True)
    params = ManeuverParams(
        max_step_windows=0.0,
        slow_side_step_s=0.0,
        rest_noise_sigmas=0.0,
        noise_min_windows=100.0,
        **A,
    )
    ours = detect(pts, params)
    fields = dict(params.__dict__)
    off = ("max_step_windows", "window_max_s", "radius_s", "edge_s", "rest_north_box")
    assert not fields.pop("rest_noise_sigmas")  # h193/h195: off here, the reference predates it
    assert not fields.pop("confirm_z")  # h203: off by default, the reference predates it
    for gone in (
        *off,
        "slow_side_step_s",
        "slow_side_span_s",
        "noise_k_law",
        "rest_noise_cap_m",
        "confirm_legs",
        "confirm_grow",
        "confirm_grow_deg",
        "step_noise_max",
    ):
        fields.pop(gone)
    ref = reference.detect(pts, reference.ManeuverParams(**fields))
    assert np.array_equal(ours.is_maneuver, ref.is_maneuver)
    assert ref.is_maneuver.sum() > 0
