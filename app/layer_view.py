"""What the window needs to show a layer, prepared off the GUI thread.

:func:`prepare_view` is pure (numpy/pandas, no Qt) and runs in the worker right after a
layer's points are made: the batch table's summary, each track's row range (so selecting
a track is a slice, not a scan of a million rows), the maneuver points, and the arrays
the map draws. The GUI thread only swaps the finished :class:`LayerView` in.
"""

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from wakeline.app.models import batch_summary, display_text
from wakeline.core.tracks import sort_points, track_index

DRAW_STYLE = {  # kind -> (symbols, line width); maneuver layers draw their turning points
    "source": (True, 1.3),
    "compressed": (True, 2.5),
    "fused": (False, 2.5),
    "maneuvers": (True, 0.0),
}


def maneuver_table(points: pd.DataFrame) -> pd.DataFrame | None:
    """Maneuver points of a layer that carries ``is_maneuver`` (else None)."""
    if "is_maneuver" not in points.columns:
        return None
    hit = points["is_maneuver"].to_numpy(dtype=bool)
    out = points.loc[hit, ["sensor", "batch", "time", "lon", "lat"]].copy()
    out["factor"] = points.loc[hit, "maneuver_factor"].to_numpy()
    return out.reset_index(drop=True)


@dataclass
class LayerView:
    """A layer's prepared view: sorted points, summary, track ranges, draw arrays."""

    points: pd.DataFrame  # sorted by sensor, batch, time
    summary: pd.DataFrame
    ranges: dict[tuple[str, str], tuple[int, int]]  # (sensor, batch) -> [start, end) rows
    maneuvers: pd.DataFrame | None
    draw: object = None  # the map's prepared arrays (see map_canvas)
    text: dict = field(default_factory=dict)  # the batch table's display columns
    extra: dict = field(default_factory=dict)

    def track_rows(self, keys: list[tuple[str, str]]) -> np.ndarray:
        """Row numbers of the tracks ``keys`` (empty when none is known)."""
        parts = [np.arange(*self.ranges[k]) for k in keys if k in self.ranges]
        return np.concatenate(parts) if parts else np.zeros(0, dtype="int64")

    def tracks(self, keys: list[tuple[str, str]]) -> pd.DataFrame:
        return self.points.iloc[self.track_rows(keys)]


def prepare_view(points: pd.DataFrame, kind: str, color: str) -> LayerView:
    """Everything the window shows of a layer; pure, for a worker thread."""
    from wakeline.app.map_canvas import prepare_draw

    pts = sort_points(points)
    index = track_index(pts)
    # Only the first row of each track becomes Python text (a million-row column turned
    # into objects would hold the GIL, and so the GUI thread, for a second).
    sensors = pts["sensor"].iloc[index.starts].astype(str).to_numpy()
    batches = pts["batch"].iloc[index.starts].astype(str).to_numpy()
    ranges = {
        (s, b): (int(a), int(e))
        for s, b, a, e in zip(sensors, batches, index.starts, index.ends, strict=True)
    }
    marks = maneuver_table(pts)
    summary = batch_summary(pts, marks if kind == "maneuvers" else None)
    symbols, width = DRAW_STYLE.get(kind, (False, 1.3))
    drawn = marks if kind == "maneuvers" and marks is not None else pts
    draw = prepare_draw(drawn, color, by_sensor=kind == "source", symbols=symbols, width=width)
    return LayerView(pts, summary, ranges, marks, draw, display_text(summary))
