"""The grown at-rest radius capped (session 28, h195; docs/prereg/session28_at_rest_noise_b.md):
``ManeuverParams.rest_noise_cap_m``.

``rest_noise_sigmas`` grows the at-rest radius to c sigma per track (h193), which holds a
moored ship seen with 15-20 m of noise at 1 s, but on a sparse noisy track (seed 000: plots
every 5 min at 600 m per axis, 16 kn) c sigma = 3 km over a 300 s window takes the moving
ship as at rest. With the noise's share at most ``rest_noise_cap_m`` metres (100 m, the
default with c 5) the berth is still at rest and the sparse moving ship is as with the
rule off, bit for bit.
"""

import numpy as np
import pandas as pd
import pytest
from test_at_rest_noise import MOOR_S, _berth, moored_then_moving

from wakeline.core import geo
from wakeline.core.errors import InputError
from wakeline.core.maneuver import ManeuverParams, detect

OFF = ManeuverParams(rest_noise_sigmas=0.0)
UNCAPPED = ManeuverParams(rest_noise_sigmas=5.0, rest_noise_cap_m=0.0)
CAPPED = ManeuverParams(rest_noise_sigmas=5.0, rest_noise_cap_m=100.0)


def sparse_noisy_moving(seed: int, sigma: float = 600.0, n: int = 60):
    """Seed 000's kind of track: a plot every 300 s, 16 kn, a 90 deg turn half way, white
    noise sigma per axis."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 300.0
    c = np.radians(rng.uniform(0, 360) + np.where(np.arange(n) >= n // 2, 90.0, 0.0))
    v = 16 * geo.KN_MS
    x = np.cumsum(v * np.sin(c) * 300.0) + rng.normal(0, sigma, n)
    y = np.cumsum(v * np.cos(c) * 300.0) + rng.normal(0, sigma, n)
    lon, lat = geo.from_local(x, y, 11.0, 57.0)
    return pd.DataFrame(
        {
            "sensor": "RADAR",
            "batch": f"p{seed}",
            "time": pd.to_datetime(1.6e9 + t, unit="s", utc=True),
            "lon": lon,
            "lat": lat,
        }
    )


def test_default_is_capped_c5():
    d = ManeuverParams()
    assert d.rest_noise_sigmas == 5.0 and d.rest_noise_cap_m == 100.0


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_sparse_noisy_moving_ship_not_at_rest(seed):
    pts = sparse_noisy_moving(seed)
    off, uncapped, capped = (detect(pts, p) for p in (OFF, UNCAPPED, CAPPED))
    # uncapped (h193): the moving ship is mostly at rest, its turns gone
    assert uncapped.at_rest.mean() > 0.5
    # capped: 5 sigma / f is capped at 100 m / (300/180) = 60 m < f * 50 m = 83 m, so the
    # rule is as off, bit for bit
    assert np.array_equal(off.at_rest, capped.at_rest)
    assert np.array_equal(off.is_maneuver, capped.is_maneuver)
    assert np.array_equal(off.factor, capped.factor, equal_nan=True)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_moored_noisy_ship_still_at_rest(seed):
    pts, _ = moored_then_moving(seed, sigma=20.0)
    berth = _berth(pts)
    capped = detect(pts, CAPPED)
    assert capped.at_rest[berth].mean() > 0.95
    assert capped.is_maneuver[berth].sum() == 0
    # 10 kn is far above 2 * 100 m / 180 s: not at rest past the departure's first window
    t = pts["time"].astype("int64").to_numpy() / 1e9
    assert not capped.at_rest[(t - t.min()) > MOOR_S + 180.0].any()


@pytest.mark.parametrize("seed", [0, 1])
def test_cap_binds_on_a_very_noisy_berth(seed):
    # 40 m of noise: 5 sigma = 200 m, capped at 100 m; the at-rest share lies between off's
    # and uncapped's (the cap is a real bound, not a no-op)
    pts, _ = moored_then_moving(seed, sigma=40.0)
    berth = _berth(pts)
    shares = [detect(pts, p).at_rest[berth].mean() for p in (OFF, CAPPED, UNCAPPED)]
    assert shares[0] <= shares[1] <= shares[2]
    assert shares[1] < shares[2]


@pytest.mark.parametrize("bad", [-1.0, 1e5 + 1, float("nan")])
def test_validation(bad):
    with pytest.raises(InputError, match="rest_noise_cap_m"):
        ManeuverParams(rest_noise_cap_m=bad).checked()
