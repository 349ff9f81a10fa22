"""The bearing view: bearing lines from the observer on a map, the detections as a table.

Self-contained: :class:`BearingView` takes the core's bearing table (``read_bearings``)
and the detector's output (``detect_with_report``) and shows

- a :class:`MapCanvas` with the observer's track and, per batch, lines from the observer
  along the measured bearings (every few samples), a colour and a legend entry per batch
  (:data:`MAX_LINE_COLOURS`; further batches share one), as long as the scene is large
  (:func:`line_length_m`); the bearings at the estimated maneuver times are drawn thicker
  in red;
- the detections (batch, detect_time, maneuver_time, z) in a sortable table, with
  Export… writing them as CSV;
- the per-batch report lines (windows tested, skipped and why, smallest visible turn).

:func:`bearing_line_points` gives the same lines as a points table a map layer draws
with its gap breaking off (:func:`line_layer`): both ends of a line carry the sample's
time, and a long leg in no time is a jump the map otherwise breaks (nothing drawn).

:func:`bearing_scene` prepares those layers and the view that frames them (pure, for the
window's worker); :func:`main_map_layers` makes copies of them for the main map, which
otherwise sat at empty 0–1° axes when only a bearing file was loaded. On the main window a
bearing file is a session layer of kind ``bearing`` (in the Layers list, saved in the
project, cut by the time window); :func:`bearing_layer_view` is the view the window keeps
of it.
"""

import dataclasses
import functools
import math
from pathlib import Path

import numpy as np
import pandas as pd
from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.core import geo
from wakeline.core.bearing import BearingLineParams, report_lines
from wakeline.core.io import write_csv
from wakeline.core.schema import time_seconds
from wakeline.core.timeline import spread_picks

from .core_text import shown
from .layer_view import LayerView, shown_range
from .map_canvas import MapCanvas
from .map_draw import DrawData, LayerGeometry, LayerStyle, layer_geometry, prepare_layer, relod
from .map_legend import LABEL_PADDING_PX, short_label
from .map_paths import with_paths
from .map_time import geometry_rows, window_draw_data
from .models import batch_summary, display_text

#: The translation context of :func:`bearing_stats`'s texts: it is handed the main
#: window's ``tr`` (:class:`BearingView`'s own texts are under ``BearingView``).
TR_CONTEXT = "MainWindow"
#: Smallest width (px) of the map's plot area: the map widget's minimum is this plus its
#: latitude axis and legend column (a dock had given the map ~200 px and its plot ~40 px).
#: The main window at 1400 px has ~410 px left for this dock.
MIN_PLOT_PX = 180
#: The map's layers, as the legend names them (its column is reserved for these).
LAYER_NAMES = ("observer", "bearing lines", "maneuvers")
#: Smallest width (px) of the detections table and report beside (or under) the map.
MIN_SIDE_PX = 260
#: Relative sizes of the map and the table beside (or under) it.
SPLIT_WEIGHTS = (3000, 2000)
#: Stacking of the layers: the observer's track over the maneuver lines over the fan of
#: bearing lines (which otherwise hid the track they start from).
Z_OBSERVER, Z_MANEUVERS, Z_LINES = 2.0, 1.0, 0.0
#: On the main map the fan of bearing lines lies under every track layer (z 0) and the
#: selection's halo (-1), over the coastline (-10): drawn over them, a fan of 60 lines a
#: batch hid the truth tracks and the plots (operator test h150).
Z_MAIN_LINES = -2.0
#: Colours of the batches' bearing lines, in turn. The first eight (the batches with a
#: colour of their own) are the eight farthest apart (least CIE76 ΔE 40) of the batch
#: palette and a few Dark2/Paired colours, keeping ΔE 30 or more from the colours the
#: first three source layers take (blue, brown, pink), the maneuvers' red, the observer's
#: and the other batches' greys, and no light colour for thin lines. The palette's own
#: order had orange beside orange (ΔE 18), navy beside purple (25) and a track layer's
#: brown (operator test h150). Then the others.
LINE_COLOURS = (
    "#ff7f0e",
    "#7b4173",
    "#17becf",
    "#2ca02c",
    "#bcbd22",
    "#637939",
    "#e7298a",
    "#000000",
    "#31a354",
    "#008080",
    "#6a3d9a",
    "#b15928",
    "#1b9e77",
    "#66a61e",
    "#a6761d",
)
#: Batches with a colour (and legend entry) of their own; the others share OTHER_COLOUR.
MAX_LINE_COLOURS = 8
OTHER_COLOUR = "#9e9e9e"
OTHER_LABEL = "other batches"
#: Longest batch name in the legend (characters; as long as "bearing lines"): the
#: legend column keeps its width and the plot its room in a narrow dock.
LABEL_CHARS = 14

#: Bearing-line length when nothing tells the range (:func:`line_length_m`): the reach of
#: a vessel at TYPICAL_SPEED_MS during the longest sequence, or SPAN_FACTOR times the
#: observer's own track, within [MIN_LENGTH_M, MAX_LENGTH_M].
TYPICAL_SPEED_MS = 5.0
SPAN_FACTOR = 4.0
#: The core's line-length parameter (``BearingLineParams.length_m``: unit and range of
#: the dock's length box; 0 there: from the data).
LENGTH_FIELD = next(f for f in dataclasses.fields(BearingLineParams) if f.name == "length_m")
MIN_LENGTH_M, MAX_LENGTH_M = 300.0, float(LENGTH_FIELD.metadata["hi"])
#: With ranges known: the lines reach this much past the far targets (95th percentile).
RANGE_MARGIN = 1.25
#: Columns that give the target's range (metres), or its true position.
RANGE_COLUMNS = ("range_m", "range")
TRUTH_COLUMNS = ("true_lon", "true_lat")
#: Margin of the fitted view (share of the scene's size on each side; at least MIN_PAD_M).
FIT_MARGIN, MIN_PAD_M = 0.06, 20.0
#: Bearing lines drawn per batch (over the whole sequence, or over a time window).
MAX_LINES = 60
#: Rows of the detections table kept visible under the map in a narrow dock.
MIN_TABLE_ROWS = 3
#: The parts of a bearing layer on the main map (the scene's layers, in this order): the
#: map names them ``<layer id>/<part>`` and the legend ``<layer name> · <label>``.
PARTS = ("observer", "lines", "maneuvers")
#: The fixed legend words each part's labels may hold (the scene's layers are made in a
#: worker, in English: these are their label keys, put in the window's language where
#: they are drawn, :func:`in_language`); the lines' other labels are batch names, kept.
PART_WORDS = {
    "observer": (LAYER_NAMES[0],),
    "lines": (OTHER_LABEL,),
    "maneuvers": (LAYER_NAMES[2],),
}


#: Every word :func:`legend_words` gave for each key (in any language shown so far): what a
#: language switch renames (:func:`reworded`).
_SHOWN: dict[str, set[str]] = {}


def legend_words() -> dict[str, str]:
    """The bearing map's fixed legend words (:data:`LAYER_NAMES`, :data:`OTHER_LABEL`)
    in the window's language (the translator installed now; context ``BearingView``)."""
    app = QtCore.QCoreApplication
    words = {
        LAYER_NAMES[0]: app.translate("BearingView", "observer"),
        LAYER_NAMES[1]: app.translate("BearingView", "bearing lines"),
        LAYER_NAMES[2]: app.translate("BearingView", "maneuvers"),
        OTHER_LABEL: app.translate("BearingView", "other batches"),
    }
    for key, word in words.items():
        _SHOWN.setdefault(key, {key}).add(word)
    return words


def reworded(label: str, part: str, words: dict[str, str] | None = None) -> str:
    """A legend label of the bearing scene's ``part`` ("word", or "layer · word" on the
    main map) with its fixed word in the window's language now (a language switch);
    other labels (batch names) as they are."""
    words = legend_words() if words is None else words
    head, sep, word = label.rpartition(" · ")
    for key in PART_WORDS.get(part, ()):
        if word in _SHOWN.get(key, ()):
            return f"{head}{sep}{words[key]}"
    return label


def in_language(data: DrawData, part: str, words: dict[str, str] | None = None) -> DrawData:
    """``data``, the bearing scene's ``part`` (:data:`PARTS`), with its fixed legend words
    (:data:`PART_WORDS`) in the window's language (:func:`legend_words`): the geometry's
    labels (a new level of detail makes the curves from them) and the curves'."""
    keys = PART_WORDS.get(part, ())
    if not any(label in keys for label in data.geometry.labels):
        return data
    words = legend_words() if words is None else words

    def word(text: str) -> str:
        return words.get(text, text) if text in keys else text

    geometry = dataclasses.replace(
        data.geometry, labels=tuple(word(t) for t in data.geometry.labels)
    )
    curves = tuple(dataclasses.replace(c, label=word(c.label)) for c in data.curves)
    return dataclasses.replace(data, geometry=geometry, curves=curves)


#: Columns of an empty points table (a bearing layer has no tracks in the batch table).
EMPTY_POINTS = pd.DataFrame(columns=["sensor", "batch", "time", "lon", "lat"])


def _finite_range_m(bearings: pd.DataFrame) -> np.ndarray:
    """The target ranges (m) the table knows: a range column, or the distance from the
    observer to the true target position; empty when it knows none."""
    for name in RANGE_COLUMNS:
        if name in bearings.columns:
            r = pd.to_numeric(bearings[name], errors="coerce").to_numpy(dtype="float64")
            r = r[np.isfinite(r) & (r > 0)]
            if len(r):
                return r
    if set(TRUTH_COLUMNS) <= set(bearings.columns):
        cols = [bearings[c].to_numpy(dtype="float64") for c in ("obs_lon", "obs_lat")]
        cols += [bearings[c].to_numpy(dtype="float64") for c in TRUTH_COLUMNS]
        r = np.asarray(geo.haversine_m(*cols), dtype="float64")
        return r[np.isfinite(r) & (r > 0)]
    return np.zeros(0)


def line_length_m(bearings: pd.DataFrame) -> float:
    """How long to draw the bearing lines (m), from the data: the range is unknown in
    bearing-only data, yet a fixed 20 km fitted a harbour scene (targets 50–500 m off, a
    camera's 100-s sequences) into a 60–90 km view with nothing to see.

    - The table knows the ranges (``range_m``/``range``, or the targets' true positions
      ``true_lon, true_lat``): :data:`RANGE_MARGIN` times their 95th percentile, so the
      lines just pass the targets;
    - else the larger of the distance a vessel covers at :data:`TYPICAL_SPEED_MS` (10 kn)
      during the longest sequence (a sensor that holds a target ~100 s — a camera in a
      harbour — sees it within ~500 m; a 15-min sonar or ESM sequence reaches kilometres)
      and :data:`SPAN_FACTOR` times the extent of the observer's track (lines reach well
      beyond the observer's own motion, the baseline that makes ranges observable);
    - within [:data:`MIN_LENGTH_M`, :data:`MAX_LENGTH_M`].

    The view is fitted to the observer's track and the lines (:meth:`BearingView.show_result`),
    so the scene is at the targets' scale; ``length_m`` there (or
    :meth:`BearingView.set_line_length`) overrides this."""
    r = _finite_range_m(bearings)
    if len(r):
        return float(np.clip(RANGE_MARGIN * np.percentile(r, 95), MIN_LENGTH_M, MAX_LENGTH_M))
    span_s = 0.0
    if len(bearings) and "time" in bearings.columns:
        t = pd.Series(time_seconds(bearings["time"]), index=bearings.index)
        spans = t.groupby(bearings["batch"].astype(str).to_numpy()).agg(lambda x: x.max() - x.min())
        span_s = float(np.nanmax(spans.to_numpy())) if len(spans) else 0.0
    extent = 0.0
    if {"obs_lon", "obs_lat"} <= set(bearings.columns):
        lon = bearings["obs_lon"].to_numpy(dtype="float64")
        lat = bearings["obs_lat"].to_numpy(dtype="float64")
        ok = np.isfinite(lon) & np.isfinite(lat)
        if ok.any():
            lon, lat = lon[ok], lat[ok]
            lon = geo.into_band(lon, geo.lon_band_west(lon))  # across 180° as the map has it
            extent = float(
                geo.haversine_m(
                    np.array([lon.min()]), np.array([lat.min()]),
                    np.array([lon.max()]), np.array([lat.max()]),
                )[0]
            )  # fmt: skip
    want = max(TYPICAL_SPEED_MS * span_s, SPAN_FACTOR * extent)
    return float(np.clip(want, MIN_LENGTH_M, MAX_LENGTH_M))


def batch_colours(batches) -> dict[str, tuple[str, str]]:
    """Each batch's line colour and legend label (its name, shortened): :data:`LINE_COLOURS`
    in turn, in sorted order. Beyond :data:`MAX_LINE_COLOURS` batches the first
    ``MAX_LINE_COLOURS - 1`` keep theirs and the rest share :data:`OTHER_COLOUR` under
    one label, :data:`OTHER_LABEL` (at most MAX_LINE_COLOURS legend entries)."""
    names = sorted({str(b) for b in batches})
    many = len(names) > MAX_LINE_COLOURS
    own = names[: MAX_LINE_COLOURS - 1] if many else names
    out = {
        b: (LINE_COLOURS[k % len(LINE_COLOURS)], short_label(b, LABEL_CHARS))
        for k, b in enumerate(own)
    }
    for b in names[len(own) :]:
        out[b] = (OTHER_COLOUR, OTHER_LABEL)
    return out


def legend_width(names) -> float:
    """Width (px) of a map legend column showing ``names`` (as :class:`SideLegend` counts
    it: the label's text in its 9-pt font, its padding, the line sample and margins)."""
    font = QtGui.QFont()
    font.setPointSizeF(9.0)
    metrics = QtGui.QFontMetricsF(font)
    text = max(metrics.horizontalAdvance(n) for n in names)
    return math.ceil(text + LABEL_PADDING_PX + 20 + 3 + 12)


def line_layer(
    points: pd.DataFrame,
    name: str,
    color: str,
    width: float,
    z: float = 0.0,
    build_index: bool = False,
    lon_west: float | None = None,
) -> DrawData:
    """A map layer of :func:`bearing_line_points`: lines only, never broken.

    The map breaks a leg faster than a ship (:func:`~wakeline.app.map_lod.gap_breaks`);
    a bearing line is a long leg between two points of one time, so with the default
    style every line lost its far end and nothing was drawn (``gaps=False``).
    ``lon_west``: the scene's band (:func:`scene_band`; None: the lines' own)."""
    style = LayerStyle(width=width, symbol_size=0, z=z, gaps=False)
    return prepare_layer(
        points, name, color, style=style, build_index=build_index, lon_west=lon_west
    )


def batch_line_geometry(
    points: pd.DataFrame, lon_west: float | None = None
) -> tuple[LayerGeometry, dict[str, tuple[str, str]]]:
    """The geometry of :func:`bearing_line_points` with a colour and a legend entry per
    batch (:func:`batch_colours`): one curve per batch, in the band ``lon_west`` (the
    scene's, :func:`scene_band`; None: the lines' own). Returns it and the colours."""
    if "line_batch" in points.columns:  # no string split per point (0.4 s per 100k lines)
        batch = points["line_batch"].astype(str)
    else:
        batch = points["batch"].astype(str).str.rsplit("#", n=1).str[0]
    colours = batch_colours(batch.unique())
    label = batch.map({b: lab for b, (_, lab) in colours.items()})
    # layer_geometry: a curve per "sensor", coloured by the sensors' sorted order.
    by_label = {lab: col for col, lab in colours.values()}
    labels = sorted(by_label)
    geom = layer_geometry(
        points.assign(sensor=label.to_numpy()),
        by_label[labels[0]] if labels else LINE_COLOURS[0],
        color_by="sensor",
        colors=tuple(by_label[lab] for lab in labels) or None,
        lon_west=lon_west,
    )
    return geom, colours


def batch_line_layer(
    points: pd.DataFrame, name: str, width: float, z: float = 0.0, build_index: bool = False
) -> tuple[DrawData, dict[str, tuple[str, str]]]:
    """:func:`line_layer` with a colour and a legend entry per batch
    (:func:`batch_line_geometry`). Returns the layer and the colours."""
    geom, colours = batch_line_geometry(points)
    style = LayerStyle(width=width, symbol_size=0, z=z, gaps=False)
    return prepare_layer(geom, name, style=style, build_index=build_index), colours


def line_batches(geom: LayerGeometry, points: pd.DataFrame) -> np.ndarray:
    """Per line (track) of ``geom`` (:func:`batch_line_geometry` of ``points``, made with
    ``source``: two rows per line, ``line_batch`` its batch): its batch's number. A hash
    lookup of the line ids, no string split."""
    ids = points["batch"].to_numpy()[0::2]
    _, code = np.unique(points["line_batch"].to_numpy(dtype=str)[0::2], return_inverse=True)
    return code[pd.Index(ids).get_indexer(geom.batch)].astype("int64")


def window_lines(
    lines: LayerGeometry,
    batch: np.ndarray,
    window: tuple[float, float] | None = None,
    max_lines: int = MAX_LINES,
) -> LayerGeometry:
    """The bearing lines to draw of ``lines`` (every bearing's, :func:`batch_line_geometry`;
    ``batch`` per line, :func:`line_batches`) with time in ``window`` (s; None: all): at
    most ``max_lines`` per batch, spread evenly over its bearings there in time
    (:func:`~wakeline.core.timeline.spread_picks`: the lines :func:`bearing_line_points`
    picks). A window of 20 s drew the few of the whole sequence's lines that fell in it;
    now it draws up to ``max_lines`` of its own. Vectorized; pure, for a worker."""
    t = lines.time_s[lines.starts]
    inside = np.arange(len(t))
    if window is not None:
        inside = np.flatnonzero((t >= window[0]) & (t <= window[1]))
    picks = inside[spread_picks(batch[inside], t[inside], max_lines)]
    keep = np.zeros(len(t), dtype=bool)
    keep[picks] = True
    return geometry_rows(lines, np.repeat(keep, lines.ends - lines.starts))


def bearing_line_points(
    bearings: pd.DataFrame,
    length_m: float = MAX_LENGTH_M,
    max_lines: int = MAX_LINES,
    at_times: pd.DataFrame | None = None,
    source: bool = False,
) -> pd.DataFrame:
    """Bearing lines as two-point tracks: ``sensor, batch, time, lon, lat`` (``batch``:
    ``<batch>#<k>``; with ``source`` also ``line_batch``, the batch itself).

    Per batch, at most ``max_lines`` lines evenly spread over its samples (or, with
    ``at_times`` holding ``batch, maneuver_time``, the samples nearest those times), each
    from the observer (``obs_lon, obs_lat``) ``length_m`` metres along the bearing."""
    cols = ["sensor", "batch", "time", "lon", "lat"]
    if bearings.empty or not {"obs_lon", "obs_lat"} <= set(bearings.columns):
        return pd.DataFrame(columns=cols)
    df = bearings.sort_values(["batch", "time"], kind="stable").reset_index(drop=True)
    batch = df["batch"].astype(str).to_numpy()
    starts = np.flatnonzero(np.r_[True, batch[1:] != batch[:-1]])
    sizes = np.diff(np.r_[starts, len(df)])
    if at_times is None:  # the time window's rule (ties in row order), batches in df order
        group = np.repeat(np.arange(len(starts)), sizes)
        rows = spread_picks(group, np.arange(len(df)), max_lines)
    else:
        t = time_seconds(df["time"])
        want = at_times.assign(batch=at_times["batch"].astype(str))
        first = dict(zip(batch[starts], starts, strict=True))
        last = dict(zip(batch[starts], starts + sizes, strict=True))
        rows = np.array(
            [
                min(
                    first[b] + int(np.searchsorted(t[first[b] : last[b]], s)),
                    last[b] - 1,
                )
                for b, s in zip(want["batch"], time_seconds(want["maneuver_time"]), strict=True)
                if b in first
            ],
            dtype=int,
        )
    sel = df.iloc[rows] if len(rows) else df.iloc[:0]
    sel = sel[np.isfinite(sel["obs_lon"].to_numpy(float)) & np.isfinite(sel["obs_lat"])]
    olon, olat = sel["obs_lon"].to_numpy(float), sel["obs_lat"].to_numpy(float)
    b = np.radians(sel["bearing"].to_numpy(float))
    x, y = length_m * np.sin(b), length_m * np.cos(b)
    lat0 = float(np.mean(olat)) if len(olat) else 0.0
    end_lon = olon + np.degrees(x / (geo.EARTH_RADIUS_M * np.cos(np.radians(lat0))))
    end_lat = olat + np.degrees(y / geo.EARTH_RADIUS_M)
    n = len(sel)
    names = sel["batch"].astype(str).to_numpy().astype(str)
    ids = np.char.add(np.char.add(names, "#"), np.arange(n).astype(str))
    out = pd.DataFrame(
        {
            "sensor": "bearing",
            "batch": np.repeat(ids, 2),
            # Kept a datetime column (not Timestamp objects: 0.1 s per 100k lines).
            "time": sel["time"].repeat(2).reset_index(drop=True),
            "lon": np.column_stack([olon, end_lon]).ravel(),
            "lat": np.column_stack([olat, end_lat]).ravel(),
        }
    )
    if source:
        out["line_batch"] = np.repeat(names, 2)
    return out


@dataclasses.dataclass(frozen=True)
class BearingScene:
    """The bearing map, prepared off the GUI thread (:func:`bearing_scene`): the layers
    (observer, bearing lines, maneuvers when there are detections), each batch's colour
    and label, the lines' length (m), the aspect latitude and the view that frames the
    observer's track and the lines (x0, x1, y0, y1, degrees)."""

    layers: tuple[DrawData, ...]
    colours: dict[str, tuple[str, str]]
    length_m: float
    lat0: float
    target: tuple[float, float, float, float] | None
    #: Every bearing's line (:func:`batch_line_geometry`) and its batch's number: a time
    #: window chooses the lines it draws among them (:func:`window_lines`).
    all_lines: LayerGeometry | None = None
    line_batch: np.ndarray | None = None


def scene_range(layers) -> tuple[float, float, float, float] | None:
    """The view (x0, x1, y0, y1, degrees) around every point of ``layers`` with a
    :data:`FIT_MARGIN` margin (at least :data:`MIN_PAD_M`): the map's own fit padded at
    least 0.01° (a kilometre) then, which left a 1 km harbour scene filling a fifth of the
    view's height (it pads at least 50 m now, ``layer_view.MIN_PAD_M``; docs/map.md)."""
    boxes = [d.geometry.bounds() for d in layers]
    boxes = [b for b in boxes if b is not None and all(map(math.isfinite, b))]
    if not boxes:
        return None
    w, s = min(b[0] for b in boxes), min(b[1] for b in boxes)
    e, n = max(b[2] for b in boxes), max(b[3] for b in boxes)
    pad_y = max((n - s) * FIT_MARGIN, np.degrees(MIN_PAD_M / geo.EARTH_RADIUS_M))
    cos = max(math.cos(math.radians(0.5 * (s + n))), 0.05)
    pad_x = max((e - w) * FIT_MARGIN, np.degrees(MIN_PAD_M / geo.EARTH_RADIUS_M) / cos)
    return (w - pad_x, e + pad_x, s - pad_y, n + pad_y)


def scene_band(bearings: pd.DataFrame, lines: pd.DataFrame) -> float:
    """The band (-180 or 0) a bearing scene is drawn in: the observer's positions and the
    lines' (:func:`bearing_line_points`) together decide it
    (:func:`wakeline.core.geo.lon_band_west`, the map's rule for a layer). Each part
    deciding its own put an observer east of 180° at −180 and the lines it casts west
    across 180° at +180: 360° apart, a view of the whole world."""
    lon = [bearings["obs_lon"].to_numpy(dtype="float64"), lines["lon"].to_numpy(dtype="float64")]
    return geo.lon_band_west(np.concatenate(lon))


def bearing_scene(
    bearings: pd.DataFrame,
    detections: pd.DataFrame,
    length_m: float | None = None,
    build_index: bool = False,
) -> BearingScene | None:
    """The bearing map's layers (pure numpy/pandas: run it in a worker): the observer's
    positions, the bearing lines ``length_m`` metres long (None: :func:`line_length_m`) a
    colour per batch, and the lines at the detections' maneuver times; None when the
    table has no observer position (nothing to draw). ``build_index``: the hover k-d tree
    and position sketch now (a worker's job), not on the GUI thread's first use."""
    if bearings.empty or not {"obs_lon", "obs_lat"} <= set(bearings.columns):
        return None
    length = float(length_m or line_length_m(bearings))
    # Every bearing's line; the ones drawn (at most MAX_LINES per batch) chosen from them.
    every = bearing_line_points(bearings, length, max_lines=max(len(bearings), 1), source=True)
    west = scene_band(bearings, every)
    obs = bearings.rename(columns={"obs_lon": "lon", "obs_lat": "lat"}).assign(sensor="observer")
    observer = prepare_layer(
        obs[["sensor", "batch", "time", "lon", "lat"]],
        LAYER_NAMES[0],
        "#555555",
        style=LayerStyle(width=1.5, symbol_size=3, z=Z_OBSERVER),
        build_index=build_index,
        lon_west=west,
    )
    all_lines, colours = batch_line_geometry(every, west)
    line_batch = line_batches(all_lines, every)
    lines = prepare_layer(
        window_lines(all_lines, line_batch),
        LAYER_NAMES[1],
        style=LayerStyle(width=1.0, symbol_size=0, z=Z_LINES, gaps=False),
        build_index=build_index,
    )
    layers = [observer, lines]
    if len(detections):
        at = bearing_line_points(bearings, length, at_times=detections)
        layers.append(
            line_layer(at, LAYER_NAMES[2], "#d62728", 2.5, Z_MANEUVERS, build_index, west)
        )
    lat = bearings["obs_lat"].to_numpy(float)
    lat0 = float(np.nanmean(lat)) if np.isfinite(lat).any() else 0.0
    target = scene_range(layers[:2])
    return BearingScene(tuple(layers), colours, length, lat0, target, all_lines, line_batch)


def main_map_layers(
    scene: BearingScene,
    view: tuple[float, float, float, float] | None = None,
    size_px: tuple[int, int] | None = None,
    lat0: float | None = None,
    shown: tuple[float, float, float, float] | None = None,
) -> list[DrawData]:
    """The scene's layers for the main map, named by their part (:data:`PARTS`; the
    window names them ``<layer id>/<part>``, :func:`~wakeline.app.layer_view.map_layers`)
    and, with ``view`` (x0, x1, y0, y1, degrees; the range asked for) and ``size_px``,
    decimated and stroked for the view the map will show at the aspect of ``lat0`` (None:
    the scene's) — or for ``shown``, that view already worked out. Pure, for a worker."""
    if shown is None and view is not None and size_px is not None:
        shown = shown_range(view, size_px, scene.lat0 if lat0 is None else lat0)
    out = []
    for data, part in zip(scene.layers, PARTS, strict=False):
        main = dataclasses.replace(data, name=part)
        if part == "lines":  # under the tracks and plots (Z_MAIN_LINES)
            main = dataclasses.replace(main, style=dataclasses.replace(data.style, z=Z_MAIN_LINES))
        out.append(with_paths(relod(main, shown, size_px)) if shown is not None else main)
    return out


def scene_cuts(scene: BearingScene) -> dict:
    """The parts' own time-window cuts of ``scene`` by part name (:data:`PARTS`;
    :func:`~wakeline.app.map_time.window_draw_data`'s ``cut``): the lines are chosen again
    among the window's bearings (:func:`window_lines`); the other parts are cut like point
    layers (no entry)."""
    if scene.all_lines is None:
        return {}
    return {"lines": functools.partial(window_lines, scene.all_lines, scene.line_batch)}


def window_scene_layers(scene: BearingScene, window: tuple[float, float] | None) -> list[DrawData]:
    """The scene's layers (the Bearing-only dock's map) cut to ``window`` (s; None: the
    layers as prepared), each part as the main map cuts its copy
    (:func:`~wakeline.app.map_time.window_draw_data` with :func:`scene_cuts`). Pure, for a
    worker."""
    if window is None:
        return list(scene.layers)
    cuts = scene_cuts(scene)
    return [
        window_draw_data(data, window, None, None, cuts.get(part))
        for data, part in zip(scene.layers, PARTS, strict=False)
    ]


def bearing_layer_view(
    bearings: pd.DataFrame,
    detections: pd.DataFrame,
    report: list[dict] | None = None,
    scene: BearingScene | None = None,
    parts: list[DrawData] | None = None,
    params=None,
    statistic: pd.DataFrame | None = None,
) -> LayerView:
    """A bearing layer's view for the main window (pure, for a worker): the bearing
    table as its points, no tracks for the batch table, and in ``extra`` the ``scene``
    (:func:`bearing_scene`; the Bearing-only dock draws it), the main map's ``parts``
    (:func:`main_map_layers`; made here from the scene when not given), the
    ``detections``, the detector's ``report`` and, with the detector's ``params``, the
    Detail panel's ``curves`` (:func:`~wakeline.app.detail.sequence_curves`: z over
    every sequence is not computed on the GUI thread; from the detector's ``statistic``
    when given, the one its detections came from, else computed)."""
    if parts is None:
        parts = main_map_layers(scene) if scene is not None else []
    summary = batch_summary(EMPTY_POINTS)
    cuts = scene_cuts(scene) if scene is not None else {}
    extra = {
        "scene": scene,
        "parts": tuple(parts),
        "cuts": cuts,  # a part's own time-window cut (map_time.window_draw_data)
        "detections": detections,
        "report": list(report or []),
    }
    if params is not None:
        from .detail import sequence_curves

        extra["curves"] = (params, sequence_curves(bearings, params, statistic=statistic))
    return LayerView(bearings, summary, {}, None, None, display_text(summary), extra)


def layer_meta(file: str, sha256: str, view: LayerView) -> dict:
    """A bearing layer's ``meta`` (kept in the project): the file it was read from and
    its hash, the detector's per-batch report and the lines' length (m)."""
    scene = view.extra.get("scene")
    return {
        "file": file,
        "sha256": sha256,
        "report": view.extra.get("report", []),
        "length_m": scene.length_m if scene is not None else None,
        # how the file was read (--map, --origin) and where its lines went
        "read_options": view.extra.get("read_options", {}),
        "read": view.extra.get("read", {}),
    }


#: The columns of the detector's table (:func:`~wakeline.core.bearing.detect_with_report`).
DETECTION_COLUMNS = ["batch", "detect_time", "maneuver_time", "z"]


def layer_detections(layer) -> pd.DataFrame:
    """A bearing layer's detections (its ``detections`` table), or an empty table with the
    detector's columns when it was stored without one."""
    found = layer.tables.get("detections")
    return found if found is not None else pd.DataFrame(columns=DETECTION_COLUMNS)


def bearing_stats(layer, tr=str) -> str:
    """The Statistics panel's text for a bearing layer: its bearings, sequences, time
    span and detections (``tr``: the window's translation)."""
    points = layer.points
    detections = layer_detections(layer)
    lines = [
        f"{tr('Layer')}: {layer.name} [{layer.kind}]  ({layer.id})",
        f"{tr('Bearings')}: {len(points):,}   {tr('Sequences')}: {points['batch'].nunique():,}"
        f"   {tr('Detections')}: {len(detections):,}",
    ]
    if len(points):
        lines.append(f"{tr('Time')}: {points['time'].min()} – {points['time'].max()}")
    if layer.meta.get("length_m"):
        lines.append(f"{tr('Bearing lines')}: {layer.meta['length_m']:,.0f} m")
    return "\n".join(lines)


def layer_scene(layer, build_index: bool = True) -> BearingScene | None:
    """The scene of a stored bearing layer (:class:`~wakeline.core.session.Layer` of kind
    ``bearing``), its lines as long as when it was read (``meta["length_m"]``)."""
    detections = layer_detections(layer)
    return bearing_scene(layer.points, detections, layer.meta.get("length_m"), build_index)


def detection_titles() -> dict[str, str]:
    """The detections table's column titles in the current language, by column (the
    Chinese window showed the column names: "batch", operator test 7, D11)."""
    return {
        "batch": QtCore.QCoreApplication.translate("BearingView", "batch"),
        "detect_time": QtCore.QCoreApplication.translate("BearingView", "detect_time"),
        "maneuver_time": QtCore.QCoreApplication.translate("BearingView", "maneuver_time"),
        "z": "z",
    }


class DetectionsModel(QtCore.QAbstractTableModel):
    """A thin table model over the detections the core returned."""

    def __init__(self, table: pd.DataFrame | None = None, parent=None) -> None:
        super().__init__(parent)
        self.table = table if table is not None else pd.DataFrame(columns=["batch"])

    def set_table(self, table: pd.DataFrame) -> None:
        self.beginResetModel()
        self.table = table.reset_index(drop=True)
        self.endResetModel()

    def rowCount(self, parent=None) -> int:  # noqa: N802 (Qt API)
        return 0 if parent is not None and parent.isValid() else len(self.table)

    def columnCount(self, parent=None) -> int:  # noqa: N802 (Qt API)
        return 0 if parent is not None and parent.isValid() else len(self.table.columns)

    def data(self, index, role=QtCore.Qt.ItemDataRole.DisplayRole):
        if role not in (QtCore.Qt.ItemDataRole.DisplayRole, QtCore.Qt.ItemDataRole.UserRole):
            return None
        value = self.table.iat[index.row(), index.column()]
        if role == QtCore.Qt.ItemDataRole.UserRole:
            return value
        if isinstance(value, pd.Timestamp):
            return value.strftime("%Y-%m-%d %H:%M:%S")
        if isinstance(value, float):
            return f"{value:.2f}"
        return str(value)

    def headerData(self, section, orientation, role=QtCore.Qt.ItemDataRole.DisplayRole):  # noqa: N802
        if role == QtCore.Qt.ItemDataRole.DisplayRole and (
            orientation == QtCore.Qt.Orientation.Horizontal
        ):
            name = str(self.table.columns[section])
            return detection_titles().get(name, name)
        return None

    def sort(self, column: int, order=QtCore.Qt.SortOrder.AscendingOrder) -> None:
        if not len(self.table.columns):
            return
        self.beginResetModel()
        self.table = self.table.sort_values(
            self.table.columns[column],
            ascending=order == QtCore.Qt.SortOrder.AscendingOrder,
            kind="stable",
        ).reset_index(drop=True)
        self.endResetModel()


class BearingView(QtWidgets.QWidget):
    """Map of bearing lines and the table of detections, with CSV export, and the lines'
    length (:attr:`length_box`, metres; its lowest value: from the data).

    ``scene_shown`` follows every scene :meth:`show_result` draws in full (the main
    window's time controller then cuts it to the time window, :meth:`draw_layers`).
    :attr:`executor` (the main window's LOD worker: ``executor(job, done)``) makes the
    scene of a new line length off the GUI thread; without one it is made here."""

    scene_shown = QtCore.Signal()
    #: The operator set another line length (:meth:`set_line_length`); the scene shown
    #: now has it (the main window prepares its map's copy of the layer again).
    length_changed = QtCore.Signal()

    def __init__(self, parent=None) -> None:
        super().__init__(parent)
        self.map = MapCanvas(self)
        self.model = DetectionsModel(parent=self)
        self.table = QtWidgets.QTableView(self)
        self.table.setModel(self.model)
        self.table.setSortingEnabled(True)
        self.table.setSelectionBehavior(QtWidgets.QAbstractItemView.SelectionBehavior.SelectRows)
        # One line per detection (times wrapped onto two lines took a narrow dock's room).
        self.table.setWordWrap(False)
        self.table.verticalHeader().hide()
        rows = self.table.verticalHeader()
        rows.setDefaultSectionSize(self.table.fontMetrics().height() + 8)
        rows.setSectionResizeMode(QtWidgets.QHeaderView.ResizeMode.Fixed)
        self.export_button = QtWidgets.QPushButton(self)
        self.export_button.clicked.connect(self._export_dialog)
        self.length_label = QtWidgets.QLabel(self)
        self.length_box = self._length_box()
        self.length_label.setBuddy(self.length_box)
        length_row = QtWidgets.QHBoxLayout()
        length_row.addWidget(self.length_label)
        length_row.addWidget(self.length_box, 1)
        self.log = QtWidgets.QPlainTextEdit(self)
        self.log.setReadOnly(True)
        self.log.setMaximumBlockCount(2000)
        side = QtWidgets.QWidget(self)
        lay = QtWidgets.QVBoxLayout(side)
        lay.setContentsMargins(0, 0, 0, 0)
        lay.addLayout(length_row)
        lay.addWidget(self.table, 3)
        lay.addWidget(self.export_button)
        lay.addWidget(self.log, 1)
        side.setMinimumWidth(MIN_SIDE_PX)
        # Under the map (a narrow dock) the table keeps its header and MIN_TABLE_ROWS rows
        # and the report two lines (the map had taken all but one clipped row).
        self.table.setMinimumHeight(self.table_min_height())
        self.log.setMinimumHeight(2 * self.log.fontMetrics().lineSpacing() + 12)
        self.side = side
        # The map's legend column is reserved for its three short names, not for the
        # 26 characters of a main map's layer names (230 px of a dock's width).
        self.map.legend.widest = legend_width(LAYER_NAMES)
        self.map.legend.updateSize()
        # The plot area keeps MIN_PLOT_PX beside the axis and the legend column.
        self.map.setMinimumWidth(self.map_min_width())
        self.split = split = QtWidgets.QSplitter(QtCore.Qt.Orientation.Horizontal, self)
        split.setChildrenCollapsible(False)
        split.addWidget(self.map)
        split.addWidget(side)
        split.setStretchFactor(0, 3)
        split.setStretchFactor(1, 2)
        split.setSizes(list(SPLIT_WEIGHTS))  # relative: the map 3/5 from the first show
        outer = QtWidgets.QVBoxLayout(self)
        outer.setContentsMargins(0, 0, 0, 0)
        outer.addWidget(split)
        self.bearings = pd.DataFrame()
        self.detections = pd.DataFrame()
        self._report: list[dict] = []
        #: The bearing lines' length (m) set by :meth:`set_line_length`; None: from the
        #: data (:func:`line_length_m`).
        self.fixed_length_m: float | None = None
        #: The length the lines are drawn with now.
        self.length_m = MAX_LENGTH_M
        #: Each batch's line colour and legend label, as drawn now.
        self.colours: dict[str, tuple[str, str]] = {}
        #: The layers drawn now (None: none).
        self.scene: BearingScene | None = None
        #: Runs a scene's making for a new line length: ``executor(job, done)`` calls
        #: ``done(job())`` on the GUI thread (the main window's LOD worker); None: here.
        self.executor = None
        self._scene_gen = 0  # the newest scene asked for (a length, or data shown)
        self._wanted: tuple | None = None  # a length's scene waiting for the executor
        self._building = False  # one is being made by the executor
        self.retranslate()

    def report_text(self) -> str:
        """The detector's line per batch (tested windows, or why none was) in the
        window's language: the only explanation of a batch without detections."""
        return "\n".join(shown(line) for line in report_lines(self._report or []))

    def retranslate(self) -> None:
        """Set the texts in the current language (the main window calls it again when the
        language changes: this view is made before the window installs its translator)."""
        self.export_button.setText(self.tr("Export detections…"))
        self.length_box.setSuffix(" " + self.tr("m"))
        if self._report:
            self.log.setPlainText(self.report_text())
            if self.scene is None:
                self.log.appendPlainText(self.tr("No observer position: no bearing lines to draw."))
        self.length_label.setText(self.tr("Line length"))
        self.length_box.setSpecialValueText(self.tr("from the data"))
        self.length_box.setToolTip(
            self.tr(
                "Length of the bearing lines from the observer; lowest value: from the "
                "data (past the targets' ranges when known, else the scene's scale)"
            )
        )
        self.map.setLabel("bottom", self.tr("longitude"), units="°")
        self.map.setLabel("left", self.tr("latitude"), units="°")
        n = self.model.columnCount()
        if n:  # the detections' column titles in the new language
            self.model.headerDataChanged.emit(QtCore.Qt.Orientation.Horizontal, 0, n - 1)
        words = legend_words()  # the legend's fixed words, as drawn, in the new language
        for name, part in zip(LAYER_NAMES, PARTS, strict=True):
            if name in self.map.layer_names():
                self.map.relabel_layer(name, functools.partial(reworded, part=part, words=words))

    def _length_box(self) -> QtWidgets.QDoubleSpinBox:
        """The line length's spin box, from the core's parameter
        (:data:`LENGTH_FIELD`: metres, its range; its lowest value reads "from the data",
        set by :meth:`retranslate`)."""
        meta = LENGTH_FIELD.metadata
        box = QtWidgets.QDoubleSpinBox(self)
        box.setDecimals(0)
        box.setRange(meta["lo"], meta["hi"])
        box.setValue(LENGTH_FIELD.default)
        box.setSuffix(f" {meta['unit']}")
        box.setStepType(QtWidgets.QAbstractSpinBox.StepType.AdaptiveDecimalStepType)
        box.setKeyboardTracking(False)  # typed: one change at Enter, not one per digit
        box.valueChanged.connect(self._length_edited)
        return box

    def _length_edited(self, value: float) -> None:
        self.set_line_length(value if value > LENGTH_FIELD.metadata["lo"] else None)

    def _show_length(self, length_m: float) -> None:
        """The length box shows ``length_m`` (m), the length drawn now (no signal)."""
        self.length_box.blockSignals(True)
        self.length_box.setValue(length_m)
        self.length_box.blockSignals(False)

    @property
    def busy(self) -> bool:
        """A line length's scene is being made or waits to be."""
        return self._building or self._wanted is not None

    def table_min_height(self) -> int:
        """Height (px) of the table's header and :data:`MIN_TABLE_ROWS` rows, with the
        room of a horizontal scroll bar."""
        header = self.table.horizontalHeader().sizeHint().height()
        rows = MIN_TABLE_ROWS * self.table.verticalHeader().defaultSectionSize()
        bar = self.table.style().pixelMetric(QtWidgets.QStyle.PixelMetric.PM_ScrollBarExtent)
        return header + rows + bar + 2 * self.table.frameWidth()

    def set_line_length(self, length_m: float | None) -> None:
        """Draw the bearing lines ``length_m`` metres long (None or 0: from the data,
        :func:`line_length_m`); redraws what is shown: the scene is made again by
        :attr:`executor` (off the GUI thread; else here) and swapped in when done, then
        ``length_changed``. Of changes made while one is being made only the last is
        made next; a scene asked for before another length or other data is dropped."""
        self.fixed_length_m = float(length_m) if length_m else None
        if not len(self.bearings):
            return
        self._scene_gen += 1
        self._wanted = (
            self._scene_gen,
            self.bearings,
            self.detections,
            self._report,
            self.fixed_length_m,
        )
        if self.executor is None or not self._building:
            self._build_next()

    def _build_next(self) -> None:
        """Make the scene of the newest length asked for (:attr:`executor`, or here)."""
        wanted, self._wanted = self._wanted, None
        _gen, bearings, detections, _report, length = wanted

        def job() -> BearingScene | None:
            return bearing_scene(bearings, detections, length, build_index=True)

        if self.executor is None:
            self._scene_built(wanted, job())
            return
        self._building = True
        self.executor(job, lambda scene: self._scene_built(wanted, scene))

    def _scene_built(self, wanted: tuple, scene: BearingScene | None) -> None:
        """A length's scene is made (GUI thread): swapped in unless a newer length or
        other data were asked for meanwhile (then the newer one is made next)."""
        self._building = False
        if self._wanted is not None:
            self._build_next()  # this one is stale: make the newest
            return
        gen, bearings, detections, report, _length = wanted
        if scene is None or gen != self._scene_gen or self.bearings is not bearings:
            return  # failed (the old drawing stays), or other data shown meanwhile
        self._show(bearings, detections, report, scene)
        self.length_changed.emit()

    def map_min_width(self) -> int:
        """The map widget's minimum width: its plot area at least :data:`MIN_PLOT_PX`."""
        axis = self.map.getAxis("left")
        # The axis: its tick labels and title; then the plot's borders and margins.
        chrome = axis.textWidth + axis.label.boundingRect().height() + 6
        return math.ceil(MIN_PLOT_PX + chrome + self.map.legend.widest)

    def minimumSizeHint(self) -> QtCore.QSize:  # noqa: N802 (Qt API)
        """As narrow as the map with the table under it (:meth:`resizeEvent` puts it
        there when the view is narrower than both side by side)."""
        return QtCore.QSize(max(self.map.minimumWidth(), MIN_SIDE_PX), 320)

    def resizeEvent(self, event) -> None:  # noqa: N802 (Qt API)
        wide = event.size().width() >= self.map.minimumWidth() + MIN_SIDE_PX + 8
        want = QtCore.Qt.Orientation.Horizontal if wide else QtCore.Qt.Orientation.Vertical
        if self.split.orientation() != want:
            self.split.setOrientation(want)
            self.split.setSizes(list(SPLIT_WEIGHTS))
        super().resizeEvent(event)

    def show_result(
        self,
        bearings: pd.DataFrame,
        detections: pd.DataFrame,
        report: list[dict] | None = None,
        length_m: float | None = None,
        scene: BearingScene | None = None,
    ) -> None:
        """Draw the observer, the bearing lines (a colour per batch) and the detections;
        list the report; fit the view to the observer's track and the lines.

        The lines are ``length_m`` long if given, else :meth:`set_line_length`'s, else as
        the data suggest (:func:`line_length_m`: the targets' ranges when known, else the
        scene's scale from the sequences' duration and the observer's track). ``scene``:
        the layers prepared in a worker (:func:`bearing_scene`; else prepared here). A
        line length's scene still being made (:meth:`set_line_length`) is dropped."""
        if scene is None:
            length = length_m or self.fixed_length_m
            scene = bearing_scene(bearings, detections, length)
        self._scene_gen += 1
        self._wanted = None
        self._show(bearings, detections, report, scene)

    def _show(
        self,
        bearings: pd.DataFrame,
        detections: pd.DataFrame,
        report: list[dict] | None,
        scene: BearingScene | None,
    ) -> None:
        """Swap in ``scene`` (made already) with its data; fit the view to it."""
        self.bearings, self.detections, self._report = bearings, detections, report or []
        self.model.set_table(detections)
        self.table.resizeColumnsToContents()
        self.log.setPlainText(self.report_text())
        for name in list(self.map.layer_names()):
            self.map.remove_layer(name)
        self.scene = scene
        if scene is None:
            self.log.appendPlainText(self.tr("No observer position: no bearing lines to draw."))
            return
        self.length_m, self.colours = scene.length_m, scene.colours
        self._show_length(scene.length_m)
        self.draw_layers(scene.layers)
        self.map.set_true_aspect(scene.lat0)
        self.map.show_range(scene.target)
        self.scene_shown.emit()

    def draw_layers(self, layers) -> None:
        """Swap in the map's layers (the scene's, or those cut to a time window:
        :func:`window_scene_layers`); the view is kept."""
        words = legend_words()
        for data, part in zip(layers, PARTS, strict=False):  # the scene's order
            self.map.set_draw_data(in_language(data, part, words))

    def clear(self) -> None:
        """Show nothing (the bearing layer shown was removed)."""
        self.bearings, self.detections, self._report = pd.DataFrame(), pd.DataFrame(), []
        self._scene_gen += 1
        self._wanted = None
        self.model.set_table(pd.DataFrame(columns=["batch"]))
        self.log.clear()
        for name in list(self.map.layer_names()):
            self.map.remove_layer(name)
        self.scene, self.colours = None, {}

    def fit_range(self) -> tuple[float, float, float, float] | None:
        """The view (x0, x1, y0, y1, degrees) around the observer's track and the lines
        with a :data:`FIT_MARGIN` margin (:func:`scene_range`); None when nothing is drawn."""
        return self.scene.target if self.scene is not None else None

    def export(self, path: str | Path) -> None:
        """Write the detections as CSV (``batch,detect_time,maneuver_time,z``)."""
        write_csv(self.model.table, path)

    def _export_dialog(self) -> None:
        path, _ = QtWidgets.QFileDialog.getSaveFileName(
            self, self.tr("Export detections"), "detections.csv", "CSV (*.csv)"
        )
        if path:
            try:
                self.export(path)
            except OSError as exc:
                QtWidgets.QMessageBox.warning(self, self.tr("Cannot export"), str(exc))
