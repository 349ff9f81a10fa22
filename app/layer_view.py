"""What the window needs to show a layer, prepared off the GUI thread.

:func:`prepare_view` is pure (numpy/pandas, no Qt) and runs in the worker right after a
layer's points are made: the batch table's summary, each track's row range (so selecting
a track is a slice, not a scan of a million rows), the maneuver points, and the arrays
the map draws. The GUI thread only swaps the finished :class:`LayerView` in.
"""

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from wakeline.app.map_frame import PositionSketch, framed_box, position_sketch
from wakeline.app.models import batch_summary, display_text, table_index
from wakeline.core import geo
from wakeline.core.geo import EARTH_RADIUS_M
from wakeline.core.tracks import sort_points, track_index

DRAW_STYLE = {  # kind -> (symbol size px, line width px); maneuver layers draw their turns
    "source": (3, 1.3),
    "compressed": (3, 2.5),
    "fused": (0, 2.5),
    "maneuvers": (8, 0.0),
}
#: The map's drawing choices the worker reads when it prepares a layer (the window sets
#: them from its settings: View menu).
MAP_OPTIONS = {"plots_as_points": True}


def looks_like_plots(points: pd.DataFrame, summary: pd.DataFrame | None = None) -> bool:
    """Whether most tracks of ``points`` (sorted) are radar plots, not ships' tracks:
    the parameter guidance's test (:func:`wakeline.core.tracks.plot_like`), by points.
    ``summary``: the points' track summary when the caller has it (no second one made)."""
    from wakeline.core.schema import time_seconds
    from wakeline.core.tracks import PLOT_MIN_INTERVAL_S, PLOT_MIN_SHARED_ROWS, track_summary

    if len(points) == 0:
        return False
    if summary is not None:
        return _mostly_plots(summary)
    # A quick no first (numpy over the sorted rows): plots need rows sharing their time
    # or steps under a second on average; counted with repeated rows in, both only
    # over-count, so no plots are missed. A million AIS points: ~40 ms, not ~400.
    index = track_index(points)
    t = time_seconds(points["time"])
    same = np.zeros(len(t), dtype=bool)
    same[1:] = t[1:] == t[:-1]
    same[index.starts] = False
    shared = np.add.reduceat(same.astype("int64"), index.starts) if len(t) else same
    sizes = index.ends - index.starts
    with np.errstate(divide="ignore", invalid="ignore"):
        span = (t[index.ends - 1] - t[index.starts]) / np.maximum(sizes - 1, 1)
    # a run of k rows at one time counts k - 1 here, at least half of its k
    maybe = (sizes > 1) & ((2 * shared >= PLOT_MIN_SHARED_ROWS) | (span < PLOT_MIN_INTERVAL_S))
    if not maybe.any():
        return False
    return _mostly_plots(track_summary(points))


def _mostly_plots(summary: pd.DataFrame) -> bool:
    """Whether the tracks :func:`~wakeline.core.tracks.plot_like` calls plots hold more
    than half of ``summary``'s points."""
    from wakeline.core.tracks import plot_like

    like = plot_like(summary)
    if not like.any():
        return False
    n = summary["points"].to_numpy(dtype="float64")
    return bool(n[like].sum() * 2 > n.sum())


#: Stacking of a kind over the others (higher on top; equal: the later layer): the
#: maneuver marks stay above the compressed and fused lines drawn through them.
DRAW_Z = {"maneuvers": 2.0}


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

    @property
    def colors(self) -> tuple[str, ...]:
        """The colours the map draws the layer in (one per sensor of a source layer)."""
        if self.draw is None:
            return ()
        geom = self.draw.geometry
        # drawn one colour per track (the active layer): the layer's own colours still
        return tuple(geom.plain[1] if geom.plain is not None else geom.colors)

    def track_rows(self, keys: list[tuple[str, str]]) -> np.ndarray:
        """Row numbers of the tracks ``keys`` (empty when none is known)."""
        parts = [np.arange(*self.ranges[k]) for k in keys if k in self.ranges]
        return np.concatenate(parts) if parts else np.zeros(0, dtype="int64")

    def tracks(self, keys: list[tuple[str, str]]) -> pd.DataFrame:
        return self.points.iloc[self.track_rows(keys)]


def drawn_lon(points: pd.DataFrame, west: float | None = None) -> np.ndarray:
    """The points' longitudes in the band the map draws them in (``west``; None: the
    points' own, :func:`wakeline.core.geo.lon_band_west`: a scene across 180° in [0, 360))."""
    lon = points["lon"].to_numpy(dtype="float64")
    west = geo.lon_band_west(lon) if west is None else west
    return lon if west == -180.0 else geo.into_band(lon, west)


def points_box(
    points: pd.DataFrame, lon_west: float | None = None
) -> tuple[float, float, float, float] | None:
    """``(west, south, east, north)`` of the finite positions (degrees; longitudes as
    the map draws them, :func:`drawn_lon`), None if none."""
    if len(points) == 0:
        return None
    lon, lat = drawn_lon(points, lon_west), points["lat"].to_numpy(dtype="float64")
    ok = np.isfinite(lon) & np.isfinite(lat)
    if not ok.any():
        return None
    lon, lat = lon[ok], lat[ok]
    return (float(lon.min()), float(lat.min()), float(lon.max()), float(lat.max()))


def points_sketch(points: pd.DataFrame) -> PositionSketch | None:
    """Where the points of a table are (:func:`~wakeline.app.map_frame.position_sketch`;
    longitudes as the map draws them, :func:`drawn_lon`)."""
    if len(points) == 0:
        return None
    return position_sketch(drawn_lon(points), points["lat"].to_numpy())


def framed_range(sketches: list) -> tuple[float, float, float, float] | None:
    """The range (x0, x1, y0, y1, degrees) a first view asks for: where the points of
    ``sketches`` are (:func:`~wakeline.app.map_frame.framed_box`), with a fit's margin."""
    return padded_range([framed_box(sketches)])


#: Smallest margin (m) of a fitted view on each side: a single fix is shown 100 m wide.
#: (It was 0.01°, a kilometre: a 1 km harbour scene filled a fifth of the rendered view's
#: height, 0.20; tests/test_map.py::test_render_frames_a_harbour_scene_closely.)
MIN_PAD_M = 50.0


def padded_range(boxes: list) -> tuple[float, float, float, float] | None:
    """The range (x0, x1, y0, y1, degrees) :meth:`MapCanvas.fit` asks for: the union of
    ``boxes`` (west, south, east, north) with a 5 % margin (at least :data:`MIN_PAD_M`
    metres, in longitude at the box's middle latitude)."""
    boxes = [b for b in boxes if b is not None]
    if not boxes:
        return None
    w, s = min(b[0] for b in boxes), min(b[1] for b in boxes)
    e, n = max(b[2] for b in boxes), max(b[3] for b in boxes)
    min_pad = math.degrees(MIN_PAD_M / EARTH_RADIUS_M)
    cos = max(math.cos(math.radians(0.5 * (s + n))), 0.05)
    pad_x = max((e - w) * 0.05, min_pad / cos)
    pad_y = max((n - s) * 0.05, min_pad)
    return (w - pad_x, e + pad_x, s - pad_y, n + pad_y)


def shown_range(
    target: tuple[float, float, float, float], size_px: tuple[int, int], lat0: float
) -> tuple[float, float, float, float]:
    """The range the map shows when asked for ``target`` on ``size_px`` pixels with the
    true aspect at ``lat0``: pyqtgraph's aspect lock widens one axis (its rule, repeated
    here so a worker can decimate for the view the map will have)."""
    x0, x1, y0, y1 = target
    aspect = max(math.cos(math.radians(lat0)), 0.05)
    tw, th = x1 - x0, y1 - y0
    if th <= 0 or size_px[1] <= 0 or size_px[0] <= 0:
        return target
    target_ratio = tw / th
    view_ratio = (size_px[0] / size_px[1]) / aspect or 1.0
    if target_ratio > view_ratio:
        dy = 0.5 * (tw / view_ratio - th)
        return (x0, x1, y0 - dy, y1 + dy)
    dx = 0.5 * (th * view_ratio - tw)
    return (x0 - dx, x1 + dx, y0, y1)


def plan_view(
    state: dict,
    sketches: list,
    lat0: float | None,
    target: tuple[float, float, float, float] | None = None,
) -> dict | None:
    """The view a job's new layers will be shown in (pure, for the worker): ``state``
    from the window (position sketches of the layers kept, plot size, aspect latitude
    or None), ``sketches`` of the new layers (:func:`points_sketch`), ``lat0`` the aspect
    latitude when none is set yet. The view frames where the points are
    (:func:`framed_range`), or is ``target`` (x0, x1, y0, y1, degrees: a project's saved
    view) when given. Returns ``target`` (the range asked for), ``shown`` (after the
    aspect lock) and ``lat0`` (None: keep the map's), or None when nothing is to be
    shown."""
    if target is None:
        target = framed_range([*state["sketches"], *sketches])
    if target is None:
        return None
    keep = state["lat0"] is not None
    aspect_lat = state["lat0"] if keep else lat0
    if aspect_lat is None or not math.isfinite(aspect_lat):
        aspect_lat = 0.5 * (target[2] + target[3])
    shown = shown_range(target, state["size_px"], aspect_lat)
    return {"target": target, "shown": shown, "lat0": None if keep else aspect_lat}


def fit_view(
    points: pd.DataFrame, lon_west: float | None = None
) -> tuple[float, float, float, float] | None:
    """The view (x0, x1, y0, y1, degrees) that :meth:`MapCanvas.fit` would ask for
    (``lon_west``: the band the points are drawn in, None: theirs)."""
    return padded_range([points_box(points, lon_west)])


def prepare_view(
    points: pd.DataFrame,
    kind: str,
    color: str,
    label: str = "",
    view: tuple[float, float, float, float] | None = None,
    size_px: tuple[int, int] | None = None,
    colors: tuple[str, ...] | None = None,
    previous: "LayerView | None" = None,
) -> LayerView:
    """Everything the window shows of a layer; pure, for a worker thread. ``view`` and
    ``size_px`` (the map's, or None for the data's extent) set the first level of detail.
    ``colors``: a source layer's sensors' colours in turn (default: ``color`` and the
    source colours after it). ``previous``: the layer's view before a change that keeps
    most tracks' rows (a review decision): their summary rows are kept."""
    from wakeline.app.map_draw import LayerStyle, prepare_layer
    from wakeline.app.map_paths import with_paths

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
    before = (previous.points, previous.summary) if previous is not None else None
    summary = batch_summary(pts, marks if kind == "maneuvers" else None, before)
    symbol, width = DRAW_STYLE.get(kind, (0, 1.3))
    drawn = marks if kind == "maneuvers" and marks is not None else pts
    # the band the layer's tracks are drawn in, decided by all its points (the maneuver
    # marks alone may lie on one side of 180°)
    west = geo.lon_band_west(pts["lon"].to_numpy(dtype="float64"))
    if size_px is not None and view is None:
        view = fit_view(drawn, west)
    draw = prepare_layer(
        drawn,
        label or kind,
        color,
        by_sensor=kind == "source",
        style=LayerStyle(
            width=width, symbol_size=symbol, z=DRAW_Z.get(kind, 0.0), gaps=kind != "compressed"
        ),
        view=view if size_px is not None else None,
        size_px=size_px,
        colors=colors,
        kind=kind,
        lon_west=west,
    )
    view = _finish(pts, kind, summary, draw, ranges, marks, previous)
    view.draw = with_paths(view.draw)
    return view


def _finish(pts, kind, summary, draw, ranges, marks, previous) -> LayerView:
    """The view's table text and index, and its plots mark (the draw's paths not made)."""
    if previous is not None and previous.text:  # a decision: the unchanged columns kept
        text = display_text(summary, previous=(previous.summary, previous.text))
    else:
        text = display_text(summary)
    old_index = previous.extra.get("table_index") if previous is not None else None
    if old_index is not None:  # its rows of the tracks kept when the tracks are
        index = table_index(
            summary.reset_index(drop=True), text, previous=(previous.text, old_index)
        )
    else:
        index = table_index(summary.reset_index(drop=True), text)
    extra = {"table_index": index}
    if kind != "maneuvers" and looks_like_plots(pts, summary):
        # radar plots (the guidance's test): dots by default, no line joins a scan's
        # detections (View ▸ Draw active layer as points turns it off or on)
        extra["plots"] = True
        if MAP_OPTIONS.get("plots_as_points", True):
            from wakeline.app.map_draw import as_points

            draw = as_points(draw, True)
    return LayerView(pts, summary, ranges, marks, draw, text, extra)


#: A decision's lines are made again alone (:func:`relabel_view`) while they hold at most
#: this share of the layer's points; beyond it the whole view is made (a first decision
#: after a bind relabels every track: the engine's targets become the review's).
RELABEL_MAX_SHARE = 0.5


def relabel_view(
    previous: LayerView,
    points: pd.DataFrame,
    targets: np.ndarray,
    kind: str,
    view: tuple[float, float, float, float] | None = None,
    size_px: tuple[int, int] | None = None,
) -> LayerView | None:
    """:func:`prepare_view` of ``points`` — ``previous.points`` with new targets (a review
    decision: ``targets`` per track, text, in the tracks' order) — made from ``previous``:
    only the lines of the targets the decision changes are sorted, unwrapped and broken at
    gaps again (:mod:`wakeline.core.line_splice`), the untouched ones copied as blocks; the
    hover tree kept (the positions are the same, in another order); the summary's target
    and status set for the tracks moved. The same view as :func:`prepare_view` makes
    (tests/test_review_relabel_view.py). None where it does not apply (then make the whole
    view): a layer not drawn one line per target (not ``associated``), other columns or
    rows than ``previous``'s, no target changed, lines holding more than
    :data:`RELABEL_MAX_SHARE` of the points to make again, targets not in the text order
    the sort leaves, a layer drawn by track colours or as plots since."""
    from wakeline.app.map_draw import (
        DrawData,
        LayerGeometry,
        curves_for,
        drawn_lines,
        layer_geometry,
    )
    from wakeline.app.map_frame import position_sketch
    from wakeline.app.map_paths import with_paths
    from wakeline.core.line_splice import line_rows, splice_lines, touched_targets
    from wakeline.core.tracks import known_order

    draw = previous.draw if previous is not None else None
    if draw is None or kind != "associated" or "target" not in points.columns:
        return None
    old_pts = previous.points
    if len(points) != len(old_pts) or "target" not in old_pts.columns:
        return None
    if list(points.columns) != list(old_pts.columns):
        return None
    geom = draw.geometry
    if geom.plain is not None or geom.point_note is not None or len(geom.colors) != 1:
        return None
    known = known_order(points)
    if known is None or known_order(old_pts) is None or known[0] is not known_order(old_pts)[0]:
        return None  # not the same rows in the same order
    for col in points.columns:  # every other column the previous points' own
        if col != "target" and not _same_values(points[col], old_pts[col]):
            return None
    index = known[0]
    summary_old = previous.summary
    if len(summary_old) != index.n_tracks or len(targets) != index.n_tracks:
        return None
    old_t = summary_old["target"].array
    new_t = pd.array(targets, dtype=old_t.dtype) if not hasattr(targets, "dtype") else targets
    if old_t.dtype != new_t.dtype or pd.isna(old_t).any() or pd.isna(new_t).any():
        return None
    moved = touched_targets(old_t, new_t)
    if not moved.any():
        return None
    tracks = np.flatnonzero(moved)
    rows = line_rows(index.starts, index.ends, tracks)
    if len(rows) > RELABEL_MAX_SHARE * len(points):
        return None
    # the old lines of the touched targets (all sensors), in line order
    hit = set(old_t[tracks].unique().tolist())
    line_target = geom.batch
    drop = np.flatnonzero(pd.Series(line_target).isin(hit).to_numpy())
    old_sizes = geom.ends - geom.starts
    if int(old_sizes[drop].sum()) != len(rows):
        return None
    cols = [c for c in ("sensor", "batch", "time", "lon", "lat", "speed") if c in points.columns]
    part = points[cols].iloc[rows].reset_index(drop=True)
    part["target"] = points["target"].iloc[rows].to_numpy()
    part["_row"] = np.arange(len(rows))
    fresh = layer_geometry(
        drawn_lines(part, kind),
        geom.colors[0],
        relative=geom.relative,
        label=geom.labels[0] if geom.labels else "",
        lon_west=geom.lon_west,
    )
    if geom.gap_break is None:
        fresh = dataclasses.replace(fresh, gap_break=None)
    plan = splice_lines(
        (geom.sensor, geom.batch), old_sizes, drop, (fresh.sensor, fresh.batch),
        fresh.ends - fresh.starts,
    )  # fmt: skip
    if plan is None:
        return None
    # where each moved row was and is: the old lines' rows in order are the part's rows
    # sorted by the old keys (the sort is stable, the part in table order)
    was = _line_order(part.assign(target=old_t.take(np.repeat(tracks, index.sizes[tracks]))), kind)
    now = _line_order(part, kind)
    old_rows = line_rows(geom.starts, geom.ends, drop)
    new_at = np.flatnonzero(np.array([s for s, _a, _b in plan.line_pieces]) == 1)
    new_rows = np.concatenate(
        [np.arange(*_piece_rows(plan, k)) for k in new_at]
    ) if len(new_at) else np.zeros(0, dtype="int64")  # fmt: skip
    if len(was) != len(rows) or len(now) != len(rows) or len(new_rows) != len(rows):
        return None
    src = np.empty(len(rows), dtype="int64")  # per part row: its old row
    src[was] = old_rows
    dst = np.empty(len(rows), dtype="int64")  # and its new row
    dst[now] = new_rows
    lon = plan.take(geom.lon, fresh.lon)
    lat = plan.take(geom.lat, fresh.lat)
    time_s = plan.take(geom.time_s, fresh.time_s)
    # the same points where they were (a line across 180° may be moved a turn; times
    # checked too: the rows found again are those points, not others at one place)
    same_place = (
        np.array_equal(lon[dst], geom.lon[src])
        and np.array_equal(lat[dst], geom.lat[src])
        and np.array_equal(time_s[dst], geom.time_s[src], equal_nan=True)
    )
    sizes = plan.sizes
    starts = np.zeros(len(sizes), dtype="int64")
    if len(sizes):
        np.cumsum(sizes[:-1], out=starts[1:])
    from wakeline.core.sorted_sets import repeat_runs

    new_geom = LayerGeometry(
        lon=lon,
        lat=lat,
        starts=starts,
        ends=starts + sizes,
        track=repeat_runs(None, sizes).astype(geom.track.dtype, copy=False),
        sensor=plan.take_lines(geom.sensor, fresh.sensor),
        batch=plan.take_lines(geom.batch, fresh.batch),
        time_s=time_s,
        speed_kn=plan.take(geom.speed_kn, fresh.speed_kn),
        group=plan.take_lines(geom.group, fresh.group),
        labels=geom.labels,
        colors=geom.colors,
        relative=geom.relative,
        gap_break=None if geom.gap_break is None else plan.take(geom.gap_break, fresh.gap_break),
        point_batch=None
        if geom.point_batch is None
        else plan.take(geom.point_batch, fresh.point_batch),
        lon_west=geom.lon_west,
    )
    if same_place and geom._tree is not None:
        moved_rows = plan.moved(src, dst, len(lon))
        new_geom._tree = geom._tree
        new_geom._tree_scale = geom._tree_scale
        old_map = geom._tree_rows
        new_geom._tree_rows = moved_rows if old_map is None else moved_rows[old_map]
    else:
        new_geom.tree()
    if geom._boxes is not None:  # the lines' boxes: the untouched ones kept
        boxes = fresh.line_boxes()
        if boxes is not None:
            new_geom._boxes = tuple(
                plan.take_lines(o, f) for o, f in zip(geom._boxes, boxes, strict=True)
            )
    like = geom._sketch if same_place else None
    new_geom._sketch = position_sketch(lon, lat, like) if len(lon) else None
    curves, box, px = curves_for(new_geom, view if size_px is not None else None, size_px)
    shown = view if px is not None else None
    data = DrawData(draw.name, new_geom, curves, draw.style, box, px, shown)
    summary = _relabeled_summary(summary_old, moved, new_t)
    out = _finish(points, kind, summary, data, previous.ranges, previous.maneuvers, previous)
    if out.extra.get("plots", False) != previous.extra.get("plots", False):
        return None  # drawn otherwise now: the whole view
    out.draw = with_paths(out.draw)
    return out


def _piece_rows(plan, line_piece: int) -> tuple[int, int]:
    """Rows ``first, stop`` of the new layout that piece ``line_piece`` fills."""
    at = 0
    for k, (_s, a, b) in enumerate(plan.pieces):
        if k == line_piece:
            return at, at + b - a
        at += b - a
    raise IndexError(line_piece)


def _line_order(part: pd.DataFrame, kind: str) -> np.ndarray:
    """The part's rows (``_row``) in the order its lines are drawn: by sensor and line
    (text), time, then the part's order — the stable sort of
    :func:`~wakeline.core.tracks.sorted_with_index` (a few lines: one lexsort)."""
    from wakeline.app.map_draw import drawn_lines
    from wakeline.core.schema import time_seconds

    lines = drawn_lines(part, kind)
    sensor = pd.factorize(lines["sensor"], sort=True, use_na_sentinel=False)[0]
    line = pd.factorize(lines["batch"], sort=True, use_na_sentinel=False)[0]
    order = np.lexsort((time_seconds(lines["time"]), line, sensor))
    return lines["_row"].to_numpy(dtype="int64")[order]


def _same_values(a: pd.Series, b: pd.Series) -> bool:
    """Whether two columns hold the same data: the same buffers (not compared by value)."""
    if a.dtype != b.dtype or len(a) != len(b):
        return False
    ka, kb = _buffers(a.array), _buffers(b.array)
    return ka is not None and ka == kb


def _buffers(arr) -> tuple | None:
    """Addresses, lengths and types of the buffers holding an array's values; None when
    they are not known without a copy."""
    if hasattr(arr, "_pa_array"):
        return tuple(
            (c.offset, len(c), tuple(None if x is None else x.address for x in c.buffers()))
            for c in arr._pa_array.chunks
        )
    parts = [getattr(arr, "_ndarray", None)]
    if parts[0] is None:
        parts = [getattr(arr, "_data", None), getattr(arr, "_mask", None)]
    if parts[0] is None or not all(isinstance(p, np.ndarray) for p in parts):
        return None
    return tuple((p.__array_interface__["data"][0], p.shape, p.strides, p.dtype.str) for p in parts)


def _relabeled_summary(summary: pd.DataFrame, moved: np.ndarray, targets) -> pd.DataFrame:
    """:func:`~wakeline.app.models.batch_summary`'s ``target`` and ``status`` of the
    tracks ``moved`` (whole targets) set from ``targets`` (per track); the other rows as
    they were (no text per track made again)."""
    out = summary.reset_index(drop=True).copy()
    keep = ~moved
    new = pd.Series(targets)
    out["target"] = out["target"].where(keep, new)
    mine = pd.Series(np.asarray(targets[moved], dtype=object))
    joined = mine.map(mine.value_counts()).to_numpy() > 1
    status = pd.Series(
        np.where(joined, "joined", ""), index=np.flatnonzero(moved), dtype=out["status"].dtype
    )
    out["status"] = out["status"].where(keep, status)
    return out


def prepare_view_apart(
    points: pd.DataFrame,
    kind: str,
    in_use: tuple[set[str], set[str]],
    label: str = "",
    view: tuple[float, float, float, float] | None = None,
    size_px: tuple[int, int] | None = None,
    first: str | None = None,
    chosen: bool = False,
) -> LayerView:
    """:func:`prepare_view` in colours no other layer shows: ``in_use`` is (colours of
    the visible layers, of the hidden ones), and takes the colours chosen, so the next
    layer prepared with it is drawn apart from this one too. ``first``: the colour to
    keep when it is free (a layer's saved colour); ``chosen``: kept even when another
    layer has it (the operator's, Layers ▸ Colour…). Pure, for a worker thread."""
    from wakeline.app.map_colors import PALETTE, layer_colors

    shown, hidden = in_use
    if chosen and first:
        shown, hidden = shown - {first}, hidden - {first}
    palette = layer_colors(kind, len(PALETTE), shown, hidden, first)
    lv = prepare_view(
        points,
        kind,
        palette[0],
        label,
        view,
        size_px,
        colors=palette if kind == "source" else None,
    )
    in_use[0].update(lv.colors)
    return lv


def draw_as(view: LayerView, layer_id: str, label: str):
    """The prepared map data keyed by the layer's id and labelled with its display name
    (the worker did not know either)."""
    import dataclasses

    data = view.draw

    def relabel(text: str) -> str:
        if not text:
            return text
        return text.replace(data.name, label, 1) if data.name else f"{label} · {text}"

    geometry = dataclasses.replace(
        data.geometry, labels=tuple(relabel(t) for t in data.geometry.labels)
    )
    curves = tuple(dataclasses.replace(c, label=relabel(c.label)) for c in data.curves)
    return dataclasses.replace(data, name=layer_id, geometry=geometry, curves=curves)


#: Between a layer's id and a part's name in the map's layer names (a bearing layer is
#: drawn as several map layers: ``L3/observer``, ``L3/lines`` …).
PART_SEP = "/"


def map_layers(view: LayerView, layer_id: str, label: str) -> list:
    """Every map layer a session layer is drawn as, keyed and labelled for the map: a
    point layer's one (:func:`draw_as`, named ``layer_id``), or the parts of a bearing
    layer (``view.extra["parts"]``, named ``layer_id/part``, legend ``label · …``)."""
    import dataclasses

    parts = view.extra.get("parts")
    if parts is None:
        return [draw_as(view, layer_id, label)] if view.draw is not None else []

    from wakeline.app.bearing_view import in_language, legend_words

    def relabel(text: str) -> str:
        return f"{label} · {text}" if text else text

    out, words = [], legend_words()
    for data in parts:
        data = in_language(data, data.name, words)  # its legend words in the window's language
        geometry = dataclasses.replace(
            data.geometry, labels=tuple(relabel(t) for t in data.geometry.labels)
        )
        curves = tuple(dataclasses.replace(c, label=relabel(c.label)) for c in data.curves)
        name = f"{layer_id}{PART_SEP}{data.name}"
        out.append(dataclasses.replace(data, name=name, geometry=geometry, curves=curves))
    return out


def is_part_of(name: str, layer_id: str) -> bool:
    """Whether the map layer ``name`` draws session layer ``layer_id`` (or a part of it)."""
    return name == layer_id or name.startswith(layer_id + PART_SEP)
