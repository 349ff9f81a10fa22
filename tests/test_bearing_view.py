"""The bearing view (pytest-qt, offscreen): bearing lines on the map, detections table."""

import numpy as np
import pandas as pd
import pytest

pytest.importorskip("pytestqt")
from wakeline.app.bearing_view import BearingView, bearing_line_points  # noqa: E402
from wakeline.core import geo  # noqa: E402
from wakeline.core.bearing import detect_with_report  # noqa: E402
from wakeline.core.bearing_eval import simulate_table  # noqa: E402

pytestmark = pytest.mark.gui


def test_bearing_lines_start_at_the_observer_and_point_along_the_bearing():
    df = simulate_table(seed=3)
    lines = bearing_line_points(df, 10_000.0, max_lines=5)
    assert lines["batch"].nunique() == 5 * df["batch"].nunique()
    start, end = lines.iloc[0::2], lines.iloc[1::2]
    assert np.isin(start["lon"].round(7), df["obs_lon"].round(7)).all()
    dist = geo.haversine_m(
        start.lon.to_numpy(), start.lat.to_numpy(), end.lon.to_numpy(), end.lat.to_numpy()
    )
    assert np.allclose(dist, 10_000.0, rtol=0.01)
    az = geo.initial_bearing_deg(
        start.lon.to_numpy(), start.lat.to_numpy(), end.lon.to_numpy(), end.lat.to_numpy()
    )
    merged = start.assign(az=az).merge(
        df[["batch", "time", "bearing"]].rename(columns={"batch": "b"}),
        left_on="time",
        right_on="time",
    )
    merged = merged[merged["batch"].str.split("#").str[0] == merged["b"]]
    assert len(merged) and np.abs(geo.angle_diff(merged["az"], merged["bearing"])).max() < 0.5
    assert bearing_line_points(df.drop(columns=["obs_lon", "obs_lat"])).empty


def test_view_shows_lines_and_exports_detections(qtbot, tmp_path):
    df = simulate_table(seed=4)
    df = df[df.batch.isin(["s2-m", "s4-straight"])]
    table, report = detect_with_report(df)
    view = BearingView()
    qtbot.addWidget(view)
    view.show_result(df, table, report)
    assert {"observer", "bearing lines"} <= set(view.map.layer_names())
    assert ("maneuvers" in view.map.layer_names()) == (len(table) > 0)
    assert view.model.rowCount() == len(table)
    assert "windows tested" in view.log.toPlainText()
    out = tmp_path / "d.csv"
    view.export(out)
    back = pd.read_csv(out)
    assert list(back.columns) == ["batch", "detect_time", "maneuver_time", "z"]
    assert len(back) == len(table)
    view.model.sort(3)  # sort by z
    assert view.model.rowCount() == len(table)
