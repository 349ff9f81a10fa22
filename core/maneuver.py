"""Maneuver detection by PCA heading and a maximum filter (seed 000, SPEC §3).

For every point ``o`` of a track (in its local plane, metres) the heading of the ``p``
points ending at ``o`` and of the ``p`` points starting at ``o`` is the direction of the
first principal component of their positions, oriented by the displacement from the
window's first to its last point. The maneuver factor δ_o is the absolute difference of
the two headings in [0°, 180°]. A maneuver point satisfies δ_o > t (condition 1) and
δ_o = max(δ_{o-n} … δ_{o+n}) (condition 2, mirror padding at the ends, one point per
plateau).

Everything runs on all tracks at once: window sums are accumulated by a loop over the
``p`` offsets (never over windows), the 2×2 PCA has a closed form, and the maximum
filter runs over all tracks concatenated with −∞ separators.

Time, not points (ours, docs/evaluation.md "Departures: cleaning, maneuvers, compression"):
the window is ``window_s`` seconds, turned into ``p`` points per track from its median
sampling interval (never fewer than ``window_p``), so one default serves 1 s radar and
5 min plots alike; ``window_s = 0`` is the paper's fixed ``p``. Gradual turns: the window
doubles while within ``max_window_s``, the last window being ``max_window_s`` itself, and a
turn seen only at a longer window is added where no turn lies within one window of it. Turns that take a while: the first scale's windows are
also compared ``gap_s`` apart (the turn itself between them; the gapped δ must also exceed
t at the neighbouring points). Sharp turns close together (radar): the window also halves
down to ``min_window_s`` on tracks sampled fast enough for 3 points in it; such a turn must
clear the noise floor (at least t) with its own point left out too, so one stray plot is
no turn. Each added turn needs no turn already found within its reach.
No maneuver where the ship covers the faster window slower than ``min_speed_kn``, the
slower one slower than ``slow_side`` (0.5) × it — where that window is measured, no step in
it longer than ``slow_side_step_s`` (180 s), else all of it too — or where a window touches
an at-rest span (cleaning's stationary
rule: positions within ``rest_radius_m`` for ``rest_window_s``, on sparse tracks for
``rest_steps`` of their median intervals with the radius grown alike). No heading window
spans a step longer than ``max_step_windows`` (4) such at-rest windows, the at-rest rule's
reach over a gap: for the headings a track is cut there (an AIS ferry unseen for an hour
in port has no course across that hour).
``ManeuverParams.paper()`` switches all of these off. Option (off by default): ``noise_lag_s``
measures the track noise of the noise floor against points that many seconds either side,
not the neighbours, so it sees an offset wandering over a window (radar; docs/evaluation.md
"Hard radar against real radar"). Option (off by default): ``window_max_s`` bounds the
window at slow radar scans — where ``window_p`` points span more than it and 3 fit, as many
points as fit, and the first scale's maximum filter reaches one window at most
(docs/evaluation.md "Radar at slower scans (h131)"). Slow scans (defaults since session 31,
h241, docs/prereg/session31_slow_scans_b.md): ``radius_s`` (15 s) bounds the maximum
filter's radius to that many seconds of median steps (where 2 or more fit), and ``edge_s``
(12 s) gives a track's first and last p − 1 plots 3-point windows where the first window
spans more than it (docs/evaluation.md "Radar at slower scans (h162)"), both only on tracks
whose noise per step's run σ / (v · step) is under ``step_noise_max`` (0.15;
docs/evaluation.md "Session 31: slow scans, gated"); by their own rules they change nothing
on a track whose median step is 3 s or less or over 7.5 s.
"""

import math
import os
import threading
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np
import pandas as pd

from wakeline.core import geo, sorted_sets
from wakeline.core.params import Params, param
from wakeline.core.tracks import (
    PLOT_MAX_SPEED_KN,
    PLOT_MIN_INTERVAL_S,
    TrackIndex,
    concat_ranges,
    local_xy,
    median_interval_s,
    plot_like,
    remember_order,
    repeated_rows,
    run_medians,
    sorted_with_index,
    track_seconds,
)
from wakeline.core.words import count as count_of

#: Tables of at least this many rows are detected in parts of whole tracks on threads
#: (numpy releases the GIL in its passes); every rule is per track, so the result is the
#: one of a single pass (tests/test_maneuver_kernel.py checks it).
PARALLEL_MIN_ROWS = 400_000
#: ... in parts of about this many rows (several per thread, taken as threads come free):
#: row-sized arrays of a part then stay below the allocator's mmap threshold (reused, not
#: fresh pages) and within the shared cache, and a thread slowed by the machine's other
#: load holds back less (10 M rows, 2 cores: 16 parts ~10 % faster than 2).
PART_ROWS = 640_000


def _threads() -> int:
    return min(os.cpu_count() or 1, 8)


MANEUVER_COLUMNS = ("sensor", "batch", "index", "time", "lon", "lat", "factor")


@dataclass(frozen=True)
class ManeuverParams(Params):
    """Parameters of the PCA + maximum-filter detector (seed 000 §3.1 defaults for p, n, t;
    windows in seconds, gradual turns, minimum speed and at-rest spans are ours)."""

    window_p: int = param(
        5,
        "points",
        "points per heading window (p); with window_s > 0 the fewest points per window",
        lo=2,
        hi=1000,
        source="ours; seed 000 leaves p open",
    )
    radius_n: int = param(
        5,
        "points",
        "maximum-filter radius (n); at least one window at each scale",
        lo=1,
        hi=1000,
        source="seed 000 §3.1",
    )
    threshold_deg: float = param(
        15.0,
        "deg",
        "smallest heading change that counts (t)",
        lo=0.0,
        hi=180.0,
        source="seed 000 §3.1",
    )
    window_s: float = param(
        10.0,
        "s",
        "heading window in seconds: p per track = window_s / its median sampling interval "
        "(never fewer than window_p points); 0 = p points whatever time they span (paper)",
        lo=0.0,
        hi=1e7,
        source="ours",
    )
    max_window_s: float = param(
        320.0,
        "s",
        "gradual turns: the longest window; windows double from window_s while within it and "
        "end with it (10 s: 10, 20, ..., 320 s); a turn found only at a longer window counts "
        "where no shorter-window turn lies within that window; 0 = one scale",
        lo=0.0,
        hi=1e7,
        source="ours",
    )
    window_max_s: float = param(
        0.0,
        "s",
        "slow scans: where window_p points would span more than this many seconds (a "
        "track's median window of window_p points) and 3 points fit in it, the fewest points "
        "per window is as many as fit, and the first scale's maximum-filter radius is at most "
        "one window; 0 = off (window_p points whatever they span)",
        lo=0.0,
        hi=1e7,
        source="ours",
    )
    radius_s: float = param(
        15.0,
        "s",
        "the maximum filter's radius in seconds: at every scale the radius_n points it reaches "
        "at least are at most as many of the track's median steps as fit in this many seconds, "
        "where 2 or more fit (a radius of one step is no filter); 0 = off (radius_n points "
        "whatever they span)",
        lo=0.0,
        hi=1e7,
        source="ours (h162, docs/prereg/session27_radar_edges.md); default since session 31 "
        "(docs/prereg/session31_slow_scans_b.md)",
    )
    edge_s: float = param(
        12.0,
        "s",
        "turns at a track's ends: where the first scale's window (p points) spans more than "
        "this many seconds (p - 1 median steps) and 3 points at most, the ends it leaves "
        "without a heading (its first and last p - 1 points) get windows of 3 points; such a turn clears the noise floor "
        "of 3-point windows (higher) and needs no turn already found within one first-scale "
        "window; 0 = off",
        lo=0.0,
        hi=1e7,
        source="ours (h162, docs/prereg/session27_radar_edges.md); default since session 31 "
        "(docs/prereg/session31_slow_scans_b.md)",
    )
    step_noise_max: float = param(
        0.15,
        "",
        "radius_s and edge_s apply only on tracks whose noise per step's run is under this: "
        "sigma / (v * step), sigma the track's position noise (noise_k's), step its median "
        "interval, v its median speed over window_p points (the chord over their time); on a "
        "noisier track a smaller radius and 3-point ends let noise maxima through; "
        "0 = on every track",
        lo=0.0,
        hi=100.0,
        source="ours (h240, docs/prereg/session31_slow_scans.md); 0.15 by "
        "docs/prereg/session31_slow_scans_b.md (h241)",
    )
    min_speed_kn: float = param(
        1.0,
        "kn",
        "no maneuver where the ship covers its window before or after slower than this",
        lo=0.0,
        hi=100.0,
        source="ours; seed 001 eq. 1's 1 kn",
    )
    slow_side: float = param(
        0.5,
        "",
        "the slower of the two windows needs only this share of min_speed_kn (the faster "
        "one all of it) where it is measured (slow_side_step_s): 1 = both windows at min "
        "speed; below 1 a ship turning as it leaves or comes to rest counts while a ship "
        "slow on both sides still does not",
        lo=0.0,
        hi=1.0,
        source="ours (session 22; default since session 27 with slow_side_step_s, "
        "docs/prereg/session27_slow_side.md)",
    )
    slow_side_step_s: float = param(
        180.0,
        "s",
        "slow_side applies only where no step of the slower window is longer than this: its "
        "speed then is measured, not a chord over an unobserved step that may hide a stop or "
        "a reversal (180 s = the at-rest window, within which a stay would be seen); "
        "elsewhere the slower window needs all of min_speed_kn; 0 = any step",
        lo=0.0,
        hi=1e7,
        source="ours (session 27: ATD's 30-min posits, docs/prereg/session27_slow_side.md)",
    )
    slow_side_span_s: float = param(
        0.0,
        "s",
        "slow_side applies only where the slower window lasts at most this long: a creep "
        "measured within one at-rest window (180 s), not a mean over a longer span that may "
        "hold a stop and a run; elsewhere the slower window needs all of min_speed_kn; "
        "0 = any length",
        lo=0.0,
        hi=1e7,
        source="ours (session 27: ATD's 30-min posits, docs/prereg/session27_slow_side.md)",
    )
    noise_k: float = param(
        2.0,
        "",
        "a turn must also exceed this many standard deviations of the heading change that the "
        "track's own position noise gives its two windows (noise estimated per track); 0 = off",
        lo=0.0,
        hi=100.0,
        source="ours; seed 000 eq. 10-12 make the same point with a fixed error",
    )
    noise_lag_s: float = param(
        0.0,
        "s",
        "the track's position noise (noise_k's) is each point against the time "
        "interpolation of the points about this many seconds before and after it "
        "(round(noise_lag_s / median interval) points, at least 1): over a window's length "
        "it also sees an offset that wanders over the window, as a radar plot's reflection "
        "centre does; 0 = against its neighbouring points",
        lo=0.0,
        hi=1e7,
        source="ours (session 18: hard radar scenes, docs/evaluation.md)",
    )
    noise_min_span: float = param(
        0.0,
        "sigma",
        "the noise floor holds where each of a turn's two windows spans at least this many "
        "of the track's position-noise sigma (first to last point, straight line); a shorter "
        "window tests no turn (longer scales still do): there the heading error is far from "
        "the normal law noise_k assumes (at 3 sigma a window pair's delta passes 4 of its sd "
        "in 4 % of the windows, not 0.006 %); 0 = off",
        lo=0.0,
        hi=1000.0,
        source="ours (session 27, h170: docs/prereg/session27_false_turns.md)",
    )
    noise_k_windows: bool = param(
        False,
        "",
        "the noise floor's k grows with the independent windows a track offers: k = "
        "max(noise_k, sqrt(2 ln N)), N = the track's points / the window's points (the "
        "largest of N normal deviates, an extreme-value bound), so false turns are held per "
        "track, not per window",
        source="ours (session 27, h170: docs/prereg/session27_false_turns.md)",
    )
    noise_min_windows: float = param(
        0.0,
        "windows",
        "noise_min_span, noise_k_windows and noise_k_law apply only on tracks that offer at least this "
        "many windows of the first scale (the track's points / the first window's points), "
        "at every scale: a short track gives few windows, few chances for a false turn, and "
        "stays as without them; 0 = every track",
        lo=0.0,
        hi=1e9,
        source="ours (session 28, h178: docs/prereg/session28_false_turns.md)",
    )
    noise_k_law: bool = param(
        False,
        "",
        "the noise floor's k is taken at the same false-alarm probability under the heading "
        "change's real law at the window's span in track-noise sigma and its points (a table "
        "simulated on straight noisy windows), not the normal law: k grows where the windows "
        "span a few sigma (there the law's tails are heavy) and stays where they span tens; "
        "with noise_min_windows only on tracks offering that many windows",
        source="ours (session 28, h185: docs/prereg/session28_false_turns_b.md, "
        "bench/noise_law_table.py)",
    )
    gap_s: float = param(
        10.0,
        "s",
        "turns that take a while: the first scale's windows are also compared with this many "
        "seconds between them (the turn itself left out; tracks sampled at least every "
        "gap_s, one point each side at least); 0 = off",
        lo=0.0,
        hi=1e7,
        source="ours",
    )
    min_window_s: float = param(
        5.0,
        "s",
        "sharp turns close together: windows also halve from window_s down to this duration "
        "on tracks sampled fast enough for 3 points in it; a turn found there counts when it "
        "also clears the noise floor with its own plot left out, and no turn already found "
        "lies within that window; 0 = off",
        lo=0.0,
        hi=1e7,
        source="ours",
    )
    rest_radius_m: float = param(
        50.0,
        "m",
        "at-rest spans (cleaning's stationary rule) are no maneuvers; 0 = off",
        lo=0.0,
        hi=1e5,
    )
    rest_window_s: float = param(
        180.0, "s", "at rest: the shortest stay that counts", lo=1.0, hi=1e7
    )
    rest_steps: float = param(
        1.0,
        "intervals",
        "at rest on sparse tracks: the stay also spans this many of the track's median "
        "sampling intervals, the radius growing with it (cleaning's stationary.steps); 0 = off",
        lo=0.0,
        hi=1000.0,
    )
    rest_noise_sigmas: float = param(
        5.0,
        "sigma",
        "at rest: the radius grows, per track, to this many of the track's position-noise "
        "sigma (the noise floor's estimate) where that is larger than rest_radius_m, so a "
        "moored ship seen with tens of metres of noise is at rest, not turning (cleaning's "
        "stationary.noise_sigmas); 0 = off",
        lo=0.0,
        hi=100.0,
        source="ours (session 28, h193: docs/prereg/session28_at_rest_noise.md; default 5 "
        "with rest_noise_cap_m 100 since h195: docs/prereg/session28_at_rest_noise_b.md)",
    )
    rest_noise_cap_m: float = param(
        100.0,
        "m",
        "at rest: the radius grown by rest_noise_sigmas is at most this many metres (the "
        "noise's share; on sparse tracks it does not grow with the window), so a sparse "
        "track with hundreds of metres of noise moving at speed is not taken as at rest; "
        "0 = no cap",
        lo=0.0,
        hi=1e5,
        source="ours (session 28, h195: docs/prereg/session28_at_rest_noise_b.md, all nine "
        "guards held)",
    )
    rest_north_box: bool = param(
        False,
        "",
        "at rest: the box aligned with north and east (before 2026-12; cleaning's "
        "stationary.north_box) instead of each track's principal axes",
    )
    confirm_z: float = param(
        0.0,
        "sd",
        "a confirmation test per turn: a straight line fitted (least squares on time) to "
        "the leg before the turn and to the leg after it (confirm_legs windows of the "
        "turn's scale each side, clipped at the track's ends, gaps and at-rest spans); the "
        "turn counts only when the two legs' courses differ by more than this many standard "
        "errors, sqrt(se_before^2 + se_after^2), se = the track's position noise / (speed "
        "* sqrt(sum (t - mean t)^2)) rad, the leg's speed taken as at least min_speed_kn; "
        "0 = off",
        lo=0.0,
        hi=100.0,
        source="ours (session 29, h203: docs/prereg/session29_confirm.md)",
    )
    confirm_legs: float = param(
        2.0,
        "windows",
        "confirm_z: each leg spans this many of the turn's windows (its scale's points, at "
        "least 2 points), the turn's own point shared by both legs",
        lo=0.5,
        hi=100.0,
        source="ours (session 29, h203)",
    )
    confirm_grow: int = param(
        0,
        "doublings",
        "confirm_z: a turn its legs do not confirm is tested again with both legs twice as "
        "long, up to this many times, and kept when a test confirms it: the grown legs' "
        "courses differ by more than confirm_z standard errors, and so do the grown leg "
        "before and the course at the turn's point (a line over both first legs) and that "
        "course and the grown leg after, all the same way round (a gradual turn's change "
        "lies mostly outside legs of a few windows; a change in one leg only is another "
        "turn further off); grown legs stop at the turns already confirmed; 0 = off",
        lo=0,
        hi=8,
        source="ours (session 29, h208: the true turns the first test lost on the hard "
        "scenes' tuning seeds were gradual, 0.04-0.2 deg/s; docs/prereg/session29_confirm_b.md)",
    )
    confirm_grow_deg: bool = param(
        False,
        "",
        "confirm_grow: a grown test confirms a turn only where the grown legs' courses also "
        "differ by threshold_deg (the turn itself, not only a change the noise does not "
        "explain)",
        source="ours (session 29, h208)",
    )
    max_step_windows: float = param(
        4.0,
        "at-rest windows",
        "no heading window spans a step longer than this many at-rest windows (rest_window_s; "
        "on sparse tracks rest_steps median intervals, at least one): the at-rest rule's reach "
        "over a gap (four windows), beyond which neither a stay nor a course was seen; the "
        "headings treat the track as cut there; 0 = off (a window spans any step)",
        lo=0.0,
        hi=1e6,
        source="ours; cleaning's at_rest reaches back four windows (docs/evaluation.md, "
        "Sampling-rate sweep: the Saronic ferry's 45-62 min AIS gaps in port)",
    )

    @classmethod
    def paper(cls) -> "ManeuverParams":
        """Seed 000 as written: p points per window, one scale, no speed or rest rule."""
        return cls(
            window_s=0.0,
            max_window_s=0.0,
            min_speed_kn=0.0,
            rest_radius_m=0.0,
            noise_k=0.0,
            min_window_s=0.0,
            gap_s=0.0,
            max_step_windows=0.0,
            radius_s=0.0,
            edge_s=0.0,
            step_noise_max=0.0,
        )


#: ``np.degrees`` is ``x * (180.0 / NPY_PI)`` (numpy's npy_rad2deg): the same product as one
#: multiplication by this constant, bit for bit, in a vectorized loop.
RAD_TO_DEG = 180.0 / math.pi

#: Windows per block: temporaries of 512 kB stay in the processor's cache (and in the
#: allocator's reusable heap), where row-sized ones (80 MB at 10 M points) would be fresh
#: pages every time. Not smaller: every numpy call is a point where a thread may wait for
#: the other's GIL (2^15 on two threads: ~10 % slower at 10 M points, 2^17 no faster).
BLOCK = 1 << 16


def window_headings(
    x: np.ndarray, y: np.ndarray, p: int, anchor: np.ndarray | None = None
) -> np.ndarray:
    """Heading (deg, [0, 360)) of the ``p`` points ending at each index; NaN for the first p-1.

    ``x``/``y`` are one track, or tracks concatenated (windows that straddle two tracks
    are the caller's to mask). Window sums are short convolutions, so nothing accumulates
    along the array; ``anchor`` (row numbers) says which point each row's coordinates are
    taken relative to — its track's first point keeps the numbers small, so E[u²] − E[u]²
    loses no precision. Work goes in blocks of ``BLOCK`` windows.
    """
    n = len(x)
    out = np.full(n, np.nan)
    if n < p:
        return out
    ref = np.zeros(n, dtype="int64") if anchor is None else anchor
    for first in range(p - 1, n, BLOCK):  # a loop over blocks, not over windows
        last = min(n, first + BLOCK)
        rows = slice(first - p + 1, last)
        u = x[rows] - x[ref[rows]]
        v = y[rows] - y[ref[rows]]
        out[first:last] = _block_headings(u, v, p)
    return out


def _block_headings(u: np.ndarray, v: np.ndarray, p: int) -> np.ndarray:
    return _axis_headings(*_block_moments(u, v, p))


def _block_moments(u: np.ndarray, v: np.ndarray, p: int):
    """Per window: cxx − cyy, 2·cxy and the displacement from its first point to its last.

    The same arithmetic, operation for operation, as mean / covariance / closed-form PCA
    written plainly; done in place so a block allocates a handful of arrays, not twenty."""
    n = len(u)
    ones = np.ones(p)
    mu = np.convolve(u, ones, "valid")
    mu /= p
    mv = np.convolve(v, ones, "valid")
    mv /= p
    tmp = np.multiply(u, u)
    cxx = np.convolve(tmp, ones, "valid")
    cxx /= p
    cxx -= np.multiply(mu, mu, out=tmp[: n - p + 1])
    np.multiply(v, v, out=tmp)
    cyy = np.convolve(tmp, ones, "valid")
    cyy /= p
    cyy -= np.multiply(mv, mv, out=tmp[: n - p + 1])
    np.multiply(u, v, out=tmp)
    cxy = np.convolve(tmp, ones, "valid")
    cxy /= p
    cxy -= np.multiply(mu, mv, out=tmp[: n - p + 1])
    cxy *= 2.0
    cxx -= cyy
    du = np.subtract(u[p - 1 :], u[: n - p + 1], out=mu)
    dv = np.subtract(v[p - 1 :], v[: n - p + 1], out=mv)
    return cxx, cxy, du, dv


def _axis_headings(a: np.ndarray, b: np.ndarray, du: np.ndarray, dv: np.ndarray) -> np.ndarray:
    """Heading (deg) of the major axis 0.5·atan2(b, a), oriented along (du, dv); overwrites
    its arguments."""
    theta = np.arctan2(b, a, out=b)
    theta *= 0.5  # major axis, radians from +x
    ax, ay = np.cos(theta, out=a), np.sin(theta, out=np.empty_like(a))
    # Orient by travel: from the window's first point to its last.
    du *= ax
    dv *= ay
    du += dv
    flip = du < 0.0
    heading = np.arctan2(ax, ay, out=theta)
    heading *= RAD_TO_DEG  # np.degrees, bit for bit, without its per-element call
    # as the plain form's "+ where(flip, 180, 0)": + 0.0 where not flipped (which also
    # makes -0.0 0.0, so no -0.0 is left)
    heading += flip * 180.0
    # in [-180, 360] (or NaN), where _wrap360 never takes np.remainder: its shift alone,
    # and not even that where every heading is in [0, 360) already (the usual case: the
    # shift would add +0.0 to every value, changing no bit now that no -0.0 is left)
    with np.errstate(invalid="ignore"):
        below, above = heading < 0.0, heading >= 360.0
        if below.any() or above.any():
            heading += (below.view(np.int8) - above.view(np.int8)) * 360.0
    return heading


def _wrap360(h: np.ndarray) -> np.ndarray:
    """``np.remainder(h, 360.0)`` bit for bit, in place (:func:`geo.remainder360`)."""
    return geo.remainder360(h)


def _angle_diff(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """:func:`geo.angle_diff` of headings in [0, 360) (or NaN), bit for bit, without the
    division of ``%``."""
    w = np.subtract(a, b)
    w += 180.0  # in (-180, 540) or NaN: the shift of _wrap360 alone, no test for far values
    with np.errstate(invalid="ignore"):
        w += ((w < 0.0).view(np.int8) - (w >= 360.0).view(np.int8)) * 360.0
    w -= 180.0
    return np.abs(w, out=w)


def maneuver_factor(
    x: np.ndarray, y: np.ndarray, index: TrackIndex, p: int, gap: int = 0
) -> np.ndarray:
    """δ per point (deg in [0, 180]); NaN where a window would leave its track. ``gap``: the
    backward window ends ``gap`` points before the point and the forward one starts
    ``gap`` points after it (0: both at the point, seed 000)."""
    anchor = index.starts[index.track_of_row]
    h = window_headings(x, y, p, anchor)  # backward window ending at i
    n = len(x)
    delta = np.full(n, np.nan)
    q = int(gap)
    if n < 2 * p - 1 + 2 * q:
        return delta
    # The forward window starting at o + q is the backward window ending at o + q + p - 1.
    back = h[: n - p + 1 - 2 * q]
    fwd = h[p - 1 + 2 * q :]
    d = geo.angle_diff(back, fwd)
    pos = np.arange(n) - anchor
    size = index.sizes[index.track_of_row]
    valid = (pos >= p - 1 + q) & (pos <= size - p - q)
    delta[q : n - p + 1 - q] = d
    delta[~valid] = np.nan
    return delta


def local_maxima(delta: np.ndarray, index: TrackIndex, radius: int) -> np.ndarray:
    """Mask of points whose δ equals the maximum over ±radius within its track's valid span.

    Mirror padding and clipping give the same maximum (a mirrored value lies inside the
    window anyway), so tracks are concatenated with ``radius`` −∞ separators and one
    maximum filter runs over all of them. On a plateau only the first point is kept.
    """
    from scipy.ndimage import maximum_filter1d  # lazy: keeps `wakeline --help` fast

    finite = np.isfinite(delta)
    if not finite.any():
        return np.zeros(len(delta), dtype=bool)
    vals = np.where(finite, delta, -np.inf)
    # -inf gaps of `radius` between tracks keep windows from reaching a neighbour track.
    n = len(vals)
    slots = np.arange(n) + index.track_of_row * radius
    padded = np.full(n + index.n_tracks * radius, -np.inf)
    padded[slots] = vals
    filtered = maximum_filter1d(padded, size=2 * radius + 1, mode="constant", cval=-np.inf)[slots]
    peak = finite & (vals == filtered)
    # One point per plateau: drop a peak when a peak (as it stands before offset k)
    # precedes it by k rows in its track, for k = 1 … radius. Two peaks of one track within
    # the radius are equal (each is the other's window maximum), so only such clustered
    # peaks are touched, and the loop runs over them alone.
    rows = np.flatnonzero(peak)
    track = index.track_of_row
    if len(rows) > 1:
        close = (np.diff(rows) <= radius) & (track[rows[1:]] == track[rows[:-1]])
        if close.any():
            clustered = np.zeros(len(rows), dtype=bool)
            clustered[1:] |= close
            clustered[:-1] |= close
            q = rows[clustered]
            alive = np.ones(len(q), dtype=bool)
            for k in range(1, radius + 1):  # a loop over offsets, on the clustered peaks only
                pos = np.minimum(np.searchsorted(q, q - k), len(q) - 1)
                hit = (q[pos] == q - k) & alive[pos] & (track[q[pos]] == track[q])
                alive &= ~hit
            peak[q[~alive]] = False
    return peak


@dataclass(frozen=True)
class ManeuverResult:
    """Detector output over a sorted point table."""

    points: pd.DataFrame  # the sorted input
    index: TrackIndex
    factor: np.ndarray  # δ per point, deg (NaN where undefined)
    is_maneuver: np.ndarray  # bool per point
    window_p: np.ndarray  # p used for each track (first scale)
    at_rest: np.ndarray | None = None  # bool per point: in an at-rest span
    params: ManeuverParams | None = None  # the parameters used

    def table(self) -> pd.DataFrame:
        """One row per maneuver point: sensor, batch, index, time, lon, lat, factor.

        Rows are taken column by column (``take`` on the Arrow/numpy arrays), never by
        converting a whole column to Python objects."""
        rows = np.flatnonzero(self.is_maneuver)
        sub = self.points[["sensor", "batch", "time", "lon", "lat"]].iloc[rows]
        sub = sub.reset_index(drop=True)
        out = pd.DataFrame(
            {
                "sensor": sub["sensor"],
                "batch": sub["batch"],
                "index": (rows - self.index.starts[self.index.track_of_row[rows]]).astype("int64"),
                "time": sub["time"],
                "lon": sub["lon"],
                "lat": sub["lat"],
                "factor": self.factor[rows],
            }
        )
        return out.astype({"sensor": "str", "batch": "str"})


def _p_per_track(
    t: np.ndarray,
    index: TrackIndex,
    params: ManeuverParams,
    window_s: float | None = None,
    med: np.ndarray | None = None,
    step: np.ndarray | None = None,
) -> np.ndarray:
    """Points per window for each track: ``window_s`` over the track's median interval
    (``med``, computed when not given), never fewer than ``window_p`` (or what
    ``window_max_s`` lowers it to, by the window step ``step``); ``window_p`` itself when
    no duration is given."""
    window_s = params.window_s if window_s is None else window_s
    if window_s <= 0:
        return np.full(index.n_tracks, int(params.window_p), dtype="int64")
    med = median_interval_s(t, index) if med is None else med
    return window_points(window_s, med, params.window_p, params.window_max_s, step)


def window_step_s(t: np.ndarray, index: TrackIndex, p: int) -> np.ndarray:
    """Per track: the median time (s) spanned by its windows of ``p`` points, per step
    (over ``p`` − 1): the step a window of ``p`` points takes, which the median interval
    understates on a track whose steps alternate (a 1.68 s radar kept every 4 s steps
    3.36, 5.04, 3.36, ...: median 3.36 s, windows 4.2 s a step). NaN where no window fits."""
    out = np.full(index.n_tracks, np.nan)
    p = max(int(p), 2)
    n = len(t)
    if n < p:
        return out
    span = t[p - 1 :] - t[: n - p + 1]
    first = np.arange(n - p + 1)
    tr = index.track_of_row[first]
    ok = first + p - 1 < index.ends[tr]
    has, m = _group_median(span[ok] / (p - 1), tr[ok], index.n_tracks)
    out[has] = m
    return out


def window_points(
    window_s: float,
    interval_s: np.ndarray,
    window_p: int,
    window_max_s: float = 0.0,
    step_s: np.ndarray | None = None,
) -> np.ndarray:
    """Points per heading window of ``window_s`` seconds at each median sampling interval
    ``interval_s`` (s): ``window_s`` / interval, rounded, never fewer than ``window_p``
    (an unknown interval: ``window_p``), within 2 … 1000. With ``window_max_s`` > 0 the
    floor is lowered to floor(``window_max_s`` / step) where that is at least 3 (``step_s``,
    the track's step over a window of ``window_p`` points; default the interval)."""
    med = np.asarray(interval_s, dtype="float64")
    with np.errstate(invalid="ignore", divide="ignore"):
        chosen = np.where(np.isfinite(med) & (med > 0), np.round(window_s / med), 0)
        floor = np.full(med.shape, float(window_p))
        if window_max_s > 0:
            step = med if step_s is None else np.asarray(step_s, dtype="float64")
            fit = np.floor(window_max_s / step * (1 + 1e-9))
            fit = np.where(np.isfinite(fit) & (fit >= 3), fit, window_p)
            floor = np.minimum(floor, fit)
    return np.clip(np.maximum(chosen, floor), 2, 1000).astype("int64")


def _scales(params: ManeuverParams) -> list[float]:
    """Window durations (s): window_s doubled while within max_window_s, then max_window_s
    itself when the doubling does not land on it (10 s up to 320 s: 10, 20, ..., 320; 8 s:
    8, 16, ..., 256, 320); [0] = points only."""
    if params.window_s <= 0:
        return [0.0]
    out = [float(params.window_s)]
    top = float(params.max_window_s)
    if top <= params.window_s * (1 + 1e-9):  # 0 = one scale; none shorter than window_s
        return out
    while out[-1] * 2 <= top * (1 + 1e-9):
        out.append(out[-1] * 2)
    if out[-1] < top * (1 - 1e-9):
        out.append(float(top))
    return out


def _fine_scales(params: ManeuverParams) -> list[float]:
    """Window durations (s) below window_s: halved down to min_window_s."""
    if params.window_s <= 0 or params.min_window_s <= 0:
        return []
    out = []
    d = params.window_s / 2
    while d >= params.min_window_s * (1 - 1e-9):
        out.append(d)
        d /= 2
    return out


def _near(
    mask: np.ndarray, index: TrackIndex, reach: np.ndarray, rows: np.ndarray | None = None
) -> np.ndarray:
    """Per row (or per row of ``rows``): is a ``mask`` row of the same track within
    ±``reach`` rows (``reach`` per row, aligned with ``rows`` when given)? For a few
    ``rows``, the marked rows are counted by two searches in their list (``mask`` may be
    that list, sorted), not by a cumulative sum over every row."""
    row = np.arange(len(mask)) if rows is None else rows
    tr = index.track_of_row[row]
    lo = np.maximum(row - reach, index.starts[tr])
    hi = np.minimum(row + reach + 1, index.ends[tr])
    if rows is None:
        cs = np.concatenate([[0], np.cumsum(mask)])
        return cs[hi] - cs[lo] > 0
    marked = np.flatnonzero(mask) if mask.dtype == bool else mask  # or the rows, sorted
    return np.searchsorted(marked, hi) > np.searchsorted(marked, lo)


def position_noise_m(
    x: np.ndarray, y: np.ndarray, t: np.ndarray, index: TrackIndex, lag: np.ndarray | int = 1
) -> np.ndarray:
    """Per track: position noise std per axis (m), robust: the median distance of each point
    from the time interpolation of the points ``lag`` before and after it (``lag`` per
    track; a lag of a window also catches error that wanders over the window, as a radar's
    reflection centre does along a hull), scaled for Gaussian noise."""
    n = len(x)
    tr = index.track_of_row
    out = np.zeros(index.n_tracks)
    if np.ndim(lag) == 0:  # one lag: neighbours are slices, no gathers
        k = int(lag)
        if n <= 2 * k:
            return out
        ta, ti, tb = t[: n - 2 * k], t[k : n - k], t[2 * k :]
        xa, xi, xb = x[: n - 2 * k], x[k : n - k], x[2 * k :]
        ya, yi, yb = y[: n - 2 * k], y[k : n - k], y[2 * k :]
        # a track's points with a neighbour k before and after: one run of r per track
        first, count = index.starts, np.maximum(index.sizes - 2 * k, 0)
    else:
        lag_row = np.asarray(lag, dtype="int64")[tr] if n else tr
        row = np.arange(n)
        a, b = row - lag_row, row + lag_row
        ok = (a >= index.starts[tr]) & (b < index.ends[tr])
        i, a, b = row[ok], a[ok], b[ok]
        if not len(i):
            return out
        ta, ti, tb, xa, xi, xb = t[a], t[i], t[b], x[a], x[i], x[b]
        ya, yi, yb = y[a], y[i], y[b]
        count = np.bincount(tr[i], minlength=index.n_tracks)
        first = np.cumsum(count) - count
    cols = (ta, ti, tb, xa, xi, xb, ya, yi, yb)
    m = len(ti)
    key = np.empty(m)
    for lo in range(0, m, BLOCK):  # blocks: no row-sized temporaries
        s = slice(lo, min(m, lo + BLOCK))
        ex, ey, w = _noise_residuals(*(col[s] for col in cols))
        # (r · scale)² up to rounding, to find each track's middle values by; r itself
        # (hypot: ~10× a product) is computed for those only
        k = np.multiply(ex, ex, out=key[s])
        ey *= ey
        k += ey
        k /= w

    def radius(rows: np.ndarray) -> np.ndarray:
        ex, ey, w = _noise_residuals(*(col[rows] for col in cols))
        # |e| of 2-D Gaussian noise has median sigma * sqrt(2 ln 2)
        r = np.hypot(ex, ey)
        r /= np.sqrt(w, out=w)
        r /= np.sqrt(2 * np.log(2))
        return r

    has = count > 0
    out[has] = _run_medians_by_key(key, radius, first, count)[has]
    return out


def _noise_residuals(ta, ti, tb, xa, xi, xb, ya, yi, yb):
    """Per point of :func:`position_noise_m`: the residual (ex, ey) from the time
    interpolation of its neighbours and 1 + w² + (1 − w)², the factor of its variance —
    the arithmetic of the plain form, in place:
    w = where(span > 0, (ti - ta) / where(span > 0, span, 1), 0.5),
    r = hypot(xi - ((1 - w) xa + w xb), yi - (…)) / sqrt(1 + w² + (1 - w)²) / scale."""
    span = np.subtract(tb, ta)
    moved = span > 0
    w = np.subtract(ti, ta)
    if moved.all():  # (times strictly increasing: the usual case) the wheres change nothing
        w /= span
    else:
        w /= np.where(moved, span, 1.0)
        np.copyto(w, 0.5, where=~moved)
    rest = np.subtract(1, w, out=span)  # 1 - w
    tmp = np.multiply(w, xb)
    ex = np.multiply(rest, xa)
    ex += tmp
    np.subtract(xi, ex, out=ex)
    np.multiply(w, yb, out=tmp)
    ey = np.multiply(rest, ya)
    ey += tmp
    np.subtract(yi, ey, out=ey)
    np.multiply(w, w, out=w)
    w += 1.0
    rest *= rest
    w += rest
    return ex, ey, w


def _run_medians_by_key(key: np.ndarray, exact, first: np.ndarray, count: np.ndarray) -> np.ndarray:
    """:func:`~wakeline.core.tracks.run_medians` of values computed by ``exact(rows)`` (rows into ``key``),
    bit for bit, computing few of them: ``key`` orders the values up to a relative
    error far below 1e-9 (each value is a root of its key, rounded a few times), so a
    value whose key lies beyond the middle keys by more than 3e-9 (relative, or 3e-200)
    is surely on that side of the middle values; those within are computed and sorted.
    Runs with a non-finite key, and runs of a length few runs share, take the values
    of all their rows and :func:`~wakeline.core.tracks.run_medians`. Keys are ≥ 0 (or not finite)."""
    out = np.full(len(count), np.nan)
    rest = count > 0
    if not rest.any():
        return out
    sizes, shared = np.unique(count[rest], return_counts=True)
    finite = bool(np.isfinite(key).all())  # (the usual case) no run is left to the groupby
    for m in sizes[shared >= 8]:  # a loop over distinct lengths, few
        m = int(m)
        g = np.flatnonzero(count == m)
        med = np.full(len(g), np.nan)
        span = np.arange(m)
        k_lo, k_hi = (m - 1) // 2, m // 2  # the middle one, or two
        step = max(1, BLOCK // m)  # runs per chunk: ~BLOCK values
        for a in range(0, len(g), step):  # a loop over chunks of runs
            fg = first[g[a : a + step]]  # each run's first row
            apart = np.diff(fg)
            if len(fg) > 1 and (apart == apart[0]).all() and apart[0] >= m:
                # runs evenly apart (tracks of one length, one after another): a strided
                # view of ``key``, no row numbers and no gather
                kb = np.lib.stride_tricks.as_strided(
                    key[fg[0] :], (len(fg), m), (int(apart[0]) * key.strides[0], key.strides[0])
                )
            else:
                kb = key[fg[:, None] + span]
            ok = np.ones(len(fg), dtype=bool) if finite else np.isfinite(kb).all(axis=1)
            if not ok.all():  # such a run takes all its values, below
                fg, kb = fg[ok], kb[ok]
            mid = kb.copy()
            mid.partition(k_hi, axis=1)  # the lower middle: the largest of the lower half
            lo = mid[:, :k_hi].max(axis=1) if k_lo != k_hi else mid[:, k_hi].copy()
            lo *= 1 - 3e-9
            lo -= 3e-200
            hi = mid[:, k_hi] * (1 + 3e-9)
            hi += 3e-200
            # keys are ≥ 0 and lo at most the lower middle, so every key below lo lies left
            # of the partition point: half the keys to count
            below = np.count_nonzero(mid[:, :k_hi] < lo[:, None], axis=1)
            br, bc = np.nonzero((kb >= lo[:, None]) & (kb <= hi[:, None]))
            vals = exact(fg[br] + bc)
            vals = vals[np.lexsort((vals, br))]  # by run, then value
            n_band = np.bincount(br, minlength=len(fg))
            at = np.cumsum(n_band) - n_band - below  # each run's rank 0 in ``vals``
            value = vals[at + k_hi]
            if k_lo != k_hi:
                value += vals[at + k_lo]
                value /= 2
            med[a : a + step][ok] = value
        done = ~np.isnan(med)
        out[g[done]] = med[done]
        rest[g[done]] = False
    if rest.any():
        g = np.flatnonzero(rest)
        vals = exact(concat_ranges(first[g], count[g]))
        out[g] = run_medians(vals, np.cumsum(count[g]) - count[g], count[g])
    return out


def _group_median(values: np.ndarray, group: np.ndarray, n_groups: int):
    """Groups present and their medians, as ``pd.Series(values).groupby(group).median()``
    gives them, bit for bit (:func:`~wakeline.core.tracks.run_medians`): ``group`` sorted."""
    count = np.bincount(group, minlength=n_groups)
    has = count > 0
    return has, run_medians(values, np.cumsum(count) - count, count)[has]


def _heading_noise_deg(
    x: np.ndarray,
    y: np.ndarray,
    index: TrackIndex,
    p_row: np.ndarray,
    sigma: np.ndarray,
    rows: np.ndarray | None = None,
) -> np.ndarray:
    """Std (deg) of δ from position noise: each window's PCA heading errs by about
    σ / L · sqrt(12 / p) rad for p points spread over L metres (a line fit's slope).
    Per row, or per row of ``rows`` (``p_row`` aligned with them)."""
    n = len(x)
    row = np.arange(n) if rows is None else rows
    a = np.clip(row - p_row + 1, 0, n - 1)
    b = np.clip(row + p_row - 1, 0, n - 1)
    xo, yo = x[row], y[row]
    with np.errstate(invalid="ignore", divide="ignore"):
        lb = np.hypot(xo - x[a], yo - y[a])
        lf = np.hypot(x[b] - xo, y[b] - yo)
        s = sigma[index.track_of_row[row]] * np.sqrt(12.0 / p_row)
        return np.degrees(np.hypot(s / lb, s / lf))


#: Relative margin of :func:`_clears_noise` and :func:`_fast_enough`: their square roots of
#: sums of squares lie within a few units in the last place (~1e-15) of ``np.hypot``'s values.
HYPOT_MARGIN = 1e-12


def _lengths_sq(x: np.ndarray, y: np.ndarray, rows: np.ndarray, a: np.ndarray, b: np.ndarray):
    """Squared lengths (m²) from row ``a`` to ``rows`` and from ``rows`` to ``b``: the same
    differences :func:`_heading_noise_deg` and :func:`_window_speed_ms` take the hypot of;
    and whether both lie where their squares and reciprocals neither overflow nor underflow
    (then the square root is within a few units in the last place of the hypot)."""
    take = np.take  # the same values as x[rows], ~30 % faster for many rows
    xo, yo = take(x, rows), take(y, rows)
    dx, dy = xo - take(x, a), yo - take(y, a)
    back = dx * dx
    back += dy * dy
    np.subtract(take(x, b), xo, out=dx)
    np.subtract(take(y, b), yo, out=dy)
    fwd = np.multiply(dx, dx, out=dx)
    fwd += dy * dy
    with np.errstate(invalid="ignore"):
        normal = (back > 1e-280) & (back < 1e280) & (fwd > 1e-280) & (fwd < 1e280)
    return back, fwd, normal


def _clears_noise(
    x: np.ndarray,
    y: np.ndarray,
    index: TrackIndex,
    p_row: np.ndarray,
    sigma: np.ndarray,
    rows: np.ndarray,
    delta: np.ndarray,
    k: "float | np.ndarray",
    threshold: float,
) -> np.ndarray:
    """Per row of ``rows``: ``delta > max(k · _heading_noise_deg(…), threshold)``, the same
    booleans, with the three hypots taken as square roots of sums of squares where that
    decides (δ beyond the noise floor by more than :data:`HYPOT_MARGIN`, relative); the
    few rows within the margin, or with lengths or σ out of the safe range, take the exact
    floor. ``k`` > 0 (one value, or one per row of ``rows``)."""
    n = len(x)
    a = np.clip(rows - p_row + 1, 0, n - 1)
    b = np.clip(rows + p_row - 1, 0, n - 1)
    back, fwd, sure = _lengths_sq(x, y, rows, a, b)
    s = sigma[index.track_of_row[rows]] * np.sqrt(12.0 / p_row)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        sure &= (s > 1e-100) & (s < 1e100)
        inv = np.divide(1.0, back, out=back)
        inv += 1.0 / fwd
        floor = np.sqrt(inv, out=inv)
        floor *= s
        floor *= RAD_TO_DEG * k  # k · heading noise (deg), to ~1e-15
        sure &= (floor > 1e-200) & (floor < 1e200)
        above = delta > threshold
        yes = above & (delta > floor * (1 + HYPOT_MARGIN))
        decided = yes | ~above | (delta < floor * (1 - HYPOT_MARGIN))
    ok = yes & sure
    j = np.flatnonzero(~(sure & decided))
    if len(j):
        with np.errstate(invalid="ignore"):
            kj = k if np.ndim(k) == 0 else np.asarray(k)[j]
            exact = np.maximum(
                kj * _heading_noise_deg(x, y, index, p_row[j], sigma, rows[j]), threshold
            )
            ok[j] = delta[j] > exact
    return ok


def _spans_noise(
    x: np.ndarray,
    y: np.ndarray,
    index: TrackIndex,
    p_row: np.ndarray,
    sigma: np.ndarray,
    rows: np.ndarray,
    spans: float,
) -> np.ndarray:
    """Per row of ``rows``: both windows of ``p_row`` points (those of
    :func:`_heading_noise_deg`) span at least ``spans`` × the track's noise σ, first to last
    point (``noise_min_span``); σ not known (NaN): True."""
    n = len(x)
    a = np.clip(rows - p_row + 1, 0, n - 1)
    b = np.clip(rows + p_row - 1, 0, n - 1)
    back, fwd, _ = _lengths_sq(x, y, rows, a, b)
    reach = spans * sigma[index.track_of_row[rows]]
    reach *= reach
    with np.errstate(invalid="ignore"):
        return ~((back < reach) | (fwd < reach))


def _k_windows(k: float, points: np.ndarray, p_row: np.ndarray) -> np.ndarray:
    """``noise_k_windows``: max(k, sqrt(2 ln N)) with N = ``points`` / ``p_row`` (the
    track's independent windows), per row."""
    n_win = np.maximum(points / np.maximum(p_row, 1), 1.0)
    return np.maximum(k, np.sqrt(2.0 * np.log(n_win)))


def _k_law(
    x: np.ndarray,
    y: np.ndarray,
    index: TrackIndex,
    p_row: np.ndarray,
    sigma: np.ndarray,
    rows: np.ndarray,
    k: "float | np.ndarray",
) -> np.ndarray:
    """``noise_k_law``: k per row of ``rows`` times :func:`noise_law.law_factor` at its
    windows' shorter span (first to last point, those of :func:`_heading_noise_deg`) in the
    track's σ and its ``p_row`` points."""
    from wakeline.core.noise_law import law_factor

    n = len(x)
    a = np.clip(rows - p_row + 1, 0, n - 1)
    b = np.clip(rows + p_row - 1, 0, n - 1)
    back, fwd, _ = _lengths_sq(x, y, rows, a, b)
    with np.errstate(invalid="ignore", divide="ignore"):
        r = np.sqrt(np.minimum(back, fwd)) / sigma[index.track_of_row[rows]]
    return k * law_factor(k, p_row, r)


def _enough_windows(points: np.ndarray, p_first: np.ndarray, n_min: float) -> np.ndarray:
    """``noise_min_windows``: per row, the track's ``points`` / its first scale's window
    points ``p_first`` is at least ``n_min`` (the track offers that many windows)."""
    return points >= n_min * np.maximum(p_first, 1)


def _fast_enough(
    x: np.ndarray,
    y: np.ndarray,
    t: np.ndarray,
    index: TrackIndex,
    p_row: np.ndarray,
    rows: np.ndarray,
    speed_ms: float,
    slow_side: float = 1.0,
    side_step_s: float = 0.0,
    side_span_s: float = 0.0,
) -> np.ndarray:
    """Per row of ``rows``: the faster of the two windows' straight-line speeds (m/s) is at
    least ``speed_ms`` and the slower at least ``slow_side`` × ``speed_ms`` (with 1:
    ``_window_speed_ms(…) >= speed_ms``, the same booleans) — the relief only where the
    slower window is measured (:func:`_slow_side_measured`: no step in it longer than
    ``side_step_s``, it lasts at most ``side_span_s``; 0 = no bound), elsewhere it needs
    ``speed_ms`` too. The two hypots are taken as
    square roots of sums of squares where that decides (every speed beyond its bound by
    more than :data:`HYPOT_MARGIN`, relative, or one below it); the others (within the
    margin, a time step ≤ 0 or not finite, lengths out of the safe range) take the exact
    speeds."""
    a, b, inside = window_ends(index, rows, p_row, len(x))
    back, fwd, sure = _lengths_sq(x, y, rows, a, b)
    to = t[rows]
    bounded = slow_side < 1 and (side_step_s > 0 or side_span_s > 0)
    low = speed_ms * slow_side
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        dt_back, dt_fwd = to - t[a], t[b] - to
        sure &= (dt_back > 1e-200) & (dt_back < 1e200) & (dt_fwd > 1e-200) & (dt_fwd < 1e200)
        v_back = np.sqrt(back, out=back)
        v_back /= dt_back
        v_fwd = np.sqrt(fwd, out=fwd)
        v_fwd /= dt_fwd
        v_lo, v_hi = np.fmin(v_back, v_fwd), np.fmax(v_back, v_fwd)
        if bounded:  # the slower window (by these speeds) unmeasured: all of speed_ms
            low = np.full(len(rows), low)
            # it matters only where the slower speed is not beyond both bounds (few rows)
            k = np.flatnonzero(
                ~(v_lo >= speed_ms * (1 + HYPOT_MARGIN)) & ~(v_lo < low * (1 - HYPOT_MARGIN))
            )
            measured = _slow_side_measured(
                t, rows[k], a[k], b[k], v_back[k] <= v_fwd[k], side_step_s, side_span_s
            )
            low[k[~measured]] = speed_ms
        no = (v_lo < low * (1 - HYPOT_MARGIN)) | (v_hi < speed_ms * (1 - HYPOT_MARGIN))
        yes = (v_lo >= low * (1 + HYPOT_MARGIN)) & (v_hi >= speed_ms * (1 + HYPOT_MARGIN))
    ok = yes & sure & inside
    # outside the track: NaN, never fast enough
    j = np.flatnonzero(inside & ~(sure & (yes | no)))
    if len(j):
        with np.errstate(invalid="ignore"):
            r, aj, bj = rows[j], a[j], b[j]
            v_b = np.hypot(x[r] - x[aj], y[r] - y[aj]) / (t[r] - t[aj])
            v_f = np.hypot(x[bj] - x[r], y[bj] - y[r]) / (t[bj] - t[r])
            low_j = speed_ms * slow_side
            if bounded:  # the slower window by the exact speeds
                measured = _slow_side_measured(t, r, aj, bj, v_b <= v_f, side_step_s, side_span_s)
                low_j = np.where(measured, low_j, speed_ms)
            ok[j] = (np.fmin(v_b, v_f) >= low_j) & (np.fmax(v_b, v_f) >= speed_ms)
    return ok


def _leg_bounds(
    index: TrackIndex,
    rows: np.ndarray,
    legs_b: np.ndarray,
    legs_a: np.ndarray,
    rest_rows: np.ndarray,
    stops: np.ndarray | None = None,
    base: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """The legs about each of ``rows``: the first row of the leg before (``legs_b`` points,
    the row included) and one past the last of the leg after (``legs_a`` points, the row
    included), clipped at the row's track's ends and at the at-rest rows ``rest_rows``
    (sorted); with ``stops`` (sorted rows of turns already confirmed) also at the nearest
    stop either side, the stop's point included, but never within ``base`` points of the
    row."""
    tr = index.track_of_row[rows]
    lo = np.maximum(rows - legs_b + 1, index.starts[tr])
    hi = np.minimum(rows + legs_a, index.ends[tr])  # one past the last row
    if len(rest_rows):
        k = np.searchsorted(rest_rows, rows)
        before = np.where(k > 0, rest_rows[np.maximum(k - 1, 0)] + 1, 0)
        after = np.where(k < len(rest_rows), rest_rows[np.minimum(k, len(rest_rows) - 1)], hi)
        lo = np.maximum(lo, np.minimum(before, rows))
        hi = np.minimum(hi, np.maximum(after, rows + 1))
    if stops is not None and len(stops):
        # the nearest stop either side of each row (a row that is a stop itself is not
        # its own neighbour); the leg stops there, but not short of its base length
        k0 = np.searchsorted(stops, rows, side="left")
        k1 = np.searchsorted(stops, rows, side="right")
        before = np.where(k0 > 0, stops[np.maximum(k0 - 1, 0)], lo)
        after = np.where(k1 < len(stops), stops[np.minimum(k1, len(stops) - 1)] + 1, hi)
        reach_b = legs_b if base is None else np.minimum(base, legs_b)
        reach_a = legs_a if base is None else np.minimum(base, legs_a)
        lo = np.maximum(lo, np.minimum(before, rows - reach_b + 1))
        hi = np.minimum(hi, np.maximum(after, rows + reach_a))
    return lo, hi


def _leg_fits(
    x: np.ndarray,
    y: np.ndarray,
    t: np.ndarray,
    first: np.ndarray,
    count: np.ndarray,
    centre: np.ndarray,
    sigma: np.ndarray,
    min_speed_ms: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per leg (rows ``first`` … ``first + count − 1``): the course (rad) of a line fitted
    by least squares of x and y on time, its standard error σ / (max(|v|, ``min_speed_ms``)
    · sqrt(Σ (t − t̄)²)) (``sigma`` per leg) and whether it could be fitted (2 or more
    points and times). Sums taken against the row ``centre`` (the leg's turn), gathered
    over all legs' points at once (``np.bincount``)."""
    m = len(first)
    leg = np.repeat(np.arange(m), count)
    start = np.cumsum(count) - count
    at = np.arange(int(count.sum())) - np.repeat(start, count) + np.repeat(first, count)
    c = np.repeat(centre, count)  # each point against its turn's point
    dt, dx, dy = t[at] - t[c], x[at] - x[c], y[at] - y[c]
    nl = count.astype(float)

    def total(w):
        return np.bincount(leg, weights=w, minlength=m)

    with np.errstate(invalid="ignore", divide="ignore"):
        tm = total(dt) / nl
        ctt = total(dt * dt) - nl * tm * tm
        vx = (total(dx * dt) - tm * total(dx)) / ctt
        vy = (total(dy * dt) - tm * total(dy)) / ctt
        # a leg slower than the detector's minimum speed (a ship leaving or coming to
        # rest, which slow_side lets turn) is taken at that speed: its course is then as
        # certain as the detector's own speed rule assumes, not lost in the noise
        speed = np.maximum(np.hypot(vx, vy), min_speed_ms)
        se = sigma / (speed * np.sqrt(ctt))
        course = np.arctan2(vx, vy)
        fits = (count >= 2) & (ctt > 0) & np.isfinite(se)
    return course, se, fits


def _confirmed(
    x: np.ndarray,
    y: np.ndarray,
    t: np.ndarray,
    index: TrackIndex,
    rows: np.ndarray,
    legs: np.ndarray,
    sigma: np.ndarray,
    rest_rows: np.ndarray,
    z: float,
    min_speed_ms: float = 0.0,
) -> np.ndarray:
    """``confirm_z``: per row of ``rows``, a line fitted (least squares of x and y on time)
    to each of its two legs of ``legs`` points (the row shared, clipped at its track's ends
    and at the at-rest rows ``rest_rows``, sorted) gives a course and its standard error
    σ / (max(|v|, ``min_speed_ms``) · sqrt(Σ (t − t̄)²)) rad, σ the track's position
    noise; True where the courses differ by more than ``z`` · sqrt(se_b² + se_a²), or
    where a leg cannot be fitted (fewer than 2 points or times, σ not known: the test does
    not apply). Gathered array operations over the legs' points, no loop per row."""
    m = len(rows)
    ok = np.ones(m, dtype=bool)
    if not m:
        return ok
    lo, hi = _leg_bounds(index, rows, legs, legs, rest_rows)
    # leg 2i before row i (lo .. row), 2i + 1 after (row .. hi)
    first = np.empty(2 * m, dtype="int64")
    first[0::2], first[1::2] = lo, rows
    count = np.empty(2 * m, dtype="int64")
    count[0::2], count[1::2] = rows - lo + 1, hi - rows
    s2 = np.repeat(sigma[index.track_of_row[rows]], 2)
    course, se, fits = _leg_fits(x, y, t, first, count, np.repeat(rows, 2), s2, min_speed_ms)
    d = np.abs(np.angle(np.exp(1j * (course[1::2] - course[0::2]))))
    with np.errstate(invalid="ignore"):
        bound = z * np.hypot(se[0::2], se[1::2])
    both = fits[0::2] & fits[1::2]
    ok[both] = d[both] > bound[both]
    return ok


def _confirmed_grown(
    x: np.ndarray,
    y: np.ndarray,
    t: np.ndarray,
    index: TrackIndex,
    rows: np.ndarray,
    base: np.ndarray,
    sigma: np.ndarray,
    rest_rows: np.ndarray,
    params: "ManeuverParams",
    stops: np.ndarray,
) -> np.ndarray:
    """``confirm_grow``: the turns at ``rows`` whose legs of ``base`` points did not confirm
    them, tested again with both legs doubled, ``confirm_grow`` times at most; True where a
    test confirms. A grown test confirms where, by more than ``confirm_z`` standard errors
    each and all three the same way round, (a) the grown legs' courses differ (and by
    ``threshold_deg`` as well with ``confirm_grow_deg``), (b) the grown leg before differs
    from the course at the row and (c) the course at the row from the grown leg after: the
    course changes on both sides of the row (a point inside a gradual turn), not only far
    off in one leg (a straight stretch before another turn). The course at the row: a line
    fitted to both base legs together. Grown legs stop at ``stops`` (the turns already
    confirmed, sorted), never shorter than ``base``. A loop over the doublings, each test
    on all the rows still out at once."""
    ok = np.zeros(len(rows), dtype=bool)
    if not len(rows):
        return ok
    v_min = params.min_speed_kn * geo.KN_MS
    z = params.confirm_z
    min_rad = np.radians(params.threshold_deg) if params.confirm_grow_deg else 0.0
    lo0, hi0 = _leg_bounds(index, rows, base, base, rest_rows)  # the course at the row
    s_row = sigma[index.track_of_row[rows]]
    j = np.arange(len(rows))
    legs = base.copy()
    for _ in range(int(params.confirm_grow)):
        if not len(j):
            break
        legs = legs * 2
        r = rows[j]
        lo, hi = _leg_bounds(index, r, legs, legs, rest_rows, stops, base[j])
        # legs 3i: grown before (lo .. r), 3i + 1: at the row, 3i + 2: grown after (r .. hi)
        first = np.column_stack([lo, lo0[j], r]).ravel()
        count = np.column_stack([r - lo + 1, hi0[j] - lo0[j], hi - r]).ravel()
        c, se, fits = _leg_fits(
            x, y, t, first, count, np.repeat(r, 3), np.repeat(s_row[j], 3), v_min
        )
        c, se, fits = c.reshape(-1, 3), se.reshape(-1, 3), fits.reshape(-1, 3)

        # the course changes: grown before to after, before to the row, the row to after
        d, d1, d2 = (
            np.angle(np.exp(1j * (c[:, b] - c[:, a]))) for a, b in ((0, 2), (0, 1), (1, 2))
        )
        with np.errstate(invalid="ignore"):
            hit = fits.all(axis=1) & (
                np.abs(d) > np.maximum(z * np.hypot(se[:, 0], se[:, 2]), min_rad)
            )
            hit &= np.abs(d1) > z * np.hypot(se[:, 0], se[:, 1])
            hit &= np.abs(d2) > z * np.hypot(se[:, 1], se[:, 2])
        hit &= (np.sign(d1) == np.sign(d)) & (np.sign(d2) == np.sign(d))
        ok[j[hit]] = True
        j, legs = j[~hit], legs[~hit]
    return ok


def _slow_side_measured(
    t: np.ndarray,
    rows: np.ndarray,
    a: np.ndarray,
    b: np.ndarray,
    back_slower: np.ndarray,
    step_s: float,
    span_s: float,
) -> np.ndarray:
    """Per row: the slower window (the one ending at the row, rows ``a`` … row, where
    ``back_slower``, else the one starting there, row … ``b``) has no step longer than
    ``step_s`` and lasts at most ``span_s`` (each bound 0 = none). Windows are inside their
    track (the caller's ``inside``; elsewhere the answer does not matter)."""
    lo = np.where(back_slower, a, rows)
    hi = np.where(back_slower, rows, b)
    ok = np.ones(len(rows), dtype=bool)
    with np.errstate(invalid="ignore"):
        if span_s > 0:
            ok &= t[hi] - t[lo] <= span_s
        if step_s > 0 and len(rows):
            # the longest step of each window, steps lo … hi − 1: a loop over the offsets
            # (the window's points), never over windows
            width = hi - lo
            longest = np.zeros(len(rows))
            for k in range(int(width.max(initial=0))):
                j = np.flatnonzero(width > k)
                i = lo[j] + k
                longest[j] = np.fmax(longest[j], t[i + 1] - t[i])
            ok &= longest <= step_s
    return ok


def window_ends(
    index: TrackIndex, rows: np.ndarray, p_row: np.ndarray, n: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The first row of the window ending at each of ``rows`` and the last row of the one
    starting there (``p_row`` points each, clipped to [0, n)), and whether both windows lie
    inside the row's track."""
    tr = index.track_of_row[rows]
    a = rows - p_row + 1
    b = rows + p_row - 1
    inside = (a >= index.starts[tr]) & (b < index.ends[tr])
    return np.clip(a, 0, n - 1), np.clip(b, 0, n - 1), inside


def _window_speeds_ms(
    x: np.ndarray,
    y: np.ndarray,
    t: np.ndarray,
    index: TrackIndex,
    p_row: np.ndarray,
    rows: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """The slower and the faster of the straight-line speeds (m/s) over the window ending
    at each point and the one starting there (p points each); NaN where a window leaves
    the track. Per row, or per row of ``rows`` (``p_row`` aligned with them)."""
    row = np.arange(len(x)) if rows is None else rows
    a, b, ok = window_ends(index, row, p_row, len(x))
    xo, yo, to = x[row], y[row], t[row]
    with np.errstate(invalid="ignore", divide="ignore"):
        v_back = np.hypot(xo - x[a], yo - y[a]) / (to - t[a])
        v_fwd = np.hypot(x[b] - xo, y[b] - yo) / (t[b] - to)
    return (
        np.where(ok, np.fmin(v_back, v_fwd), np.nan),
        np.where(ok, np.fmax(v_back, v_fwd), np.nan),
    )


def _window_speed_ms(
    x: np.ndarray,
    y: np.ndarray,
    t: np.ndarray,
    index: TrackIndex,
    p_row: np.ndarray,
    rows: np.ndarray | None = None,
) -> np.ndarray:
    """The slower of :func:`_window_speeds_ms` (m/s)."""
    return _window_speeds_ms(x, y, t, index, p_row, rows)[0]


def _one_scale(
    x: np.ndarray,
    y: np.ndarray,
    index: TrackIndex,
    p_track: np.ndarray,
    radius: np.ndarray,
    active: np.ndarray | None = None,
    gap: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    """δ per point and its local maxima (radius per track), one pass per distinct p; only
    on the ``active`` tracks when given (NaN and no peak elsewhere)."""
    factor = np.full(len(x), np.nan)
    peaks = np.zeros(len(x), dtype=bool)
    active = np.ones(index.n_tracks, dtype=bool) if active is None else active
    for p in np.unique(p_track[active]):  # usually one or a few
        chosen = (p_track == p) & active
        rows = np.flatnonzero(chosen[index.track_of_row])
        sub = TrackIndex(*_sub_index(index, chosen))
        factor[rows] = maneuver_factor(x[rows], y[rows], sub, int(p), gap)
        for r in np.unique(radius[chosen]):
            same_r = chosen & (radius == r)
            rr = np.flatnonzero(same_r[index.track_of_row])
            sub_r = TrackIndex(*_sub_index(index, same_r))
            peaks[rr] = local_maxima(factor[rr], sub_r, int(r))
    return factor, peaks


def _search_sorted(
    ts: np.ndarray,
    q: np.ndarray,
    index: TrackIndex,
    step: np.ndarray,
    window_s: float,
    first: int = 0,
) -> np.ndarray:
    """``np.searchsorted(ts, q)`` for ``q = ts[first:first + len(q)] - window_s + 1e-3``
    (``ts`` sorted): guessed from each track's mean step ``step``, checked, and searched
    only where the guess is wrong (irregular sampling) — a regular track needs no search.
    ``ts`` must be finite (the caller checks once)."""
    n = len(ts)
    with np.errstate(invalid="ignore", divide="ignore"):
        back = np.where(step > 0, np.floor((window_s - 1e-3) / step), 0.0)
    back = np.clip(back, 0, n).astype("int64")
    row = np.arange(first, first + len(q))
    tr = index.track_of_row[first : first + len(q)]
    a = np.maximum(row - back[tr], index.starts[tr])
    below = ts[np.maximum(a - 1, 0)]
    good = ((a == 0) | (below < q)) & (ts[a] >= q)
    bad = np.flatnonzero(~good)
    if len(bad):
        a[bad] = np.searchsorted(ts, q[bad])
    return a


def _rest_mask(
    x: np.ndarray,
    y: np.ndarray,
    t: np.ndarray,
    index: TrackIndex,
    radius_m: float,
    window_s: float,
    steps: float = 0.0,
    med: np.ndarray | None = None,
    north_box: bool = False,
    sigmas: float = 0.0,
    lag: "np.ndarray | int" = 1,
    sigma: np.ndarray | None = None,
    cap_m: float = 0.0,
) -> np.ndarray:
    """Cleaning's at-rest rule (:func:`wakeline.core.clean.at_rest`, on sparse tracks over
    ``steps`` sampling intervals: :func:`wakeline.core.clean.rest_frame`, ``med`` each
    track's median interval when known), run only on the tracks that can hold a stay
    (:func:`_rest_possible`; same result, less work). ``sigmas`` > 0: the radius grown
    per track with its noise (:func:`wakeline.core.clean.rest_radius`; its noise share at
    most ``cap_m`` metres when ``cap_m`` > 0)."""
    from wakeline.core.clean import at_rest, rest_frame, rest_radius  # cleaning's rule

    n = len(x)
    rest = np.zeros(n, dtype=bool)
    if n == 0:
        return rest
    radius_m = rest_radius(
        x, y, t, index, radius_m, sigmas, window_s, steps, med, lag, sigma, cap_m
    )
    x, y, t = rest_frame(x, y, t, index, window_s, steps, med)
    possible = _rest_possible(x, y, t, index, radius_m, window_s)
    if not possible.any():
        return rest
    if possible.all():
        return at_rest(x, y, t, index, radius_m, window_s, north_box)
    rows = np.flatnonzero(possible[index.track_of_row])
    sub = TrackIndex(*_sub_index(index, possible))
    r_sub = radius_m if np.ndim(radius_m) == 0 else np.asarray(radius_m)[possible]
    rest[rows] = at_rest(x[rows], y[rows], t[rows], sub, r_sub, window_s, north_box)
    return rest


#: The longest stride of :func:`_rest_possible`'s pairs (rows apart).
REST_STRIDE_MAX = 64


def _rest_strides(t: np.ndarray, index: TrackIndex, window_s: float) -> np.ndarray:
    """Per track, a stride K (rows, a power of two up to :data:`REST_STRIDE_MAX`) such that
    a stay of :func:`wakeline.core.clean.at_rest` in it spans at least 2K − 1 steps; 1 where
    none is known (a time step as long as half the window, non-finite times), 0 where the
    track cannot hold a stay (one fix).

    A stay from row a to row b lasts at least ``window_s`` (at_rest's ts[b] − ts[a], to
    within rounding of its shifted seconds: ``slack``), and each of its b − a steps is at
    most the track's longest step M, so b − a ≥ ceil((window_s − slack) / M) = L; any K
    with 2K − 1 ≤ L will do."""
    n = len(t)
    step = np.empty(n)
    np.subtract(t[1:], t[:-1], out=step[:-1])
    step[index.ends - 1] = -np.inf  # no step from a track's last row into the next track
    has = index.sizes > 0
    longest = np.full(index.n_tracks, np.nan)
    longest[has] = np.maximum.reduceat(step, index.starts[has])  # NaN time: NaN
    with np.errstate(invalid="ignore", over="ignore"):
        # at_rest shifts each track's seconds to start after the previous one's: |ts| ≤ total
        total = float(np.nansum(np.abs(t[index.ends[has] - 1] - t[index.starts[has]])))
        total += index.n_tracks * (2.0 * window_s + 1.0)
        slack = 1e-3 + 8.0 * float(np.spacing(total)) + 1e-9 * window_s
        stride = np.ones(index.n_tracks, dtype="int64")
        fine = np.isfinite(longest) & (longest > 0)
        steps = np.ceil((window_s - slack) / (longest[fine] * (1 + 1e-9)))
        k = np.floor((np.minimum(steps, 4 * REST_STRIDE_MAX) + 1) / 2)  # 2K - 1 ≤ L
        k = np.clip(k, 1, REST_STRIDE_MAX).astype("int64")
        stride[fine] = 1 << (np.log2(k).astype("int64"))  # a power of two at most k
        stride[index.sizes < 2] = 0
        # all steps 0 s (or -inf: one fix): no stay lasts window_s > 0 (0 s: any stride)
        still = (longest <= 0) & (index.sizes >= 2)
        stride[still] = REST_STRIDE_MAX if window_s > 0 else 1
    return stride


def _rest_possible(
    x: np.ndarray, y: np.ndarray, t: np.ndarray, index: TrackIndex, radius_m, window_s: float
) -> np.ndarray:
    """Per track: can it hold a stay of :func:`wakeline.core.clean.at_rest` (a screen: False
    only where it surely holds none)?

    Every two fixes of a stay lie within 2·``radius_m`` of each other (its bounding box's
    diagonal is at most that). On a track whose stays span 2K − 1 steps or more
    (:func:`_rest_strides`) some row j that is a multiple of K and j + K both lie in the
    stay, so the pairs (j, j + K) alone are tested: n / K distances, no search. Other
    tracks take the first fix of the window before each point (:func:`_rest_screen`)."""
    tr = index.track_of_row
    possible = np.zeros(index.n_tracks, dtype=bool)
    stride = _rest_strides(t, index, window_s)
    reach = 2.0 * np.asarray(radius_m, dtype="float64") * (1 + 1e-9) + 1e-6  # or per track
    limit = reach * reach * (1 + 1e-9)  # a margin far above the rounding of d²
    for k in np.unique(stride[stride >= 2]):  # a few distinct strides
        k = int(k)
        xs, ys, ts = x[::k], y[::k], tr[::k]
        d2 = np.subtract(xs[1:], xs[:-1])
        d2 *= d2
        dy = np.subtract(ys[1:], ys[:-1])
        dy *= dy
        d2 += dy
        with np.errstate(invalid="ignore"):
            close = ~(d2 > (limit if np.ndim(limit) == 0 else limit[ts[:-1]]))  # NaN: possible
        close &= ts[1:] == ts[:-1]
        hit = ts[:-1][close]
        possible[hit[stride[hit] == k]] = True
    other = stride == 1
    if other.all():
        return _rest_screen(x, y, t, index, radius_m, window_s)
    if other.any():
        rows = np.flatnonzero(other[tr])
        sub = TrackIndex(*_sub_index(index, other))
        r_sub = radius_m if np.ndim(radius_m) == 0 else np.asarray(radius_m)[other]
        possible[other] = _rest_screen(x[rows], y[rows], t[rows], sub, r_sub, window_s)
    return possible


def _rest_screen(
    x: np.ndarray, y: np.ndarray, t: np.ndarray, index: TrackIndex, radius_m, window_s: float
) -> np.ndarray:
    """Per track, :func:`_rest_possible` by the window before each point: a stay ending at a
    point covers every fix of the last ``window_s`` before it, so somewhere the point and
    the first fix of that window lie within 2·``radius_m``, at least ``window_s`` after the
    track's first fix."""
    n = len(x)
    tr = index.track_of_row
    sizes = index.sizes
    possible = np.zeros(index.n_tracks, dtype=bool)
    if n == 0:
        return possible
    rel = np.repeat(t[index.starts], sizes)
    rel = np.subtract(t, rel, out=rel)  # in place: row-sized temporaries are fresh pages
    span = np.zeros(index.n_tracks)
    has = sizes > 0
    span[has] = rel[index.ends[has] - 1]
    offset = np.concatenate([[0.0], np.cumsum(span + 2.0 * window_s + 1.0)[:-1]])
    ts = np.repeat(offset, sizes)
    ts += rel
    step = span / np.maximum(sizes - 1, 1)
    reach = 2.0 * np.asarray(radius_m, dtype="float64") * (1 + 1e-9) + 1e-6  # or per track
    finite = bool(np.isfinite(ts).all())
    for first in range(0, n, BLOCK):  # blocks: no row-sized temporaries
        s = slice(first, min(n, first + BLOCK))
        # first fix at or after t - window_s (a little later, so rounding never widens it)
        q = ts[s] - window_s + 1e-3
        if finite:
            a = _search_sorted(ts, q, index, step, window_s, first)
        else:
            a = np.searchsorted(ts, q)
        dx = x[s] - x[a]
        dy = y[s] - y[a]
        d2 = dx * dx
        d2 += dy * dy
        # squared distances with a margin far above their rounding: a screen keeps a
        # track that may hold a stay, never drops one
        r = reach if np.ndim(reach) == 0 else reach[tr[s]]
        close = (d2 <= r * r * (1 + 1e-9)) & (rel[s] >= window_s * (1 - 1e-9))
        possible[tr[s][close]] = True
    return possible


# --- the kernel of detect(): δ only where a maneuver can be, peaks only above t ------------
#
# The helpers below give detect() the same output, bit for bit, as running maneuver_factor,
# local_maxima and the rules on every row (tests/test_maneuver_kernel.py pins it against a
# frozen copy of that straightforward detector): every window sum is the same np.convolve
# dot product of the same p numbers, and every elementwise step the same ufunc on the same
# operands, only on fewer rows.


def _runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """First and one-past-last row of every run of True in ``mask``: the rows where the
    value changes (one comparison and one search of the mask), runs of True every other
    run from the first."""
    n = len(mask)
    if n == 0:
        return np.zeros(0, dtype="int64"), np.zeros(0, dtype="int64")
    change = np.flatnonzero(mask[1:] != mask[:-1])
    bounds = np.empty(len(change) + 2, dtype="int64")
    bounds[0], bounds[-1] = 0, n
    np.add(change, 1, out=bounds[1:-1])
    if mask[0]:
        return bounds[0:-1:2].copy(), bounds[1::2].copy()
    return bounds[1:-1:2].copy(), bounds[2::2].copy()


def _dilate(
    lo: np.ndarray, hi: np.ndarray, reach: np.ndarray, index: TrackIndex, n: int, inside=True
):
    """Mask of the rows within ``reach`` (per run) of the runs ``[lo, hi)``, in their track
    (``inside=False``: of the other rows)."""
    if not len(lo):
        return np.full(n, not inside)
    tr = index.track_of_row[lo]
    a = np.maximum(lo - reach, index.starts[tr])  # sorted, as lo is
    b = np.minimum(hi + reach, index.ends[tr])
    return _span_mask(a, b, n, inside)


def _merge_runs(lo: np.ndarray, hi: np.ndarray, tr: np.ndarray):
    """Union of sorted runs ``[lo, hi)`` of tracks ``tr`` (a run never spans two tracks)."""
    if len(lo) < 2:
        return lo, hi, tr
    reach = np.maximum.accumulate(hi)
    new = np.ones(len(lo), dtype=bool)
    new[1:] = (lo[1:] > reach[:-1]) | (tr[1:] != tr[:-1])
    first = np.flatnonzero(new)
    last = np.append(first[1:], len(lo)) - 1
    return lo[first], reach[last], tr[first]


def _headings_of(u: np.ndarray, v: np.ndarray, p: int) -> np.ndarray:
    """:func:`window_headings` of coordinates already taken relative to their anchor."""
    n = len(u)
    out = np.full(n, np.nan)
    for first in range(p - 1, n, BLOCK):  # a loop over blocks, not over windows
        last = min(n, first + BLOCK)
        out[first:last] = _block_headings(u[first - p + 1 : last], v[first - p + 1 : last], p)
    return out


def _anchored(x: np.ndarray, index: TrackIndex) -> bool:
    """Are ``x``'s coordinates already taken relative to each track's first point (every
    track's first value +0.0)? Then subtracting the anchor changes no bit (x − (+0.0) is
    x, −0.0 included), and the kernels below skip it."""
    x0 = x[index.starts]
    return bool((x0 == 0.0).all() and not np.signbit(x0).any())


def _anchored_xy(x: np.ndarray, y: np.ndarray, index: TrackIndex) -> tuple[np.ndarray, np.ndarray]:
    """Coordinates relative to each track's first point, the anchor every window sum is
    taken against (once per table, not once per scale and block)."""
    u = np.repeat(x[index.starts], index.sizes)
    np.subtract(x, u, out=u)
    v = np.repeat(y[index.starts], index.sizes)
    np.subtract(y, v, out=v)
    return u, v


def _factor_every_row(
    x: np.ndarray, y: np.ndarray, index: TrackIndex, p: int, chosen: np.ndarray
) -> np.ndarray:
    """δ of every row of the ``chosen`` tracks (NaN elsewhere and where a window would
    leave the track), block by block over the rows as they lie: no row-sized temporaries
    (fresh pages of 80 MB at 10 M points cost more than the arithmetic), only the output."""
    n = len(x)
    tr = index.track_of_row
    anchored = _anchored(x, index) and _anchored(y, index)
    x0, y0 = x[index.starts], y[index.starts]  # each track's anchor
    # δ is defined from a track's p-th row to its p-th last
    lo, hi = index.starts + (p - 1), index.ends - (p - 1)
    keep = chosen & (hi > lo)
    every = bool(keep.all())
    if every:
        # every track chosen and long enough: δ goes in as it comes, and NaN after it in
        # the few rows outside the spans (a track's first and last p - 1), not through a
        # row mask; the rows before the first span and after the last are never written
        out = np.empty(n)
        gap_lo = np.concatenate([[0], hi])
        outside = concat_ranges(gap_lo, np.concatenate([lo, [n]]) - gap_lo)
    else:
        out = np.full(n, np.nan)
        valid = _span_mask(lo[keep], hi[keep], n)
    for first in range(p - 1, n - p + 1, BLOCK):  # a loop over blocks, not over windows
        last = min(n - p + 1, first + BLOCK)  # δ rows; windows end at first … last + p - 2
        raw = slice(first - p + 1, last + p - 1)
        if anchored:
            h = _block_headings(x[raw], y[raw], p)
        else:
            t_raw = tr[raw]
            h = _block_headings(x[raw] - x0[t_raw], y[raw] - y0[t_raw], p)
        d = _angle_diff(h[: last - first], h[p - 1 :])
        if every:
            out[first:last] = d
        else:
            np.copyto(out[first:last], d, where=valid[first:last])
    if every:
        out[outside] = np.nan
    return out


def _factor_on_runs(
    x: np.ndarray,
    y: np.ndarray,
    index: TrackIndex,
    p: int,
    lo: np.ndarray,
    hi: np.ndarray,
    above: float | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Rows and δ of the runs ``[lo, hi)``, each inside its track's defined span
    (``start + p - 1`` to ``end - p + 1``): their windows, ``p - 1`` rows either side, are
    gathered run after run and the headings computed once per window.

    With ``above`` (deg), only the rows whose δ may exceed it are returned: a screen
    without trigonometry (the two oriented axes from the same window moments by half-angle
    formulas, their dot product against cos(above) with a margin of 1e-9, orders of
    magnitude above its rounding) leaves out rows whose δ is surely at most ``above``;
    the others get δ exactly as everywhere else."""
    tr = index.track_of_row[lo]
    raw_lo = lo - (p - 1)
    raw_len = hi - lo + 2 * (p - 1)
    n = len(x)
    anchored = _anchored(x, index) and _anchored(y, index)
    if len(lo) == index.n_tracks and int(raw_len.sum()) == n and (raw_lo == index.starts).all():
        rows = None  # every row: no gather
        if anchored:
            u, v = x, y
        else:
            u = x - np.repeat(x[index.starts], index.sizes)
            v = y - np.repeat(y[index.starts], index.sizes)
    else:
        rows = concat_ranges(raw_lo, raw_len)
        u = np.take(x, rows)  # x[rows], ~30 % faster for many rows
        v = np.take(y, rows)
        if not anchored:
            u -= np.repeat(x[index.starts[tr]], raw_len)  # each run's track anchor
            v -= np.repeat(y[index.starts[tr]], raw_len)
    # δ of row o: the window ending at o against the window ending at o + p - 1
    seg = np.concatenate([[0], np.cumsum(raw_len)[:-1]])
    m = len(u)
    if above is None:
        pos = concat_ranges(seg + (p - 1), hi - lo)
        out_rows = pos + np.repeat(raw_lo - seg, hi - lo)
        h = _headings_of(u, v, p)
        return out_rows, _angle_diff(h[pos], h[pos + (p - 1)])
    is_pos = _span_mask(seg + (p - 1), seg + (p - 1) + (hi - lo), m)  # runs apart: a mask
    limit = _screen_limit(above)
    found_pos, found_delta = [], []
    for first in range(p - 1, m - p + 1, BLOCK):  # a loop over blocks, not over windows
        last = min(m - p + 1, first + BLOCK)  # δ positions first..last-1 need windows to
        # last + p - 2: the block's moments overlap the next block's by p - 1 windows
        raw = slice(first - p + 1, last + p - 1)
        j, d = _screen_block(u[raw], v[raw], p, limit, is_pos[first:last], exact=False)
        found_pos.append(j + first)
        found_delta.append(d)
    if not found_pos:
        return np.zeros(0, dtype="int64"), np.zeros(0)
    j = np.concatenate(found_pos)
    # the exact δ of the positions left in, all blocks at once (few: one call, not one a block)
    delta = _exact_at(u, v, p, j) if limit is not None else np.concatenate(found_delta)
    return (j if rows is None else rows[j]), delta


def _screen_every_row(
    x: np.ndarray,
    y: np.ndarray,
    index: TrackIndex,
    p: int,
    lo: np.ndarray,
    hi: np.ndarray,
    above: float,
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_factor_on_runs` with ``above`` when the runs cover most rows: block by
    block over the rows as they lie instead of gathering the runs (windows across a track
    boundary are computed and never used)."""
    n = len(x)
    tr = index.track_of_row
    anchored = _anchored(x, index) and _anchored(y, index)
    x0, y0 = x[index.starts], y[index.starts]  # each track's anchor
    is_pos = _span_mask(lo, hi, n)
    limit = _screen_limit(above)
    found_rows, found_delta = [], []
    for first in range(p - 1, n - p + 1, BLOCK):  # a loop over blocks, not over windows
        last = min(n - p + 1, first + BLOCK)
        if not is_pos[first:last].any():
            continue
        raw = slice(first - p + 1, last + p - 1)
        if anchored:
            ub, vb = x[raw], y[raw]
        else:
            t_raw = tr[raw]
            ub, vb = x[raw] - x0[t_raw], y[raw] - y0[t_raw]
        j, d = _screen_block(ub, vb, p, limit, is_pos[first:last], exact=not anchored)
        found_rows.append(j + first)
        found_delta.append(d)
    if not found_rows:
        return np.zeros(0, dtype="int64"), np.zeros(0)
    j = np.concatenate(found_rows)
    if anchored and limit is not None:  # the exact δ of the rows left in, all at once
        return j, _exact_at(x, y, p, j)
    return j, np.concatenate(found_delta)


def _screen_block(
    ub: np.ndarray,
    vb: np.ndarray,
    p: int,
    limit: float | None,
    is_pos: np.ndarray,
    exact: bool = True,
) -> tuple[np.ndarray, np.ndarray | None]:
    """One block of the screen: positions (offsets from the block's first δ position,
    ``is_pos`` of them) whose δ may exceed the threshold behind ``limit``
    (:func:`_screen_limit`; None: every position), and their δ, exactly (None without
    ``exact`` and with a ``limit``: the caller computes it, for all blocks at once —
    :func:`_exact_at` of position j + first of the array the block is cut from).
    ``ub``/``vb`` hold the windows of the block plus p − 1 after."""
    k = len(is_pos)
    if limit is None:  # δ of every position, as :func:`_factor_on_runs` without a screen
        j = np.flatnonzero(is_pos)
        h = _headings_of(ub, vb, p)
        return j, _angle_diff(h[p - 1 : p - 1 + k][j], h[2 * (p - 1) :][j])
    ex, ey, tau = _screen_axes(ub, vb, p)
    with np.errstate(invalid="ignore"):
        # 4·c1·c2·cos(angle) − 4τ1 − 4τ2 against 4·(cos t + margins); NaN: left in
        dot = np.multiply(ex[:k], ex[p - 1 :])
        dot += np.multiply(ey[:k], ey[p - 1 :], out=ex[:k])
        dot -= tau[:k]
        dot -= tau[p - 1 :]
        out = np.greater(dot, limit, out=np.empty(k, dtype=bool))
    j = np.flatnonzero(np.greater(is_pos, out, out=out))  # a position, not screened out
    if not exact:
        return j, None
    return j, _exact_at(ub, vb, p, j + (p - 1))


#: np.convolve sums kernels of up to 11 numbers in a plain loop (numpy's small_correlate);
#: longer ones call BLAS once per window, ~20 ns a window and sum whatever p is.
SMALL_KERNEL = 11

#: The rows of interest of a longer scale are screened block by block over the rows as they
#: lie (:func:`_screen_every_row`) when their windows (each run with p − 1 more either side)
#: are at least this share of all rows; else gathered run after run (:func:`_factor_on_runs`),
#: which costs two gathers a window (10 M-point bench scene, p = 8: windows 0.86 of the rows,
#: 0.19 s gathered against 0.12 s in place; p = 16, 0.64: the same either way).
EVERY_ROW_SHARE = 0.7

#: The screen's own rounding (float32 unit vectors, ~1e-6): δ is screened out only where
#: the cosine of the angle between the two oriented axes exceeds cos(t) by this much on
#: top of the bounds on the axes themselves.
SCREEN_MARGIN = 3e-5


def _screen_limit(above: float) -> float | None:
    """The limit that :func:`_screen_block` compares its dot products (scaled by 4) with,
    to screen out δ at most ``above`` (deg); None where the screen cannot tell (``above``
    near 90° or past it, where the weights that keep uncertain axes in no longer do)."""
    limit = math.cos(math.radians(above)) + 1e-9 + SCREEN_MARGIN
    return 4.0 * limit if limit > 1e-3 else None


def _window_sums(a: np.ndarray, p: int) -> np.ndarray:
    """Sums of every ``p`` consecutive values, in some order (not ``np.convolve``'s bits):
    sums of 1, 2, 4, … values by doubling, those of p's binary digits added up."""
    nw = len(a) - p + 1
    out = None
    done = 0  # values of the window summed so far, from its first
    piece, width = a, 1  # piece[i]: the sum of a[i : i + width]
    while True:
        if p & width:
            seg = piece[done : done + nw]
            if out is None:  # a sum of sums of 2 or more is an array of its own: no copy
                out = seg.copy() if width == 1 else seg
            else:
                out = np.add(out, seg, out=out)
            done += width
        if 2 * width > p:
            return out
        piece = np.add(piece[:-width], piece[width:])
        width *= 2


def _screen_axes(u: np.ndarray, v: np.ndarray, p: int):
    """Per window of ``p`` points, in float32: ``2c·o``, where o is the unit vector along
    the window's major axis oriented by its displacement d, as :func:`_axis_headings`
    orients it, and c the cosine of the angle between that axis and d (≤ 1; an orientation
    too close to call has c ≈ 0); and ``4τ``, τ a bound on the angle (rad) between that
    axis and the one :func:`_axis_headings` computes (infinite or NaN where unsure).

    No trigonometry, no half angles. The moments are sums in any order, scaled by p²:
    A = p²·(cxx − cyy), B = p²·2cxy; both these and the exact moments of
    :func:`_block_moments` (times p²) lie within (10p + 15)·p²·eps·G of the true ones in
    |A| + |B| (G = (max|u| + max|v|)², every term at most G), so within E = 64·p³·eps·G of
    each other, and the axis (half the angle of (A, B)) turns by at most τ = E / (R − E)
    between them, R = |(A, B)|, trusted where R > 4E. The projection of d onto the axis,
    times 2R, is W = ((R + A)·du + B·dv, B·du + (R − A)·dv) (the projection matrix in
    doubled-angle form): it points along the oriented axis, |W| = 2R·|d|·c. The rest runs
    in float32 on A/E, B/E (at most 1/(32·p·eps) in size) and d; its rounding, ~1e-6 on
    the unit vectors, is what :data:`SCREEN_MARGIN` covers."""
    n = len(u)
    nw = n - p + 1
    f32 = np.float32
    q = np.multiply(u, u)
    tmp = np.multiply(v, v)
    q -= tmp  # u² − v²
    np.multiply(u, v, out=tmp)
    su = _window_sums(u, p)
    sv = _window_sums(v, p)
    s_q = _window_sums(q, p)
    s_x = _window_sums(tmp, p)
    with np.errstate(invalid="ignore", over="ignore"):
        big = float(np.maximum(u.max(), -u.min()) + np.maximum(v.max(), -v.min()))
        e = 64.0 * float(p) ** 3 * float(np.finfo(float).eps) * big * big
    inv = 1.0 / e if 1e-280 < e < 1e280 else math.nan  # NaN: no window sure
    t = np.multiply(su, sv, out=tmp[:nw])
    s_x *= float(p)
    s_x -= t  # B / 2 = p·Σuv − Σu·Σv
    np.subtract(su, sv, out=t)
    su += sv
    t *= su
    s_q *= float(p)
    s_q -= t  # A = p·Σ(u² − v²) − (Σu − Σv)(Σu + Σv)
    a = np.multiply(s_q, inv, out=np.empty(nw, dtype=f32), casting="same_kind")
    b = np.multiply(s_x, 2.0 * inv, out=np.empty(nw, dtype=f32), casting="same_kind")
    du = np.subtract(u[p - 1 :], u[:nw], out=np.empty(nw, dtype=f32), casting="same_kind")
    dv = np.subtract(v[p - 1 :], v[:nw], out=np.empty(nw, dtype=f32), casting="same_kind")
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        r = np.multiply(a, a)
        w = np.multiply(b, b)
        r += w
        np.sqrt(r, out=r)  # R / E
        ex = np.add(r, a)
        ex *= du
        np.multiply(b, dv, out=w)
        ex += w  # (R + A)·du + B·dv
        ey = np.subtract(r, a, out=a)
        ey *= dv
        np.multiply(b, du, out=w)
        ey += w  # B·du + (R − A)·dv
        du *= du
        dv *= dv
        du += dv  # |d|²
        sure = np.greater(du, 1e-30, out=np.empty(nw, dtype=bool))  # d well inside float32
        sure &= r > 4.0
        np.sqrt(du, out=du)
        du *= r
        np.divide(1.0, du, out=du)  # 1 / (R·|d|)
        ex *= du
        ey *= du
        tau = np.subtract(r, 1.0, out=r)
        tau *= sure
        np.abs(tau, out=tau)  # (R < E: -0.0 where unsure)
        np.divide(4.0, tau, out=tau)  # 4·E / (R − E); +inf (or NaN) where unsure
    return ex, ey, tau


def _exact_at(u: np.ndarray, v: np.ndarray, p: int, j: np.ndarray) -> np.ndarray:
    """δ of positions ``j`` exactly as :func:`_headings_of` gives it: the headings of the
    windows needed (ending at j and at j + p − 1) only, from :func:`_gathered_moments`."""
    if not len(j):
        return np.zeros(0)
    ends = sorted_sets.union(j, j + (p - 1))  # sorted, each window once
    h = _axis_headings(*_gathered_moments(u, v, p, ends))
    return _angle_diff(h[np.searchsorted(ends, j)], h[np.searchsorted(ends, j + (p - 1))])


def _gathered_moments(u: np.ndarray, v: np.ndarray, p: int, ends: np.ndarray):
    """:func:`_block_moments` of the windows ending at ``ends``, the same bits, each window
    gathered as a row of p values. For p ≤ :data:`SMALL_KERNEL` ``np.convolve`` sums each
    window in a plain loop over its p values in order, wherever the window lies: the rows
    one after another are convolved the same way, and every p-th sum is a window's. For
    longer p it sums each window by numpy's dot with the kernel (BLAS ``ddot``), and
    ``np.matmul`` of a 1 × p row by a p × 1 column makes that same call (numpy's matmul,
    row @ column)."""
    first = ends - (p - 1)
    rows = first[:, None] + np.arange(p)
    wu = u[rows]  # one row of p per window
    wv = v[rows]
    if p <= SMALL_KERNEL:
        ones = np.ones(p)

        def sums(w: np.ndarray) -> np.ndarray:
            return np.convolve(w.ravel(), ones, "valid")[::p]

    else:
        column = np.ones((p, 1))

        def sums(w: np.ndarray) -> np.ndarray:
            return np.matmul(w[:, None, :], column)[:, 0, 0]

    mu = sums(wu)
    mu /= p
    mv = sums(wv)
    mv /= p
    tmp = np.multiply(wu, wu)
    cxx = sums(tmp)
    cxx /= p
    cxx -= mu * mu
    np.multiply(wv, wv, out=tmp)
    cyy = sums(tmp)
    cyy /= p
    cyy -= mv * mv
    np.multiply(wu, wv, out=tmp)
    cxy = sums(tmp)
    cxy /= p
    cxy -= mu * mv
    cxy *= 2.0
    cxx -= cyy
    return cxx, cxy, u[ends] - u[first], v[ends] - v[first]


def _peaks_above(
    rows: np.ndarray, delta: np.ndarray, track: np.ndarray, radius: np.ndarray, threshold: float
) -> np.ndarray:
    """Rows (sorted) above ``threshold`` that are the maximum of δ within ±``radius`` rows
    of their track (``radius`` per track) — :func:`local_maxima`'s first condition on the
    rows above the threshold only, which changes nothing there: a row at most t never beats
    one above it. ``rows``/``delta`` must hold every row within the radius of the rows
    asked about (a row left out counts as undefined)."""
    with np.errstate(invalid="ignore"):
        above = delta > threshold
    q = np.flatnonzero(above) if rows is None else rows[above]
    # delta[above]: a gather of the rows above t, not a boolean subscript over every row
    w = np.take(delta, q) if rows is None else delta[above]
    tq = np.take(track, q)
    reach = int(radius.max()) if len(radius) else 0
    # rows of later tracks moved on by more than any radius: "within the radius in the same
    # track" is one difference of slots
    slot = tq * (reach + 1)
    slot += q
    per_track = not (radius == reach).all()
    rq = radius[tq] if per_track else reach
    m = len(q)
    peak = np.ones(m, dtype=bool)
    gap = np.empty(max(m - 1, 0), dtype=slot.dtype)  # buffers for every offset
    close, beaten = np.empty(max(m - 1, 0), dtype=bool), np.empty(max(m - 1, 0), dtype=bool)
    for j in range(1, m):  # a loop over offsets in the list of rows above t
        k = m - j
        d = np.subtract(slot[j:], slot[:-j], out=gap[:k])
        c = np.less_equal(d, rq[j:] if per_track else rq, out=close[:k])
        if not c.any():  # rows are sorted: no pair further apart can be closer
            break
        # a row loses to a close row of larger δ (w holds no NaN: every row is above t);
        # peak &= ~close | (w >= other) as peak &= ~(close & (w < other))
        b = np.less(w[:-j], w[j:], out=beaten[:k])
        b &= c
        peak[:-j] &= np.logical_not(b, out=b)
        b = np.less(w[j:], w[:-j], out=beaten[:k])
        b &= c
        peak[j:] &= np.logical_not(b, out=b)
    return q[peak]


def _clusters(q: np.ndarray, track: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """Per peak (sorted rows): its cluster number, or -1 when no other peak of its track lies
    within the radius. Peaks within the radius of each other are equal (each is the other's
    window maximum), so the plateau rule only ever touches clustered peaks."""
    label = np.full(len(q), -1, dtype="int64")
    if len(q) < 2:
        return label
    tq = track[q]
    close = (np.diff(q) <= radius[tq[1:]]) & (tq[1:] == tq[:-1])
    if not close.any():
        return label
    clustered = np.zeros(len(q), dtype=bool)
    clustered[1:] |= close
    clustered[:-1] |= close
    starts = np.ones(len(q), dtype=bool)
    starts[1:] = ~close
    label[clustered] = (np.cumsum(starts) - 1)[clustered]
    return label


def _one_per_plateau(
    q: np.ndarray, label: np.ndarray, track: np.ndarray, radius: np.ndarray
) -> np.ndarray:
    """Mask over the peaks ``q``: kept by :func:`local_maxima`'s plateau rule."""
    keep = np.ones(len(q), dtype=bool)
    clustered = label >= 0
    if not clustered.any():
        return keep
    c = q[clustered]
    tc = track[c]
    rc = radius[tc]
    alive = np.ones(len(c), dtype=bool)
    for k in range(1, int(rc.max()) + 1):  # a loop over offsets, on the clustered peaks only
        pos = np.minimum(np.searchsorted(c, c - k), len(c) - 1)
        hit = (c[pos] == c - k) & alive[pos] & (tc[pos] == tc) & (k <= rc)
        alive &= ~hit
    keep[np.flatnonzero(clustered)[~alive]] = False
    return keep


def _span_mask(lo: np.ndarray, hi: np.ndarray, n: int, inside: bool = True) -> np.ndarray:
    """Mask of the rows of the runs ``[lo, hi)`` (``lo`` sorted; runs may overlap): one
    repeat of alternating False/True over the merged runs, no row-sized counts
    (``inside=False``: the mask of the other rows, the same way)."""
    if not len(lo):
        return np.full(n, not inside)
    reach = np.maximum.accumulate(hi)
    new = np.ones(len(lo), dtype=bool)
    new[1:] = lo[1:] > reach[:-1]
    first = np.flatnonzero(new)
    lo, hi = lo[first], reach[np.append(first[1:], len(lo)) - 1]
    counts = np.empty(2 * len(lo) + 1, dtype="int64")
    counts[0:-1:2] = lo - np.concatenate([[0], hi[:-1]])  # gaps
    counts[1::2] = hi - lo
    counts[-1] = n - hi[-1]
    values = np.zeros(len(counts), dtype=bool)
    values[1 if inside else 0 :: 2] = True
    return np.repeat(values, counts)


def _scale_candidates(
    x: np.ndarray,
    y: np.ndarray,
    index: TrackIndex,
    p_track: np.ndarray,
    radius: np.ndarray,
    threshold: float,
    active: np.ndarray,
    interest: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Candidates of one window scale: rows where δ > ``threshold`` is the maximum within
    ±radius (one per plateau), on the ``active`` tracks; their δ; and δ of every row
    (NaN where undefined) when ``interest`` is None.

    With ``interest`` (a row mask), only candidates among those rows are wanted: δ is then
    computed, only where it may exceed the threshold (:func:`_factor_on_runs`), first on
    those rows alone, then on the radius around each of them above the threshold (their
    peak test needs δ within it; a row of interest at most t is no candidate, so the
    radius around it is not needed: on the benchmark scene 1 row of interest in 300 to
    6000 is above t, and the longer scales screen 1.0 rows per point instead of 1.8). A
    row of interest that is a peak is one for sure; a peak near the edge of the rows
    computed may not be, but it then equals any peak of interest within its radius, so it
    only matters through the one-point-per-plateau rule: a cluster of equal peaks holding
    a row of interest must lie with two radii around each member inside the rows computed
    (then every peak that can touch it was seen), or its track goes back to the full
    computation (rare: equal δ at nearby rows takes exact ties)."""
    n = len(x)
    tr = index.track_of_row
    full = None  # δ of every row, when interest is None
    cand_rows, cand_delta = [], []
    for p in np.unique(p_track[active]):  # usually one or a few
        p = int(p)
        trk = np.flatnonzero((p_track == p) & active & (index.sizes >= 2 * p - 1))
        if not len(trk):
            continue
        v_lo = index.starts[trk] + (p - 1)  # the rows where δ is defined
        v_hi = index.ends[trk] - (p - 1)
        if interest is None:
            lo, hi, redo = v_lo, v_hi, None
        else:
            lo, hi = _runs(interest & _span_mask(v_lo, v_hi, n))
            redo = np.zeros(index.n_tracks, dtype=bool)
            if len(lo):
                # first the rows of interest alone: only those above t can be candidates,
                # and only around them is δ needed for the peak test (the screen leaves
                # most rows out, so their radius is computed, not every interest row's)
                if (hi - lo + 2 * (p - 1)).sum() >= EVERY_ROW_SHARE * n:
                    s_rows, s_delta = _screen_every_row(x, y, index, p, lo, hi, threshold)
                else:
                    s_rows, s_delta = _factor_on_runs(x, y, index, p, lo, hi, threshold)
                with np.errstate(invalid="ignore"):
                    lo = s_rows[s_delta > threshold]
                hi = lo + 1
        while True:
            if interest is not None:
                rt = tr[lo]
                reach = radius[rt]
                vl = index.starts[rt] + (p - 1)
                vh = index.ends[rt] - (p - 1)
                d_lo, d_hi, d_tr = _merge_runs(
                    np.maximum(lo - reach, vl), np.minimum(hi + reach, vh), rt
                )
                if redo.any():  # whole tracks, where a plateau reached too far
                    whole = trk[redo[trk]]
                    keep = ~redo[d_tr]
                    order = np.argsort(np.concatenate([d_lo[keep], index.starts[whole]]))
                    d_lo = np.concatenate([d_lo[keep], index.starts[whole] + (p - 1)])[order]
                    d_hi = np.concatenate([d_hi[keep], index.ends[whole] - (p - 1)])[order]
                    d_tr = np.concatenate([d_tr[keep], whole])[order]
            else:
                d_lo, d_hi = lo, hi
            if not len(d_lo):
                break
            if interest is None and index.sizes[trk].sum() >= 0.8 * n:  # (nearly) all rows
                chosen = np.zeros(index.n_tracks, dtype=bool)
                chosen[trk] = True
                delta = _factor_every_row(x, y, index, p, chosen)
                rows = None
            elif interest is not None and (d_hi - d_lo).sum() >= 0.6 * n:
                rows, delta = _screen_every_row(x, y, index, p, d_lo, d_hi, threshold)
            else:
                screen = None if interest is None else threshold
                rows, delta = _factor_on_runs(x, y, index, p, d_lo, d_hi, screen)
            q = _peaks_above(rows, delta, tr, radius, threshold)
            label = _clusters(q, tr, radius)
            if interest is not None:
                # a clustered peak counts only when its whole cluster was seen: every
                # member's ±2·radius inside the rows computed (or the track's defined span)
                clustered = np.flatnonzero(label >= 0)
                if len(clustered):  # only clusters holding a row of interest matter
                    seen = np.bincount(label[clustered], interest[q[clustered]])
                    clustered = clustered[seen[label[clustered]] > 0]
                if len(clustered):
                    m = q[clustered]
                    mt = tr[m]
                    j = np.searchsorted(d_lo, m, side="right") - 1
                    r2 = 2 * radius[mt]
                    vl = index.starts[mt] + (p - 1)
                    vh = index.ends[mt] - (p - 1)
                    ok_lo = (m - r2 >= d_lo[j]) | (d_lo[j] == vl)
                    ok_hi = (m + r2 < d_hi[j]) | (d_hi[j] == vh)
                    bad = ~(ok_lo & ok_hi) & ~redo[mt]
                    if bad.any():
                        redo[mt[bad]] = True
                        continue
            break
        if len(d_lo):
            if interest is None and rows is None and full is None:
                # the first δ of every row is the array itself, with NaN as np.full has it
                delta[np.isnan(delta)] = np.nan
                full = delta
            elif interest is None:
                if full is None:
                    full = np.full(n, np.nan)
                if rows is None:
                    np.copyto(full, delta, where=~np.isnan(delta))
                else:
                    full[rows] = delta
            keep = _one_per_plateau(q, label, tr, radius)
            q = q[keep]
            if interest is not None:
                q = q[interest[q]]
            cand_rows.append(q)
            cand_delta.append(delta[q] if rows is None else delta[np.searchsorted(rows, q)])
    if interest is None and full is None:
        full = np.full(n, np.nan)
    if not cand_rows:
        return np.zeros(0, dtype="int64"), np.zeros(0), full
    cand = np.concatenate(cand_rows)
    values = np.concatenate(cand_delta)
    order = np.argsort(cand, kind="stable")
    return cand[order], values[order], full


def _gathered_headings(x: np.ndarray, y: np.ndarray, first: np.ndarray, p: int) -> np.ndarray:
    """PCA heading (deg) of the ``p`` points from each row of ``first`` (a few candidate
    windows, gathered as a candidates × p block), oriented first to last point."""
    rows = first[:, None] + np.arange(p)
    u = x[rows] - x[first][:, None]
    v = y[rows] - y[first][:, None]
    u0, v0 = u - u.mean(axis=1, keepdims=True), v - v.mean(axis=1, keepdims=True)
    cxx, cyy, cxy = (u0 * u0).mean(axis=1), (v0 * v0).mean(axis=1), (u0 * v0).mean(axis=1)
    theta = 0.5 * np.arctan2(2.0 * cxy, cxx - cyy)
    ax, ay = np.cos(theta), np.sin(theta)
    flip = (u[:, -1] - u[:, 0]) * ax + (v[:, -1] - v[:, 0]) * ay < 0
    return np.remainder(np.degrees(np.arctan2(ax, ay)) + np.where(flip, 180.0, 0.0), 360.0)


def _leave_one_out_deg(
    x: np.ndarray, y: np.ndarray, index: TrackIndex, p_c: np.ndarray, cand: np.ndarray
) -> np.ndarray:
    """Per candidate o: the heading change between the ``p`` points before o and the ``p``
    after it, o itself left out (a single stray plot bends both of o's own windows, and
    neither of these); NaN where a window would leave the track."""
    out = np.full(len(cand), np.nan)
    tr = index.track_of_row[cand]
    ok = (cand - p_c >= index.starts[tr]) & (cand + p_c < index.ends[tr])
    for p in np.unique(p_c[ok]):  # a few distinct window sizes
        sel = ok & (p_c == p)
        o = cand[sel]
        out[sel] = geo.angle_diff(
            _gathered_headings(x, y, o - p, int(p)), _gathered_headings(x, y, o + 1, int(p))
        )
    return out


def detect(
    points: pd.DataFrame,
    params: ManeuverParams | None = None,
    progress=None,
    parts: int | None = None,
) -> ManeuverResult:
    """Run the detector on every track of a canonical table.

    At the first window duration the paper's rule runs as written (δ > t and the maximum
    within ±n points). Gradual turns: at each doubled duration within ``max_window_s`` (and at ``max_window_s``) a peak
    above t counts where no turn already found lies within one window of it. Turns that
    take a while: the first scale's windows ``gap_s`` apart. Sharp turns close together:
    windows halved down to ``min_window_s`` where 3 points fit, a turn counting only when it
    clears the noise floor with its own point left out. Every added turn needs no turn
    already found within its reach. No maneuver inside an at-rest span, on a window touching
    one, or where the ship covers a window slower than ``min_speed_kn``. The extra tests run
    on the candidates (peaks above t) only.

    The first duration gives δ of every row (``ManeuverResult.factor``); the longer ones
    compute δ only on the rows where a new turn may count (no turn within one window, no
    at-rest span within it) and a radius around them, and look for peaks among the rows
    above t only. Same output as running every rule on every row
    (tests/test_maneuver_kernel.py).

    ``parts``: groups of whole tracks detected on threads, one thread per core at most
    (default: parts of about :data:`PART_ROWS` rows, at least one per core, from
    :data:`PARALLEL_MIN_ROWS` rows; else 1); the result does not depend on it.
    """
    params = (params or ManeuverParams()).checked()
    pts, index = sorted_with_index(points)
    bounds = _parts(index, parts)
    if len(bounds) > 2:
        # the parts look for repeated rows themselves, on the threads: None if any holds one
        result = _detect_in_parts(pts, index, params, progress, bounds)
        if result is not None:
            return result
    repeat = repeated_rows(pts, index)
    if repeat.any():
        return _detect_without_repeats(pts, index, repeat, params, progress, parts)
    return _detect_sorted(pts, index, params, progress)


def _detect_without_repeats(pts, index, repeat, params, progress, parts) -> "ManeuverResult":
    """:func:`detect` on the rows that do not repeat their predecessor; each repeat gets its
    original's factor and at-rest flag and is never a maneuver point itself."""
    keep = ~repeat
    sub = pts.iloc[np.flatnonzero(keep)].reset_index(drop=True)
    res = detect(sub, params, progress, parts)
    original = np.cumsum(keep) - 1  # each row's row in ``sub`` (a repeat: its original's)
    is_maneuver = np.zeros(len(pts), dtype=bool)
    is_maneuver[keep] = res.is_maneuver
    at_rest = None if res.at_rest is None else res.at_rest[original]
    return ManeuverResult(
        pts, index, res.factor[original], is_maneuver, res.window_p, at_rest, res.params
    )


def _parts(index: TrackIndex, parts: int | None) -> np.ndarray:
    """Row bounds of ``parts`` groups of whole tracks of about equal size (default: about
    :data:`PART_ROWS` rows each and at least one per core for a large table, else one)."""
    n = int(index.ends[-1]) if index.n_tracks else 0
    if parts is None:
        parts = max(_threads(), -(-n // PART_ROWS)) if n >= PARALLEL_MIN_ROWS else 1
    parts = max(1, min(int(parts), index.n_tracks))
    if parts == 1:
        return np.array([0, n], dtype="int64")
    cut = np.searchsorted(index.starts, np.arange(1, parts) * (n / parts))
    cut = np.clip(cut, 1, index.n_tracks - 1)  # a part starts with a track, never empty
    bounds = np.unique(np.concatenate([[0], index.starts[cut], [n]]))
    return bounds.astype("int64")


def _detect_in_parts(
    pts: pd.DataFrame, index: TrackIndex, params: "ManeuverParams", progress, bounds
) -> "ManeuverResult | None":
    """:func:`_detect_sorted` on groups of whole tracks at once, results put together;
    None when a part holds rows that repeat their predecessor (:func:`repeated_rows`, a
    rule within tracks: checked by each part on its thread, before any detection)."""
    t = track_seconds(pts)
    pieces = []
    for a, b in zip(bounds[:-1], bounds[1:], strict=True):
        k0, k1 = np.searchsorted(index.starts, [a, b])
        sub = pts.iloc[a:b].reset_index(drop=True)
        sub_index = TrackIndex(
            index.starts[k0:k1] - a,
            index.ends[k0:k1] - a,
            index.track_of_row[a:b] - k0,
            index.keys.iloc[k0:k1].reset_index(drop=True),
        )
        remember_order(sub, sub_index, t[a:b])
        pieces.append((sub, sub_index))
    stop: list[BaseException] = []
    share = np.diff(bounds) / max(int(bounds[-1]), 1)  # each part's share of the rows
    done = np.zeros(len(pieces))  # each part's own fraction
    one_at_a_time = threading.Lock()

    def relay(k: int):
        # Every part reports the fraction of all rows done, one call at a time; every part
        # stops at its next report once any part was stopped (a caller cancels by raising
        # from ``progress``).
        def report(fraction: float, text: str = "") -> None:
            if stop:
                raise stop[0]
            done[k] = fraction
            if progress is not None:
                with one_at_a_time:
                    try:
                        progress(float(min(1.0, share @ done)), text)
                    except BaseException as exc:
                        stop.append(exc)
                        raise

        return report

    n = len(pts)
    factor = np.empty(n)
    is_maneuver = np.empty(n, dtype=bool)
    at_rest = np.empty(n, dtype=bool)

    def repeats(k: int) -> bool:
        return bool(repeated_rows(*pieces[k]).any())

    def part(k: int) -> np.ndarray:
        # each part puts its rows in place itself: the copies run on the threads, not one
        # after the other on the caller's
        if stop:  # a part stopped before this one began
            raise stop[0]
        sub, sub_index = pieces[k]
        res = _detect_sorted(sub, sub_index, params, relay(k))
        rows = slice(bounds[k], bounds[k + 1])
        factor[rows] = res.factor
        is_maneuver[rows] = res.is_maneuver
        at_rest[rows] = res.at_rest
        return res.window_p

    workers = min(len(pieces), _threads())
    with ThreadPoolExecutor(workers, thread_name_prefix="wakeline-detect") as pool:
        if any(pool.map(repeats, range(len(pieces)))):
            return None
        futures = [pool.submit(part, k) for k in range(len(pieces))]
        window_p = [f.result() for f in futures]
    return ManeuverResult(
        pts, index, factor, is_maneuver, np.concatenate(window_p), at_rest, params
    )


def _detect_sorted(
    pts: pd.DataFrame, index: TrackIndex, params: "ManeuverParams", progress=None
) -> "ManeuverResult":
    """The detector on a table in track order with its index (see :func:`detect`)."""
    x, y = local_xy(pts, index)
    t = track_seconds(pts)
    n = len(pts)
    tr = index.track_of_row
    noise: list[np.ndarray] = []  # the track noise, computed when first needed
    # each track's median interval (s), once for the windows, the rest rule and the noise
    wants_med = params.window_s > 0 or params.noise_lag_s > 0
    wants_med |= params.rest_radius_m > 0 and params.rest_steps > 0
    wants_med |= params.max_step_windows > 0
    wants_med |= params.radius_s > 0 or params.edge_s > 0
    med = median_interval_s(t, index) if wants_med else None
    step = None
    if params.window_max_s > 0 and params.window_s > 0:
        step = window_step_s(t, index, int(params.window_p))
    track_index, med_track = index, med  # the tracks as given (the result's index)
    rest = np.zeros(n, dtype=bool)
    sigma_track = None  # the track noise, when the at-rest radius wants it first
    if params.rest_radius_m > 0 and n:
        lag_track = _noise_lag(med if params.window_s > 0 else None, params)
        if params.rest_noise_sigmas > 0:
            sigma_track = position_noise_m(x, y, t, index, lag_track)
        rest = _rest_mask(
            x,
            y,
            t,
            index,
            params.rest_radius_m,
            params.rest_window_s,
            params.rest_steps,
            med,
            params.rest_north_box,
            params.rest_noise_sigmas,
            lag_track,
            sigma_track,
            params.rest_noise_cap_m,
        )
    rest_lo, rest_hi = _runs(rest)
    any_rest = bool(len(rest_lo))
    # headings are not taken across a step longer than max_step_windows at-rest windows:
    # from here on each piece between such steps is a track (the median interval, p, the
    # track noise and the at-rest spans stay the whole track's)
    parent = None
    pieces = _heading_pieces(t, index, med, params)
    if pieces is not None:
        index, parent = pieces
        tr = index.track_of_row
        med = med[parent]
        step = None if step is None else step[parent]

    rest_rows = np.flatnonzero(rest) if params.confirm_z > 0 else None

    def track_noise() -> np.ndarray:
        """Each track's (piece's) position noise, computed when first needed."""
        if not noise:
            lag = _noise_lag(med_track if params.window_s > 0 else None, params)
            sigma = sigma_track
            if sigma is None:
                sigma = position_noise_m(x, y, t, track_index, lag)
            noise.append(sigma if parent is None else sigma[parent])
        return noise[0]

    def accept(f_c: np.ndarray, cand: np.ndarray, p_c: np.ndarray, reach: np.ndarray, fine: bool):
        """The candidates (δ ``f_c``) that clear the noise floor (always at a fine scale,
        with the candidate's own point left out too), the minimum speed over ``reach``
        points and the at-rest spans."""
        ok = np.ones(len(cand), dtype=bool)
        if not len(cand):
            return ok
        # each test runs on the candidates still standing only (a candidate out stays out)
        if params.noise_k > 0 or fine:
            track_noise()
            k = params.noise_k
            gate = None  # noise_min_windows: the rows whose track offers enough windows
            options = params.noise_k_windows or params.noise_min_span > 0 or params.noise_k_law
            if params.noise_k > 0 and options:
                pt = index.track_of_row[cand]
                points = track_index.sizes[pt if parent is None else parent[pt]]
                if params.noise_min_windows > 0:
                    gate = _enough_windows(points, p_first[pt], params.noise_min_windows)
            if params.noise_k > 0 and params.noise_k_windows:
                k = _k_windows(params.noise_k, points, p_c)
                if gate is not None:
                    k = np.where(gate, k, params.noise_k)
            if params.noise_k > 0 and params.noise_k_law:
                law = _k_law(x, y, index, p_c, noise[0], cand, k)
                k = law if gate is None else np.where(gate, law, k)
            if params.noise_k > 0 and params.noise_min_span > 0:
                spans = _spans_noise(x, y, index, p_c, noise[0], cand, params.noise_min_span)
                ok &= spans if gate is None else spans | ~gate
            if fine:  # the floor itself is wanted below
                with np.errstate(invalid="ignore"):
                    floor = np.maximum(
                        k * _heading_noise_deg(x, y, index, p_c, noise[0], cand),
                        params.threshold_deg,
                    )
                    ok &= f_c > floor
                    j = np.flatnonzero(ok)
                    ok[j] = _leave_one_out_deg(x, y, index, p_c[j], cand[j]) > floor[j]
            else:
                ok &= _clears_noise(x, y, index, p_c, noise[0], cand, f_c, k, params.threshold_deg)
        if params.min_speed_kn > 0:
            j = np.flatnonzero(ok)
            ok[j] = _fast_enough(
                x,
                y,
                t,
                index,
                reach[j],
                cand[j],
                params.min_speed_kn * geo.KN_MS,
                params.slow_side,
                params.slow_side_step_s,
                params.slow_side_span_s,
            )
        if any_rest:
            j = np.flatnonzero(ok)
            ok[j] = ~_near(rest, index, reach[j] - 1, cand[j])
        if params.confirm_z > 0:
            j = np.flatnonzero(ok)
            legs = np.maximum(np.round(params.confirm_legs * p_c[j]), 2).astype("int64")
            ok[j] = _confirmed(
                x,
                y,
                t,
                index,
                cand[j],
                legs,
                track_noise(),
                rest_rows,
                params.confirm_z,
                params.min_speed_kn * geo.KN_MS,
            )
            if params.confirm_grow > 0:  # the turns not confirmed: legs grown
                out = ~ok[j]
                j = j[out]
                ok[j] = _confirmed_grown(
                    x,
                    y,
                    t,
                    index,
                    cand[j],
                    legs[out],
                    track_noise(),
                    rest_rows,
                    params,
                    np.union1d(found_rows[0], cand[ok]),
                )
        return ok

    def add(f_c: np.ndarray, cand: np.ndarray, ok: np.ndarray, reach: np.ndarray) -> None:
        new, f_new = cand[ok], f_c[ok]
        far = ~_near(found_rows[0], index, reach[ok], new)
        factor[new[far]] = f_new[far]
        found[new[far]] = True
        added = new[far]  # sorted, none of them found already
        found_rows[0] = np.insert(found_rows[0], np.searchsorted(found_rows[0], added), added)

    scales = _scales(params)
    fine_scales = _fine_scales(params)
    r_first = _radius_per_track(med, index.n_tracks, params)
    slow_ok = None  # step_noise_max: the tracks radius_s and edge_s apply on
    if params.step_noise_max > 0 and (params.radius_s > 0 or params.edge_s > 0) and n:
        v = median_window_speed_ms(x, y, t, track_index, int(params.window_p))
        if parent is not None:
            v = v[parent]
        with np.errstate(invalid="ignore", divide="ignore"):
            ratio = track_noise() / (v * med)
        slow_ok = ratio < params.step_noise_max  # NaN (no speed, no step): not
        r_first = np.where(slow_ok, r_first, int(params.radius_n))
    edge_med = med
    med = med if params.window_s > 0 else None
    found = np.zeros(n, dtype=bool)
    found_rows = [np.zeros(0, dtype="int64")]  # the rows of ``found``, sorted
    factor = np.empty(0)  # δ of every row: the first scale's, below
    u, v = _anchored_xy(x, y, index)  # what every window sum is taken against
    p_first = np.full(index.n_tracks, int(params.window_p), dtype="int64")
    prev_p = np.zeros(index.n_tracks, dtype="int64")
    n_steps = len(scales) + len(fine_scales) + (params.gap_s > 0)
    for k, duration in enumerate(scales):
        if progress:
            progress(k / n_steps, f"maneuver factor, {duration:g} s windows")
        p_track = _p_per_track(t, index, params, duration, med, step)
        if k > 0:
            # tracks whose window did not grow at this duration have nothing new to find
            grew = p_track > prev_p
            if not grew.any():
                continue
            radius = np.maximum(p_track, r_first)
            # rows where a new turn may count: none found within one window, no at-rest
            # span within one window less one (the tests below, as rows)
            f_rows = found_rows[0]
            # (the masks of the rows outside made as such, not negated; no per-row gather
            # where every track grew, as on regularly sampled tracks)
            masks = []
            if len(f_rows):
                reach = p_track[tr[f_rows]]
                masks.append(_dilate(f_rows, f_rows + 1, reach, index, n, inside=False))
            if len(rest_lo):
                reach = p_track[tr[rest_lo]] - 1
                masks.append(_dilate(rest_lo, rest_hi, reach, index, n, inside=False))
            if not grew.all():
                masks.append(grew[tr])
            interest = masks[0] if masks else np.ones(n, dtype=bool)
            for mask in masks[1:]:
                interest &= mask
            cand, f_c, _ = _scale_candidates(
                u, v, index, p_track, radius, params.threshold_deg, grew, interest
            )
        else:
            radius = r_first.copy()
            if params.window_max_s > 0:  # the radius reaches no further than one window
                radius = np.minimum(radius, p_track)
            active = np.ones(index.n_tracks, dtype=bool)
            cand, f_c, factor = _scale_candidates(
                u, v, index, p_track, radius, params.threshold_deg, active
            )
            p_first = p_track
        p_c = p_track[tr[cand]]
        ok = accept(f_c, cand, p_c, p_c, fine=False)
        if k == 0:
            found[cand[ok]] = True
            found_rows[0] = cand[ok]  # cand is sorted
        else:
            add(f_c, cand, ok, p_c)
        prev_p = p_track
    if params.gap_s > 0 and med is not None:
        if progress:
            progress(len(scales) / n_steps, f"maneuver factor, windows {params.gap_s:g} s apart")
        with np.errstate(invalid="ignore", divide="ignore"):
            gap = np.where(np.isfinite(med) & (med > 0), np.round(params.gap_s / med / 2), 0)
        gap = gap.astype("int64")  # points left out either side of the point
        for g in np.unique(gap[gap > 0]):  # a few distinct gaps
            f_g, peaks = _one_scale(x, y, index, p_first, p_first + g, gap == g, int(g))
            with np.errstate(invalid="ignore"):
                cand = np.flatnonzero(peaks & (f_g > params.threshold_deg))
            p_c = p_first[tr[cand]]
            ok = accept(f_g[cand], cand, p_c, p_c + g, fine=False)
            # a turn that takes a while bends the gapped windows at the neighbouring points
            # too; one noisy window pair does not
            lo, hi = np.maximum(cand - 1, 0), np.minimum(cand + 1, len(f_g) - 1)
            with np.errstate(invalid="ignore"):
                ok &= np.fmin(f_g[lo], f_g[hi]) > params.threshold_deg
            add(f_g[cand], cand, ok, p_c + g)
    shortest = p_first
    for k, duration in enumerate(fine_scales):
        if progress:
            progress((len(scales) + k + 1) / n_steps, f"maneuver factor, {duration:g} s windows")
        with np.errstate(invalid="ignore", divide="ignore"):
            chosen = np.where(np.isfinite(med) & (med > 0), np.round(duration / med), 0)
        p_track = np.clip(chosen, 3, 1000).astype("int64")
        # only where 3 points fit and the window is shorter than any before
        active = (chosen >= 3) & (p_track < shortest)
        if not active.any():
            continue
        f_k, peaks = _one_scale(x, y, index, p_track, p_track, active)
        with np.errstate(invalid="ignore"):
            cand = np.flatnonzero(peaks & (f_k > params.threshold_deg))
        p_c = p_track[tr[cand]]
        add(f_k[cand], cand, accept(f_k[cand], cand, p_c, p_c, fine=True), p_c)
        shortest = np.where(active, p_track, shortest)
    if params.edge_s > 0 and edge_med is not None and n:
        f_e, cand = _edge_candidates(x, y, index, p_first, edge_med, params, slow_ok)
        p_c = np.full(len(cand), EDGE_P, dtype="int64")
        add(f_e, cand, accept(f_e, cand, p_c, p_c, fine=False), p_first[tr[cand]])
    if progress:
        progress(1.0, "maneuvers found")
    if parent is not None:  # each track's p: its first piece's (every piece has the same)
        p_first = p_first[np.searchsorted(parent, np.arange(track_index.n_tracks))]
    return ManeuverResult(pts, track_index, factor, found, p_first, rest, params)


#: Points per window at a track's ends (``edge_s``): the fewest that have a heading and a
#: noise floor.
EDGE_P = 3


def median_window_speed_ms(
    x: np.ndarray, y: np.ndarray, t: np.ndarray, index: TrackIndex, points: int
) -> np.ndarray:
    """Per track: the median over its rows of the speed (m/s) of the chord from each row to
    the row ``points`` − 1 steps later (both in the track, a later time); NaN where it has
    none. ``step_noise_max``'s v: over a few steps, noise adds little to it."""
    q = max(int(points) - 1, 1)
    n = len(x)
    out = np.full(index.n_tracks, np.nan)
    if n <= q:
        return out
    tr = index.track_of_row
    i = np.flatnonzero(tr[: n - q] == tr[q:])
    dt = t[i + q] - t[i]
    with np.errstate(invalid="ignore", divide="ignore"):
        sp = np.hypot(x[i + q] - x[i], y[i + q] - y[i]) / dt
    keep = (dt > 0) & np.isfinite(sp)
    i, sp = i[keep], sp[keep]
    count = np.bincount(tr[i], minlength=index.n_tracks)
    first = np.cumsum(count) - count
    has = count > 0
    out[has] = run_medians(sp, first, count)[has]
    return out


def _radius_per_track(med: np.ndarray | None, n_tracks: int, params: ManeuverParams) -> np.ndarray:
    """The maximum filter's radius (points) per track at the first scale: ``radius_n``, or
    with ``radius_s`` > 0 as many of the track's median steps ``med`` as fit in ``radius_s``
    seconds where that is fewer and at least 2."""
    r = np.full(n_tracks, int(params.radius_n), dtype="int64")
    if params.radius_s <= 0 or med is None:
        return r
    with np.errstate(invalid="ignore", divide="ignore"):
        fit = np.floor(params.radius_s / med * (1 + 1e-9))
        fit = np.where(np.isfinite(fit) & (fit >= 2), fit, params.radius_n)
    return np.minimum(r, fit).astype("int64")


def _edge_candidates(
    x: np.ndarray,
    y: np.ndarray,
    index: TrackIndex,
    p_first: np.ndarray,
    med: np.ndarray,
    params: ManeuverParams,
    tracks_ok: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """``edge_s``: δ of 3-point windows at the rows where the first scale's window (``p_first``
    points) leaves the track, on the tracks where that window spans more than ``edge_s``
    ((p − 1) median steps ``med``) and 3 points at most (2 steps), and among those only the
    ``tracks_ok`` (``step_noise_max``'s) if given; the rows among those where δ > t is the
    largest within one 3-point window (one per plateau). Returns their δ and rows."""
    tr = index.track_of_row
    with np.errstate(invalid="ignore"):
        fits = np.isfinite(med) & ((EDGE_P - 1) * med <= params.edge_s * (1 + 1e-9))
        fits &= (p_first - 1) * med > params.edge_s * (1 + 1e-9)
    if tracks_ok is not None:
        fits &= tracks_ok
    active = fits & (index.sizes >= 2 * EDGE_P - 1)
    none = np.zeros(0), np.zeros(0, dtype="int64")
    if not active.any():
        return none
    p3 = np.full(index.n_tracks, EDGE_P, dtype="int64")
    f3, _ = _one_scale(x, y, index, p3, p3, active)
    pos = np.arange(len(x)) - index.starts[tr]
    pf = p_first[tr]
    edge = active[tr] & ((pos < pf - 1) | (pos > index.sizes[tr] - pf))
    f3[~edge] = np.nan
    peaks = local_maxima(f3, index, EDGE_P)
    with np.errstate(invalid="ignore"):
        cand = np.flatnonzero(peaks & (f3 > params.threshold_deg))
    return f3[cand], cand


def _noise_lag(med: np.ndarray | None, params: ManeuverParams) -> "np.ndarray | int":
    """Points between a point and the neighbours its noise is measured against, per track
    (``noise_lag_s`` over the track's median interval ``med`` in s, at least 1); 1 when
    that is all."""
    if params.noise_lag_s <= 0 or med is None or not len(med):
        return 1
    with np.errstate(invalid="ignore", divide="ignore"):
        lag = np.where(np.isfinite(med) & (med > 0), np.round(params.noise_lag_s / med), 1)
    lag = np.clip(lag, 1, 1000).astype("int64")
    # one lag for every track: the slices of position_noise_m, not its per-row gathers
    return int(lag[0]) if (lag == lag[0]).all() else lag


def _heading_pieces(
    t: np.ndarray, index: TrackIndex, med: np.ndarray | None, params: ManeuverParams
) -> tuple[TrackIndex, np.ndarray] | None:
    """The tracks cut, for the heading windows, at every step (s, ``t``) longer than
    ``max_step_windows`` at-rest windows — per track max(``rest_window_s``,
    max(``rest_steps``, 1) × its median interval ``med``): cleaning's at-rest rule reaches
    back over a step of up to four such windows (:func:`wakeline.core.clean.at_rest`,
    :func:`wakeline.core.clean.rest_frame`), and a heading across a longer one is a chord over
    time nobody observed. Returns the index of the pieces and each piece's track, or None
    when no step is that long (or the rule is off)."""
    if params.max_step_windows <= 0 or len(t) < 2 or med is None:
        return None
    tr = index.track_of_row
    # a track without a median interval (one fix) takes rest_window_s (fmax skips NaN)
    window = np.fmax(params.rest_window_s, max(params.rest_steps, 1.0) * med)
    with np.errstate(invalid="ignore"):
        cut = np.diff(t) > params.max_step_windows * window[tr[1:]]
    cut &= tr[1:] == tr[:-1]
    if not cut.any():
        return None
    first = np.zeros(len(t), dtype=bool)
    first[index.starts[index.sizes > 0]] = True
    first[1:] |= cut
    starts = np.flatnonzero(first)
    ends = np.append(starts[1:], len(t))
    parent = tr[starts]
    track_of_row = np.repeat(np.arange(len(starts)), ends - starts)
    keys = index.keys.iloc[parent].reset_index(drop=True)
    return TrackIndex(starts, ends, track_of_row, keys), parent


def _sub_index(index: TrackIndex, selected: np.ndarray):
    sizes = index.sizes[selected]
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype("int64")
    ends = starts + sizes
    track_of_row = np.repeat(np.arange(len(sizes)), sizes)
    return starts, ends, track_of_row, index.keys[selected].reset_index(drop=True)


def smallest_detectable_turn_deg(
    eps_m: float, speed_kn: float, t1_s: float, t2_s: float | None = None
) -> float:
    """Seed 000 eq. 10: the smallest turn (deg) that position errors of at most ``eps_m``
    cannot fake, for legs of ``t1_s`` and ``t2_s`` seconds at ``speed_kn``."""
    t2_s = t1_s if t2_s is None else t2_s
    v = speed_kn * geo.KN_MS
    return 180.0 - math.degrees(
        math.atan(v * t1_s / (2 * eps_m)) + math.atan(v * t2_s / (2 * eps_m))
    )


def largest_tolerable_error_m(threshold_deg: float, speed_kn: float, leg_s: float) -> float:
    """Seed 000 eq. 12 (equal legs): the largest position error (m) for which a turn of
    ``threshold_deg`` stays above the noise; 16 kn, 30 min legs, 15° → ≈ 975 m."""
    v = speed_kn * geo.KN_MS
    return v * leg_s / (2.0 * math.tan(math.radians(180.0 - threshold_deg) / 2.0))


#: Below this median time per point (s), batches all at one time or moving faster than a
#: ship are radar plots, not tracks sampled in time (fast tracks, GNSS at 10 Hz, are tracks).
GUIDANCE_MIN_INTERVAL_S = PLOT_MIN_INTERVAL_S
#: Above this median speed (kn) the batches are not one ship each (no ship goes faster;
#: AIS itself tops out at 102.2 kn).
GUIDANCE_MAX_SPEED_KN = PLOT_MAX_SPEED_KN


@dataclass(frozen=True)
class DetectionLimit:
    """Seed 000's detection limit for a data set: the typical speed (kn) and sampling
    interval (s), legs of ``window_p`` points (``leg_s``), the largest position error (m)
    a ``threshold_deg`` turn stands out from, and the smallest turn (deg) found with
    100 m errors. ``reason`` is set (and the numbers are NaN) when no limit can be given."""

    speed_kn: float
    interval_s: float
    leg_s: float
    eps_m: float
    turn_deg: float
    reason: str | None = None
    #: Points per heading window at that interval, as the detector chooses them.
    window_p: int = 0
    #: Rows repeating an earlier row of their track (same time and position), left out.
    repeats: int = 0
    #: Tracks (of ``tracks`` with two points or more) most of whose span is long gaps
    #: (:func:`wakeline.core.tracks._long_gaps`): the speed is taken between the gaps.
    gap_tracks: int = 0
    tracks: int = 0
    #: Their median span (s) and the share of it in gaps.
    gap_span_s: float = float("nan")
    gap_share: float = float("nan")


def detection_limit(
    summary: pd.DataFrame,
    window_p: int,
    threshold_deg: float,
    eps_m: float = 100.0,
    window_s: float = 0.0,
    window_max_s: float = 0.0,
) -> DetectionLimit | None:
    """The detection limit of seed 000 eq. 10/12 from a :func:`track_summary` table, or
    None when there is nothing to judge (no track with two points). The interval is the
    median over tracks of each one's median sampling interval (its ``interval_s``; the
    detector's own figure, so gaps do not stretch it), the legs ``window_p`` points or, with
    ``window_s`` > 0, the points the detector takes for that many seconds at that interval
    (never fewer than ``window_p``; with ``window_max_s`` > 0 fewer where the detector's
    rule lowers them, the interval taken as the step). When the batches are no tracks —
    their points share times (radar plots written one batch per scan: each batch's time
    per point, median over batches, below :data:`GUIDANCE_MIN_INTERVAL_S`, and half the
    batches at one time or moving faster than :data:`GUIDANCE_MAX_SPEED_KN`), or their
    median speed is no ship's (above :data:`GUIDANCE_MAX_SPEED_KN`) — ``reason`` says why
    no limit is given.

    Rows that repeat an earlier row of their batch (same time and position: a file
    writing each fix again, as Autoferry's GNSS truth does once per radar scan; the
    summary's ``repeats``) are no evidence of plots: they are not counted. Fast tracks
    (GNSS at 5–12 Hz: steps of 0.08–0.2 s) are tracks: their median step is the
    interval, below 1 s (it was read as "radar plots" once the gaps were left out)."""
    if summary.empty:
        return None
    points = summary["points"].to_numpy(dtype="float64")
    repeats = 0
    if "repeats" in summary.columns:
        repeated = summary["repeats"].to_numpy(dtype="float64")
        points = points - repeated
        repeats = int(repeated.sum())
    duration = summary["duration_s"].to_numpy(dtype="float64")
    moving = points > 1
    if not moving.any():
        return None
    span = float(np.nanmedian(duration[moving] / (points[moving] - 1)))
    speeds = summary["mean_speed_kn"].to_numpy(dtype="float64")
    gaps = {}
    if "gap_s" in summary.columns:
        # the speed between the long gaps (a track spanning days of runs: Autoferry's truth
        # read 0.1 kn over its 2 days), and how many tracks are mostly gaps
        gap_s = summary["gap_s"].to_numpy(dtype="float64")
        gap_m = summary["gap_m"].to_numpy(dtype="float64")
        length = summary["length_m"].to_numpy(dtype="float64")
        run = duration - gap_s
        with np.errstate(divide="ignore", invalid="ignore"):
            speeds = np.where((gap_s > 0) & (run > 0), (length - gap_m) / run / geo.KN_MS, speeds)
        gappy = moving & (gap_s > 0.5 * duration)
        if gappy.any():
            gaps = {
                "gap_tracks": int(gappy.sum()),
                "gap_span_s": float(np.median(duration[gappy])),
                "gap_share": float(gap_s[gappy].sum() / duration[gappy].sum()),
            }
    speeds = speeds[moving]
    speed = float(np.nanmedian(speeds)) if np.isfinite(speeds).any() else float("nan")
    shared = int(np.count_nonzero(duration[moving] <= 0))
    # Plots: batches close in time whose points are all at one time (half of them at
    # least) or far apart for that time (no ship's speed); fast tracks move as ships do.
    # Or half the batches plots by :func:`~wakeline.core.tracks.plot_like` (several
    # positions at one time), the test fusion and association warn with.
    plots = (
        not span >= GUIDANCE_MIN_INTERVAL_S
        and (
            2 * shared >= int(moving.sum())
            or not (np.isfinite(speed) and speed <= GUIDANCE_MAX_SPEED_KN)
        )
    ) or 2 * int(plot_like(summary)[moving].sum()) >= int(moving.sum())
    interval = span
    if "interval_s" in summary.columns and not plots:
        steps = summary["interval_s"].to_numpy(dtype="float64")[moving]
        if np.isfinite(steps).any():
            interval = float(np.nanmedian(steps))
    nan = float("nan")

    tracks = int(moving.sum())

    def none_because(reason: str) -> DetectionLimit:
        return DetectionLimit(
            speed, interval, nan, nan, nan, reason, repeats=repeats, tracks=tracks, **gaps
        )

    n_plot = int(plot_like(summary)[moving].sum())
    if plots and 2 * shared < tracks and n_plot:
        return none_because(
            f"points share times ({n_plot:,} of {count_of(tracks, 'batch', 'batches')} hold "
            f"several positions at one time; median interval {interval:.1f} s): these look "
            "like radar plots (one batch per scan), not tracks; no detection limit can be "
            "given until the plots are joined into tracks"
        )
    if plots:
        return none_because(
            f"points share times (median interval {interval:.1f} s; {shared:,} of "
            f"{count_of(int(moving.sum()), 'batch', 'batches')} have all their points at one "
            "time): these look "
            "like radar plots (one batch per scan), not tracks; no detection limit can be "
            "given until the plots are joined into tracks"
        )
    if not np.isfinite(speed) or speed <= 0:
        return none_because("the tracks do not move: no typical speed")
    if speed > GUIDANCE_MAX_SPEED_KN:
        return none_because(
            f"median speed {speed:.0f} kn is no ship's: the batches are not one ship each "
            "(radar plots, or one id for several ships); no detection limit can be given"
        )
    p = int(window_p)
    if window_s > 0:  # as the detector chooses them (:func:`_p_per_track`)
        p = int(window_points(window_s, np.array([interval]), window_p, window_max_s)[0])
    leg = interval * p
    return DetectionLimit(
        speed,
        interval,
        leg,
        largest_tolerable_error_m(threshold_deg, speed, leg),
        smallest_detectable_turn_deg(eps_m, speed, leg),
        window_p=p,
        repeats=repeats,
        tracks=tracks,
        **gaps,
    )
