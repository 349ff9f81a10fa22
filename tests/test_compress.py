import json

import numpy as np
import pandas as pd
import pytest
from test_maneuver import legs, track_from_xy

from wakeline.app.cli import main
from wakeline.core import simulate
from wakeline.core.compress import (
    compress_with,
    douglas_peucker_count_mask,
    douglas_peucker_mask,
)
from wakeline.core.evaluate import SEED000_TABLE1, evaluate_maneuver, match_turns
from wakeline.core.maneuver import detect
from wakeline.core.tracks import TrackIndex, local_xy, sort_points, track_index


def test_keeping_every_point_gives_zero_error():
    df = simulate.maneuver_tracks(3, "short", 300.0, seed=1)
    pts = sort_points(df)
    comp = compress_with(None, np.ones(len(pts), bool), refine=False, sorted_points=pts)
    assert comp.report()["overall"]["dis_e_m"] == pytest.approx(0.0, abs=1e-6)


def test_noise_free_polyline_is_exact_with_its_vertices():
    x, y = legs([10.0, 70.0, 20.0], [10, 12, 9])
    df = track_from_xy(x, y)
    keep = np.zeros(len(df), bool)
    keep[[10, 22]] = True
    for refine in (False, True):
        comp = compress_with(df, keep, refine=refine)
        # straight in the plane about the first point; in the plane about the track's
        # centre (azimuthal equidistant, 35 km off) its 77 km bow by 1.4 cm (measured)
        assert comp.report()["overall"]["dis_e_m"] < 0.02
        assert len(comp.kept_points()) == 4


def test_least_squares_vertices_beat_raw_vertices_on_simulation():
    df = simulate.maneuver_tracks(30, "medium", 300.0, seed=2)
    result = detect(df)
    raw = compress_with(
        None, result.is_maneuver, refine=False, sorted_points=result.points
    ).report()
    ls = compress_with(None, result.is_maneuver, refine=True, sorted_points=result.points).report()
    assert ls["overall"]["dis_e_true_m"] < 0.75 * raw["overall"]["dis_e_true_m"]
    assert ls["overall"]["dis_e_m"] < raw["overall"]["dis_e_m"]
    assert ls["overall"]["ratio"] == raw["overall"]["ratio"] < 0.15


@pytest.mark.parametrize("seed", [2, 5])
def test_keep_ends_fixes_the_ends_and_fits_the_rest_by_constrained_least_squares(seed):
    df = simulate.maneuver_tracks(12, "short", 300.0, seed=seed)
    res = detect(df)
    pts, index = res.points, res.index
    free = compress_with(None, res.is_maneuver, True, pts)
    fixed = compress_with(None, res.is_maneuver, True, pts, keep_ends=True)
    assert (fixed.kept == free.kept).all()
    knot_rows = np.flatnonzero(fixed.kept)
    ends = np.isin(knot_rows, np.concatenate([index.starts, index.ends - 1]))
    # the ends where observed; the default moves them (its docstring says so)
    assert np.allclose(fixed.knot_xy[ends], fixed.xy[knot_rows[ends]], atol=1e-9)
    assert np.abs(free.knot_xy[ends] - free.xy[knot_rows[ends]]).max() > 1.0
    # the knots between: the least-squares solution with the ends given, track by track
    # (a dense solve of the same objective, per track)
    x = fixed.xy
    from wakeline.core.compress import _segments
    from wakeline.core.tracks import track_seconds

    left, w = _segments(fixed.kept, index, track_seconds(pts))
    k = len(knot_rows)
    a = np.zeros((len(x), k))
    a[np.arange(len(x)), left] += 1 - w
    a[np.arange(len(x)), np.minimum(left + 1, k - 1)] += w
    rhs = x - a[:, ends] @ fixed.xy[knot_rows[ends]]
    sol = np.linalg.lstsq(a[:, ~ends], rhs, rcond=None)[0]
    assert np.allclose(fixed.knot_xy[~ends], sol, atol=1e-6)
    # least squares over fewer free knots: never a smaller sum of squares than the default
    sq = [np.sum((c.reconstructed_xy - c.xy) ** 2) for c in (free, fixed)]
    assert sq[0] <= sq[1]


def test_keep_ends_on_the_command_line(tmp_path):
    src = tmp_path / "m.csv"
    simulate.maneuver_tracks(4, "short", 300.0, seed=1).to_csv(src, index=False)
    out = tmp_path / "c.csv"
    assert main(["compress", str(src), "-o", str(out), "--keep-ends"]) == 0
    got = pd.read_csv(out, dtype={"batch": str})
    inp = sort_points(pd.read_csv(src, dtype={"batch": str}))
    for col in ("lon", "lat"):
        first = got.groupby("batch")[col].first().sort_index()
        last = got.groupby("batch")[col].last().sort_index()
        assert np.allclose(first, inp.groupby("batch")[col].first().sort_index(), atol=2e-7)
        assert np.allclose(last, inp.groupby("batch")[col].last().sort_index(), atol=2e-7)


def test_single_point_and_two_point_tracks():
    df = pd.concat(
        [
            track_from_xy([0.0], [0.0], batch="one"),
            track_from_xy([0.0, 10.0], [0.0, 0.0], batch="two"),
        ]
    )
    comp = compress_with(df, None)
    rep = comp.report()
    assert rep["overall"]["kept"] == 3 and rep["overall"]["dis_e_m"] == pytest.approx(0.0, abs=1e-9)


def _dp_reference(x, y, a, b, tol, keep):
    if b - a < 2:
        return
    dx, dy = x[b] - x[a], y[b] - y[a]
    norm = np.hypot(dx, dy)
    i = np.arange(a + 1, b)
    d = (
        np.abs(dx * (y[i] - y[a]) - dy * (x[i] - x[a])) / norm
        if norm > 0
        else np.hypot(x[i] - x[a], y[i] - y[a])
    )
    m = int(i[np.argmax(d)])
    if d.max() > tol:
        keep[m] = True
        _dp_reference(x, y, a, m, tol, keep)
        _dp_reference(x, y, m, b, tol, keep)


def _dp_segment_reference(x, y, a, b, tol, keep):
    """Recursive Douglas–Peucker, distance to the chord segment (as GEOS measures it)."""
    if b - a < 2:
        return
    dx, dy = x[b] - x[a], y[b] - y[a]
    i = np.arange(a + 1, b)
    den = dx * dx + dy * dy
    u = np.clip(((x[i] - x[a]) * dx + (y[i] - y[a]) * dy) / den, 0, 1) if den > 0 else 0.0
    d = np.hypot(x[i] - (x[a] + u * dx), y[i] - (y[a] + u * dy))
    m = int(i[np.argmax(d)])
    if d.max() > tol:
        keep[m] = True
        _dp_segment_reference(x, y, a, m, tol, keep)
        _dp_segment_reference(x, y, m, b, tol, keep)


@pytest.mark.parametrize("distance", ["line", "segment"])
def test_douglas_peucker_matches_recursive_reference(distance):
    df = simulate.maneuver_tracks(8, "short", 300.0, seed=5)
    pts = sort_points(df)
    index = track_index(pts)
    x, y = local_xy(pts, index)
    reference = _dp_reference if distance == "line" else _dp_segment_reference
    for tol in (100.0, 600.0, 3000.0):
        got = douglas_peucker_mask(x, y, index, tol, distance)
        ref = np.zeros(len(x), bool)
        for a, b in zip(index.starts, index.ends, strict=True):
            ref[a] = ref[b - 1] = True
            reference(x, y, a, b - 1, tol, ref)
        assert np.array_equal(got, ref)


@pytest.mark.parametrize("distance", ["line", "segment"])
def test_douglas_peucker_count_keeps_the_count_and_matches_tolerances(distance):
    """At equal points kept: exactly k per track (2 at least, all at most); where a
    tolerance keeps k, the same points as Douglas–Peucker at that tolerance; one more
    point allowed keeps the same points and one more (nested, as tolerances are)."""
    rng = np.random.default_rng(3)
    for seed in (5, 6):
        pts = sort_points(simulate.maneuver_tracks(6, "short", 300.0, seed=seed))
        index = track_index(pts)
        x, y = local_xy(pts, index)
        for tol in (100.0, 600.0, 3000.0):
            at_tol = douglas_peucker_mask(x, y, index, tol, distance)
            k = np.bincount(index.track_of_row[at_tol], minlength=index.n_tracks)
            got = douglas_peucker_count_mask(x, y, index, k, distance)
            assert np.array_equal(got, at_tol)
        k = rng.integers(0, index.sizes + 3)
        got = douglas_peucker_count_mask(x, y, index, k, distance)
        kept = np.bincount(index.track_of_row[got], minlength=index.n_tracks)
        assert np.array_equal(kept, np.clip(k, 2, index.sizes))
        more = douglas_peucker_count_mask(x, y, index, k + 1, distance)
        assert not (got & ~more).any()
        grown = np.bincount(index.track_of_row[more], minlength=index.n_tracks)
        assert np.array_equal(grown, np.clip(k + 1, 2, index.sizes))


def test_douglas_peucker_count_with_a_nan_position_keeps_the_count():
    """A track with a NaN position (review h231: IndexError before): the count is kept,
    the NaN point weighs least, both distances."""
    x = np.array([0.0, 1.0, np.nan, 3.0, 4.0])
    y = np.array([0.0, 1.0, 0.0, 1.0, 0.0])
    idx = TrackIndex(np.array([0]), np.array([5]), np.zeros(5, dtype="int64"), None)
    for distance in ("line", "segment"):
        for k in (2, 3, 4):
            got = douglas_peucker_count_mask(x, y, idx, np.array([k]), distance)
            assert got.sum() == k and got[0] and got[-1]
            assert not got[2]


def test_douglas_peucker_distances_differ_beyond_the_chord():
    """A point behind the chord's start: 0 m from its line, 100 m from the segment."""
    x = np.array([0.0, -100.0, 1000.0])
    y = np.zeros(3)
    idx = TrackIndex(np.array([0]), np.array([3]), np.zeros(3, dtype="int64"), None)
    assert douglas_peucker_mask(x, y, idx, 50.0, "line").tolist() == [True, False, True]
    assert douglas_peucker_mask(x, y, idx, 50.0, "segment").tolist() == [True, True, True]
    with pytest.raises(ValueError, match="segment, line"):
        douglas_peucker_mask(x, y, idx, 50.0, "chord")


def test_douglas_peucker_straight_and_corner():
    x, y = legs([30.0], [20])
    df = track_from_xy(x, y)
    pts = sort_points(df)
    idx = track_index(pts)
    assert douglas_peucker_mask(*local_xy(pts, idx), idx, 10.0).sum() == 2
    x, y = legs([0.0, 90.0], [10, 10])
    pts = sort_points(track_from_xy(x, y))
    assert np.flatnonzero(douglas_peucker_mask(*local_xy(pts, idx), idx, 10.0)).tolist() == [
        0,
        10,
        20,
    ]


def test_match_turns():
    tr = np.zeros(20, int)
    truth = np.zeros(20, bool)
    truth[[5, 15]] = True
    pred = np.zeros(20, bool)
    pred[[7, 12]] = True
    s = match_turns(pred, truth, tr, tol=2)
    assert s["precision"] == 0.5 and s["recall"] == 0.5


def test_evaluation_beats_seed_000_table_1():
    ev = evaluate_maneuver(n_tracks=15, seed=1)
    t = ev.table
    assert set(t.method) == {
        "IMM",
        "entropy",
        "PCA (paper)",
        "PCA + LS vertices",
        "Douglas-Peucker",
    }
    ours = t[t.method == "PCA + LS vertices"].set_index(["sigma", "class"])["dis_e_true_m"]
    for key, paper in SEED000_TABLE1.items():
        assert ours.loc[key] < paper[2], key
    text = ev.format()
    assert "Mean Dis_e against the TRUE path" in text and "(   1005)" in text


def test_cli_maneuvers_compress_and_evaluate(tmp_path, capsys):
    src = tmp_path / "m.csv"
    assert (
        main(["simulate", "maneuver", "--tracks", "4", "--length", "medium", "-o", str(src)]) == 0
    )
    out = tmp_path / "mp.csv"
    assert main(["maneuvers", str(src), "-o", str(out)]) == 0
    mp = pd.read_csv(out)
    assert list(mp.columns) == ["sensor", "batch", "index", "time", "lon", "lat", "factor"]
    assert (mp.factor > 15).all() and len(mp) > 4
    for method in ("imm", "entropy"):
        assert (
            main(["maneuvers", str(src), "-o", str(tmp_path / f"{method}.csv"), "--method", method])
            == 0
        )
    comp, rep = tmp_path / "c.csv", tmp_path / "r.json"
    assert main(["compress", str(src), "-o", str(comp), "--report", str(rep)]) == 0
    report = json.loads(rep.read_text())
    assert report["overall"]["dis_e_true_m"] < 600 and len(report["tracks"]) == 4
    assert len(pd.read_csv(comp)) == report["overall"]["kept"]
    assert (
        main(["compress", str(src), "-o", str(comp), "--method", "dp", "--tolerance", "500"]) == 0
    )
    capsys.readouterr()
    assert main(["evaluate", "maneuver", "--tracks", "2"]) == 0
    assert "PCA + LS vertices" in capsys.readouterr().out
    assert main(["maneuvers", str(src), "-o", str(out), "--threshold", "200"]) == 2
    assert "threshold_deg must be at most 180" in capsys.readouterr().err


def test_stops_and_speed_changes_are_kept_for_time_synchronized_dis_e():
    # sail 20 min at 12 kn, moor 1 h (4 m jitter), sail on at 6 kn: one course, no turn
    from wakeline.core.compress import CompressParams, turning_keep

    rng = np.random.default_rng(0)
    period = 10.0
    v1, v2 = 12 * 0.5144, 6 * 0.5144
    y = np.concatenate(
        [
            np.arange(120) * v1 * period,
            np.full(360, 120 * v1 * period),
            120 * v1 * period + np.arange(1, 121) * v2 * period,
        ]
    )
    x = rng.normal(0, 4.0, len(y))
    y = y + rng.normal(0, 4.0, len(y))
    result = detect(track_from_xy(x, y, period_s=period))
    assert result.is_maneuver.sum() == 0
    assert result.at_rest[130:470].all()
    ours = compress_with(None, turning_keep(result), sorted_points=result.points).report()
    paper = compress_with(
        None,
        turning_keep(result, CompressParams.paper()),
        refine=False,
        sorted_points=result.points,
    ).report()
    assert paper["overall"]["kept"] == 2  # the ends only: the stop is smeared over 2 h
    assert paper["overall"]["dis_e_m"] > 1000
    assert ours["overall"]["dis_e_m"] < 20
    assert ours["overall"]["kept"] <= 8


def test_synchronized_split_bounds_the_error_between_kept_points():
    from wakeline.core.compress import synchronized_split_mask

    rng = np.random.default_rng(3)
    n = 400
    t = np.cumsum(rng.uniform(5, 15, n))
    speed = np.where(np.arange(n) < 200, 6.0, 2.0)  # a speed change and a turn
    heading = np.where(np.arange(n) < 300, 0.0, 1.2)
    x = np.cumsum(speed * np.sin(heading) * np.diff(t, prepend=0)) + rng.normal(0, 3, n)
    y = np.cumsum(speed * np.cos(heading) * np.diff(t, prepend=0)) + rng.normal(0, 3, n)
    x2, y2, t2 = (
        np.concatenate([x, x[:50]]),
        np.concatenate([y, y[:50]]),
        np.concatenate([t, t[:50]]),
    )
    index = TrackIndex(
        np.array([0, n]),
        np.array([n, n + 50]),
        np.repeat([0, 1], [n, 50]),
        pd.DataFrame(index=[0, 1]),
    )
    start = np.zeros(n + 50, dtype=bool)
    start[[120]] = True  # kept rows stay kept
    for tol in (5.0, 25.0, 100.0):
        keep = synchronized_split_mask(x2, y2, t2, index, start, np.array([tol, tol]))
        assert keep[120] and keep[[0, n - 1, n, n + 49]].all()
        # time interpolation between consecutive kept points of each track stays within tol
        for a, b in zip(index.starts, index.ends, strict=True):
            k = np.flatnonzero(keep[a:b]) + a
            rx = np.interp(t2[a:b], t2[k], x2[k])
            ry = np.interp(t2[a:b], t2[k], y2[k])
            assert np.hypot(rx - x2[a:b], ry - y2[a:b]).max() <= tol + 1e-9
    assert synchronized_split_mask(x2, y2, t2, index, start, 5.0).sum() > keep.sum()


@pytest.mark.parametrize("seed", [3, 11])
def test_rows_repeated_in_time_and_place_change_no_result(seed):
    """Every row of an export twice (a feed logged by two recorders, a file appended to
    itself): the maneuver points and the compressed track are those of the single rows;
    fuzzing found 100 % of points kept and false turns. A repeat with another position is
    not a repeat."""
    from wakeline.core.pipeline import step_compress, step_maneuvers

    once = simulate.maneuver_tracks(12, "medium", 30.0, seed=seed)
    rng = np.random.default_rng(seed)
    twice_rows = np.sort(
        np.concatenate([np.arange(len(once)), rng.choice(len(once), len(once) // 2)])
    )
    twice = once.iloc[twice_rows].sample(frac=1.0, random_state=seed).reset_index(drop=True)
    m1, m2 = step_maneuvers(once, None), step_maneuvers(twice, None)
    same = ["sensor", "batch", "time", "lon", "lat", "factor"]  # "index" counts the repeats
    pd.testing.assert_frame_equal(m1.tables["maneuvers"][same], m2.tables["maneuvers"][same])
    c1, c2 = step_compress(once, None, None), step_compress(twice, None, None)
    k1, k2 = c1.tables["points"], c2.tables["points"]
    pd.testing.assert_frame_equal(k1.reset_index(drop=True), k2.reset_index(drop=True))
    assert c2.report["overall"]["dis_e_m"] == pytest.approx(c1.report["overall"]["dis_e_m"])
    moved = twice.copy()
    first = int(np.flatnonzero(twice.duplicated(keep=False))[0])
    moved.loc[first, "lon"] += 1e-3  # same time, another place: a conflict, not a repeat
    from wakeline.core.tracks import repeated_rows, sorted_with_index

    pts, index = sorted_with_index(twice)
    assert repeated_rows(pts, index).sum() == len(twice) - len(once)
    pts, index = sorted_with_index(moved)
    assert repeated_rows(pts, index).sum() == len(twice) - len(once) - 1
    # Two fixes of one time, the pair logged twice (P, Q, P, Q): both second copies.
    pq = once.iloc[[5, 5, 5, 5]].copy()
    pq.iloc[[1, 3], pq.columns.get_loc("lon")] += 1e-3
    pts, index = sorted_with_index(pd.concat([once, pq.iloc[1:]], ignore_index=True))
    rep = repeated_rows(pts, index)
    assert rep.sum() == 2
    kept = pts[~rep]
    assert kept.duplicated(["sensor", "batch", "time", "lon", "lat"]).sum() == 0


def test_blank_truth_cells_are_unknown_not_an_error(tmp_path):
    """A blank or unreadable true_lon/true_lat cell (fuzzing: an internal error) is a
    point without a truth: Dis_e against truth over the others."""
    df = simulate.maneuver_tracks(3, "short", 30.0, seed=1)
    df["true_lon"] = df["true_lon"].astype(object)
    df.loc[[2, 5], "true_lon"] = ""
    df.loc[7, "true_lon"] = "n/a"
    rep = compress_with(df, detect(df).is_maneuver).report()
    assert np.isfinite(rep["overall"]["dis_e_true_m"])
    assert all(np.isfinite(t["dis_e_true_m"]) for t in rep["tracks"])


@pytest.mark.parametrize("dtype", ["str", object])
@pytest.mark.parametrize("junk", [[], ["n/a"]])  # Arrow parses every cell / refuses one
def test_text_truth_parses_as_pandas_would(dtype, junk):
    """The truth columns of a file read as text (a blank cell makes the whole column
    text) are parsed by Arrow in the worker (it releases the GIL, pandas' parser holds
    it — a quarter of a second at a million rows, the GUI thread waiting); the values
    are those of ``pd.to_numeric(errors="coerce")``, blanks and junk NaN."""
    from wakeline.core.schema import PARSE_SLICE, to_float

    cells = ["121.525035", "", "  ", None, " 2.5 ", "1e3", "-inf", "nan", ".5", "+3", *junk]
    col = pd.Series(cells * (PARSE_SLICE // 5), dtype=dtype)
    expected = pd.to_numeric(col, errors="coerce").to_numpy(dtype="float64", na_value=np.nan)
    np.testing.assert_array_equal(to_float(col), expected)
    assert to_float(pd.Series([], dtype=dtype)).dtype == np.float64
    np.testing.assert_array_equal(to_float(pd.Series([1, 2])), [1.0, 2.0])


def test_a_stay_of_a_sparse_track_is_simplified_at_its_own_radius():
    # a port call seen every 30 min with ~70 m of noise (the ATD 2025 set): 12 fixes at the
    # berth. The stay spans the track's sampling and its radius grows with it (500 m here),
    # so inside it Douglas-Peucker runs at that radius: the span's ends and a fix or two,
    # not every noisy fix (at the 50 m of a 3-min stay nearly all 12 were kept)
    from test_maneuver import _port_call

    from wakeline.core.compress import turning_keep
    from wakeline.core.maneuver import ManeuverParams

    result = detect(_port_call(stop=12, seed=9))
    assert result.at_rest[8:20].all() and result.is_maneuver.sum() == 0
    keep = turning_keep(result)
    assert keep[8] and keep[19]  # where and when the ship stopped and left
    assert keep[9:19].sum() <= 2
    x, y = local_xy(result.points, result.index)
    span = track_index(result.points.iloc[8:20].reset_index(drop=True))
    at_50 = douglas_peucker_mask(x[8:20], y[8:20], span, 50.0)
    assert at_50[1:-1].sum() >= 6  # what the 3-min stay's radius keeps of the noise
    assert not detect(result.points, ManeuverParams(rest_steps=0)).at_rest.any()


def _sparse_curving_tracks(seed=0, n_tracks=4):
    """Ships at 14–18 kn reported every 30 min (ATD 2025's posits) on slow curves (radius
    60–150 km, a few degrees per fix), 30 m of position noise. The
    interpolation of a fix's neighbours misses it by the curve's sagitta, about a km, so
    the track's "noise" estimate is the ship's motion (operator test 7, D9)."""
    rng = np.random.default_rng(seed)
    frames = []
    for k in range(n_tracks):
        n = int(rng.integers(30, 50))
        v = rng.uniform(14, 18) * 0.5144
        radius = rng.uniform(60e3, 150e3) * rng.choice([-1, 1])
        s = np.arange(n) * v * 1800.0
        ang = s / radius
        x = radius * (1 - np.cos(ang)) + rng.normal(0, 30, n)
        y = abs(radius) * np.sin(np.abs(ang)) + rng.normal(0, 30, n)
        frames.append(track_from_xy(x, y, period_s=1800.0, batch=f"s{k}"))
    return pd.concat(frames, ignore_index=True)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_error_bound_is_reported_per_track_and_can_be_capped(seed):
    """D9: on 30-min posits 10× the "noise" is kilometres, and fixes lay kilometres off the
    compressed track with nothing saying why. The report now gives each track's noise
    estimate and bound (and the largest), the summary the largest bound and the farthest
    fix; ``error_cap_m`` caps the bound, and with raw vertices no fix is then farther than
    the cap from the compressed track."""
    from wakeline.core.compress import CompressParams, turning_keep
    from wakeline.core.pipeline import STEPS

    df = _sparse_curving_tracks(seed)
    result = detect(df)
    cap = 300.0
    res = STEPS["compress"](df)
    rep = res.report
    bound = rep["error_bound"]
    for track in rep["tracks"]:
        assert track["error_tol_m"] == pytest.approx(max(10 * track["noise_m"], 50.0))
    assert bound["tol_m"]["max"] == max(t["error_tol_m"] for t in rep["tracks"]) > 1000
    top = bound["largest"][0]
    assert top["error_tol_m"] == bound["tol_m"]["max"] and bound["capped_tracks"] == 0
    assert rep["overall"]["max_error_m"] == max(t["max_error_m"] for t in rep["tracks"]) > cap
    text = STEPS["compress"].summary(res)
    assert f"largest error bound {top['error_tol_m']:,.0f} m (track S1:{top['batch']}" in text
    assert f"farthest point {rep['overall']['max_error_m']:,.0f} m off" in text
    json.dumps(rep, allow_nan=False)  # the report stays plain JSON

    capped = STEPS["compress"](df, {"compress": CompressParams(error_cap_m=cap)}).report
    assert all(t["error_tol_m"] <= cap for t in capped["tracks"])
    assert capped["error_bound"]["capped_tracks"] == len(capped["tracks"])
    assert capped["overall"]["kept"] > rep["overall"]["kept"]
    assert capped["overall"]["dis_e_m"] < rep["overall"]["dis_e_m"]
    assert "(capped at 300 m on 4 tracks)" in STEPS["compress"].summary(
        STEPS["compress"](df, {"compress": CompressParams(error_cap_m=cap)})
    )
    raw = CompressParams(error_cap_m=cap, refine=False)
    comp = compress_with(None, turning_keep(result, raw), refine=False, sorted_points=result.points)
    assert comp.point_errors().max() <= cap + 1e-6
    # no cap (the default): the same kept points as before the option
    assert np.array_equal(turning_keep(result), turning_keep(result, CompressParams(error_cap_m=0)))


def test_tracks_too_short_for_a_noise_estimate_report_none_and_are_not_the_largest():
    """Review h209: one- and two-point tracks reported noise_m 0.0 and could head the
    "largest" bounds ("noise 0 m" in the summary); their noise is not known."""
    from wakeline.core.pipeline import STEPS

    rng = np.random.default_rng(5)
    big = track_from_xy(np.arange(200) * 50.0 + rng.normal(0, 5, 200), np.zeros(200), batch="big")
    one = track_from_xy(np.array([0.0]), np.array([0.0]), batch="one")
    two = track_from_xy(np.array([0.0, 50.0]), np.array([0.0, 0.0]), batch="two")
    for df, named in (
        (pd.concat([one, big, two], ignore_index=True), ["big"]),
        (pd.concat([one, two]), []),
    ):
        res = STEPS["compress"](df.reset_index(drop=True))
        rep = res.report
        noise = {t["batch"]: t["noise_m"] for t in rep["tracks"]}
        assert noise["one"] is None and noise["two"] is None
        assert all(noise[b] > 0 for b in named)
        assert [r["batch"] for r in rep["error_bound"]["largest"]] == named
        assert rep["error_bound"]["tol_m"]["min"] == 50.0  # their bound: the floor
        json.dumps(rep, allow_nan=False)
        text = STEPS["compress"].summary(res)
        assert "noise 0 m" not in text
        assert ("largest error bound" in text) == bool(named)


def test_rows_without_a_position_are_left_out_of_compress_and_counted():
    """Review h209: a NaN longitude (a table not read by import nor cleaned) crashed
    compress (ValueError in _least_squares_knots); the rows are left out and counted."""
    from wakeline.core.pipeline import STEPS, CompressOptions

    df = track_from_xy(np.arange(60) * 50.0, np.arange(60) * 20.0, batch="a")
    df.loc[10, "lon"] = np.nan
    df.loc[20, "lat"] = np.inf
    for method in ("maneuver", "dp"):
        res = STEPS["compress"](df, {"compress_options": CompressOptions(method=method)})
        rep = res.report
        assert rep["rows_without_position"] == 2 and rep["overall"]["points"] == 58
        assert "(2 rows without a position left out)" in STEPS["compress"].summary(res)
    full = STEPS["compress"](df.drop(index=[10, 20]).reset_index(drop=True)).report
    assert "rows_without_position" not in full


def _two_ships_under_one_id(seed: int) -> pd.DataFrame:
    """A ship off Florida and one off California reporting under one MMSI, in turn every
    30 min (operator test 10's ATD 211002010), and a ship of its own alongside."""
    rng = np.random.default_rng(seed)
    t0 = pd.Timestamp("2024-01-01T00:00:00Z")
    n = 48
    t = t0 + pd.to_timedelta(np.arange(n) * 1800, "s")
    west = np.arange(n) % 2 == 1
    lon = np.where(west, -120.5, -80.1) + np.arange(n) * 0.01 + rng.normal(0, 1e-4, n)
    lat = np.where(west, 34.2, 25.8) + rng.normal(0, 1e-4, n)
    mixed = pd.DataFrame({"sensor": "S1", "batch": "211002010", "time": t, "lon": lon, "lat": lat})
    k = np.arange(200)
    own = pd.DataFrame(
        {
            "sensor": "S1",
            "batch": "366970770",
            "time": t0 + pd.to_timedelta(k * 60, "s"),
            "lon": -90 + k * 0.003 + rng.normal(0, 2e-5, 200),
            "lat": 29 + 0.5 * np.sin(k / 40) + rng.normal(0, 2e-5, 200),
        }
    )
    return pd.concat([mixed, own], ignore_index=True)


@pytest.mark.parametrize("seed", [1, 2])
def test_compress_says_when_tracks_hold_jumps_clean_would_split(seed, monkeypatch):
    """Operator test 10: compress on a raw ATD table gave "largest error bound 27,062,943
    m … farthest point 2,601,752 m off" for an MMSI two ships share, with no word of why
    nor of cleaning first. The summary now names the tracks with legs no ship makes, by
    clean's own speed test, and says to clean first; compress's result is unchanged."""
    from wakeline.core import clean as clean_mod
    from wakeline.core.pipeline import STEPS

    df = _two_ships_under_one_id(seed)
    res = STEPS["compress"](df)
    jumps = res.report["jumps"]
    assert (jumps["sensor"], jumps["batch"]) == ("S1", "211002010") and jumps["tracks"] == 1
    assert jumps["legs"] == jumps["track_legs"] == 47  # every leg crosses the continent
    text = STEPS["compress"].summary(res)
    assert "1 track with jumps no ship can make (47 legs beyond 40 kn" in text
    assert (
        "track S1:211002010" in text
        and "clean first (wakeline clean; Clean in the window): it splits" in text
    )
    # clean's rule sees the same legs: it breaks that track and no other
    cleaned = STEPS["clean"](df)
    speed = cleaned.report["rules"]["speed"]
    assert speed["breaks"] + speed["removed"] > 0
    assert clean_mod.track_jumps(df[df["batch"] == "366970770"]) is None
    # said, not changed: the compressed points are those compress keeps without the check
    monkeypatch.setattr(clean_mod, "track_jumps", lambda *_a, **_k: None)
    plain = STEPS["compress"](df)
    assert "jumps" not in plain.report and "jumps" not in STEPS["compress"].summary(plain)
    kept = [lay for lay in res.layers if lay.suffix == "compressed"][0].points
    again = [lay for lay in plain.layers if lay.suffix == "compressed"][0].points
    pd.testing.assert_frame_equal(kept, again)
