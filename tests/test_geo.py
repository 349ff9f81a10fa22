import numpy as np
import pytest

from wakeline.core import geo


def test_haversine_one_degree_of_latitude():
    assert geo.haversine_m(0, 0, 0, 1) == pytest.approx(111_194.9, abs=0.5)


def test_haversine_across_the_antimeridian_is_short():
    # 0.2° of longitude at the equator, not 359.8°
    assert geo.haversine_m(179.9, 0, -179.9, 0) == pytest.approx(22_239, rel=1e-3)


@pytest.mark.parametrize(
    ("lon2", "lat2", "expected"),
    [(0, 1, 0.0), (1, 0, 90.0), (0, -1, 180.0), (-1, 0, 270.0)],
)
def test_bearing_cardinal(lon2, lat2, expected):
    assert geo.initial_bearing_deg(0, 0, lon2, lat2) == pytest.approx(expected, abs=1e-9)


def test_bearing_across_the_antimeridian():
    assert geo.initial_bearing_deg(179.95, 10, -179.95, 10) == pytest.approx(90.0, abs=0.01)
    assert geo.initial_bearing_deg(-179.95, 10, 179.95, 10) == pytest.approx(270.0, abs=0.01)


def test_wrap_and_angle_diff():
    assert geo.wrap360(-10) == pytest.approx(350)
    assert geo.wrap360(-1e-17) == 0.0
    assert geo.wrap180(190) == pytest.approx(-170)
    assert geo.angle_diff(350, 10) == pytest.approx(20)
    assert geo.angle_diff(10, 350) == pytest.approx(20)


def test_local_plane_round_trip_across_the_antimeridian():
    lon = np.array([179.8, 179.95, -179.9, -179.7])
    lat = np.array([-16.0, -16.1, -16.2, -16.3])
    x, y = geo.to_local(lon, lat, 180.0, -16.15)
    assert np.all(np.diff(x) > 0)  # eastward, continuous
    back_lon, back_lat = geo.from_local(x, y, 180.0, -16.15)
    assert np.allclose(geo.wrap180(back_lon - lon), 0, atol=1e-9)
    assert np.allclose(back_lat, lat)
    # local distances agree with great-circle distances to well under 1 %
    d_local = np.hypot(np.diff(x), np.diff(y))
    d_gc = geo.haversine_m(lon[:-1], lat[:-1], lon[1:], lat[1:])
    assert np.allclose(d_local, d_gc, rtol=2e-3)


def test_destination_inverts_distance_and_bearing():
    lon, lat = geo.destination(179.99, 45.0, 75.0, 10_000.0)
    assert geo.haversine_m(179.99, 45.0, lon, lat) == pytest.approx(10_000.0, rel=1e-9)
    assert geo.initial_bearing_deg(179.99, 45.0, lon, lat) == pytest.approx(75.0, abs=1e-6)
    assert lon < 0  # crossed to the western hemisphere


def test_circular_mean():
    assert geo.circular_mean_deg(np.array([350.0, 10.0])) == pytest.approx(0.0, abs=1e-9)
    assert abs(geo.circular_mean_deg(np.array([179.0, -179.0]))) == pytest.approx(180.0)


def test_short_legs_agree_with_great_circle():
    rng = np.random.default_rng(0)
    lon1 = rng.uniform(-180, 180, 1000)
    lat1 = rng.uniform(-70, 70, 1000)
    lon2, lat2 = geo.destination(
        lon1, lat1, rng.uniform(0, 360, 1000), rng.uniform(1, 50_000, 1000)
    )
    dist, course = geo.short_legs(lon1, lat1, lon2, lat2)
    assert np.allclose(dist, geo.haversine_m(lon1, lat1, lon2, lat2), rtol=1e-3)
    assert np.all(geo.angle_diff(course, geo.initial_bearing_deg(lon1, lat1, lon2, lat2)) < 0.5)
    d, c = geo.short_legs(179.99, 0.0, -179.99, 0.0)
    assert d == pytest.approx(2224, rel=1e-3) and c == pytest.approx(90.0)


# -- the local plane at any latitude (tests/test_geometry_invariance.py: real scenes) -----


@pytest.mark.parametrize("lat0", [0.0, 37.5, 72.0, -60.0, 85.0])
def test_local_plane_keeps_distance_and_azimuth_from_its_origin_at_any_latitude(lat0):
    rng = np.random.default_rng(1)
    n = 500
    brg = rng.uniform(0, 360, n)
    dist = rng.uniform(0, 200_000, n)
    lon, lat = geo.destination(179.5, lat0, brg, dist)  # across 180° too
    x, y = geo.to_local(lon, lat, 179.5, lat0)
    np.testing.assert_allclose(np.hypot(x, y), dist, rtol=1e-9, atol=1e-6)
    assert geo.angle_diff(np.degrees(np.arctan2(x, y)), brg)[dist > 1].max() < 1e-7
    back_lon, back_lat = geo.from_local(x, y, 179.5, lat0)
    assert geo.haversine_m(lon, lat, back_lon, back_lat).max() < 1e-6
    # a 20 km step 50 km north of the origin: its length in the plane within 0.01 %
    # (the equirectangular plane about lat0 had it off by tan(lat0) x 0.45°: 2.5 % at 72°)
    a = geo.destination(179.5, lat0, 0.0, 50_000.0)
    b = geo.destination(*a, 90.0, 20_000.0)
    xa, ya = geo.to_local(*a, 179.5, lat0)
    xb, yb = geo.to_local(*b, 179.5, lat0)
    assert np.hypot(xb - xa, yb - ya) == pytest.approx(20_000.0, rel=1e-4)


def test_local_plane_of_scalars_and_its_origin():
    assert geo.to_local(10.0, 50.0, 10.0, 50.0) == (0.0, 0.0)
    x, y = geo.to_local(np.array([[10.0, 10.01]]), np.array([[50.0, 50.0]]), 10.0, 50.0)
    assert x.shape == (1, 2) and x[0, 0] == 0.0 and x[0, 1] > 700.0


def test_centre_of_points_across_the_antimeridian_and_with_gaps():
    lon = np.array([179.9, -179.9, np.nan, 179.8])
    lat = np.array([60.0, 60.2, 61.0, 60.1])
    c_lon, c_lat = geo.centre_deg(lon, lat)
    assert abs(geo.wrap180(c_lon - 179.933)) < 0.01 and 60.0 < c_lat < 60.2
    assert np.isnan(geo.centre_deg(np.array([np.nan]), np.array([1.0]))[0])


def test_plane_turn_carries_a_direction_into_another_origins_plane():
    lon0, lat0 = 10.0, 72.0
    lon, lat = 11.0, 72.2  # 35 km away: the meridians converge by ~0.95°
    a = geo.destination(lon, lat, 37.0, 50.0)
    x1, y1 = geo.to_local(lon, lat, lon0, lat0)
    x2, y2 = geo.to_local(*a, lon0, lat0)
    in_plane = np.degrees(np.arctan2(x2 - x1, y2 - y1))
    s, c = geo.plane_turn(lon, lat, lon0, lat0)
    assert abs(in_plane - 37.0) > 0.9  # east/north taken as they are: a degree off
    assert 37.0 + np.degrees(np.arctan2(s, c)) == pytest.approx(in_plane, abs=1e-3)
    vx, vy = geo.turn_into_plane(np.sin(np.radians(37.0)), np.cos(np.radians(37.0)), (s, c))
    assert np.degrees(np.arctan2(vx, vy)) == pytest.approx(in_plane, abs=1e-3)
    assert geo.plane_turn(lon0, lat0, lon0, lat0) == (0.0, 1.0)
