"""Real camera bearings (Autoferry, CC0, read from ../shared): EO bearings gated to each
target by its GNSS truth bearing (within 3 deg, one per scan). With the defaults every
sequence is reported with why nothing could be tested (the series are shorter than the
windows, or the ferry maneuvers); with 40 s / 12 s windows the detector runs and stays sane.
This is a harbour at a few hundred metres, far from the 10-30 km the detector is built
for; the test checks that it runs and stays sane, the figures go to docs/evaluation.md."""

import numpy as np
import pandas as pd
import pytest

from conftest import real_file
from wakeline.core import geo
from wakeline.core.bearing import (
    BearingParams,
    detect_sequence,
    detect_with_report,
    observer_maneuvering,
    statistic,
)

pytestmark = pytest.mark.real
ORIGIN = (10.39908278, 63.4389029083)  # the dataset's local NED origin, lon/lat


def gated_sequences(gate_deg: float = 3.0):
    det = pd.read_csv(real_file("autoferry-fusion", "detections.csv.gz"))
    truth = pd.read_csv(real_file("autoferry-fusion", "ground_truth.csv.gz"))
    det = det[(det.sensor == "eo") & det.bearing_rad.notna()]
    truth = truth.drop_duplicates(["scenario", "target_id", "time"]).sort_values("time")
    for (scenario, target), tr in truth.groupby(["scenario", "target_id"]):
        d = det[det.scenario == scenario]
        north = np.interp(d.time, tr.time, tr.north)
        east = np.interp(d.time, tr.time, tr.east)
        true_b = np.degrees(np.arctan2(east - d.own_east, north - d.own_north))
        b = np.degrees(d.bearing_rad.to_numpy())
        err = geo.angle_diff(b, true_b)
        seq = d.assign(bearing=b % 360.0, err=err)[err < gate_deg]
        seq = seq.sort_values("err").drop_duplicates("time").sort_values("time")
        yield scenario, target, seq, tr


def truth_turned(tr: pd.DataFrame, t0: float, t1: float, turn_deg: float = 20.0) -> bool:
    """Whether the GNSS truth changes course by ``turn_deg`` within 10 s in [t0, t1]."""
    tr = tr.drop_duplicates("time")
    grid = np.arange(max(t0 - 10.0, tr.time.min()), min(t1, tr.time.max()), 1.0)
    if len(grid) < 12:
        return False
    n, e = np.interp(grid, tr.time, tr.north), np.interp(grid, tr.time, tr.east)
    course = np.degrees(np.unwrap(np.arctan2(np.gradient(e), np.gradient(n))))
    return bool((np.abs(course[10:] - course[:-10]) >= turn_deg).any())


def test_detector_runs_on_real_camera_bearings():
    rows = []
    for scenario, target, seq, tr in gated_sequences():
        if len(seq) < 100:
            continue
        t = seq.time.to_numpy()
        params = BearingParams(window_x_s=40.0, min_window_x_s=40.0, window_y_s=24.0)
        olon, olat = geo.from_local(seq.own_east.to_numpy(), seq.own_north.to_numpy(), *ORIGIN)
        excluded = observer_maneuvering(t, olon, olat, params.observer_dv_ms)
        st = statistic(t, seq.bearing.to_numpy(), params, excluded)
        hits = detect_sequence(t, seq.bearing.to_numpy(), params, excluded)
        for h in hits:
            # the maneuver time is refined over the whole run of rejections, which may
            # outlast the first alarm
            assert t[0] <= h.maneuver_time_s <= t[-1] and t[0] <= h.detect_time_s <= t[-1]
        turned = len(st.z) and truth_turned(
            tr, st.boundary_t.min(), st.boundary_t.max() + params.window_y_s
        )
        rows.append((scenario, target, len(seq), len(st.z), bool(turned), len(hits)))
    print(rows)
    assert len(rows) >= 15  # 9 scenarios x 2 targets, bar the ones with too few gated bearings
    # a boat that truly turns by 20 deg within 10 s while windows are tested is detected
    assert all(hits > 0 for *_, turned, hits in rows if turned)


def test_defaults_say_why_on_real_camera_bearings():
    frames = []
    for scenario, target, seq, _ in gated_sequences():
        lon, lat = geo.from_local(seq.own_east.to_numpy(), seq.own_north.to_numpy(), *ORIGIN)
        frames.append(
            pd.DataFrame(
                {
                    "batch": f"{scenario}-{target}",
                    "time": pd.to_datetime(seq.time.to_numpy(), unit="s", utc=True),
                    "bearing": seq.bearing.to_numpy(),
                    "obs_lon": lon,
                    "obs_lat": lat,
                }
            )
        )
    table, report = detect_with_report(pd.concat(frames, ignore_index=True))
    assert len(report) >= 15
    for r in report:
        if r["tested"] == 0:  # nothing tested: the report says why
            assert r["too_short"] or sum(r["excluded"].values()) == r["windows"]
    print([(r["batch"], r["samples"], r["tested"], r["too_short"], r["excluded"]) for r in report])


def test_fit_windows_test_every_real_camera_sequence_and_fixed_ones_say_why():
    """The 18 gated EO sequences (60-152 s): the fixed windows test none and the report
    names the fit option; windows="fit" tests every one (the detections it makes are
    mostly not maneuvers: bench/bearing_real.py, docs/evaluation.md)."""
    from wakeline.core.real_sets import autoferry_bearings

    folder = real_file("autoferry-fusion", "detections.csv.gz").parent
    bearings, _ = autoferry_bearings(folder)
    bearings = bearings.drop(columns="truth_bearing")
    _, report = detect_with_report(bearings)
    assert len(report) == 18
    assert all(r["tested"] == 0 and "windows=fit" in r["too_short"] for r in report)
    _, report = detect_with_report(bearings, BearingParams(windows="fit"))
    assert all(r["tested"] > 0 and r["window_rule"].startswith("fit") for r in report)
    assert all(
        r["x_s"] == pytest.approx(max(30.0, 0.4 * r["duration_s"]), abs=0.06) for r in report
    )
