"""Cleaning (SPEC §2, seed 001 §4.1, seed 003 §2.2): switchable removal rules with a
full reject trail.

Every rule works on all tracks at once (sorted table, per-track runs), never with a
Python loop per point. Every point a rule removes or changes goes to the *rejected*
table with the rule's name, the action (``removed``/``changed``) and the rule's
parameters, keyed by ``wl_id`` (the row's number in the input table, or the ``wl_id`` it already carries from an
earlier cleaning), so
:func:`restore` can put any of them back.

Rules, in the order they run (each can be switched off):

1. ``duplicates`` — several rows of one track at one timestamp: keep the first, or
   the first with the mean position (``keep="mean"``; the kept row is then *changed*).
   Ours: a same-time row farther than ``same_place_m`` from the row kept is no duplicate
   of it (several targets in one batch — detections of one scan — or times cut to the
   minute, as Excel's m/d/yyyy h:mm does): it is removed all the same (the first row of a
   time stays, as before) but under its own reason, ``same_time``, with the median
   distance in the report, and keep_mean does not average it in. ``paper_rule`` calls
   every same-time row a duplicate (SPEC §2 rule 1 as written).
2. ``stationary`` — at-rest spans: every position over ``window_s`` seconds stays within
   ``radius_m`` metres (:func:`at_rest`; tolerant of GPS jitter and a ship swinging at its
   berth). On a track sampled more sparsely than that (AIS posits every 30 min) the window
   spans ``steps`` of its median intervals and the radius grows with it, the speed limit
   2 · radius / window kept (:func:`rest_frame`). The inside of each span is removed; its
   first and last point stay (where and when the ship stopped and left); the report lists
   the spans (``at_rest_spans``). Seed 001 eq. 1 (speed below ``speed_kn`` and the
   identical lon/lat at the next point — 1–6 m of jitter defeats it) is ``paper_rule``.
3. ``speed`` — the distance from the last *kept* point is longer than ``v_max_kn`` · Δt
   plus ``tolerance_m`` (seed 001 eq. 2–3; the tolerance is ours: position noise alone
   fakes high speeds over short intervals). Rounds of vectorized passes, each removing the first point of every run of
   impossible legs, until none is left, so one outlier never takes its good neighbour
   with it. A first point whose only leg is impossible while the next leg is fine is the
   outlier itself.
4. ``turn`` — the turn at a point exceeds what the ship can turn in the time of the leg
   after it: ω = v / R, R = k · L (seed 001 eq. 4–7); only the sharpest point of a
   spike is removed. Ours: the limit grows by the course error a position error of
   ``position_error_m`` allows on each leg; legs shorter than ``min_leg_m`` or
   slower than ``min_speed_kn`` (a ship at rest turns on the spot, where ω = v/R says
   it cannot) are not judged.
5. ``speed_outliers`` — reported speed above Q3 + f·IQR of its track: replaced by the
   mean of the track's other speeds and flagged (seed 003 §2.2). Ours: a value within
   ``agree_kn`` of the speed the positions give (leg before or after) is genuine — on a
   track that is mostly at rest, the box plot would otherwise flag every cruising speed.
6. ``isolated`` — both the step into and the step out of a point are box-plot outliers
   of its track's step lengths (seed 003 §2.2), and the step from the point before to
   the point after is not (ours: a ship sailing between stops has long steps too, but
   skipping one of its points makes a longer step, not a shorter one).
7. ``short_tracks`` — tracks with fewer than ``min_points`` points are set aside (in
   the rejected table, restorable), not deleted. Ours: the points the stationary rule
   took out of an at-rest span count (``count_at_rest``), so a ship moored for the whole
   capture keeps its span ends instead of vanishing from the cleaned layer; and the
   tracks judged are those that come out (``after_split``): a track the speed rule
   splits at an impossible jump (``batch#2`` …) is judged piece by piece.

Then the transforming steps, off by default (:mod:`wakeline.core.transform`), in the order
``bspline`` (seed 001's sampling–segmentation–spline–interpolation), ``resample``,
``smooth``; the points each replaces go to the rejected table with action ``replaced``.

Units we chose where the paper states none (seed 001 Table 2: L = 12, V_max = 12): V_max
read as 12 m/s = 23.3 kn, but we default to 40 kn — at 23.3 kn a passenger ferry of the
Saronic Gulf data (26 kn) loses whole legs, since every point is compared with the last
kept one, and at 30 kn (the default until session 19) so did its 32 kn ferry once sampled
every 10 min, where the 200 m tolerance no longer hides 2 kn too many (at 60 s it hides
6 kn: the rule's verdict on a ship faster than V_max depended on the sampling); L in metres, defaulting to 100 m — with L = 12 m (R = 36 m) a
ship at 10 kn may turn 80° in 10 s, so the rule would never fire at radar rates.
"""

import dataclasses
import json
import threading
from concurrent.futures import FIRST_EXCEPTION, ThreadPoolExecutor, wait
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from wakeline.core import geo
from wakeline.core.errors import Cancelled, InputError
from wakeline.core.params import Params, param
from wakeline.core.progress import Progress, null_progress
from wakeline.core.schema import ordered_columns, time_seconds
from wakeline.core.tracks import TrackIndex, median_interval_s, sorted_with_index, track_seconds
from wakeline.core.transform import (
    BsplineParams,
    ResampleParams,
    SmoothParams,
    bspline_segments,
    resample,
    smooth,
    stated_max_gap,
)


@dataclass(frozen=True)
class DuplicatesParams(Params):
    enabled: bool = param(True, "", "remove same-time duplicates within a track")
    keep_mean: bool = param(
        False, "", "keep the mean position of the duplicates instead of the first row"
    )
    same_place_m: float = param(
        25.0,
        "m",
        "a same-time row within this distance of the row kept is a duplicate; one farther "
        "away is removed too but reported apart (same_time: several targets in one batch, "
        "or times cut to the minute)",
        lo=0,
        hi=1e7,
        source="ours: two steps of the 0.0001° (11 m) rounding of AIS exports such as DMA's, "
        "whose sample_ship's 68 same-time rows lie 0-22 m apart (median 0 m); a ship at 10 kn "
        "covers 25 m in 5 s",
    )
    paper_rule: bool = param(
        False,
        "",
        "SPEC §2 rule 1 as written: every same-time row is a duplicate wherever it lies "
        "(no same_time reason; keep_mean averages them all)",
    )


@dataclass(frozen=True)
class StationaryParams(Params):
    enabled: bool = param(True, "", "take out the inside of at-rest spans (moored or anchored)")
    radius_m: float = param(
        50.0,
        "m",
        "at rest: every position over window_s stays within this radius (GPS jitter, a ship "
        "swinging at its berth)",
        lo=0,
        hi=1e5,
        source="ours; seed 001 eq. 1 asks for the identical position",
    )
    window_s: float = param(
        180.0,
        "s",
        "at rest: the shortest stay that counts (2 * radius_m / window_s = 0.56 m/s, about "
        "seed 001's 1 kn: a ship slower than that over the window is at rest)",
        lo=1,
        hi=1e7,
        source="ours, from seed 001 eq. 1's 1 kn",
    )
    steps: float = param(
        1.0,
        "intervals",
        "sparse tracks: a stay also spans at least this many of the track's median sampling "
        "intervals (a stay needs two fixes to be seen), the radius growing with the window so "
        "2 * radius / window, the speed limit, stays; 0 = window_s and radius_m on every track",
        lo=0,
        hi=1000,
        source="ours",
    )
    north_box: bool = param(
        False,
        "",
        "the box of the at-rest test aligned with north and east (before 2026-12) instead of "
        "each track's principal axes (the same wherever the scene lies on the globe)",
    )
    noise_sigmas: float = param(
        0.0,
        "sigma",
        "at rest: the radius grows, per track, to this many of the track's position-noise "
        "sigma (per axis, the maneuver detector's noise estimate) where that is larger than "
        "radius_m, so a moored ship seen with tens of metres of noise stays at rest; "
        "0 = off (radius_m on every track)",
        lo=0,
        hi=100,
        source="ours (session 28, h193: docs/prereg/session28_at_rest_noise.md)",
    )
    paper_rule: bool = param(
        False,
        "",
        "seed 001 eq. 1 instead: speed below speed_kn and the same lon/lat as the next point",
    )
    speed_kn: float = param(
        1.0,
        "kn",
        "paper rule: below this speed a point that does not move is stationary",
        lo=0,
        hi=100,
        source="seed 001 eq. 1",
    )


@dataclass(frozen=True)
class SpeedParams(Params):
    enabled: bool = param(
        True, "", "remove points that imply an impossible speed (seed 001 eq. 2-3)"
    )
    v_max_kn: float = param(
        40.0,
        "kn",
        "largest plausible speed from the last kept point",
        lo=0.1,
        hi=200,
        source="seed 001 Table 2: V_max = 12 (m/s = 23.3 kn); 40 kn keeps fast ferries whole "
        "at any sampling (Saronic ferry 32 kn for 10 min; the ATD fixes 30 kn cut report a "
        "median SOG of 33 kn)",
    )
    tolerance_m: float = param(
        200.0,
        "m",
        "position error allowed on top of v_max * dt (noise alone fakes high speeds over short intervals)",
        lo=0,
        hi=1e6,
    )
    break_run: int = param(
        3,
        "points",
        "an impossible leg followed by this many plausible ones is a break (another ship), "
        "not an outlier",
        lo=1,
        hi=1000,
    )
    split_factor: float = param(
        3.0,
        "",
        "a break whose jump needs more than this many times v_max, over more than split_km, "
        "starts a new track (two ships under one id: batch#2, #3 …); 0 never splits",
        lo=0,
        hi=1000,
    )
    split_km: float = param(
        10.0,
        "km",
        "shortest jump that splits a track at a break (far beyond any position error)",
        lo=0,
        hi=1e5,
    )
    split_at_breaks: bool = param(
        False,
        "",
        "also split (batch#2 …) at every break whose leg stays impossible after the other "
        "rules (longer than v_max * dt + tolerance_m from the last kept point), so that no "
        "later step (maneuvers, compress, associate) takes the jump for motion; off: only "
        "the jumps beyond split_factor and split_km split, the others stay in the track "
        "(the report and the summary list them)",
        source="ours (operator test 7, D3: a clock set back 10 min left an 8.7 km leg in 60 s)",
    )


@dataclass(frozen=True)
class TurnParams(Params):
    enabled: bool = param(
        True, "", "remove points that imply an impossible turn (seed 001 eq. 4-7)"
    )
    ship_length_m: float = param(
        100.0,
        "m",
        "ship length L",
        lo=1,
        hi=500,
        source="seed 001 Table 2 gives L = 12 without a unit; 12 m makes the rule inert at radar rates",
    )
    radius_factor: float = param(3.0, "", "turning radius R = k * L", lo=0.1, hi=100)
    min_leg_m: float = param(
        100.0, "m", "legs shorter than this are not judged (their course is noise)", lo=0, hi=1e6
    )
    min_speed_kn: float = param(
        2.0,
        "kn",
        "legs slower than this are not judged (a ship at rest turns on the spot)",
        lo=0,
        hi=100,
    )
    position_error_m: float = param(
        100.0,
        "m",
        "position error: each leg's course may be off by atan(error / leg length)",
        lo=0,
        hi=1e5,
    )


@dataclass(frozen=True)
class SpeedOutliersParams(Params):
    enabled: bool = param(True, "", "replace box-plot outliers of reported speed (seed 003 §2.2)")
    iqr_factor: float = param(
        1.5, "", "outlier above Q3 + f * IQR", lo=0, hi=100, source="seed 003 §2.2"
    )
    agree_kn: float = param(
        5.0,
        "kn",
        "an outlier within this of the speed derived from positions is genuine and kept",
        lo=0,
        hi=1000,
    )


@dataclass(frozen=True)
class IsolatedParams(Params):
    enabled: bool = param(
        True, "", "remove isolated points by box-plot of step lengths (seed 003 §2.2)"
    )
    iqr_factor: float = param(
        1.5, "", "a step is an outlier above Q3 + f * IQR", lo=0, hi=100, source="seed 003 §2.2"
    )
    bridge: bool = param(
        True,
        "",
        "a point is isolated only if the step over it is no longer than two ordinary steps "
        "(the upper fence): a ship sailing between stops keeps its points (ours); false: "
        "both steps outliers is enough (seed 003's plain box plot)",
        source="ours",
    )


@dataclass(frozen=True)
class ShortTracksParams(Params):
    enabled: bool = param(True, "", "set aside tracks with too few points")
    min_points: int = param(
        10, "points", "tracks with fewer points are set aside", lo=1, hi=1_000_000, source="SPEC §2"
    )
    count_at_rest: bool = param(
        True,
        "",
        "points the stationary rule took out of an at-rest span still count: a ship moored "
        "the whole capture keeps its span ends (false: only what is left counts, and the "
        "ship is set aside)",
        source="ours",
    )
    after_split: bool = param(
        True,
        "",
        "judge the tracks that come out: each piece of a track the speed rule splits at a "
        "jump no ship could make (batch#2 …) counts on its own (false: the track as it came "
        "in, before the split)",
        source="ours (h179, operator test 4 D-clean-2: judged before the split, a 10-day "
        "file kept 1,681 pieces of at most 3 points that the same ships' one-day file set "
        "aside)",
    )


#: Column that keys points between the cleaned and the rejected table.
ID = "wl_id"
#: Rows per block when cleaning large tables (whole tracks per block).
BLOCK_ROWS = 1_000_000

RULES = ("duplicates", "stationary", "speed", "turn", "speed_outliers", "isolated", "short_tracks")
#: Transforming steps, off by default, run after the rules in this order.
TRANSFORMS = ("bspline", "resample", "smooth")
STEPS = RULES + TRANSFORMS


@dataclass(frozen=True)
class CleanParams:
    """All cleaning rules' parameters; ``rule.param`` names address one value."""

    duplicates: DuplicatesParams = field(default_factory=DuplicatesParams)
    stationary: StationaryParams = field(default_factory=StationaryParams)
    speed: SpeedParams = field(default_factory=SpeedParams)
    turn: TurnParams = field(default_factory=TurnParams)
    speed_outliers: SpeedOutliersParams = field(default_factory=SpeedOutliersParams)
    isolated: IsolatedParams = field(default_factory=IsolatedParams)
    short_tracks: ShortTracksParams = field(default_factory=ShortTracksParams)
    bspline: BsplineParams = field(default_factory=BsplineParams)
    resample: ResampleParams = field(default_factory=ResampleParams)
    smooth: SmoothParams = field(default_factory=SmoothParams)

    def problems(self) -> list[str]:
        return [f"{rule}.{p}" for rule in STEPS for p in getattr(self, rule).problems()]

    def checked(self) -> "CleanParams":
        problems = self.problems()
        if problems:
            raise InputError("invalid parameters: " + "; ".join(problems))
        return self

    def with_settings(self, settings: list[str] | dict[str, str]) -> "CleanParams":
        """Apply ``["speed.v_max_kn=25", ...]`` (or a dict of the same)."""
        items = (
            settings.items()
            if isinstance(settings, dict)
            else [_split_setting(s) for s in settings]
        )
        changes: dict[str, dict[str, str]] = {}
        for key, value in items:
            rule, _, name = key.partition(".")
            if rule not in STEPS or not name:
                raise InputError(
                    f"--set {key}={value}: expected rule.param with rule one of {', '.join(STEPS)}"
                )
            changes.setdefault(rule, {})[name] = value
        if "resample" in changes:
            # A max_gap_s given (--max-gap, --set, a saved table from before the adaptive
            # limit) is the limit, as SPEC §2.8 has it: no track's own step overrides it.
            changes["resample"] = stated_max_gap(changes["resample"])
        out = self
        for rule, values in changes.items():
            out = dataclasses.replace(out, **{rule: getattr(out, rule).replace(**values)})
        return out.checked()

    @classmethod
    def describe(cls) -> list[dict]:
        return [
            {"rule": rule, **d} for rule in STEPS for d in type(getattr(cls(), rule)).describe()
        ]


def _split_setting(text: str) -> tuple[str, str]:
    key, sep, value = text.partition("=")
    if not sep or not key.strip():
        raise InputError(f"--set {text!r}: expected rule.param=value, e.g. speed.v_max_kn=25")
    return key.strip(), value.strip()


@dataclass(frozen=True)
class CleanResult:
    """Cleaned points, the reject trail and the report."""

    points: pd.DataFrame  # cleaned, sorted, with wl_id
    rejected: pd.DataFrame  # original rows + wl_id, rule, action, params
    report: dict


# --------------------------------------------------------------------------------------


def _runs(index_of_row: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per row: is it the first of its track among the given rows, and is it the last."""
    n = len(index_of_row)
    first = np.ones(n, dtype=bool)
    last = np.ones(n, dtype=bool)
    if n > 1:
        same = index_of_row[1:] == index_of_row[:-1]
        first[1:] = ~same
        last[:-1] = ~same
    return first, last


class _Legs:
    """Legs between consecutive rows of a block, computed once; a subset of rows reuses
    them wherever its rows are still adjacent, and computes only the legs that bridge
    removed points."""

    def __init__(self, lon: np.ndarray, lat: np.ndarray, t: np.ndarray, track: np.ndarray) -> None:
        self.lon, self.lat, self.t, self.track = lon, lat, t, track
        n = len(lon)
        self.dist = np.full(n, np.nan)
        self.course = np.full(n, np.nan)
        if n > 1:
            self.dist[1:], self.course[1:] = geo.short_legs(lon[:-1], lat[:-1], lon[1:], lat[1:])

    def __call__(
        self, rows: np.ndarray, group: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Distance (m), time (s), course (deg) of the leg arriving at each of ``rows``
        from the previous one of the same track — or of the same ``group`` when given
        (NaN for a track's or group's first)."""
        first, _ = _runs((self.track if group is None else group)[rows])
        dist = np.full(len(rows), np.nan)
        course = np.full(len(rows), np.nan)
        dt = np.full(len(rows), np.nan)
        if len(rows) > 1:
            cur, prev = rows[1:], rows[:-1]
            adjacent = cur - prev == 1
            dist[1:] = np.where(adjacent, self.dist[cur], np.nan)
            course[1:] = np.where(adjacent, self.course[cur], np.nan)
            gap = np.flatnonzero(~adjacent) + 1
            if len(gap):
                a, b = rows[gap - 1], rows[gap]
                dist[gap], course[gap] = geo.short_legs(
                    self.lon[a], self.lat[a], self.lon[b], self.lat[b]
                )
            dt[1:] = self.t[cur] - self.t[prev]
        dist[first] = np.nan
        dt[first] = np.nan
        course[first] = np.nan
        return dist, dt, course


def _tukey_upper(values: np.ndarray, group: np.ndarray, factor: float) -> np.ndarray:
    """Per row: Q3 + factor·IQR of its group's values (NaN-aware)."""
    s = pd.Series(values)
    g = s.groupby(group)
    q1 = g.transform("quantile", 0.25)
    q3 = g.transform("quantile", 0.75)
    return (q3 + factor * (q3 - q1)).to_numpy()


def impossible_legs(
    dist: np.ndarray, dt: np.ndarray, v_max_ms: float, tolerance_m: float
) -> np.ndarray:
    """The impossible-speed rule's test of legs (``dist`` m in ``dt`` s; NaN: no leg):
    longer than ``v_max_ms · dt + tolerance_m``, a jump no ship makes."""
    with np.errstate(invalid="ignore"):
        return dist > v_max_ms * dt + tolerance_m


def track_jumps(points: pd.DataFrame, speed: "SpeedParams | None" = None) -> dict | None:
    """Legs between consecutive points of a track that no ship can make and at which
    clean splits a track, by clean's own tests (:func:`impossible_legs` and
    :func:`split_legs` with ``speed``: clean's defaults): ``{"legs", "tracks", "sensor",
    "batch", "track_legs", "kn", "v_max_kn"}`` (the track of the most such legs and its
    fastest leg's speed), None when there are none (or clean never splits:
    ``split_factor`` 0 and no ``split_at_breaks``). What compress says
    of a raw table that clean would split (operator test 10: one MMSI alternating
    Florida and California gave a "largest error bound 27,062,943 m")."""
    speed = speed or SpeedParams()
    if len(points) < 2 or not {"lon", "lat", "time"} <= set(points.columns):
        return None
    if speed.split_factor <= 0 and not speed.split_at_breaks:
        return None
    pts, index = sorted_with_index(points)
    lon = pts["lon"].to_numpy(dtype="float64")
    lat = pts["lat"].to_numpy(dtype="float64")
    t = track_seconds(pts)
    track = index.track_of_row
    dist, dt, _ = _Legs(lon, lat, t, track)(np.arange(len(pts)))
    bad = impossible_legs(dist, dt, speed.v_max_kn * geo.KN_MS, speed.tolerance_m)
    bad &= split_legs(dist, dt, speed)
    if not bad.any():
        return None
    per_track = np.bincount(track[bad], minlength=index.n_tracks)
    worst = int(np.argmax(per_track))
    on_worst = bad & (track == worst)
    with np.errstate(divide="ignore", invalid="ignore"):
        kn = np.where(dt[on_worst] > 0, dist[on_worst] / dt[on_worst] / geo.KN_MS, np.inf)
    keys = index.keys
    return {
        "legs": int(bad.sum()),
        "tracks": int((per_track > 0).sum()),
        "sensor": str(keys["sensor"].iloc[worst]),
        "batch": str(keys["batch"].iloc[worst]),
        "track_legs": int(per_track[worst]),
        "kn": float(np.max(kn)) if np.isfinite(kn).any() else None,
        "v_max_kn": float(speed.v_max_kn),
    }


def _speed_rule(
    legs: "_Legs", alive, track, v_max_ms: float, tolerance_m: float, run: int, max_rounds: int = 64
) -> tuple[np.ndarray, np.ndarray]:
    """Rows removed by the impossible-speed rule (compared with the last kept point: the
    leg is impossible when longer than v_max · dt + tolerance), and rows where the batch
    *breaks*: an impossible leg followed by ``run`` plausible ones is another ship (or
    the same one re-acquired elsewhere), not an outlier — the points after it are kept
    and the comparison starts afresh there."""
    removed = np.zeros(len(alive), dtype=bool)
    breaks = np.zeros(len(alive), dtype=bool)
    track_start = np.ones(len(alive), dtype=bool)
    track_start[1:] = track[1:] != track[:-1]
    for _ in range(max_rounds):
        rows = np.flatnonzero(alive & ~removed)
        if len(rows) < 2:
            break
        group = np.cumsum(track_start | breaks)
        dist, dt, _ = legs(rows, group)
        bad = impossible_legs(dist, dt, v_max_ms, tolerance_m)  # the leg arriving at a row
        first, _ = _runs(group[rows])
        prev_bad = np.zeros_like(bad)
        prev_bad[1:] = bad[:-1] & ~first[1:]
        flag = bad & ~prev_bad
        # A track's first point is the outlier when its leg is impossible but the next is not.
        next_ok = np.zeros_like(bad)
        next_ok[:-1] = ~bad[1:] & ~first[1:]
        second = np.zeros_like(bad)
        second[1:] = first[:-1] & ~first[1:]
        first_is_outlier = second & bad & next_ok
        flag_first = np.zeros_like(bad)
        flag_first[:-1] = first_is_outlier[1:]
        flag = np.where(first_is_outlier, False, flag) | flag_first
        # A flagged row followed by `run` plausible legs within its group starts a new piece.
        calm = flag & ~first_is_outlier
        for k in range(1, run + 1):
            ok = np.zeros_like(bad)
            ok[:-k] = ~bad[k:] & (group[rows][k:] == group[rows][:-k]) & ~first[k:]
            calm &= ok
        breaks[rows[calm]] = True
        flag &= ~calm
        if not flag.any() and not calm.any():
            break
        removed[rows[flag]] = True
    return removed, breaks


def clean(
    points: pd.DataFrame, params: CleanParams | None = None, progress: Progress | None = None
) -> CleanResult:
    """Apply the enabled rules, then the enabled transforming steps; return cleaned points,
    the rejected trail and the report."""
    params = (params or CleanParams()).checked()
    if "time" in points.columns and points["time"].isna().any():
        raise InputError(
            f"{int(points['time'].isna().sum()):,} points have no time: read the file with "
            "import, which sets such rows aside in its quarantine"
        )
    lost = without_position(points)
    if lost:
        raise InputError(
            f"{lost:,} points have no position (lon or lat missing or not a number): read "
            "the file with import, which sets such rows aside in its quarantine"
        )
    progress = progress or null_progress
    enabled = [name for name in TRANSFORMS if getattr(params, name).enabled]
    share = 1.0 / (1 + len(enabled))
    result = _remove(points, params, lambda f, text: progress(f * share, text))
    for k, name in enumerate(enabled):
        progress((k + 1) * share, name)
        result = _transform(result, name, getattr(params, name))
    progress(1.0, "cleaned")
    return result


def without_position(points: pd.DataFrame) -> int:
    """How many rows of ``points`` have no position: lon or lat missing, NaN or infinite
    (the importers quarantine such rows; a table made otherwise may hold them)."""
    if not len(points) or "lon" not in points.columns or "lat" not in points.columns:
        return 0
    lon = pd.to_numeric(points["lon"], errors="coerce").to_numpy(dtype="float64")
    lat = pd.to_numeric(points["lat"], errors="coerce").to_numpy(dtype="float64")
    return int((~(np.isfinite(lon) & np.isfinite(lat))).sum())


def _transform(result: CleanResult, name: str, step_params) -> CleanResult:
    before = result.points
    ids = np.concatenate(
        [before[ID].to_numpy(dtype="int64"), result.rejected[ID].to_numpy(dtype="int64")]
    )
    next_id = int(ids.max()) + 1 if len(ids) else 0
    if name == "bspline":
        after = bspline_segments(before, step_params, next_id)
    elif name == "resample":
        after = resample(before, step_params, next_id)
    else:
        after = smooth(before, step_params)
    if name != "smooth" and len(after):
        # New points: speed and course from their own track (they were left blank)
        from wakeline.core.tracks import derive_motion

        after, index = sorted_with_index(after)
        speed, course = derive_motion(after, index)
        after = after.copy()
        for col, derived, digits in (("speed", speed, 2), ("course", course, 1)):
            values = (
                after[col].to_numpy(dtype="float64")
                if col in after
                else np.full(len(after), np.nan)
            )
            after[col] = np.where(np.isfinite(values), values, np.round(derived, digits))
    if name == "smooth":
        moved = (before["lon"].to_numpy() != after["lon"].to_numpy()) | (
            before["lat"].to_numpy() != after["lat"].to_numpy()
        )
        replaced = before[moved]
    else:
        replaced = before
    trail = replaced.assign(
        rule=name, action="replaced", params=json.dumps(dataclasses.asdict(step_params))
    )
    rejected = pd.concat([result.rejected, trail], ignore_index=True)
    report = dict(result.report)
    report["points_out"] = int(len(after))
    report["tracks_out"] = int(after.groupby(["sensor", "batch"]).ngroups) if len(after) else 0
    report["rules"] = {
        **report["rules"],
        name: {
            "enabled": True,
            "replaced": int(len(replaced)),
            "points_out": int(len(after)),
            "params": dataclasses.asdict(step_params),
        },
    }
    order = ordered_columns(after)
    return CleanResult(after[order].reset_index(drop=True), rejected, report)


def _remove(points: pd.DataFrame, params: CleanParams, progress: Progress) -> CleanResult:
    """The removal rules (see the module docstring)."""
    src = points.copy()
    given = pd.to_numeric(src[ID], errors="coerce") if ID in src.columns else None
    if given is None or given.isna().any() or given.duplicated().any():
        src[ID] = np.arange(len(src), dtype="int64")
    else:
        src[ID] = given.astype("int64")
    pts, index = sorted_with_index(src)
    blocks = _blocks(index, BLOCK_ROWS)
    if len(blocks) == 1:
        return _clean_block(pts, index, params, progress)
    # Rules are per track: clean blocks of whole tracks on two threads (numpy releases the
    # GIL) and keep every temporary small enough for the allocator to reuse.

    def run(bounds: tuple[int, int]) -> CleanResult:
        a, b = bounds
        k0, k1 = np.searchsorted(index.starts, [a, b])
        block_index = TrackIndex(
            index.starts[k0:k1] - a,
            index.ends[k0:k1] - a,
            index.track_of_row[a:b] - k0,
            index.keys.iloc[k0:k1].reset_index(drop=True),
        )
        return _clean_block(pts.iloc[a:b].reset_index(drop=True), block_index, params, check)

    # Cancel stops within a rule's time: the caller's progress (which raises to cancel) is
    # polled every 0.1 s while blocks run, and blocks stop between rules once told to.
    stop = threading.Event()

    def check(_fraction: float = 0.0, _text: str = "") -> None:
        if stop.is_set():
            raise Cancelled()

    pool = ThreadPoolExecutor(max_workers=2)
    futures = [pool.submit(run, b) for b in blocks]
    try:
        while True:
            done = sum(f.done() for f in futures)
            progress(done / len(futures), f"cleaning: {done} of {len(futures)} blocks done")
            if done == len(futures):
                break
            wait(futures, timeout=0.1, return_when=FIRST_EXCEPTION)
        results = [f.result() for f in futures]
    except BaseException:
        stop.set()
        pool.shutdown(wait=True, cancel_futures=True)
        raise
    pool.shutdown(wait=True)
    progress(1.0, "cleaned")
    return _merge(results)


def _blocks(index: TrackIndex, rows: int) -> list[tuple[int, int]]:
    """Row ranges of about ``rows`` rows each, cut at track boundaries."""
    return block_cuts(index.ends, rows)


def block_cuts(ends: np.ndarray, rows: int) -> list[tuple[int, int]]:
    """Row ranges of about ``rows`` rows each, cut at track boundaries, for tracks in
    sorted order ending at rows ``ends`` (the blocks :func:`clean` cleans one at a time;
    the streamed clean, :mod:`wakeline.core.clean_stream`, cuts the same blocks)."""
    if len(ends) == 0:
        return [(0, 0)]
    cuts = [0]
    while cuts[-1] < ends[-1]:
        k = int(np.searchsorted(ends, cuts[-1] + rows, side="left"))
        cuts.append(int(ends[min(k, len(ends) - 1)]))
    return list(zip(cuts[:-1], cuts[1:], strict=True))


def _merge(results: list[CleanResult]) -> CleanResult:
    points = pd.concat([r.points for r in results], ignore_index=True)
    rejected = pd.concat([r.rejected for r in results], ignore_index=True)
    rejected = rejected.sort_values([ID, "action"], kind="stable").reset_index(drop=True)
    return CleanResult(points, rejected, merge_reports([r.report for r in results]))


def merge_reports(reports: list[dict]) -> dict:
    """The report of several blocks of whole tracks cleaned one by one."""
    first = reports[0]
    report = {
        key: sum(r[key] for r in reports)
        for key in ("points_in", "points_out", "tracks_in", "tracks_out")
    }
    report["rules"] = {
        rule: {
            key: (
                sum(r["rules"][rule][key] for r in reports)
                if key
                in ("removed", "changed", "breaks", "splits", "breaks_kept", "spans", "at_rest_s")
                else value
            )
            for key, value in info.items()
        }
        for rule, info in first["rules"].items()
    }
    if "break_legs" in report["rules"].get("speed", {}):  # every block's, the fastest first
        legs = [leg for r in reports for leg in r["rules"]["speed"]["break_legs"]]
        legs.sort(key=lambda leg: -(leg["kn"] if leg["kn"] is not None else np.inf))
        report["rules"]["speed"]["break_legs"] = legs[:BREAK_LEGS_LISTED]
    if "same_time" in report["rules"]:
        # the blocks' medians, each weighted by its rows (the median of a block of tracks)
        pairs = sorted(
            (r["rules"]["same_time"]["median_m"], r["rules"]["same_time"]["removed"])
            for r in reports
            if r["rules"].get("same_time", {}).get("removed")
        )
        if pairs:
            w = np.cumsum([k for _, k in pairs])
            median = pairs[int(np.searchsorted(w, w[-1] / 2.0))][0]
            report["rules"]["same_time"]["median_m"] = median
    report["tracks"] = [row for r in reports for row in r["tracks"]]
    report["at_rest_spans"] = [row for r in reports for row in r["at_rest_spans"]]
    return report


def _paper_stationary(legs, rows, lon, lat, track, speed_col, speed_kn, n) -> np.ndarray:
    """Seed 001 eq. 1: speed below ``speed_kn`` and the same lon/lat as the next point."""
    dist, dt, _ = legs(rows)
    with np.errstate(invalid="ignore", divide="ignore"):
        arriving = dist / dt / geo.KN_MS
    first_rows, last = _runs(track[rows])
    leaving = np.append(arriving[1:], np.nan)
    derived = np.where(first_rows, leaving, arriving)  # as tracks.derive_motion does
    v = np.where(np.isnan(speed_col[rows]), derived, speed_col[rows])
    same_next = np.zeros(len(rows), dtype=bool)
    same_next[:-1] = (lon[rows][:-1] == lon[rows][1:]) & (lat[rows][:-1] == lat[rows][1:])
    same_next &= ~last
    mask = np.zeros(n, dtype=bool)
    mask[rows[(v < speed_kn) & same_next]] = True
    return mask


def _sub_index_rows(track_of_row: np.ndarray, n_tracks: int):
    """A TrackIndex's arrays for sorted rows given their track numbers (empty tracks kept)."""
    sizes = np.bincount(track_of_row, minlength=n_tracks).astype("int64")
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype("int64")
    return starts, starts + sizes, track_of_row.astype("int64"), pd.DataFrame(index=range(n_tracks))


def _local_xy_rows(lon: np.ndarray, lat: np.ndarray, index: TrackIndex):
    """Local metres about each track's first point."""
    has = index.sizes > 0
    first = np.where(has, index.starts, 0)
    lon0 = lon[first] if len(lon) else np.zeros(index.n_tracks)
    lat0 = lat[first] if len(lat) else np.zeros(index.n_tracks)
    tr = index.track_of_row
    # geo.to_local(lon, lat, lon0[tr], lat0[tr]) bit for bit, the origins' sines and
    # cosines taken once per track
    per_track = (*geo.sin_cos_deg(lon0), *geo.sin_cos_lat(lat0))
    return geo.plane_xy(*geo.sin_cos_deg(lon), *geo.sin_cos_lat(lat), *(v[tr] for v in per_track))


def rest_frame(
    x: np.ndarray,
    y: np.ndarray,
    t: np.ndarray,
    index: TrackIndex,
    window_s: float,
    steps: float,
    med: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Positions (m) and times (s) in which :func:`at_rest` with ``window_s`` and its radius
    is, per track, the rule with a window of at least ``steps`` median sampling intervals.

    A stay is seen only when two fixes fall in it: on a track reported every 30 min a
    3-min window holds one fix and nothing is ever at rest. Each track whose ``steps``
    median intervals exceed ``window_s`` has its times and positions divided by
    f = steps · median / window_s about its first fix: its window becomes f · window_s
    and its radius f · radius, so the speed the rule tolerates (2 · radius / window) is the
    same at every sampling, and so is the reach back over a gap (four windows). The arrays
    come back as they are (the same objects) when no track is that sparse. ``med``: each
    track's median interval (s) when the caller has it."""
    if steps <= 0 or len(t) < 2:
        return x, y, t
    if med is None:
        med = median_interval_s(t, index)
    with np.errstate(invalid="ignore"):
        f = np.fmax(steps * med / window_s, 1.0)
    f[~np.isfinite(f)] = 1.0
    sparse = f > 1.0
    if not sparse.any():
        return x, y, t
    # only the sparse tracks' rows are scaled (the others' divide by 1: left as they are)
    tr = index.track_of_row
    rows = np.flatnonzero(sparse[tr])
    fr = f[tr[rows]]
    t0 = t[index.starts[tr[rows]]]
    x, y, t = x.copy(), y.copy(), t.copy()
    x[rows] /= fr
    y[rows] /= fr
    t[rows] = t0 + (t[rows] - t0) / fr
    return x, y, t


def rest_radius(
    x: np.ndarray,
    y: np.ndarray,
    t: np.ndarray,
    index: TrackIndex,
    radius_m: float,
    sigmas: float,
    window_s: float,
    steps: float,
    med: np.ndarray | None = None,
    lag: "np.ndarray | int" = 1,
    sigma: np.ndarray | None = None,
    cap_m: float = 0.0,
) -> "float | np.ndarray":
    """The at-rest radius :func:`at_rest` takes in :func:`rest_frame`'s frame: ``radius_m``
    (a float) when ``sigmas`` is 0, else per track max(``radius_m``, ``sigmas`` · σ / f), σ
    the track's position noise per axis (:func:`wakeline.core.maneuver.position_noise_m`
    with ``lag``, or ``sigma`` when the caller has it) and f the factor by which
    :func:`rest_frame` shrinks a sparse track (its radius there is f · ``radius_m`` in
    metres; the noise's share, ``sigmas`` · σ metres, is not a speed and does not grow;
    ``cap_m`` > 0: that share at most ``cap_m`` metres, session 28 h195).
    ``x``/``y`` metres before :func:`rest_frame`."""
    if sigmas <= 0 or index.n_tracks == 0:
        return radius_m
    if sigma is None:
        from wakeline.core.maneuver import position_noise_m  # the noise floor's estimate

        sigma = position_noise_m(x, y, t, index, lag)
    f = np.ones(index.n_tracks)
    if steps > 0 and len(t) >= 2:
        if med is None:
            med = median_interval_s(t, index)
        with np.errstate(invalid="ignore"):
            f = np.fmax(steps * med / window_s, 1.0)
        f[~np.isfinite(f)] = 1.0
    grown = np.where(np.isfinite(sigma), sigmas * np.asarray(sigma, dtype="float64"), 0.0)
    if cap_m > 0:
        grown = np.fmin(grown, float(cap_m))
    grown = grown / f
    return np.fmax(float(radius_m), grown)


def track_axes(x: np.ndarray, y: np.ndarray, index: TrackIndex) -> tuple[np.ndarray, np.ndarray]:
    """``x``/``y`` turned, per track, into the track's own principal axes (about its mean
    position: u along the direction of its largest spread, v across it).

    The axes come from the track alone, so they turn with it: a rotation of the globe,
    which turns each track's local plane (azimuthal equidistant about its centre) by one
    angle ψ about its origin, turns the principal axes by ψ too and leaves (u, v) as they
    were, up to rounding. A track with no spread (one fix, all fixes alike, or a second
    moment that is not finite) keeps its x/y directions. Rows sorted by track."""
    n = len(x)
    if n == 0:
        return x, y
    tr, k = index.track_of_row, index.n_tracks
    # rows sorted by track, the tracks one after the other: a per-track value spread to
    # its rows by np.repeat (a gather by track number costs twice as much)
    runs = bool(index.sizes.sum() == n) and bool(np.all(index.starts[1:] == index.ends[:-1]))

    has = index.sizes > 0
    first = index.starts[has]

    def per_row(v: np.ndarray) -> np.ndarray:
        return np.repeat(v, index.sizes) if runs else v[tr]

    def per_track(v: np.ndarray) -> np.ndarray:  # sums
        if not runs:
            return np.bincount(tr, v, k)
        out = np.zeros(k)
        out[has] = np.add.reduceat(v, first)
        return out

    ok = np.isfinite(x) & np.isfinite(y)
    if ok.all():
        xf, yf = x, y
        cnt = (index.sizes if runs else np.bincount(tr, minlength=k)).astype("float64")
    else:
        xf, yf = np.where(ok, x, 0.0), np.where(ok, y, 0.0)
        cnt = per_track(ok.astype("float64"))
    with np.errstate(invalid="ignore", divide="ignore"):
        mx = per_track(xf) / cnt
        my = per_track(yf) / cnt
    mx[~np.isfinite(mx)] = 0.0
    my[~np.isfinite(my)] = 0.0
    dx, dy = xf - per_row(mx), yf - per_row(my)
    if not ok.all():
        dx[~ok] = 0.0
        dy[~ok] = 0.0
    sxy = per_track(dx * dy)
    dx *= dx
    dy *= dy
    sxx, syy = per_track(dx), per_track(dy)
    phi = 0.5 * np.arctan2(2.0 * sxy, sxx - syy)  # atan2(0, 0) = 0: the x/y directions
    phi[~np.isfinite(phi)] = 0.0
    c, s = per_row(np.cos(phi)), per_row(np.sin(phi))
    u = x * c
    u += y * s
    v = y * c
    v -= x * s
    return u, v


def at_rest(
    x: np.ndarray,
    y: np.ndarray,
    t: np.ndarray,
    index: TrackIndex,
    radius_m: "float | np.ndarray",
    window_s: float,
    north_box: bool = False,
) -> np.ndarray:
    """Per point: does it lie in a stay of at least ``window_s`` seconds whose positions
    all fit in a circle of ``radius_m`` metres (a float, or one per track) (their bounding box's diagonal ≤ 2·radius,
    the box aligned with the track's own principal axes, :func:`track_axes`)?

    Tolerates position jitter, unlike an identical-position test. ``x``/``y`` are metres in
    each track's frame, ``t`` seconds, rows sorted by track then time. Runs as time-based
    rolling extrema over all tracks at once (tracks are set apart in time so no window
    reaches a neighbour): a window ending at each point, reaching back to the last fix at or
    before ``t - window_s``; every point of a window that fits is at rest.

    The bound: a window's diameter D (its two farthest positions) and its box's diagonal d
    satisfy D ≤ d ≤ √2·D in any frame, so a window that passes fits in a circle of
    ``radius_m`` (about the box's centre) and any window with D ≤ √2·``radius_m`` passes;
    a ship moving straight passes up to 2·radius / window whatever its course (on a line
    d = D: the rule's ≈ 1 kn). Which verdict a window between the two bounds gets (a round
    cloud of jitter wider than √2·radius) depends on how its spread lies to the box's
    axes. Until 2026-12 the axes were north and east (``north_box``, kept as the option),
    which turn against the track when the scene is rotated on the globe: a point near the
    threshold changed its verdict (Saronic, 1 of 18,834). The track's principal axes turn
    with the track, so the verdict is the same wherever the scene lies; the bound, the
    cost (four rolling extrema) and the speed meaning are the box's as before. Tried and
    not taken: the widest of the window's widths across 8 directions (≤ 2·radius; D
    within cos(π/16) of it, invariant too when the directions turn with these axes)
    passes round jitter up to √2 wider than the box does, and moved the real sets more
    (DMA slow share 0.036 → 0.038, ATD example maneuvers 1,422 → 1,416; the box in these
    axes left both as they were); the distance of every point to the window's first
    point or centroid is no rolling extremum.
    """
    n = len(x)
    if n == 0:
        return np.zeros(0, dtype=bool)
    if not north_box:
        x, y = track_axes(x, y, index)
    tr = index.track_of_row
    first = index.starts[tr]
    rel = t - t[first]
    span = np.zeros(index.n_tracks)
    has = index.sizes > 0
    span[has] = rel[index.ends[has] - 1]
    offset = np.concatenate([[0.0], np.cumsum(span + 2.0 * window_s + 1.0)[:-1]])
    ts = rel + offset[tr]
    when = pd.DatetimeIndex(pd.to_datetime(ts, unit="s"))
    win = f"{int(round(window_s * 1e6))}us"

    def rolling(values: np.ndarray, how: str) -> np.ndarray:
        r = pd.Series(values, index=when).rolling(win, closed="both")
        return getattr(r, how)().to_numpy()

    count = rolling(np.ones(n), "sum").astype("int64")
    row = np.arange(n)
    # the window reaches back to the last fix at or before t - window_s (sparse reports of
    # a moored ship, every 3 min for AIS class A), if that fix is of the same track and
    # no more than four windows back
    prev = row - count
    ok_prev = (prev >= first) & (ts - ts[np.maximum(prev, 0)] <= 4.0 * window_s)
    prev = np.where(ok_prev, prev, row - count + 1)
    px, py = x[prev], y[prev]
    dx = np.fmax(rolling(x, "max"), px) - np.fmin(rolling(x, "min"), px)
    dy = np.fmax(rolling(y, "max"), py) - np.fmin(rolling(y, "min"), py)
    stay = ts - ts[prev]
    # a stay: at least window_s long, two fixes or more, small enough
    reach = 2.0 * radius_m if np.ndim(radius_m) == 0 else 2.0 * np.asarray(radius_m)[tr]
    ends_rest = (np.hypot(dx, dy) <= reach) & (stay >= window_s) & (row > prev)
    # every point of such a window is at rest
    mark = np.zeros(n + 1, dtype="int64")
    np.add.at(mark, prev[ends_rest], 1)
    np.add.at(mark, row[ends_rest] + 1, -1)
    return np.cumsum(mark[:-1]) > 0


def rest_spans(rest: np.ndarray, index: TrackIndex) -> np.ndarray:
    """(k, 2) first and last row of every run of at-rest points within a track."""
    if not rest.any():
        return np.zeros((0, 2), dtype="int64")
    tr = index.track_of_row
    prev = np.zeros(len(rest), dtype=bool)
    prev[1:] = rest[:-1] & (tr[1:] == tr[:-1])
    nxt = np.zeros(len(rest), dtype=bool)
    nxt[:-1] = rest[1:] & (tr[1:] == tr[:-1])
    return np.column_stack([np.flatnonzero(rest & ~prev), np.flatnonzero(rest & ~nxt)])


#: Times formatted per call of numpy's formatter (each call holds the GIL: ~10 ms).
_TEXT_CHUNK = 20_000


def time_texts(times: pd.Series) -> np.ndarray:
    """The text pandas' ``astype(str)`` gives each time (``2024-01-01 00:00:00+00:00``;
    the fraction of a second to the finest the times need, as pandas does), made by
    numpy in chunks: pandas holds the GIL over the whole column (2.5 s for 200 k times,
    the window's event loop blocked 0.6–1.4 s in Clean on 1.1 M points; operator test
    4), numpy takes ~0.7 µs a time and lets the GUI thread run between chunks."""
    values = times.array
    tz = getattr(times.dtype, "tz", None)
    ns = np.asarray(values.tz_convert(None) if tz is not None else values, dtype="datetime64[ns]")
    nat = np.isnat(ns)
    whole = ns[~nat].astype("int64")
    unit = "s" if not (whole % 1_000_000_000).any() else "us" if not (whole % 1000).any() else "ns"
    if tz is None and not (whole % 86_400_000_000_000).any():
        unit = "D"  # naive times all at midnight: pandas writes the dates alone
    suffix = ""
    if tz is not None:
        suffix = pd.Timestamp(0, tz=tz).strftime("%z")
        suffix = suffix[:3] + ":" + suffix[3:] if suffix else ""
    out = np.empty(len(ns), dtype=object)
    for k in range(0, len(ns), _TEXT_CHUNK):
        part = np.datetime_as_string(ns[k : k + _TEXT_CHUNK], unit=unit)
        out[k : k + _TEXT_CHUNK] = [x.replace("T", " ") + suffix for x in part.tolist()]
    out[nat] = np.nan  # as pandas: a missing text
    return out


def _span_table(
    pts: pd.DataFrame, rows: np.ndarray, spans: np.ndarray, t: np.ndarray
) -> pd.DataFrame:
    """One row per at-rest span: sensor, batch, start, end, duration_s, points, lon, lat."""
    a, b = rows[spans[:, 0]], rows[spans[:, 1]]
    return pd.DataFrame(
        {
            # The spans' rows only (a whole text column as objects would hold the GIL).
            "sensor": pts["sensor"].iloc[a].astype(str).to_numpy(),
            "batch": pts["batch"].iloc[a].astype(str).to_numpy(),
            "start": time_texts(pts["time"].iloc[a]),
            "end": time_texts(pts["time"].iloc[b]),
            "duration_s": t[b] - t[a],
            "points": spans[:, 1] - spans[:, 0] + 1,
            "lon": pts["lon"].to_numpy()[a],
            "lat": pts["lat"].to_numpy()[a],
        }
    )


def _clean_block(
    pts: pd.DataFrame, index: TrackIndex, params: CleanParams, progress: Progress | None
) -> CleanResult:
    progress = progress or null_progress
    n = len(pts)
    lon = pts["lon"].to_numpy(dtype="float64").copy()
    lat = pts["lat"].to_numpy(dtype="float64").copy()
    t = time_seconds(pts["time"])
    track = index.track_of_row
    alive = np.ones(n, dtype=bool)
    removed_by: dict[str, np.ndarray] = {}
    changed_by: dict[str, np.ndarray] = {}
    changed_rows: list[pd.DataFrame] = []
    speed_col = (
        pts["speed"].to_numpy(dtype="float64").copy()
        if "speed" in pts.columns
        else np.full(n, np.nan)
    )

    def step(k: int, name: str) -> None:
        progress(k / len(RULES), name)

    # 1. duplicates
    step(0, "duplicates")
    if params.duplicates.enabled and n > 1:
        dp = params.duplicates
        same = np.zeros(n, dtype=bool)
        same[1:] = (track[1:] == track[:-1]) & (t[1:] == t[:-1])
        group = np.cumsum(~same) - 1
        keeper = np.flatnonzero(~same)
        # how far each same-time row lies from the row kept (the first of its time)
        away = np.zeros(n)
        if same.any():
            k = keeper[group[same]]
            away[same] = geo.haversine_m(lon[k], lat[k], lon[same], lat[same])
        far = same & (away > dp.same_place_m) & (not dp.paper_rule)
        removed_by["duplicates"] = same & ~far
        removed_by["same_time"] = far
        same_time_median_m = float(np.median(away[far])) if far.any() else 0.0
        if dp.keep_mean and (same & ~far).any():
            # the mean of the row kept and its duplicates (not of rows at another place)
            w = (~far).astype("float64")
            has_dup = np.bincount(group, (same & ~far).astype("float64"), minlength=len(keeper)) > 0
            ref = lon[keeper][group]
            wsum = np.bincount(group, w)
            mean_dlon = np.bincount(group, w * geo.wrap180(lon - ref)) / wsum
            mean_lat = np.bincount(group, w * lat) / wsum
            rows = keeper[has_dup]
            changed_rows.append(pts.iloc[rows].assign(rule="duplicates", action="changed"))
            lon[rows] = geo.wrap180(lon[rows] + mean_dlon[has_dup])
            lat[rows] = mean_lat[has_dup]
            mask = np.zeros(n, dtype=bool)
            mask[rows] = True
            changed_by["duplicates"] = mask
        alive &= ~same

    legs = _Legs(lon, lat, t, track)  # positions are final from here on

    # 2. stationary
    step(1, "stationary")
    rest_table = None
    if params.stationary.enabled:
        rows = np.flatnonzero(alive)
        sp = params.stationary
        if sp.paper_rule:
            mask = _paper_stationary(legs, rows, lon, lat, track, speed_col, sp.speed_kn, n)
        else:
            sub = TrackIndex(*_sub_index_rows(track[rows], index.n_tracks))
            x, y = _local_xy_rows(lon[rows], lat[rows], sub)
            radius = rest_radius(
                x, y, t[rows], sub, sp.radius_m, sp.noise_sigmas, sp.window_s, sp.steps
            )
            x, y, t_rest = rest_frame(x, y, t[rows], sub, sp.window_s, sp.steps)
            rest = at_rest(x, y, t_rest, sub, radius, sp.window_s, sp.north_box)
            spans = rest_spans(rest, sub)
            inside = rest.copy()
            inside[spans[:, 0]] = False  # a span's first and last point stay: where and
            inside[spans[:, 1]] = False  # when the ship stopped and left
            mask = np.zeros(n, dtype=bool)
            mask[rows[inside]] = True
            rest_table = _span_table(pts, rows, spans, t)
        removed_by["stationary"] = mask
        alive &= ~mask

    # 3. impossible speed
    step(2, "speed")
    if params.speed.enabled:
        mask, speed_breaks = _speed_rule(
            legs,
            alive,
            track,
            params.speed.v_max_kn * geo.KN_MS,
            params.speed.tolerance_m,
            params.speed.break_run,
        )
        removed_by["speed"] = mask
        alive &= ~mask

    # 4. impossible turn
    step(3, "turn")
    if params.turn.enabled:
        rows = np.flatnonzero(alive)
        dist, dt, course = legs(rows)
        first, last = _runs(track[rows])
        nxt = lambda a: np.append(a[1:], np.nan)  # noqa: E731 - the leg leaving each row
        d_out, dt_out, c_out = nxt(dist), nxt(dt), nxt(course)
        d_out[last] = np.nan
        turn = geo.angle_diff(course, c_out)
        radius = params.turn.radius_factor * params.turn.ship_length_m
        with np.errstate(invalid="ignore", divide="ignore"):  # a leg at one time: inf
            v = dist / dt  # m/s on the leg arriving
            err = params.turn.position_error_m
            slack = np.degrees(np.arctan2(err, dist) + np.arctan2(err, d_out))
            limit = np.minimum(np.degrees(v / radius * dt_out) + slack, 180.0)
            v_out = d_out / dt_out
            slow = params.turn.min_speed_kn * geo.KN_MS
            judged = (dist >= params.turn.min_leg_m) & (d_out >= params.turn.min_leg_m)
            judged &= (v >= slow) & (v_out >= slow)
            # a leg the speed rule let through as a break (another ship) is not a turn
            v_cap = params.speed.v_max_kn * geo.KN_MS
            judged &= (dist <= v_cap * dt + params.speed.tolerance_m) & (
                d_out <= v_cap * dt_out + params.speed.tolerance_m
            )
            over = judged & (turn > limit)
        tn = np.where(np.isfinite(turn), turn, -1.0)
        prev_t = np.append(-1.0, tn[:-1])
        next_t = np.append(tn[1:], -1.0)
        mask = np.zeros(n, dtype=bool)
        mask[rows[over & (tn >= prev_t) & (tn >= next_t)]] = True
        removed_by["turn"] = mask
        alive &= ~mask

    # 5. speed attribute outliers (reported speeds only)
    step(4, "speed_outliers")
    if params.speed_outliers.enabled and np.isfinite(speed_col).any():
        rows = np.flatnonzero(alive)
        s = speed_col[rows]
        upper = _tukey_upper(s, track[rows], params.speed_outliers.iqr_factor)
        dist, dt, _ = legs(rows)
        with np.errstate(invalid="ignore", divide="ignore"):
            derived = dist / dt / geo.KN_MS
        derived_next = np.append(derived[1:], np.nan)
        derived_next[_runs(track[rows])[1]] = np.nan
        # the positions back the reported speed on the leg before or after the point
        backed = (np.abs(s - derived) <= params.speed_outliers.agree_kn) | (
            np.abs(s - derived_next) <= params.speed_outliers.agree_kn
        )
        out = np.isfinite(s) & (s > upper) & ~backed
        if out.any():
            good = np.isfinite(s) & ~out
            sums = np.bincount(track[rows], np.where(good, s, 0.0), minlength=index.n_tracks)
            counts = np.bincount(track[rows], good.astype(float), minlength=index.n_tracks)
            with np.errstate(invalid="ignore", divide="ignore"):
                means = sums / counts
            bad_rows = rows[out]
            changed_rows.append(pts.iloc[bad_rows].assign(rule="speed_outliers", action="changed"))
            speed_col[bad_rows] = means[track[bad_rows]]
        mask = np.zeros(n, dtype=bool)
        mask[rows[out]] = True
        changed_by["speed_outliers"] = mask

    # 6. isolated points
    step(5, "isolated")
    if params.isolated.enabled and not alive.any():  # nothing left (or an empty table)
        removed_by["isolated"] = np.zeros(n, dtype=bool)
    elif params.isolated.enabled:
        rows = np.flatnonzero(alive)
        dist, _, _ = legs(rows)
        upper = _tukey_upper(dist, track[rows], params.isolated.iqr_factor)
        out_in = np.isfinite(dist) & (dist > upper)
        out_out = np.append(out_in[1:], False)
        first, last = _runs(track[rows])
        # Isolated: both steps are outliers, yet the step over the point is not — taking
        # the point out restores continuity: the step over it is no longer than two ordinary
        # steps (a ship sailing between stops fails this: skipping a point doubles the step).
        r_prev = np.append(rows[0], rows[:-1])
        r_next = np.append(rows[1:], rows[-1])
        bridge, _ = geo.short_legs(lon[r_prev], lat[r_prev], lon[r_next], lat[r_next])
        mask = np.zeros(n, dtype=bool)
        isolated = out_in & out_out & ~first & ~last
        if params.isolated.bridge:
            isolated &= bridge <= 2.0 * upper
        mask[rows[isolated]] = True
        removed_by["isolated"] = mask
        alive &= ~mask

    # Where the tracks split (a jump no ship could make: batch#2 …), so that the short
    # tracks rule judges the tracks that come out.
    split = np.zeros(n, dtype=bool)
    if params.speed.enabled and params.speed.split_factor > 0 and speed_breaks.any():
        split = _split_rows(speed_breaks & alive, alive, track, lon, lat, t, params.speed)
    piece = track
    if split.any():
        head = np.zeros(n, dtype=bool)
        head[index.starts[index.sizes > 0]] = True
        piece = np.cumsum(head | split) - 1  # one number per track piece, in row order

    # 7. short tracks
    step(6, "short_tracks")
    if params.short_tracks.enabled:
        seen = alive.copy()
        if params.short_tracks.count_at_rest and "stationary" in removed_by:
            seen |= removed_by["stationary"]
        judged, n_judged = track, index.n_tracks
        if params.short_tracks.after_split and split.any():
            judged, n_judged = piece, int(piece[-1]) + 1
        counts = np.bincount(judged[seen], minlength=n_judged)
        short = (counts < params.short_tracks.min_points)[judged] & alive
        removed_by["short_tracks"] = short
        alive &= ~short
        if not params.short_tracks.after_split:
            split &= alive  # the order before: a track set aside whole is not split
    progress(1.0, "cleaned")

    if split.any():
        pts, changed_rows = _split_batches(pts, index, split, changed_rows)
    cleaned = pts[alive].reset_index(drop=True)  # one copy of the surviving rows
    cleaned["lon"] = lon[alive]
    cleaned["lat"] = lat[alive]
    if "speed" in cleaned.columns or np.isfinite(speed_col).any():
        cleaned["speed"] = speed_col[alive]

    param_text = {rule: json.dumps(dataclasses.asdict(getattr(params, rule))) for rule in RULES}
    param_text["same_time"] = param_text["duplicates"]
    parts = [
        pts[mask].assign(rule=rule, action="removed")
        for rule, mask in removed_by.items()
        if mask.any()
    ]
    parts += changed_rows
    if parts:
        rejected = pd.concat(parts, ignore_index=True)
        rejected["params"] = rejected["rule"].map(param_text)
        rejected = rejected.sort_values([ID, "action"], kind="stable").reset_index(drop=True)
    else:
        rejected = pts.iloc[:0].assign(rule="", action="", params="")
    report = _report(index, track, removed_by, changed_by, alive, params)
    if "same_time" in report["rules"]:
        report["rules"]["same_time"]["median_m"] = same_time_median_m
    report["at_rest_spans"] = rest_table.to_dict(orient="records") if rest_table is not None else []
    if rest_table is not None:
        report["rules"]["stationary"]["spans"] = int(len(rest_table))
        report["rules"]["stationary"]["at_rest_s"] = float(rest_table["duration_s"].sum())
    if params.speed.enabled:
        report["rules"]["speed"]["breaks"] = int(speed_breaks[alive].sum())
        report["rules"]["speed"]["splits"] = int(split.sum())
        # the impossible legs left inside a track (not split): D3, operator test 7
        n_kept, legs_kept = _kept_break_legs(
            pts, speed_breaks, alive, piece, lon, lat, t, params.speed
        )
        report["rules"]["speed"]["breaks_kept"] = n_kept
        report["rules"]["speed"]["break_legs"] = legs_kept
    if split.any():  # each piece with a point left is a track (batch#2 …)
        report["tracks_out"] = int(len(np.unique(piece[alive])))
    order = ordered_columns(cleaned)
    return CleanResult(
        cleaned if order == list(cleaned.columns) else cleaned[order], rejected, report
    )


def _split_rows(
    breaks: np.ndarray,
    alive: np.ndarray,
    track: np.ndarray,
    lon: np.ndarray,
    lat: np.ndarray,
    t: np.ndarray,
    sp: "SpeedParams",
) -> np.ndarray:
    """The breaks no ship could make: a jump from the last kept point of the same track
    longer than ``split_km`` and than ``split_factor`` × v_max × the time between; with
    ``split_at_breaks`` also every break whose leg is still impossible (longer than
    v_max × dt + ``tolerance_m``)."""
    rows, prev, has, d, dt = _break_legs(breaks, alive, track, lon, lat, t)
    far = split_legs(d, dt, sp)
    out = np.zeros(len(alive), dtype=bool)
    out[rows[has & far]] = True
    return out


def split_legs(d: np.ndarray, dt: np.ndarray, sp: "SpeedParams") -> np.ndarray:
    """The legs (``d`` m in ``dt`` s) at which a break splits its track: longer than
    ``split_km`` and than ``split_factor`` × v_max × dt; with ``split_at_breaks`` every
    impossible one (:func:`impossible_legs`)."""
    v_max = sp.v_max_kn * geo.KN_MS
    with np.errstate(invalid="ignore"):
        far = (d > sp.split_km * 1000.0) & (d > sp.split_factor * v_max * dt)
    if sp.split_at_breaks:
        far |= impossible_legs(d, dt, v_max, sp.tolerance_m)
    return far


def _break_legs(
    breaks: np.ndarray,
    alive: np.ndarray,
    track: np.ndarray,
    lon: np.ndarray,
    lat: np.ndarray,
    t: np.ndarray,
) -> tuple[np.ndarray, ...]:
    """For each kept break row: the previous kept row, whether it is of the same track
    (``track``: a number per track or per piece), and the leg's length (m) and time (s)."""
    rows = np.flatnonzero(breaks & alive)
    kept = np.flatnonzero(alive)
    pos = np.searchsorted(kept, rows)  # rows are kept: the previous kept row is at pos - 1
    has = pos > 0
    prev = kept[np.maximum(pos - 1, 0)]
    has &= track[prev] == track[rows]
    d = geo.haversine_m(lon[prev], lat[prev], lon[rows], lat[rows])
    dt = t[rows] - t[prev]
    return rows, prev, has, d, dt


BREAK_LEGS_LISTED = 100
"""The clean report lists at most this many impossible legs kept (the fastest); its
``breaks_kept`` counts them all (MTAD's noise gives 1,343, some 200 KB of JSON)."""


def _kept_break_legs(
    pts: pd.DataFrame,
    breaks: np.ndarray,
    alive: np.ndarray,
    piece: np.ndarray,
    lon: np.ndarray,
    lat: np.ndarray,
    t: np.ndarray,
    sp: "SpeedParams",
) -> tuple[int, list[dict]]:
    """The breaks whose impossible leg stayed inside an output track (not split, its
    leg from the last kept point of the same piece still longer than v_max · dt +
    tolerance): how many, and one record each for the fastest :data:`BREAK_LEGS_LISTED`
    (sensor, batch as written out, time, from_time, km, s, kn), the fastest first."""
    rows, prev, has, d, dt = _break_legs(breaks, alive, piece, lon, lat, t)
    with np.errstate(invalid="ignore", divide="ignore"):
        bad = has & (d > sp.v_max_kn * geo.KN_MS * dt + sp.tolerance_m)
        kn = np.where(dt > 0, d / dt / geo.KN_MS, np.inf)
    rows, prev, d, dt, kn = rows[bad], prev[bad], d[bad], dt[bad], kn[bad]
    n_kept = int(len(rows))
    order = np.argsort(-kn, kind="stable")[:BREAK_LEGS_LISTED]
    rows, prev, d, dt, kn = rows[order], prev[order], d[order], dt[order], kn[order]
    return n_kept, [
        {
            "sensor": sensor,
            "batch": batch,
            "time": time,
            "from_time": before,
            "km": round(float(km), 3),
            "s": float(s),
            "kn": round(float(v), 1) if np.isfinite(v) else None,
        }
        for sensor, batch, time, before, km, s, v in zip(
            pts["sensor"].iloc[rows].astype(str),
            pts["batch"].iloc[rows].astype(str),
            time_texts(pts["time"].iloc[rows]),
            time_texts(pts["time"].iloc[prev]),
            d / 1000.0,
            dt,
            kn,
            strict=True,
        )
    ]


def _split_batches(
    pts: pd.DataFrame, index: TrackIndex, split: np.ndarray, changed_rows: list[pd.DataFrame]
) -> tuple[pd.DataFrame, list[pd.DataFrame]]:
    """Rows from each split on get their batch with ``#2``, ``#3`` … (removed and changed
    rows too, so that a restored point returns to its piece)."""
    piece = np.cumsum(split)
    piece -= np.repeat(piece[index.starts] - split[index.starts], index.sizes)
    rows = np.flatnonzero(piece > 0)
    batch = pts["batch"].astype("str")
    renamed = (
        batch.iloc[rows] + "#" + pd.Series(piece[rows] + 1, index=batch.index[rows]).astype("str")
    )
    pts = pts.copy()
    pts["batch"] = batch.mask(piece > 0, renamed)
    # Only the renamed rows become Python text (the whole column would hold the GIL).
    new_of = pd.Series(pts["batch"].iloc[rows].to_numpy(), index=pts[ID].to_numpy()[rows])
    out = []
    for part in changed_rows:
        hit = part[ID].isin(new_of.index).to_numpy()
        if hit.any():
            part = part.copy()
            part.loc[hit, "batch"] = new_of.reindex(part.loc[hit, ID]).to_numpy()
        out.append(part)
    return pts, out


def _report(
    index: TrackIndex,
    track: np.ndarray,
    removed_by: dict,
    changed_by: dict,
    alive: np.ndarray,
    params: CleanParams,
) -> dict:
    per = index.keys.copy()
    per["points_in"] = index.sizes
    per["points_out"] = np.bincount(track[alive], minlength=index.n_tracks)
    rules = {}
    # same_time: the duplicates rule's rows at another place, reported apart
    for rule in (RULES[0], "same_time", *RULES[1:]):
        if rule == "same_time" and rule not in removed_by:
            continue
        removed = removed_by.get(rule)
        changed = changed_by.get(rule)
        n_removed = int(removed.sum()) if removed is not None else 0
        n_changed = int(changed.sum()) if changed is not None else 0
        if removed is not None:
            per[f"{rule}_removed"] = np.bincount(track[removed], minlength=index.n_tracks)
        if changed is not None:
            per[f"{rule}_changed"] = np.bincount(track[changed], minlength=index.n_tracks)
        own = getattr(params, "duplicates" if rule == "same_time" else rule)
        rules[rule] = {
            "enabled": bool(own.enabled),
            "removed": n_removed,
            "changed": n_changed,
            "params": dataclasses.asdict(own),
        }
    return {
        "points_in": int(index.sizes.sum()),
        "points_out": int(alive.sum()),
        "tracks_in": int(index.n_tracks),
        "tracks_out": int((per["points_out"] > 0).sum()),
        "rules": rules,
        "tracks": per.to_dict(orient="records"),
    }


def restore(
    cleaned: pd.DataFrame, rejected: pd.DataFrame, point_ids
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Put rejected points back: removed rows return, changed rows get their original
    values again. Returns new (cleaned, rejected) tables; the inputs are not modified."""
    ids = np.asarray(list(point_ids), dtype="int64")
    unknown = np.setdiff1d(ids, rejected[ID].to_numpy())
    if len(unknown):
        raise InputError(f"not in the rejected table: {ID} {', '.join(map(str, unknown[:10]))}")
    chosen = rejected[ID].isin(ids).to_numpy()
    if (rejected["action"].to_numpy()[chosen] == "replaced").any():
        raise InputError(
            "points replaced by a transforming step (bspline, resample, smooth) come back by "
            "cleaning again without that step, not one by one"
        )
    back = rejected[chosen]
    # A changed row's original values win over its current (changed) row.
    originals = back.drop_duplicates(ID, keep="first").drop(columns=["rule", "action", "params"])
    keep = cleaned[~cleaned[ID].isin(ids)]
    merged = pd.concat(
        [keep, originals[keep.columns.intersection(originals.columns)]], ignore_index=True
    )
    merged, _ = sorted_with_index(merged)
    return merged, rejected[~chosen].reset_index(drop=True)
