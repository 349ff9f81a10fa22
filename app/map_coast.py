"""The background coastline as a map geometry (each NaN-separated line a track)."""

import numpy as np

from wakeline.app.map_draw import LayerGeometry


def coastline_draw(lon: np.ndarray, lat: np.ndarray) -> LayerGeometry:
    """A NaN-separated coastline as a geometry (each line a track) for the same LOD.

    Every line reaching west of 0° is drawn a second time one turn east (+360°), so the
    coast is there under a layer drawn in [0, 360) (a scene across the antimeridian,
    :func:`wakeline.core.geo.lon_band_west`) as under one in [-180, 180)."""
    lon, lat = _with_east_copy(np.asarray(lon, dtype="float64"), np.asarray(lat, dtype="float64"))
    finite = np.isfinite(lon) & np.isfinite(lat)
    idx = np.flatnonzero(finite)
    if len(idx) == 0:
        empty = np.zeros(0)
        ei = np.zeros(0, dtype="int64")
        return LayerGeometry(
            empty, empty, ei, ei, ei, np.zeros(0, object), np.zeros(0, object), empty, empty,
            ei, ("coast",), ("#8a8a8a",), False,
        )  # fmt: skip
    start = np.ones(len(idx), dtype=bool)
    start[1:] = np.diff(idx) > 1
    starts = np.flatnonzero(start)
    ends = np.append(starts[1:], len(idx))
    track = np.cumsum(start) - 1
    zeros = np.zeros(len(idx))
    return LayerGeometry(
        lon=lon[idx].astype("float64"),
        lat=lat[idx].astype("float64"),
        starts=starts,
        ends=ends,
        track=track,
        sensor=np.full(len(starts), "coast", dtype=object),
        batch=np.arange(len(starts)).astype(str).astype(object),
        time_s=zeros,
        speed_kn=zeros,
        group=np.zeros(len(starts), dtype="int64"),
        labels=("coast",),
        colors=("#8a8a8a",),
        relative=False,
    )


def _with_east_copy(lon: np.ndarray, lat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``lon``/``lat`` (NaN-separated lines) followed by a copy, 360° east, of the lines
    with a point west of 0°."""
    if len(lon) == 0:
        return lon, lat
    finite = np.isfinite(lon) & np.isfinite(lat)
    line = np.cumsum(~finite)  # a line's points share the count of the NaNs before them
    west = np.bincount(line, weights=(finite & (lon < 0)).astype("float64")) > 0
    copy = finite & west[line]
    nan = np.array([np.nan])
    return (
        np.concatenate([lon, nan, np.where(copy, lon + 360.0, np.nan)]),
        np.concatenate([lat, nan, np.where(copy, lat, np.nan)]),
    )
