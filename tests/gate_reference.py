"""Gating bearings on tracks as core/bearing_read.py did before h167 (frozen reference
copy): every track against every bearing. tests/test_gate_by_time.py checks the
vectorized-by-time gate gives the same table and report; bench/bench_gate.py times both.
"""

import numpy as np
import pandas as pd

from wakeline.core.errors import InputError


def gate_to_tracks(
    bearings: pd.DataFrame, tracks: pd.DataFrame, gate_deg: float = 3.0, max_gap_s: float = 10.0
) -> tuple[pd.DataFrame, dict]:
    """One target's sequence per series and track, from bearings of several targets in one
    series (a camera's detections): a bearing goes to a track (``batch, time, lon, lat``:
    GNSS truth, AIS) when the track's bearing from the observer at that time lies within
    ``gate_deg``; per series, track and time the nearest one is kept (the rule of
    :func:`~wakeline.core.real_sets.autoferry_bearings`, which gates on the Autoferry
    truth). The track is interpolated between fixes at most ``max_gap_s`` apart (outside
    its span, or in a longer gap, it takes no bearing). New series ``SERIES/TRACK``, with
    ``track_bearing`` (degrees) beside; bearings no track is near are left out and counted.
    Returns the table and ``{"gate_deg", "tracks", "bearings_in", "kept", "series",
    "no_track", "in_two"}``."""
    from wakeline.core import geo
    from wakeline.core.schema import time_seconds

    if not {"obs_lon", "obs_lat"} <= set(bearings.columns):
        raise InputError(
            "gating bearings on tracks needs the observer's positions (obs_lon/obs_lat, "
            "or obs_east/obs_north with --origin)"
        )
    t = time_seconds(bearings["time"])
    olon = bearings["obs_lon"].to_numpy(dtype="float64")
    olat = bearings["obs_lat"].to_numpy(dtype="float64")
    b = bearings["bearing"].to_numpy(dtype="float64")
    rows, names, errs, truth = [], [], [], []
    tracks = tracks.sort_values(["batch", "time"], kind="stable")
    for name, tr in tracks.groupby("batch", sort=True):  # per track, all bearings at once
        tt = time_seconds(tr["time"])
        keep = np.concatenate([[True], np.diff(tt) > 0])  # one fix per time
        tt = tt[keep]
        if len(tt) < 2:
            continue
        lon = tr["lon"].to_numpy(dtype="float64")[keep]
        lat = tr["lat"].to_numpy(dtype="float64")[keep]
        k = np.clip(np.searchsorted(tt, t), 1, len(tt) - 1)
        inside = (t >= tt[0]) & (t <= tt[-1]) & (tt[k] - tt[k - 1] <= max_gap_s)
        plon, plat = np.interp(t, tt, lon), np.interp(t, tt, lat)
        true_b = geo.initial_bearing_deg(olon, olat, plon, plat)
        err = np.abs(geo.angle_diff(b, true_b))
        hit = np.flatnonzero(inside & (err < gate_deg) & np.isfinite(olon) & np.isfinite(olat))
        rows.append(hit)
        names.append(np.full(len(hit), str(name), dtype=object))
        errs.append(err[hit])
        truth.append(true_b[hit] % 360.0)
    cat = lambda xs, dtype: np.concatenate(xs) if xs else np.zeros(0, dtype)  # noqa: E731
    row, track = cat(rows, "int64"), cat(names, object)
    cand = pd.DataFrame(
        {
            "row": row,
            "track": track,
            "err": cat(errs, "float64"),
            "track_bearing": cat(truth, "float64"),
            "series": bearings["batch"].to_numpy()[row],
            "t": t[row],
        }
    )
    cand = cand.sort_values(["err", "row"], kind="stable").drop_duplicates(["series", "track", "t"])
    cand = cand.sort_values(["series", "track", "t"], kind="stable")
    out = bearings.iloc[cand["row"].to_numpy()].reset_index(drop=True)
    out["batch"] = (cand["series"].astype(str) + "/" + cand["track"].astype(str)).to_numpy()
    out["track_bearing"] = cand["track_bearing"].to_numpy()
    used = cand["row"].value_counts()
    report = {
        "gate_deg": float(gate_deg),
        "tracks": int(tracks["batch"].nunique()),
        "bearings_in": int(len(bearings)),
        "kept": int(len(out)),
        "series": int(out["batch"].nunique()),
        "no_track": int(len(bearings) - len(used)),
        "in_two": int((used > 1).sum()),
    }
    return out, report
