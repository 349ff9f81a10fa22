"""A review decision's view made from the layer's earlier one (session 31): only the lines
of the targets it changes made again (:func:`wakeline.app.layer_view.relabel_view`,
:mod:`wakeline.core.line_splice`) — the same view as a whole :func:`prepare_view` of the
same decided points, over random sequences of rejects, accepts, joins by hand, undos and
redos, on a small and a medium associated layer. Headless (no window)."""

import numpy as np
import pandas as pd
import pytest

from wakeline.app import layer_view
from wakeline.app.layer_view import prepare_view, relabel_view
from wakeline.core import review as R
from wakeline.core import simulate
from wakeline.core.review_session import bind, decided_points, relabeled, snapshot
from wakeline.core.session import Session

GEOMETRY = ("lon", "lat", "starts", "ends", "track", "sensor", "batch", "time_s", "speed_kn")
GEOMETRY += ("group", "gap_break", "point_batch")
VIEW = (-180.0, 180.0, -80.0, 80.0)


def _layer(n_ships: int, seed: int):
    pts = simulate.segments_scene(seed=seed, n_ships=n_ships, area_km=15 + n_ships)
    s = Session()
    src = s.add_layer("seg.csv", "source", pts)
    (lay,) = s.apply_result(src.id, s.run_step(src.id, "associate"))
    state, _ = bind(s, lay)
    return lay, state


def _same_view(quick, full, probes) -> None:
    pd.testing.assert_frame_equal(quick.points, full.points)
    pd.testing.assert_frame_equal(quick.summary, full.summary)
    assert quick.ranges == full.ranges
    assert set(quick.text) == set(full.text)
    for k in full.text:
        np.testing.assert_array_equal(quick.text[k], full.text[k])
    assert quick.extra["table_index"].keys == full.extra["table_index"].keys
    assert quick.extra.get("plots") == full.extra.get("plots")
    a, b = quick.draw.geometry, full.draw.geometry
    for name in GEOMETRY:
        x, y = getattr(a, name), getattr(b, name)
        if x is None or y is None:
            assert x is None and y is None, name
        else:
            assert x.dtype.hasobject == y.dtype.hasobject, name
            assert len(x) == len(y) and (x == y).all(), name
    assert (a.labels, a.colors, a.relative, a.lon_west) == (
        b.labels,
        b.colors,
        b.relative,
        b.lon_west,
    )
    sa, sb = a.sketch(), b.sketch()
    assert sa.n == sb.n
    np.testing.assert_array_equal(sa.lon, sb.lon)
    np.testing.assert_array_equal(sa.lat, sb.lat)
    assert len(quick.draw.curves) == len(full.draw.curves)
    for c, d in zip(quick.draw.curves, full.draw.curves, strict=True):
        np.testing.assert_array_equal(c.lon, d.lon)
        np.testing.assert_array_equal(c.lat, d.lat)
    assert (quick.draw.lod_box, quick.draw.px, quick.draw.view) == (
        full.draw.lod_box,
        full.draw.px,
        full.draw.view,
    )
    # hover: the kept tree finds the point a new one finds (the same place, a point of it)
    for lon, lat in probes:
        d1, i1 = a.nearest(lon, lat)
        d2, i2 = b.nearest(lon, lat)
        assert d1 == pytest.approx(d2, abs=1e-12)
        assert (a.lon[i1], a.lat[i1]) == (b.lon[i2], b.lat[i2])


def _decisions(state: R.ReviewState, rng, n: int):
    """``n`` random changes: mostly rejects, some accepts and joins of two targets by
    hand, undos and redos of earlier ones (as the window's undo stack makes them)."""
    done: list[R.Change] = []
    undone: list[R.Change] = []
    for _ in range(n):
        pending = np.flatnonzero(state.status == "pending")
        roll = rng.random()
        if roll < 0.2 and done:
            change = done.pop().inverse()
            undone.append(change)
        elif roll < 0.3 and undone:
            change = undone.pop().inverse()
            done.append(change)
        elif roll < 0.4:
            tg = state.target_of_track()
            names = np.unique(tg)
            if len(names) < 2:
                continue
            a, b = rng.choice(names, 2, replace=False)
            first = [state.members(str(a))[0], state.members(str(b))[0]]
            change = R.merge(state, first)
            done.append(change)
        elif len(pending):
            pid = state.proposals["proposal"].iloc[int(rng.choice(pending))]
            change = (R.accept if roll < 0.5 else R.reject)(state, pid)
            done.append(change)
        else:
            continue
        if change.empty:
            continue
        state.apply(change)
        yield


@pytest.mark.parametrize("n_ships, seeds", [(8, (1, 2, 3)), (40, (4, 5))])
def test_a_decisions_lines_made_alone_are_the_whole_views(n_ships, seeds, monkeypatch):
    monkeypatch.setattr(layer_view, "RELABEL_MAX_SHARE", 1.0)  # every decision, even large
    made = 0
    for seed in seeds:
        lay, state = _layer(n_ships, seed)
        rng = np.random.default_rng(seed)
        pts = decided_points(lay, snapshot(state), None)
        previous = prepare_view(pts, lay.kind, lay.color, lay.name)
        lon = previous.draw.geometry.lon
        lat = previous.draw.geometry.lat
        probes = list(
            zip(
                rng.uniform(lon.min(), lon.max(), 20),
                rng.uniform(lat.min(), lat.max(), 20),
                strict=True,
            )
        )
        size_px = (800, 600)
        x0, x1 = float(lon.min()), float(lon.max())
        y0, y1 = float(lat.min()), float(lat.max())
        views = [None, (x0, (x0 + x1) / 2, y0, (y0 + y1) / 2), VIEW]
        cache: dict = {}
        for k, _ in enumerate(_decisions(state, rng, 25)):
            snap = snapshot(state)
            quick = relabeled(previous.points, snap, cache)
            assert quick is not None
            pts, per_track = quick
            whole = decided_points(
                lay.__class__(**{**lay.__dict__, "points": previous.points}), snap, None
            )
            pd.testing.assert_frame_equal(pts, whole)  # the decided points, taken per track
            view = views[k % len(views)]
            sz = size_px if view is not None else None
            new = relabel_view(previous, pts, per_track, lay.kind, view, sz)
            if new is None:  # no target changed (an accept of a pending proposal)
                old = previous.summary["target"].to_numpy(dtype=object)
                assert (old == per_track).all()
                continue
            made += 1
            full = prepare_view(pts, lay.kind, lay.color, lay.name, view, sz, previous=previous)
            _same_view(new, full, probes)
            previous = new  # the next decision from this one (its tree's rows mapped again)
    assert made >= 10


def test_what_the_lines_alone_do_not_make():
    """Not a relabel: another kind of layer, other rows, no target changed, too many
    lines (the share) — None, and the window makes the whole view."""
    lay, state = _layer(8, 2)
    pts = decided_points(lay, snapshot(state), None)
    previous = prepare_view(pts, lay.kind, lay.color, lay.name)
    quick = relabeled(previous.points, snapshot(state), {})
    assert quick is not None
    pts, per_track = quick
    assert relabel_view(previous, pts, per_track, lay.kind) is None  # nothing changed
    pid = state.proposals["proposal"].iloc[0]
    state.apply(R.reject(state, pid))
    pts, per_track = relabeled(previous.points, snapshot(state), {})
    assert relabel_view(previous, pts, per_track, "source") is None
    assert relabel_view(previous, pts.iloc[1:].reset_index(drop=True), per_track, lay.kind) is None
    touched = relabel_view(previous, pts, per_track, lay.kind)
    assert touched is not None
    # every track moved to a target of its own: more than the share of the points
    alone = pts.assign(target=pts["sensor"].astype(str) + ":" + pts["batch"].astype(str))
    from wakeline.core.tracks import known_order, remember_order

    remember_order(alone, *known_order(previous.points))
    labels = previous.summary["sensor"].astype(str) + ":" + previous.summary["batch"].astype(str)
    assert relabel_view(previous, alone, labels.to_numpy(dtype=object), lay.kind) is None
