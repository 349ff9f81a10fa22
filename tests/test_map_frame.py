"""The first view's frame (app/map_frame.py, pure numpy): far-flung positions beyond an
empty stretch are left out, routes running on past the quantiles are shown (operator
test 4, D-map-1: 58 ATD routes east of 78° W were cut off)."""

import numpy as np
import pytest

from wakeline.app.map_frame import framed_box, position_sketch


def _body(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    return rng.uniform(-98.0, -78.0, n), rng.uniform(22.0, 31.0, n)


def test_a_route_running_on_past_the_quantile_is_shown():
    for seed in range(5):
        rng = np.random.default_rng(seed)
        lon, lat = _body(rng, 100_000)
        # 40 routes of 15 fixes running east from the body to 72° W: 0.6 % of the points,
        # farther than a quarter of the body's span past it.
        r_lon = np.concatenate(
            [np.linspace(-78.0, rng.uniform(-72.5, -72.0), 15) for _ in range(40)]
        )
        r_lat = rng.uniform(26.0, 28.0, len(r_lon))
        west, _, east, _ = framed_box([position_sketch(np.r_[lon, r_lon], np.r_[lat, r_lat])])
        assert east >= np.max(r_lon) - 0.3, (seed, east)
        assert west <= -97.9


def test_far_flung_positions_beyond_an_empty_stretch_stay_out():
    for seed in range(5):
        rng = np.random.default_rng(seed)
        lon, lat = _body(rng, 100_000)
        far_lon = rng.uniform(-123.5, -122.5, 300)  # a West-Coast speck: 0.3 %
        far_lat = rng.uniform(47.0, 49.0, 300)
        west, _, _, north = framed_box([position_sketch(np.r_[lon, far_lon], np.r_[lat, far_lat])])
        assert west > -99.0 and north < 32.0, (seed, west, north)


def test_two_layers_merge_by_their_points():
    rng = np.random.default_rng(1)
    a = position_sketch(*_body(rng, 50_000))
    b = position_sketch(rng.uniform(-90.0, -89.0, 500), rng.uniform(25.0, 26.0, 500))
    box = framed_box([a, b])
    assert box is not None and -98.0 <= box[0] < -97.5 and -78.5 < box[2] <= -78.0


def test_the_frame_of_mirrored_points_is_mirrored():
    # h175 review F1: the upper tail was judged with the lower edge already extended, so a
    # near lower tail widened the gap allowed above (east 1.3 framed, 1.15 mirrored)
    rng = np.random.default_rng(0)
    core = rng.uniform(0.0, 1.0, 100_000)
    low_tail = np.linspace(-0.24, 0.0, 600)  # within NEAR_TAIL: shown whole
    high = np.r_[np.linspace(1.0, 1.15, 150), np.linspace(1.265, 1.30, 50)]  # gap 0.115
    lon = np.r_[core, low_tail, high]
    lat = rng.uniform(0.0, 1.0, len(lon))
    w, _, e, _ = framed_box([position_sketch(lon, lat)])
    mw, _, me, _ = framed_box([position_sketch(-lon, lat)])
    assert (-me, -mw) == pytest.approx((w, e), abs=1e-9)
