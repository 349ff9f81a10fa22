"""The background coastline as a map geometry (each NaN-separated line a track)."""

import numpy as np

from wakeline.app.map_draw import LayerGeometry


def coastline_draw(lon: np.ndarray, lat: np.ndarray) -> LayerGeometry:
    """A NaN-separated coastline as a geometry (each line a track) for the same LOD."""
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
