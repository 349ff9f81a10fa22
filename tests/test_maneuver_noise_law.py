"""``noise_k_law`` (session 28, h185; D-man-1): the noise floor's k at the same false-alarm
probability under the heading change's real law at a window's span in σ (a table simulated
by bench/noise_law_table.py, core/noise_law.py), not the normal law. Off by default
(docs/prereg/session28_false_turns_b.md)."""

import numpy as np
import pandas as pd
import pytest
from test_maneuver_long_noisy import _false_and_found, long_noisy_track

from wakeline.core import maneuver as m
from wakeline.core import noise_law
from wakeline.core.errors import InputError
from wakeline.core.maneuver import ManeuverParams, detect
from wakeline.core.tracks import TrackIndex

LAW = {"noise_k_law": True}


def test_factor_values():
    f = noise_law.law_factor
    r = np.geomspace(0.5, 500.0, 60)
    for p in (3, 5, 10, 20, 40):
        c = f(2.0, np.full(len(r), p), r)
        assert (c >= 1.0).all()
        assert (np.diff(c) <= 1e-12).all()  # the shorter the span, the larger
        assert c[-1] == 1.0  # far out the law is normal: today's k
    # a 10-point window over 3 σ (1 s, 15 m, 10 kn): k about 2.9 times today's
    assert 2.5 < f(2.0, np.array([10]), np.array([3.0]))[0] < 3.3
    assert f(2.0, np.array([10]), np.array([np.nan]))[0] >= 1.0
    # k beyond the table (noise_k_windows' k): its last plane
    assert np.isfinite(f(np.array([6.0]), np.array([10]), np.array([3.0]))).all()


@pytest.mark.parametrize("p,sigma", [(10, 15.0), (5, 15.0), (40, 15.0), (10, 5.0)])
def test_false_alarm_as_the_normal_law_says(p, sigma):
    # straight noisy track at 1 s, 5 m/s: the share of windows whose δ passes the floor at
    # the law's k is about the normal law's P(|Z| > 2) = 0.0455 at every span; at today's
    # k it is far more where the windows span a few σ
    rng = np.random.default_rng(1)
    n = 40000
    x = rng.normal(0, sigma, n)
    y = 5.0 * np.arange(n) + rng.normal(0, sigma, n)
    idx = TrackIndex(np.array([0]), np.array([n]), np.zeros(n, dtype="int64"), None)
    s = m.position_noise_m(x, y, np.arange(n, dtype=float), idx, 1)
    d = m.maneuver_factor(x, y, idx, p)
    rows = np.flatnonzero(np.isfinite(d))
    pr = np.full(len(rows), p)
    sd = m._heading_noise_deg(x, y, idx, pr, s, rows)
    k = m._k_law(x, y, idx, pr, s, rows, 2.0)
    share = np.mean(d[rows] > k * sd)
    assert 0.015 < share < 0.08, share
    if 5.0 * (p - 1) / sigma < 4:  # a few σ: today's k lets through more
        assert np.mean(d[rows] > 2.0 * sd) > 1.5 * share


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_long_noisy_track_fewer_false_turns(seed):
    pts, spans = long_noisy_track(seed)
    false_default, found_default = _false_and_found(pts, spans, ManeuverParams())
    false, found = _false_and_found(pts, spans, ManeuverParams(**LAW))
    assert false < false_default * 0.6
    assert found >= found_default - 1


@pytest.mark.parametrize("seed", [0, 1])
def test_short_track_unchanged_with_the_gate(seed):
    pts, _ = long_noisy_track(seed, hours=0.4)  # 144 windows < 500
    base = detect(pts, ManeuverParams())
    gated = detect(pts, ManeuverParams(noise_min_windows=500.0, **LAW))
    assert np.array_equal(gated.is_maneuver, base.is_maneuver)
    assert np.array_equal(gated.factor, base.factor, equal_nan=True)
    assert not np.array_equal(detect(pts, ManeuverParams(**LAW)).is_maneuver, base.is_maneuver)


def test_gate_is_per_track():
    long_pts, _ = long_noisy_track(5)
    short_pts, _ = long_noisy_track(6, hours=0.4)
    both = pd.concat([long_pts, short_pts], ignore_index=True)
    res = detect(both, ManeuverParams(noise_min_windows=500.0, **LAW))
    batch = res.points["batch"].to_numpy()
    assert np.array_equal(
        res.is_maneuver[batch == "s5"], detect(long_pts, ManeuverParams(**LAW)).is_maneuver
    )
    assert np.array_equal(
        res.is_maneuver[batch == "s6"], detect(short_pts, ManeuverParams()).is_maneuver
    )


def test_clean_ais_track_unchanged():
    # 30 s AIS, 10 m noise: windows span ~40 σ, where the law is normal
    pts, _ = long_noisy_track(3, dt=30.0, sigma=10.0, hours=3.0)
    base = detect(pts, ManeuverParams()).is_maneuver
    assert np.array_equal(detect(pts, ManeuverParams(**LAW)).is_maneuver, base)


def test_off_by_default_and_validated():
    assert ManeuverParams().noise_k_law is False
    ManeuverParams(noise_k_law=True, noise_min_windows=500.0).checked()
    with pytest.raises(InputError, match="noise_k_law"):
        ManeuverParams(noise_k_law=1.0).checked()
