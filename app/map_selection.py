"""The selection's curves, pure numpy (worker-safe): every selected batch in its own colour.

Colours come from the batch palette without colours that look like those of the layers
shown (and without the oranges of the selection halo), so a selected batch stands out
from its layer; beyond the palette, batches share colours (one curve per colour). The
palette's order keeps the first colours apart for a deuteranope too (no red next to green).
"""

import numpy as np
import pandas as pd

from wakeline.app.map_colors import apart_from
from wakeline.app.map_draw import BATCH_PALETTE, Curve, _tr, reused_label, unwrap_tracks
from wakeline.app.map_lod import gap_breaks, nan_join

#: Colours of selected batches: the batch palette without the oranges of the halo.
SELECTION_PALETTE = tuple(c for c in BATCH_PALETTE if c not in ("#ff7f0e", "#e6550d"))
#: At most this many batches of a selection get their own legend line.
LEGEND_BATCHES = 12


class _SelectedTracks:
    """The few selected tracks sorted (sensor, batch, time) with numpy alone: the map's
    full :func:`~wakeline.app.map_draw.layer_geometry` (pandas sort, times, speeds) costs
    the GUI thread tens of ms for a click."""

    def __init__(self, points: pd.DataFrame, lon_west: float = -180.0) -> None:
        s_code, s_names = pd.factorize(points["sensor"].astype(str), sort=True)
        b_code, b_names = pd.factorize(points["batch"].astype(str), sort=True)
        t = points["time"]
        if isinstance(t.dtype, pd.DatetimeTZDtype) or np.issubdtype(t.dtype, np.datetime64):
            t = t.to_numpy(dtype="datetime64[ns]").view("int64").astype("float64") / 1e9
        else:
            t = pd.to_numeric(t, errors="coerce").to_numpy(dtype="float64")
        order = np.lexsort((t, b_code, s_code))
        s_code, b_code = s_code[order], b_code[order]
        n = len(order)
        new = np.ones(n, dtype=bool)
        new[1:] = (s_code[1:] != s_code[:-1]) | (b_code[1:] != b_code[:-1])
        self.starts = np.flatnonzero(new)
        sizes = np.diff(np.append(self.starts, n))
        self.n_points, self.n_tracks = n, len(self.starts)
        self.track = np.cumsum(new) - 1
        lon = points["lon"].to_numpy(dtype="float64")[order]
        self.lon = unwrap_tracks(lon, self.starts, sizes, lon_west)  # in its layer's band
        self.lat = points["lat"].to_numpy(dtype="float64")[order]
        self.sensor = np.asarray(s_names, dtype=object)[s_code[self.starts]]
        self.batch = np.asarray(b_names, dtype=object)[b_code[self.starts]]
        self.gap_break = gap_breaks(
            t[order], self.starts, np.append(self.starts[1:], n), lon, self.lat
        )


def selection_curves(
    points: pd.DataFrame,
    avoid: set[str] | frozenset[str] = frozenset(),
    gaps: bool = True,
    lon_west: float = -180.0,
    own: dict[tuple[str, str], str] | None = None,
) -> tuple[Curve, tuple[Curve, ...], dict[tuple[str, str], str]]:
    """The halo (every selected track, full resolution), one curve per colour, and the
    colour of every selected track by ``(sensor, batch)``.

    A curve's label is its first batch (``sensor:batch`` when several sensors; ``· +k same colour`` when k
    more share the colour); beyond :data:`LEGEND_BATCHES` colours the last line says
    "… and N more selected" and the rest have none.
    ``lon_west``: the band of the layer the tracks are drawn in (its geometry's
    ``lon_west``), so they lie on it across 180°.
    ``own``: tracks the legend already names in a colour of their own (a layer coloured
    by track, :func:`~wakeline.app.map_draw.named_tracks`): drawn in that colour under the
    halo, with no second legend line ("9001:412434718-0" and "9001 · 412434718-0" named
    one track twice in two colours, operator test 10).
    """
    geom = _SelectedTracks(points, lon_west)
    keep = np.ones(geom.n_points, dtype=bool)
    brk = np.zeros(geom.n_points, dtype=bool)
    brk[geom.starts] = True
    if gaps:  # as the layer is drawn (a compressed layer's long legs are no gaps)
        brk |= geom.gap_break
    lon, lat = nan_join(geom.lon, geom.lat, keep, brk)
    halo = Curve("", "#ffaa00", lon, lat)
    palette = list(apart_from(SELECTION_PALETTE, avoid)) or list(SELECTION_PALETTE)
    k = len(palette)
    own = own or {}
    mine = [own.get((str(s), str(b))) for s, b in zip(geom.sensor, geom.batch, strict=True)]
    rest = np.flatnonzero([c is None for c in mine])  # the tracks the selection names
    n_rest = len(rest)
    color_of_track = np.full(geom.n_tracks, -1, dtype="int64")
    color_of_track[rest] = np.arange(n_rest) % k
    color_of_point = color_of_track[geom.track] if geom.n_points else np.zeros(0, "int64")
    curves = []
    said = False  # a reused colour explained in words once
    groups = min(k, n_rest)
    for g in range(groups):
        x, y = nan_join(geom.lon, geom.lat, color_of_point == g, brk)
        more = int(np.count_nonzero(color_of_track == g)) - 1
        label = ""
        if groups > LEGEND_BATCHES and g == LEGEND_BATCHES - 1:
            # the legend stops here and says so (it stopped silently: h225 item 2)
            named = int(np.count_nonzero((color_of_track >= 0) & (color_of_track < g)))
            label = _tr("… and {0} more selected").format(f"{n_rest - named:,}")
        elif g < LEGEND_BATCHES:
            # "(+k same colour)": k more selected tracks share this colour (the palette
            # has fewer colours than tracks); it said "(+k)", which nobody could read
            # "sensor · batch", as the review names a proposal's pieces in the legend
            first = rest[g]
            name = f"{geom.sensor[first]} · {geom.batch[first]}"
            label = reused_label(name, more, said)
            said = said or more > 0
        curves.append(Curve(label, palette[g], x, y))
    track_colour = [c if c is not None else palette[color_of_track[i]] for i, c in enumerate(mine)]
    for colour in dict.fromkeys(c for c in mine if c is not None):
        on = np.asarray([c == colour for c in mine], dtype=bool)
        x, y = nan_join(geom.lon, geom.lat, on[geom.track], brk)
        curves.append(Curve("", colour, x, y))
    colors = {
        (str(s), str(b)): c for s, b, c in zip(geom.sensor, geom.batch, track_colour, strict=True)
    }
    return halo, tuple(curves), colors
