"""Drawing preparation for the map, pure numpy (no Qt): safe to run in a worker thread.

A layer is prepared in two stages:

1. :func:`layer_geometry` (the slow part, once per layer): rows sorted per track,
   longitudes unwrapped across 180° and each track moved by whole turns into the layer's
   band (:func:`wakeline.core.geo.lon_band_west`: [0, 360) for a scene across the
   antimeridian, so its tracks are drawn side by side, not 360° apart), per-point time
   (s) and speed (kn), the track of every point, and a k-d tree for hover/pick built on
   demand.
2. :func:`decimate` / :func:`prepare_layer` (cheap, again on every zoom): the
   level of detail. Per track, a point is dropped when it falls in the same screen pixel
   as the previous point of its track (so the previous *kept* point too, since a run of
   points in one pixel keeps its first); the first and last point of every track are
   always kept. A turn therefore survives down to the pixel, and every input point lies
   in the pixel of a drawn vertex. With a view box, points whose both legs lie wholly on
   one side outside the box are dropped too, and the curve is broken (NaN) there, so no
   false straight line joins the two sides of a gap.

The canvas only swaps in finished :class:`DrawData`. Colours: :mod:`wakeline.app.map_colors`;
the coastline's geometry: :mod:`wakeline.app.map_coast`.
"""

import math
from dataclasses import dataclass, field, replace

import numpy as np
import pandas as pd
from PySide6 import QtCore
from scipy.spatial import cKDTree

from wakeline.app.map_colors import BATCH_PALETTE, PALETTE, layer_colors
from wakeline.app.map_frame import PositionSketch, position_sketch
from wakeline.app.map_lod import decimate, gap_breaks, lod_box, nan_join, split_at
from wakeline.app.time_text import format_time, is_relative_time
from wakeline.core import geo
from wakeline.core.schema import time_seconds
from wakeline.core.sorted_sets import repeat_runs
from wakeline.core.tracks import concat_ranges, sorted_with_index


@dataclass(frozen=True)
class LayerStyle:
    """How a layer is drawn: line width (px, 0 = no line), symbol size (px, 0 = none),
    stacking (``z``: higher over lower; equal: the later layer on top)."""

    width: float = 1.5
    symbol_size: float = 0.0
    z: float = 0.0
    #: Break the line at gaps of hours and impossible jumps (off for a compressed layer:
    #: its long legs are the compression's, and the ship was seen along them).
    gaps: bool = True
    #: The marker of a markers-only layer (``width`` 0) while few: pyqtgraph's symbol
    #: name ("o" dots, "x" crosses); many are drawn as small 1-px crosses anyway.
    symbol: str = "o"
    #: Radar plots drawn as dots (:func:`as_points`): the time slider still runs over
    #: them (a markers-only layer else is a step's marks, not tracks).
    plots: bool = False


@dataclass
class LayerGeometry:
    """Full-resolution points of one layer, sorted per track, ready for drawing.

    ``lon`` is unwrapped along each track (a track crossing 180° stays continuous) and
    each track's first point lies in [``lon_west``, ``lon_west`` + 360), the layer's band
    (:func:`wakeline.core.geo.lon_band_west`; a selection or marks of the layer are drawn
    in it too);
    ``starts``/``ends`` delimit the tracks; ``track`` is the track of every point;
    ``sensor``/``batch`` are per track; ``time_s`` and ``speed_kn`` per point;
    ``group`` is the curve (colour) of each track; ``gap_break`` per point: the leg
    arriving at it spans a gap of hours and is not drawn (:func:`~wakeline.app.map_lod.gap_breaks`).
    """

    lon: np.ndarray
    lat: np.ndarray
    starts: np.ndarray
    ends: np.ndarray
    track: np.ndarray
    sensor: np.ndarray
    batch: np.ndarray
    time_s: np.ndarray
    speed_kn: np.ndarray
    group: np.ndarray
    labels: tuple[str, ...]
    colors: tuple[str, ...]
    relative: bool
    gap_break: np.ndarray | None = None
    #: Per point, the batch it belongs to where a line joins several (an associated layer
    #: is drawn one line per target, :func:`drawn_lines`): hover and click name it, not the
    #: line's target. None: each line is one batch.
    point_batch: np.ndarray | None = None
    #: West edge of the band the layer's tracks start in: -180 ([-180, 180)) or 0.
    lon_west: float = -180.0
    #: A note the hover shows per point (a removed point's rule and reason): the code of
    #: every point and the texts, or None.
    point_note: tuple[np.ndarray, tuple[str, ...]] | None = None
    #: The layer's own ``(group, colors, labels)`` while its tracks are drawn each in its
    #: own colour (:func:`recolor`); None: drawn as prepared.
    plain: tuple | None = None
    _tree: cKDTree | None = field(default=None, repr=False)
    _sketch: PositionSketch | None = field(default=None, repr=False)
    #: The tree kept from an earlier order of the same positions (lines made again by a
    #: review decision, :func:`wakeline.app.layer_view.relabel_view`): per point of the
    #: tree, its row now; None: the tree's points are the rows.
    _tree_rows: np.ndarray | None = field(default=None, repr=False)
    #: ``x_scale`` the tree was built with (None: not built yet)
    _tree_scale: float | None = field(default=None, repr=False)
    #: Each line's (west, east, south, north), made on first use (:meth:`line_boxes`)
    _boxes: tuple | None = field(default=None, repr=False)

    @property
    def n_points(self) -> int:
        return len(self.lon)

    @property
    def n_tracks(self) -> int:
        return len(self.starts)

    def bounds(self) -> tuple[float, float, float, float] | None:
        """``(west, south, east, north)`` in degrees, None when empty."""
        if len(self.lon) == 0:
            return None
        return (
            float(self.lon.min()),
            float(self.lat.min()),
            float(self.lon.max()),
            float(self.lat.max()),
        )

    def sketch(self) -> PositionSketch | None:
        """Where the points are (:mod:`wakeline.app.map_frame`), made on first use (in the
        worker, by :func:`prepare_layer`); None when empty."""
        if self._sketch is None and len(self.lon):
            self._sketch = position_sketch(self.lon, self.lat)
        return self._sketch

    @property
    def x_scale(self) -> float:
        """cos(mean latitude): degrees of longitude to degrees of latitude."""
        lat0 = float(np.mean(self.lat)) if len(self.lat) else 0.0
        return max(math.cos(math.radians(lat0)), 0.05)

    def tree(self) -> cKDTree:
        """k-d tree over (lon·cos lat0, lat), built on first use (call it in a worker)."""
        if self._tree is None:
            scale = self.x_scale
            xy = np.column_stack([self.lon * scale, self.lat])
            self._tree = cKDTree(xy, balanced_tree=False, compact_nodes=False)
            self._tree_rows, self._tree_scale = None, scale
        return self._tree

    def line_boxes(self) -> tuple | None:
        """Each line's (west, east, south, north) arrays (degrees, as drawn), made on first
        use; None when a position is not finite (then no line is left out by its box)."""
        if self._boxes is None and self.n_tracks and self.n_points:
            lon, lat, at = self.lon, self.lat, self.starts
            if not (np.isfinite(lon).all() and np.isfinite(lat).all()):
                return None
            self._boxes = (
                np.minimum.reduceat(lon, at),
                np.maximum.reduceat(lon, at),
                np.minimum.reduceat(lat, at),
                np.maximum.reduceat(lat, at),
            )
        return self._boxes

    def nearest(self, lon: float, lat: float) -> tuple[float, int]:
        """Distance (degrees of latitude) and index of the point nearest ``lon, lat``."""
        tree = self.tree()
        scale = self.x_scale if self._tree_scale is None else self._tree_scale
        d, i = tree.query([lon * scale, lat])
        i = int(i)
        if self._tree_rows is not None and i < len(self._tree_rows):
            i = int(self._tree_rows[i])
        return float(d), i

    def describe(self, i: int) -> dict:
        """Sensor, batch, time (text), speed (kn) of point ``i``."""
        k = int(self.track[i])
        batch = self.batch[k] if self.point_batch is None else self.point_batch[i]
        return {
            "sensor": str(self.sensor[k]),
            "batch": str(batch),
            "time": format_time(float(self.time_s[i]), self.relative),
            "time_s": float(self.time_s[i]),
            "speed_kn": float(self.speed_kn[i]),
            "lon": float(self.lon[i]),
            "lat": float(self.lat[i]),
            **({"note": self.point_note[1][self.point_note[0][i]]} if self.point_note else {}),
        }


@dataclass(frozen=True)
class Curve:
    """One drawn curve: tracks NaN-separated, after the level of detail."""

    label: str
    color: str
    lon: np.ndarray
    lat: np.ndarray
    #: The curve's QPainterPath when a worker built it (:mod:`wakeline.app.map_paths`),
    #: so the GUI thread's paint only strokes it; None: built on the first paint.
    path: object = field(default=None, compare=False, repr=False)
    #: The curve stroked into an image for the view it was decimated for, by a worker
    #: (:class:`wakeline.app.map_paths.Sprite`); the paint then only copies it.
    sprite: object = field(default=None, compare=False, repr=False)

    @property
    def n_vertices(self) -> int:
        return int(np.count_nonzero(np.isfinite(self.lon)))


@dataclass(frozen=True)
class DrawData:
    """A layer ready to swap into the canvas: geometry, curves, the view they were made for.

    ``lod_box`` is ``(x0, x1, y0, y1)`` (degrees) the curves are valid in and ``px`` the
    pixel size (degrees) they were decimated for; both None for full resolution.
    ``view`` is the view (x0, x1, y0, y1, degrees) they were made for.
    """

    name: str
    geometry: LayerGeometry
    curves: tuple[Curve, ...]
    style: LayerStyle
    lod_box: tuple[float, float, float, float] | None = None
    px: tuple[float, float] | None = None
    view: tuple[float, float, float, float] | None = None

    @property
    def n_vertices(self) -> int:
        """Vertices actually in the drawn paths (NaN separators not counted)."""
        return sum(c.n_vertices for c in self.curves)


# -- geometry --------------------------------------------------------------------------


def unwrap_tracks(
    lon: np.ndarray, starts: np.ndarray, sizes: np.ndarray, west: float = -180.0
) -> np.ndarray:
    """Longitudes made continuous along each track (±360° steps removed), degrees; with
    ``west`` other than -180, each track moved by whole turns so its first point lies in
    [``west``, ``west`` + 360)."""
    if len(lon) == 0:
        return lon.astype("float64")
    step = np.diff(lon, prepend=lon[0])
    step[starts] = 0.0
    jumps = np.where(step > 180.0, -360.0, np.where(step < -180.0, 360.0, 0.0))
    cum = np.cumsum(jumps)
    cum -= repeat_runs(cum[starts], sizes)
    if west != -180.0 and len(starts):
        first = lon[starts]
        cum += repeat_runs(geo.into_band(first, west) - first, sizes)
    return lon + cum


def leg_speed_kn(
    lon: np.ndarray, lat: np.ndarray, time_s: np.ndarray, starts: np.ndarray
) -> np.ndarray:
    """Speed (kn) of the leg arriving at each point; a track's first point takes the leg
    leaving it; NaN for single points and zero time steps."""
    n = len(lon)
    speed = np.full(n, np.nan)
    if n < 2:
        return speed
    dist = geo.haversine_m(lon[:-1], lat[:-1], lon[1:], lat[1:])
    dt = np.diff(time_s)
    with np.errstate(divide="ignore", invalid="ignore"):
        speed[1:] = np.where(dt > 0, dist / dt / geo.KN_MS, np.nan)
    speed[starts] = np.nan
    second = starts + 1
    ok = second < np.append(starts[1:], n)
    speed[starts[ok]] = speed[second[ok]]
    return speed


def layer_geometry(
    points: pd.DataFrame,
    color: str = PALETTE[0],
    by_sensor: bool = False,
    color_by: str = "layer",
    relative: bool | None = None,
    label: str = "",
    colors: tuple[str, ...] | None = None,
    lon_west: float | None = None,
) -> LayerGeometry:
    """Sort, unwrap and describe ``points`` (canonical table) for drawing.

    ``color_by``: "layer" (one curve in ``color``), "sensor" (one curve per sensor:
    ``color``, then the next free source colours, :func:`~wakeline.app.map_colors.layer_colors`;
    ``by_sensor=True`` means the same) or "batch" (every track in one of
    :data:`BATCH_PALETTE`, neighbours in the table differing). ``colors``: the colours
    the sensors (or batches) take in turn instead (chosen apart from other layers').
    ``relative`` forces elapsed-time display; None decides from the time values.
    ``lon_west``: the band the tracks are drawn in (-180 or 0); None decides from the
    points (:func:`wakeline.core.geo.lon_band_west`).
    """
    if by_sensor and color_by == "layer":
        color_by = "sensor"
    if color_by not in ("layer", "sensor", "batch"):
        raise ValueError(f"color_by must be layer, sensor or batch, not {color_by!r}")
    cols = [
        c
        for c in ("sensor", "batch", "time", "lon", "lat", "speed", "piece_batch")
        if c in points.columns
    ]
    df, index = sorted_with_index(points[cols])
    lon = df["lon"].to_numpy(dtype="float64")
    lat = df["lat"].to_numpy(dtype="float64")
    t = time_seconds(df["time"]) if len(df) else np.zeros(0)
    speed = np.full(len(df), np.nan)
    if "speed" in df.columns:
        speed = df["speed"].to_numpy(dtype="float64", na_value=np.nan)
    if np.isnan(speed).any():
        speed = np.where(np.isnan(speed), leg_speed_kn(lon, lat, t, index.starts), speed)
    west = geo.lon_band_west(lon) if lon_west is None else float(lon_west)
    lon = unwrap_tracks(lon, index.starts, index.sizes, west)
    sensor = index.keys["sensor"].to_numpy(dtype=object)
    batch = index.keys["batch"].to_numpy(dtype=object)
    if color_by == "sensor":
        names, group = np.unique(sensor.astype(str), return_inverse=True)
        if colors:
            colors = tuple(colors[k % len(colors)] for k in range(len(names)))
        else:
            colors = layer_colors("source", len(names), first=color)
        labels = tuple(f"{label} · {s}" if label else str(s) for s in names)
    elif color_by == "batch":
        palette = tuple(colors or BATCH_PALETTE)
        k = len(palette)
        group = np.arange(index.n_tracks) % k
        used = min(k, index.n_tracks)
        colors = palette[:used]
        # One legend line for the layer; the other colours carry no legend entry.
        head = f"{label} · " if label else ""
        labels = (f"{head}{index.n_tracks} batches",) + ("",) * (used - 1)
    else:
        group = np.zeros(index.n_tracks, dtype="int64")
        colors, labels = (color,), (label,)
    return LayerGeometry(
        lon=lon,
        lat=lat,
        starts=index.starts,
        ends=index.ends,
        track=index.track_of_row,
        sensor=sensor,
        batch=batch,
        time_s=t,
        speed_kn=np.asarray(speed, dtype="float64"),
        group=np.asarray(group, dtype="int64"),
        labels=labels,
        colors=colors,
        relative=is_relative_time(t) if relative is None else bool(relative),
        gap_break=gap_breaks(t, index.starts, index.ends, lon, lat),
        point_batch=shared_strings(df["piece_batch"]) if "piece_batch" in df else None,
        lon_west=west,
    )


def shared_strings(values: pd.Series) -> np.ndarray:
    """``values`` as an object array in which equal values are one Python object (a
    batch name per point: 1 M points of a few thousand batches made 1 M strings, 65 MB,
    where each batch's one string will do)."""
    codes, uniques = pd.factorize(values, use_na_sentinel=False)
    return np.asarray(uniques, dtype=object)[codes]


def curves_for(
    geom: LayerGeometry,
    view: tuple[float, float, float, float] | None = None,
    size_px: tuple[int, int] | None = None,
    margin: float = 1.0,
) -> tuple[tuple[Curve, ...], tuple | None, tuple | None]:
    """The curves of ``geom`` decimated for ``view`` (x0, x1, y0, y1, degrees) shown on
    ``size_px`` (w, h) pixels; full resolution when either is None. Returns the curves,
    the box they are valid in and the pixel size used."""
    px = box = None
    if view is not None and size_px is not None and size_px[0] > 0 and size_px[1] > 0:
        x0, x1, y0, y1 = view
        px = ((x1 - x0) / size_px[0], (y1 - y0) / size_px[1])
        if not (px[0] > 0 and px[1] > 0):
            px = None
        else:
            box = lod_box(view, margin)
    origin = (view[0], view[2]) if view is not None else (0.0, 0.0)
    starts, ends = geom.starts, geom.ends
    lon, lat, gap, line = geom.lon, geom.lat, geom.gap_break, geom.track
    near = _lines_near(geom, box)
    if near is not None:
        # Only the lines whose box meets the region: a line wholly beyond it keeps no
        # point and breaks the curve at its start anyway (the same curves; a zoomed view
        # of a million points decimated a million).
        sizes = (ends - starts)[near]
        rows = concat_ranges(starts[near], sizes)
        lon, lat, line = lon[rows], lat[rows], line[rows]
        gap = gap[rows] if gap is not None else None
        starts = np.zeros(len(sizes), dtype="int64")
        np.cumsum(sizes[:-1], out=starts[1:])
        ends = starts + sizes
    if gap is not None:
        starts, ends = split_at(starts, ends, gap)
    keep, brk = decimate(lon, lat, starts, ends, px, box, origin)
    group_of_point = geom.group[line] if len(lon) else np.zeros(0, dtype="int64")
    all_lon, all_lat = lon, lat
    curves = []
    for g, (label, color) in enumerate(zip(geom.labels, geom.colors, strict=True)):
        sel = keep & (group_of_point == g) if len(geom.labels) > 1 else keep
        # Tracks of one group are not contiguous when coloured by batch: a break at every
        # track start keeps them apart.
        lon, lat = nan_join(all_lon, all_lat, sel, brk)
        curves.append(Curve(label, color, lon, lat))
    return tuple(curves), box, px


#: Lines are left out of a level of detail by their boxes (:func:`curves_for`) when those
#: that meet its region hold at most this share of the points.
NEAR_LINES_SHARE = 0.5


def _lines_near(geom: LayerGeometry, box) -> np.ndarray | None:
    """The lines (numbers) whose box meets ``box`` (x0, x1, y0, y1), when they hold at
    most :data:`NEAR_LINES_SHARE` of the points; None: decimate them all."""
    if box is None or geom.n_tracks < 2:
        return None
    boxes = geom.line_boxes()
    if boxes is None:
        return None
    west, east, south, north = boxes
    x0, x1, y0, y1 = box
    meets = (east >= x0) & (west <= x1) & (north >= y0) & (south <= y1)
    near = np.flatnonzero(meets)
    sizes = geom.ends - geom.starts
    if int(sizes[near].sum()) > NEAR_LINES_SHARE * geom.n_points:
        return None
    return near


def drawn_lines(points: pd.DataFrame, kind: str) -> pd.DataFrame:
    """``points`` as their lines are drawn: an associated layer (``kind`` "associated",
    with a ``target`` column) one line per target, so each join shows as a leg from the
    old piece's end to the new one's start (drawn as the pieces it joined, each on its
    own, no join could be seen, however far); a gap of hours is still left open. The
    layer's table keeps its batches; only the drawing is per target (each point keeps its
    batch in ``piece_batch``: what hover and click name)."""
    if kind == "associated" and "target" in points.columns:
        return points.assign(piece_batch=points["batch"], batch=points["target"].astype(str))
    return points


def prepare_layer(
    points: pd.DataFrame | LayerGeometry,
    name: str = "",
    color: str = PALETTE[0],
    by_sensor: bool = False,
    color_by: str = "layer",
    style: LayerStyle | None = None,
    view: tuple[float, float, float, float] | None = None,
    size_px: tuple[int, int] | None = None,
    relative: bool | None = None,
    build_index: bool = True,
    colors: tuple[str, ...] | None = None,
    kind: str = "",
    lon_west: float | None = None,
) -> DrawData:
    """Everything the canvas needs to draw a layer, computed off the GUI thread.

    ``points`` is a canonical point table (or a geometry from an earlier call, to redo
    only the level of detail). ``view``/``size_px``: the canvas' view (x0, x1, y0, y1,
    degrees) and plot size in pixels, for the level of detail; None draws every point.
    ``build_index`` builds the hover/pick k-d tree and the position sketch (where the
    points are, for the first view) now, else on first use. ``colors``:
    the colours of the sensors (or batches) in turn (see :func:`layer_geometry`).
    ``kind``: the layer's kind (``source``, ``associated``…); see :func:`drawn_lines`.
    ``lon_west``: the band to draw in (None: the points decide, :func:`layer_geometry`).
    """
    if isinstance(points, LayerGeometry):
        geom = points
    else:
        points = drawn_lines(points, kind)
        geom = layer_geometry(points, color, by_sensor, color_by, relative, name, colors, lon_west)
    if style is not None and not style.gaps and geom.gap_break is not None:
        geom = replace(geom, gap_break=None)
    if build_index and geom.n_points:
        geom.tree()
        geom.sketch()
    curves, box, px = curves_for(geom, view, size_px)
    shown = view if px is not None else None
    return DrawData(name, geom, curves, style or LayerStyle(), box, px, shown)


def relod(
    data: DrawData, view: tuple[float, float, float, float], size_px: tuple[int, int]
) -> DrawData:
    """``data`` with its curves decimated again for a new view (pure; for a worker)."""
    curves, box, px = curves_for(data.geometry, view, size_px)
    return replace(data, curves=curves, lod_box=box, px=px, view=view if px else None)


def lod_is_stale(
    data: DrawData, view: tuple[float, float, float, float], size_px: tuple[int, int]
) -> bool:
    """True when the view left the region ``data`` was decimated for, or the pixel size
    changed by more than a quarter (zoom)."""
    if data.geometry.n_points == 0:
        return False
    if data.px is None or data.lod_box is None:
        return True
    x0, x1, y0, y1 = view
    bx0, bx1, by0, by1 = data.lod_box
    if x0 < bx0 or x1 > bx1 or y0 < by0 or y1 > by1:
        return True
    px = ((x1 - x0) / max(size_px[0], 1), (y1 - y0) / max(size_px[1], 1))
    ratio = px[0] / data.px[0] if data.px[0] > 0 else 0.0
    # Coarser than decimated for: merge more; finer: detail would be missing.
    return not (0.99 <= ratio <= 1.25)


def nan_separated(
    points: pd.DataFrame, lon_west: float | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """lon, lat of all tracks (full resolution), a NaN between consecutive tracks.

    Longitudes are unwrapped along each track so a track crossing 180° stays continuous,
    in the band ``lon_west`` (None: the points decide, :func:`layer_geometry`).
    """
    geom = layer_geometry(points, lon_west=lon_west)
    keep = np.ones(geom.n_points, dtype=bool)
    brk = np.zeros(geom.n_points, dtype=bool)
    brk[geom.starts] = True
    if geom.gap_break is not None:
        brk |= geom.gap_break
    return nan_join(geom.lon, geom.lat, keep, brk)


# -- colour by track ---------------------------------------------------------------------

#: A layer of at most this many tracks is drawn one colour per track while it is the
#: active layer and View ▸ Colour by track is on (beyond it the palette's 20 colours
#: would each stand for several tracks, and a colour names no ship).
TRACK_COLORS_MAX = 30
#: Legend lines of a layer coloured by track; the last says how many more there are.
LEGEND_TRACKS = 12


def track_legend_labels(names: list[str], counts: np.ndarray, n_tracks: int) -> tuple[str, ...]:
    """Legend labels of the curves of a layer coloured by track (one per colour): the
    colour's first track's name, with "+k same colour" when k more tracks share it
    (:func:`reused_label`); beyond
    :data:`LEGEND_TRACKS` lines none, the last line saying "… and N more tracks"."""
    n_groups = len(names)
    out = []
    said = False
    for g, name in enumerate(names):
        more = int(counts[g]) - 1
        text = reused_label(name, more, said)
        said = said or more > 0
        if n_groups > LEGEND_TRACKS and g >= LEGEND_TRACKS - 1:
            named = sum(int(c) for c in counts[: LEGEND_TRACKS - 1])
            text = (
                _tr("… and {0} more tracks").format(f"{n_tracks - named:,}")
                if g == LEGEND_TRACKS - 1
                else ""
            )
        out.append(text)
    return tuple(out)


def reused_label(name: str, more: int, said: bool) -> str:
    """A legend line of a colour ``more`` more tracks share: the first such line says it
    on a second line of its own ("name · +2 same colour": the legend's "FILE · what"),
    the next ones only "name (+2)" (one line each: a legend of two-line entries ran off
    the bottom of a 1366 × 768 window)."""
    if more <= 0:
        return name
    return f"{name} (+{more})" if said else _tr("{0} · +{1} same colour").format(name, more)


def _tr(text: str) -> str:
    """``text`` in the window's language (callable from the map's worker threads)."""
    return QtCore.QCoreApplication.translate("MainWindow", text)


def track_names(geom: LayerGeometry) -> list[str]:
    """Each track's short name: its batch, ``sensor · batch`` when the layer has several
    sensors (as the selection's legend names a track: "9001:412434718-0" beside
    "9001 · 412434718-0" named one track twice, operator test 10)."""
    sensors = {str(s) for s in geom.sensor}
    if len(sensors) > 1:
        return [f"{s} · {b}" for s, b in zip(geom.sensor, geom.batch, strict=True)]
    return [str(b) for b in geom.batch]


def named_tracks(geom: LayerGeometry) -> dict[tuple[str, str], str]:
    """The tracks a layer coloured by track (:func:`recolor`) names on a legend line of
    their own, with their colour, by ``(sensor, batch)``; empty for a layer in its own
    colours. (The first track of each colour has the line; beyond :data:`LEGEND_TRACKS`
    lines the last says "… and N more tracks".)"""
    if geom.plain is None:
        return {}
    n_groups = len(geom.colors)
    named = n_groups if n_groups <= LEGEND_TRACKS else LEGEND_TRACKS - 1
    return {
        (str(geom.sensor[g]), str(geom.batch[g])): geom.colors[g]
        for g in range(min(named, geom.n_tracks))
    }


def recolor(data: DrawData, by_track: bool, palette: tuple[str, ...] | None = None) -> DrawData:
    """``data`` with every track in its own colour of ``palette`` (default
    :data:`~wakeline.app.map_colors.TRACK_PALETTE`; ``by_track``; in turn,
    repeating beyond the palette) or in its layer's colours again; the curves decimated
    for the view they were made for (pure, for a worker)."""
    geom = data.geometry
    if by_track == (geom.plain is not None):
        return data
    if palette is None:
        from wakeline.app.map_colors import TRACK_PALETTE

        palette = TRACK_PALETTE
    if by_track:
        k = max(len(palette), 1)
        group = np.arange(geom.n_tracks, dtype="int64") % k
        used = max(min(k, geom.n_tracks), 1)
        names = track_names(geom)[:used] or [""]
        counts = np.bincount(group, minlength=used)
        labels = track_legend_labels(names, counts, geom.n_tracks)
        if geom.labels and geom.labels[0]:  # the first entry names the layer on a line of its own
            # (joined by " · " the legend shortened the layer's steps away: "demo.csv ·…
            # AIS:340 · +1 same colour" named no layer)
            labels = (f"{geom.labels[0]}\n{labels[0]}", *labels[1:])
        new = replace(
            geom,
            group=group,
            colors=tuple(palette[:used]),
            labels=labels,
            plain=(geom.group, geom.colors, geom.labels),
        )
    else:
        group, colors, labels = geom.plain
        new = replace(geom, group=group, colors=colors, labels=labels, plain=None)
    size = None
    if data.view is not None and data.px is not None:
        x0, x1, y0, y1 = data.view
        size = ((x1 - x0) / data.px[0], (y1 - y0) / data.px[1])
    curves, box, px = curves_for(new, data.view if size else None, size)
    return replace(data, geometry=new, curves=curves, lod_box=box, px=px)


def with_colors(data: DrawData, colors: tuple[str, ...]) -> DrawData:
    """``data`` drawn in the layer colours ``colors`` (one per curve of the layer's own
    colouring, :attr:`LayerGeometry.colors`; fewer: the rest kept): an operator's colour
    (Layers ▸ Colour…). Its tracks drawn each in its own colour (the active layer) keep
    them: only the layer's own colours, drawn again after, change. No new level of
    detail (pure, cheap); the curves' sprites, stroked in the old colours, are dropped."""
    geom = data.geometry
    own = geom.plain[1] if geom.plain is not None else geom.colors
    new = tuple(colors[: len(own)]) + tuple(own[len(colors) :])
    if new == tuple(own):
        return data
    if geom.plain is not None:
        group, _old, labels = geom.plain
        return replace(data, geometry=replace(geom, plain=(group, new, labels)))
    swap = dict(zip(own, new, strict=True))
    curves = tuple(
        replace(c, color=swap.get(c.color, c.color), sprite=None)
        if swap.get(c.color, c.color) != c.color
        else c
        for c in data.curves
    )
    return replace(data, geometry=replace(geom, colors=new), curves=curves)


def as_points(data: DrawData, points: bool, symbol_size: float = 3.0) -> DrawData:
    """``data`` drawn as dots alone (``points``: radar plots, no line joins a scan's
    detections) or as lines again (the line width it was prepared with, kept in
    ``style``'s history); pure, cheap (no new level of detail)."""
    style = data.style
    if points == (style.width == 0 and style.symbol_size > 0):
        return data
    if points:
        style = replace(style, width=0.0, symbol_size=symbol_size, symbol="o", plots=True)
    else:
        style = replace(style, width=1.3, symbol_size=3.0, plots=False)
    return replace(data, style=style)


#: Colours of the rules that removed points (the clean step's ``rejected`` table): none
#: within ΔE 20 of a layer colour or a track colour (an orange "stationary" × sat on the
#: orange track of a layer coloured by track), the common rules each its own.
RULE_COLOR = {
    "stationary": "#ff00ff",
    "turn": "#4b0082",
    "isolated": "#b8860b",
    "speed": "#800000",
    "duplicates": "#006400",
    "same_time": "#9acd32",
}
RULE_COLORS = tuple(RULE_COLOR.values())


def removed_label(rule: str, count: int) -> str:
    """The legend line of the × marks of one clean rule, in the window's language and with
    the rule's name as the clean summary and the Parameters say it ("已删除：静止 (12,169)";
    made in a worker: :func:`_tr`). Operator test 11, F20: the Chinese window said
    "removed: turn (3)"."""
    from wakeline.app.core_text import shown

    return _tr("removed: {0} ({1})").format(shown(rule), f"{count:,}")


def rejected_layer(rejected: pd.DataFrame, name: str, lon_west: float = -180.0) -> DrawData | None:
    """The points a clean step removed or replaced (its ``rejected`` table: original rows
    with ``rule``, ``action`` and ``params``) as small × markers, one colour per rule; the
    hover says the rule, the action and the rule's parameters (pure, for a worker). None
    when the table has no positions."""
    if rejected is None or len(rejected) == 0 or not {"lon", "lat"} <= set(rejected):
        return None
    rule = (
        rejected["rule"].astype(str).to_numpy(dtype=object)
        if "rule" in rejected
        else np.full(len(rejected), "removed", dtype=object)
    )

    def text(col: str) -> np.ndarray:
        if col not in rejected:
            return np.full(len(rejected), "", dtype=object)
        return rejected[col].astype(str).to_numpy(dtype=object)

    lon = rejected["lon"].to_numpy(dtype="float64")
    lat = rejected["lat"].to_numpy(dtype="float64")
    ok = np.isfinite(lon) & np.isfinite(lat)
    if not ok.any():
        return None
    lon, lat, rule = lon[ok], lat[ok], rule[ok]
    action, params, sensor, batch = (text(c)[ok] for c in ("action", "params", "sensor", "batch"))
    if lon_west != -180.0:
        lon = geo.into_band(lon, lon_west)
    else:
        lon = np.where((lon < -180.0) | (lon >= 180.0), ((lon + 180.0) % 360.0) - 180.0, lon)
    n = len(lon)
    # one text per (rule, action, parameters) met, not per point (469 k texts held the GIL)
    codes = [pd.factorize(pd.Series(col), use_na_sentinel=False) for col in (rule, action, params)]
    combo = codes[0][0].astype("int64")
    for c, u in codes[1:]:
        combo = combo * max(len(u), 1) + c
    kinds, note_code = np.unique(combo, return_inverse=True)
    texts = []
    for k in kinds:
        parts = []
        for _c, u in reversed(codes):
            k, r = divmod(int(k), max(len(u), 1))
            parts.append(str(u[r]))
        p, a, r = parts
        texts.append(f"removed by clean: {r} ({a}) {p}".rstrip())
    note = (note_code.astype("int64"), tuple(texts))
    names, code = np.unique(rule.astype(str), return_inverse=True)
    counts = np.bincount(code, minlength=len(names))
    starts = np.arange(n, dtype="int64")  # one "track" per point: no line joins them
    t = time_seconds(rejected["time"])[ok] if "time" in rejected else np.zeros(n)
    geom = LayerGeometry(
        lon=lon,
        lat=lat,
        starts=starts,
        ends=starts + 1,
        track=starts.copy(),
        sensor=sensor,
        batch=batch,
        time_s=np.asarray(t, dtype="float64"),
        speed_kn=np.full(n, np.nan),
        group=code.astype("int64"),
        labels=tuple(removed_label(str(r), int(c)) for r, c in zip(names, counts, strict=True)),
        colors=tuple(
            RULE_COLOR.get(str(r), RULE_COLORS[k % len(RULE_COLORS)]) for k, r in enumerate(names)
        ),
        relative=is_relative_time(t),
        gap_break=None,
        lon_west=lon_west,
        point_note=note,
    )
    style = LayerStyle(width=0.0, symbol_size=6.0, z=3.0, gaps=False, symbol="x")
    return prepare_layer(geom, name, style=style)
