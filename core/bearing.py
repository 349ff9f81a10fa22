"""Bearing-only maneuver detection (seed 002, SPEC §4), in seconds: a generalized
likelihood ratio test by default, seed 002's AUC test and its eq. 15 as options.

Two adjacent windows slide over a target's bearing sequence: X (the ``window_x_s``
seconds before a boundary) and Y (up to ``window_y_s`` seconds after it, tested over
``y_scales`` nested spans). Every span is in seconds, so the detector runs unchanged at
any sampling rate and on irregular sampling (jitter, dropped samples): a window holds
whatever samples fall in its span. X starts after the last gap; Y stops before the next
one (its shorter spans are still tested).

**The motion model: the target's motion fitted on X, with the observer's known positions.**
In the frame of X's last line of sight (τ: time from the boundary, per X span), a
constant-velocity target seen from the observer's positions has the bearing

    β(τ) = β₀ + atan2(p + q·τ − s·d_c(τ), 1 + r·τ − s·d_a(τ))

(d_a, d_c: the observer's displacement from its position at X's last sample, along and
across that line of sight, in 10 km; s = 10 km / range; p, q, r: the target's offset and
its own velocity over range). Multiplied out, tan β·(1 + rτ − s·d_a) = p + qτ − s·d_c is
linear in the four parameters (pseudo-linear least squares, the tan β regressors taken from
a smooth fit as an instrument), then one Gauss–Newton step; all boundaries at once. On a
steady leg d is linear in τ and s trades off exactly against (q, r): a weak prior s ~ 0
makes the fit the target's *relative* motion (three parameters, range unobservable), the
first version's model, which is also where the fit starts (the step only keeps what lowers
X's residuals). While the observer maneuvers, s — the range — becomes observable, so its
turns are fitted through rather than excluded. A static observer (or none given) has
d = 0: the relative-motion fit as before. ``exclude_observer_turns`` keeps the first
version's way: X starts after the observer's last maneuvering sample, Y stops before the
next one, and the relative motion is fitted. A quadratic in time is kept as the
alternative model (``relative_motion`` off).

**The GLR test (default, ``glr``).** A turn changes the bearing rate at some time t_c:
β = model + Δω·max(t − t_c, 0). For t_c at the boundary and each Y span, the ramp is
fitted together with the motion model over X and the span (one Gauss–Newton step from
X's fit, the ramp's column added); z = Δω̂ / se(Δω̂), se from the 4×4 (5×5 with s)
normal matrix and σ from X's residuals. This is the likelihood-ratio test of "constant
velocity" against "bearing-rate change at t_c" (Gaussian noise), linearized; it uses the ramp
shape of a turn's residual, where the AUC only sees a shift of Y's median. Its null is
N(0, 1) per test; the threshold covers the many boundaries and spans (alpha). The
smallest rate change the data can show is z_crit·se (reported per batch).

**The AUC test (``glr`` off; seed 002).** X's and Y's residuals from the X fit (Y:
extrapolated) are compared by the Mann–Whitney AUC. **The null.** Y's residuals share the extrapolation error of X's fit, so the textbook
null AUC ~ N(½, (m+n+1)/(12mn)) is too narrow. Near H0 a common offset δ moves the AUC
by δ / (σ√(4π)) and the offset's variance is σ²·h̄ᵀ(JᵀJ)⁻¹h̄ (J: the fit's Jacobian on X,
h̄: its rows averaged over Y), so σ cancels:
Var(AUC) = (m+n+1)/(12mn) + h̄ᵀ(JᵀJ)⁻¹h̄ / (4π). We reject "no maneuver" when
|AUC − ½| / sd > z_{α/2}. With ``auc_mean`` (seed 002 eq. 15) the AUCs of the boundaries
in the last ``mean_span_s`` are averaged and tested as |AUC̄ − ½| / (sd/√N) > z_{α/2}.

Detection time is the last sample of the shortest rejecting Y span (causal);
the estimated maneuver time is where a bearing-rate change best explains the residuals
of that boundary's fit (:func:`maneuver_time`; seed 002's largest |z| of the run comes
late here). Later rejections count as a new detection only once X no longer holds the
previous estimated maneuver time. Bearings are unwrapped, so 359° → 1° is a 2° step.
"""

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from wakeline.core import geo
from wakeline.core.bearing_read import (  # noqa: F401 - the reader, re-exported
    BEARING_FIELDS,
    BEARING_NAMES,
    read_bearing_file,
    read_bearings,
    read_bearings_checked,
)
from wakeline.core.params import Params, param
from wakeline.core.schema import seconds_to_time, time_seconds

DETECTION_COLUMNS = ("batch", "detect_time", "maneuver_time", "z")
EXCLUSION_REASONS = ("gap", "sparse", "observer_maneuvering")
RANGE_FLOOR = 0.9
R_PRIOR = 1e-6  # weight of the prior r ~ 0, per sample of X
S_PRIOR = 1e-8  # weight of the prior s ~ 0 (range unknown), per sample of X
OBS_UNIT_M = 10_000.0  # the observer's displacement in units of 10 km (s = 10 km / range)
S_MAX = 50.0  # range at least 200 m


@dataclass(frozen=True)
class BearingParams(Params):
    """AUC detector settings (ours; seed 002 leaves window sizes and α open). Spans in s."""

    window_x_s: float = param(
        600.0, "s", "window X before the boundary (the motion fit), at most", lo=5, hi=86_400
    )
    min_window_x_s: float = param(
        240.0,
        "s",
        "shortest X: X starts after the observer's last maneuver or gap, if not shorter",
        lo=5,
        hi=86_400,
    )
    window_y_s: float = param(
        240.0, "s", "window Y after the boundary (the longest span tested)", lo=2, hi=86_400
    )
    alpha: float = param(
        4e-5, "", "significance level per boundary and span (z = 4.11)", lo=1e-12, hi=0.5
    )
    glr: bool = param(
        True,
        "",
        "test a bearing-rate change at the boundary by a generalized likelihood ratio, the "
        "motion refitted over X and Y (off: seed 002's AUC of X's and Y's residuals)",
    )
    relative_motion: bool = param(
        True,
        "",
        "fit the target's constant relative velocity on X (off: a quadratic in time)",
    )
    auc_mean: bool = param(
        False, "", "seed 002 eq. 15: test the mean AUC over mean_span_s", source="seed 002 eq. 15"
    )
    mean_span_s: float = param(
        20.0, "s", "span of boundaries averaged by the AUC-mean test", lo=0, hi=3600
    )
    step_s: float = param(2.0, "s", "spacing of the tested boundaries", lo=0.01, hi=600)
    max_gap_s: float = param(
        45.0, "s", "windows holding a longer interval without bearings are skipped", lo=0.1
    )
    y_scales: int = param(
        10,
        "",
        "spans of Y tested (k = this): the GLR's k spans from Y/8 to Y, geometric (240 s, 10: "
        "30, 38, 48, … 190, 240 s), the AUC's 1/k, 2/k, … of Y; short spans report strong "
        "turns sooner",
        lo=1,
        hi=12,
    )
    min_samples: int = param(6, "samples", "fewest samples in X and in Y", lo=4, hi=100_000)
    exclude_observer_turns: bool = param(
        False,
        "",
        "exclude the windows where the observer maneuvers and fit the target's relative motion "
        "(the first version; off: the observer's known positions enter the fit, through its "
        "turns, with a constant-velocity target)",
    )
    observer_dv_ms: float = param(
        1.0,
        "m/s",
        "observer velocity change within 60 s that marks its own maneuver (excluded with "
        "exclude_observer_turns, else counted in the report)",
        lo=0,
        hi=1000,
    )
    windows: str = param(
        "fixed",
        "",
        "fixed: the spans above for every sequence (a shorter one is not tested, and the "
        "report says why); fit: a sequence shorter than X_min + the shortest Y span gets "
        "X = X_min = max(30 s, 0.4 x its duration) and Y = max(16 s, 0.4 x its duration) "
        "(not sound on real harbour sequences of 1-2 min: docs/evaluation.md)",
        choices=("fixed", "fit"),
    )

    @property
    def z_crit(self) -> float:
        from statistics import NormalDist  # scipy.stats is slow to import

        return float(NormalDist().inv_cdf(1.0 - self.alpha / 2.0))


@dataclass(frozen=True)
class BearingLineParams(Params):
    """How the bearing lines are drawn from the observer (a drawing setting, not the
    detector's: the Bearing-only dock's length box is made from this field's range and
    unit). A bearing layer keeps the length it is drawn with (``meta["length_m"]``)."""

    length_m: float = param(
        0.0,
        "m",
        "length of each bearing line from the observer (0: from the data: past the targets' "
        "ranges when known, else the scene's scale, 300 m to 20 km)",
        lo=0.0,
        hi=20_000.0,
    )


def auc_windows(values: np.ndarray, m: np.ndarray | int) -> np.ndarray:
    """AUC of the first ``m`` columns against the rest, for every row (ranks, ties ½).

    ``m`` may differ per row; NaN columns (padding) are left out."""
    values = np.where(np.isnan(values), np.inf, values)
    n_valid = np.isfinite(values).sum(axis=1)
    m = np.broadcast_to(np.asarray(m), (values.shape[0],))
    from scipy.stats import rankdata  # lazy: scipy.stats is slow to import

    ranks = rankdata(values, axis=1)
    in_x = np.arange(values.shape[1])[None, :] < m[:, None]
    n = n_valid - m
    return (np.where(in_x, ranks, 0.0).sum(axis=1) - m * (m + 1) / 2.0) / (m * n)


# --------------------------------------------------------------------------------------
# windows


@dataclass
class Windows:
    """Candidate boundaries of one sequence and why some are not tested."""

    k: np.ndarray  # boundary sample index (first sample of Y)
    xs: np.ndarray  # first sample of X
    ye: np.ndarray  # one past the last sample of Y (Y stops at a gap or observer maneuver)
    reason: np.ndarray  # "" when tested, else one of EXCLUSION_REASONS
    too_short: str = ""  # why there is no window at all
    y_cover: np.ndarray = field(default_factory=lambda: np.zeros(0))  # s of Y with data


#: ``windows="fit"``: a sequence shorter than the windows gets X = X_min = FIT_X of its
#: duration (at least FIT_X_MIN_S) and Y = FIT_Y of it (at least FIT_Y_MIN_S).
FIT_X, FIT_Y = 0.4, 0.4
FIT_X_MIN_S, FIT_Y_MIN_S = 30.0, 16.0


def windows_for(params: BearingParams, t: np.ndarray) -> BearingParams:
    """The windows used on a sequence of times ``t`` (s): ``params`` itself, or with
    ``windows="fit"`` and a sequence shorter than X_min + the shortest Y span, X, X_min and
    Y shrunk to it (:data:`FIT_X`, :data:`FIT_Y` of its duration, floors
    :data:`FIT_X_MIN_S`, :data:`FIT_Y_MIN_S`); the result has ``windows="fixed"``."""
    if params.windows != "fit" or len(t) < 2:
        return params
    duration = float(t[-1] - t[0])
    x_min = min(float(params.min_window_x_s), float(params.window_x_s))
    if duration >= x_min + float(y_spans(params)[0]):
        return params.replace(windows="fixed")
    x = max(FIT_X_MIN_S, FIT_X * duration)
    y = max(FIT_Y_MIN_S, FIT_Y * duration)
    return params.replace(window_x_s=x, min_window_x_s=x, window_y_s=y, windows="fixed")


def y_spans(params: BearingParams) -> np.ndarray:
    """The spans of Y tested (s), shortest first: the GLR takes ``y_scales`` spans spaced
    geometrically from ``window_y_s``/8 to ``window_y_s``, the AUC takes 1/k, 2/k, … of it (eq. 15: all of it)."""
    k, y = int(params.y_scales), float(params.window_y_s)
    if params.glr:
        return y * (1.0 / 8.0) ** (np.arange(k - 1, -1, -1.0) / max(k - 1, 1))
    if params.auc_mean:
        return np.array([y])
    return y * np.arange(1, k + 1) / k


def _windows(t: np.ndarray, params: BearingParams, excluded: np.ndarray | None = None) -> Windows:
    """Boundaries every ``step_s`` from ``min_window_x_s`` after the start to the shortest
    Y span before the end. X reaches back ``window_x_s`` but starts after the observer's
    last maneuvering sample and the last gap; Y stops before the next ones. A boundary is
    skipped when its shortest Y span is cut so, when X is shorter than ``min_window_x_s``,
    or when a window has too few samples."""
    x_s, x_min, y_s = (
        float(params.window_x_s),
        float(params.min_window_x_s),
        float(params.window_y_s),
    )
    y_min = float(y_spans(params)[0])
    x_min = min(x_min, x_s)
    empty = np.zeros(0, dtype=int)
    if len(t) < 2 or t[-1] - t[0] < x_min + y_min:
        span = t[-1] - t[0] if len(t) else 0.0
        return Windows(
            empty,
            empty,
            empty,
            np.zeros(0, dtype=object),
            f"series too short for the windows: {len(t)} samples over {span:.0f} s "
            f"< X + Y = {x_min:.0f} + {y_min:.0f} s"
            + (
                " (windows=fit shrinks them to a short series; on real camera sequences of "
                "1-2 min most of its detections were not maneuvers: docs/evaluation.md)"
                if x_min > FIT_X_MIN_S
                else ""
            ),
        )
    n = len(t)
    tol = float(np.median(np.diff(t)))
    grid = np.arange(t[0] + x_min, t[-1] - y_min + 1e-9, float(params.step_s))
    k = np.unique(np.searchsorted(t, grid))
    k = k[(k > 0) & (k < n)]
    k = k[t[k] + y_min <= t[-1] + tol]
    tk = t[k]
    idx = np.arange(n)
    gap_after = np.append(np.diff(t) > params.max_gap_s, False)  # gap between i and i+1
    excl = excluded if excluded is not None else np.zeros(n, dtype=bool)
    # first sample after the last gap / observer-maneuvering sample at or before i
    after_gap = np.maximum.accumulate(np.where(gap_after, idx + 1, 0))
    after_excl = np.maximum.accumulate(np.where(excl, idx + 1, 0))
    # the next gap / maneuvering sample at or after i (n: none)
    next_gap = np.minimum.accumulate(np.where(gap_after, idx, n)[::-1])[::-1]
    next_excl = np.minimum.accumulate(np.where(excl, idx, n)[::-1])[::-1]
    xs_full = np.maximum(np.searchsorted(t, tk - x_s), 0)
    xs = np.maximum.reduce([xs_full, after_gap[k - 1], after_excl[k - 1]])
    ye_full = np.searchsorted(t, tk + y_s)
    ye_gap = np.minimum(next_gap[k] + 1, n)
    ye_exc = next_excl[k]
    ye = np.minimum.reduce([ye_full, ye_gap, ye_exc])
    cover = np.where(ye > k, t[np.maximum(ye - 1, 0)] - tk, 0.0)
    cover = np.where((ye == ye_full) & (ye_full < n), y_s, cover + tol)
    reason = np.full(len(k), "", dtype=object)
    short_x = (tk - t[np.minimum(xs, n - 1)]) < x_min - max(tol, 0)
    cut = cover < y_min - 1e-9
    x_gap = short_x & (after_gap[k - 1] >= after_excl[k - 1]) & (xs > xs_full)
    reason[(cut & (ye == ye_gap) & (ye < ye_exc)) | x_gap] = "gap"
    x_exc = short_x & (after_excl[k - 1] > after_gap[k - 1]) & (xs > xs_full)
    reason[(reason == "") & ((cut & (ye == ye_exc)) | x_exc)] = "observer_maneuvering"
    few = ((k - xs) < params.min_samples) | ((ye - k) < params.min_samples) | short_x | cut
    reason[(reason == "") & few] = "sparse"
    return Windows(k, xs, ye, reason, "", cover)


def _padded(t, u, k, xs, ye, x_s):
    """Per boundary: τ (units of X), bearings relative to the last X sample, masks."""
    length = int((ye - xs).max())
    idx = xs[:, None] + np.arange(length)[None, :]
    valid = idx < ye[:, None]
    idx = np.minimum(idx, len(t) - 1)
    tau = (t[idx] - t[k][:, None]) / x_s
    ref = u[np.maximum(k - 1, 0)]
    w = u[idx] - ref[:, None]
    in_x = idx < k[:, None]
    return tau, w, valid & in_x, valid & ~in_x, idx


def _observer_frame(obs, u, k, idx, x_s):
    """The observer's displacement from its position at X's last sample, along and across
    that sample's bearing (units of ``OBS_UNIT_M``), per boundary and padded sample, and
    its velocity along the bearing there (``OBS_UNIT_M`` per X span, over the last 5 s)."""
    ox, oy, t = obs
    ref = np.maximum(k - 1, 0)
    dx = (ox[idx] - ox[ref][:, None]) / OBS_UNIT_M
    dy = (oy[idx] - oy[ref][:, None]) / OBS_UNIT_M
    sa, ca = np.sin(u[ref])[:, None], np.cos(u[ref])[:, None]
    back = np.minimum(np.searchsorted(t, t[ref] - 5.0, side="right") - 1, ref - 1)
    back = np.maximum(back, 0)
    dt = np.maximum(t[ref] - t[back], 1e-9) / x_s
    vx, vy = (ox[ref] - ox[back]) / OBS_UNIT_M / dt, (oy[ref] - oy[back]) / OBS_UNIT_M / dt
    return dx * sa + dy * ca, dx * ca - dy * sa, vx * sa[:, 0] + vy * ca[:, 0]


def _solve(gram: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    ridge = 1e-9 * (np.trace(gram, axis1=1, axis2=2)[:, None, None] + 1e-12)
    return np.linalg.solve(gram + ridge * np.eye(gram.shape[1]), rhs[..., None])[..., 0]


def _gram(cols: list[np.ndarray], mask: np.ndarray) -> np.ndarray:
    """JᵀJ over the masked samples, per boundary, from J's columns (each (B, L))."""
    q = len(cols)
    masked = [np.where(mask, c, 0.0) for c in cols]
    gram = np.empty((mask.shape[0], q, q))
    for i in range(q):  # q ≤ 3 columns: a handful of row-wise dot products
        for j in range(i, q):
            gram[:, i, j] = gram[:, j, i] = np.einsum("bl,bl->b", masked[i], cols[j])
    return gram


def _rhs(cols: list[np.ndarray], mask: np.ndarray, y: np.ndarray) -> np.ndarray:
    ym = np.where(mask, y, 0.0)
    return np.stack([np.einsum("bl,bl->b", ym, c) for c in cols], axis=1)


def _fit_poly(tau, w, mx, order=2):
    """Least-squares polynomial in τ on X: fitted curve, columns, XᵀX and coefficients."""
    cols = [np.ones_like(tau)] + [tau**p for p in range(1, order + 1)]
    gram = _gram(cols, mx)
    coef = _solve(gram, _rhs(cols, mx, w))
    return sum(c * coef[:, i : i + 1] for i, c in enumerate(cols)), cols, gram, coef


def _fit_relative(tau, w, mx, y_over_x, polish=1, obs=None, mall=None):
    """Fit of β(τ) = atan2(p + q τ − s·d_c, 1 + r τ − s·d_a) on X (bearings relative to X's
    last sample, whose line of sight is the frame). Without ``obs`` (d = 0): a constant
    relative velocity (p ≈ bearing offset, q = cross-bearing and r = range rate over range,
    per X span). With ``obs`` = (d_a, d_c), the observer's displacement along and across
    the line of sight (units of ``OBS_UNIT_M``): a constant-velocity target seen from the
    observer's known positions, (q, r) its own velocity over range and s = OBS_UNIT_M /
    range; on a steady leg s trades off exactly against (q, r) and a weak prior s ~ 0 makes
    it the relative-motion fit, while an observer maneuver makes s (the range) observable.
    Pseudo-linear least squares — tan β (1 + r τ − s d_a) = p + q τ − s d_c is linear in
    p, q, r, s; the regressors holding tan β take the quadratic fit's smooth bearings (an
    instrument: the noisy ones bias r and s) — then ``polish`` Gauss–Newton steps. Returns
    the fitted curve, the Jacobian's columns, JᵀJ on X (with the priors), the parameters
    and the priors' weights. ``mall``: the samples of X and Y (the observer model keeps
    the observer's displacement over them below ``RANGE_FLOOR`` of the range)."""
    lo, hi = -RANGE_FLOOR / y_over_x, RANGE_FLOOR  # the range stays > 1 - RANGE_FLOOR of now
    tan = np.tan(np.clip(w, -1.4, 1.4))
    smooth = np.tan(np.clip(_fit_poly(tau, w, mx)[0], -1.4, 1.4))
    cols = [np.ones_like(tau), tau, -tau * smooth]
    # r is unobservable when the bearing hardly moves (a target running along the line of
    # sight): a weak prior r ~ 0 keeps it from bending the curve to fit X's noise
    n_x = mx.sum(axis=1).mean()
    q = 3 if obs is None else 4
    prior = np.zeros((mx.shape[0], q, q))
    prior[:, 2, 2] = R_PRIOR * n_x
    if obs is not None:
        # the prior r ~ 0 acts on the relative range rate r − s·v_a (v_a: the observer's
        # velocity along the line of sight), so on a steady leg it is today's prior and the
        # exact trade-off between s and (q, r) is settled by the weak prior s ~ 0 alone
        da, dc, va = obs
        cols.append(smooth * da - dc)
        a = np.zeros((mx.shape[0], q))
        a[:, 2], a[:, 3] = 1.0, -va
        prior = R_PRIOR * n_x * a[:, :, None] * a[:, None, :]
        prior[:, 3, 3] += S_PRIOR * n_x
    if q > 3:  # the observer stays nearer than RANGE_FLOOR of the range over X and Y
        reach = np.sqrt(np.where(mall, da * da + dc * dc, 0.0)).max(axis=1)
        s_max = np.minimum(RANGE_FLOOR / np.maximum(reach, 1e-12), S_MAX)

    def clip(theta, rows=slice(None)):
        theta[:, 2] = np.clip(theta[:, 2], lo, hi)
        if q > 3:
            theta[:, 3] = np.clip(theta[:, 3], 0.0, s_max[rows])
        return theta

    def curve(theta):
        num = theta[:, 0:1] + theta[:, 1:2] * tau
        den = 1.0 + theta[:, 2:3] * tau
        if q > 3:
            num = num - theta[:, 3:4] * dc
            den = den - theta[:, 3:4] * da
        d = num * num + den * den
        j0 = den / d
        jac = [j0, tau * j0, -num * tau / d]
        if q > 3:
            jac.append((num * da - den * dc) / d)
        return np.arctan2(num, den), jac

    theta = clip(_solve(_gram(cols, mx) + prior, _rhs(cols, mx, tan)))
    if q == 3:  # today's relative-motion fit, unchanged
        f, jac = curve(theta)
        for _ in range(polish):
            g = _rhs(jac, mx, w - f) - np.einsum("bij,bj->bi", prior, theta)
            theta = clip(theta + _solve(_gram(jac, mx) + prior, g))
            f, jac = curve(theta)
        return f, jac, _gram(jac, mx) + prior, theta, prior

    lx = int(mx.any(axis=0).nonzero()[0].max()) + 1 if mx.any() else 1  # X's columns

    def cost(th, rows):  # X's residual sum of squares plus the prior, for some rows
        tr = tau[rows, :lx]
        num = th[:, 0:1] + th[:, 1:2] * tr - th[:, 3:4] * dc[rows, :lx]
        den = 1.0 + th[:, 2:3] * tr - th[:, 3:4] * da[rows, :lx]
        res = np.where(mx[rows, :lx], w[rows, :lx] - np.arctan2(num, den), 0.0)
        return (res**2).sum(axis=1) + np.einsum("bi,bij,bj->b", th, prior[rows], th)

    # Start from the better of today's relative-motion fit (s = 0) and the pseudo-linear
    # solution with s; a Gauss–Newton step is halved (twice at most) where X's cost would
    # rise, else the parameters stay, so the fit is never worse on X than the
    # relative-motion one.
    every = np.arange(len(theta))
    rel = np.concatenate(
        [_solve(_gram(cols[:3], mx) + prior[:, :3, :3], _rhs(cols[:3], mx, tan)), 0 * tan[:, :1]],
        axis=1,
    )
    rel = clip(rel)
    c_rel, c_new = cost(rel, every), cost(theta, every)
    theta = np.where((c_new < c_rel)[:, None], theta, rel)
    best = np.minimum(c_new, c_rel)
    f, jac = curve(theta)
    for _ in range(polish):
        g = _rhs(jac, mx, w - f) - np.einsum("bij,bj->bi", prior, theta)
        gram = _gram(jac, mx) + prior
        step = _solve(gram, g)
        # where s would go below 0 (the range beyond infinity), step with s held at 0
        held = np.concatenate([_solve(gram[:, :3, :3], g[:, :3]), 0 * g[:, :1]], axis=1)
        step = np.where((theta[:, 3] + step[:, 3] < 0)[:, None], held, step)
        rows = every
        for damp in (1.0, 0.5, 0.25):
            cand = clip(theta[rows] + damp * step[rows], rows)
            c = cost(cand, rows)
            take = c <= best[rows] * (1.0 + 1e-9)  # at the optimum the step is ~0
            theta[rows[take]], best[rows[take]] = cand[take], c[take]
            rows = rows[~take]
            if len(rows) == 0:
                break
        f, jac = curve(theta)
    return f, jac, _gram(jac, mx) + prior, theta, prior

    def cost(theta):
        f = curve(theta)[0]
        return (np.where(mx, w - f, 0.0) ** 2).sum(axis=1) + np.einsum(
            "bi,bij,bj->b", theta, prior, theta
        )

    # Start from the better of today's relative-motion fit (s = 0) and the pseudo-linear
    # solution with s; every Gauss–Newton step is halved until X's cost drops (else the
    # parameters stay), so the fit is never worse on X than the relative-motion one.
    rel = clip(
        np.concatenate(
            [
                _solve(_gram(cols[:3], mx) + prior[:, :3, :3], _rhs(cols[:3], mx, tan)),
                0 * tan[:, :1],
            ],
            axis=1,
        )
    )
    c_rel, c_new = cost(rel), cost(theta)
    theta = np.where((c_new < c_rel)[:, None], theta, rel)
    best = np.minimum(c_new, c_rel)
    f, jac = curve(theta)
    for _ in range(polish):
        g = _rhs(jac, mx, w - f) - np.einsum("bij,bj->bi", prior, theta)
        step = _solve(_gram(jac, mx) + prior, g)
        done = np.zeros(len(best), dtype=bool)
        new = theta.copy()
        for damp in (1.0, 0.5, 0.25):
            cand = clip(theta + damp * step)
            c = cost(cand)
            take = ~done & (c < best)
            new[take], best[take] = cand[take], c[take]
            done |= take
        theta = new
        f, jac = curve(theta)
    return f, jac, _gram(jac, mx) + prior, theta, prior


@dataclass
class Statistic:
    """Per tested boundary: time (s), z, AUC, its null sd, X's residual rms (deg), fit."""

    boundary_t: np.ndarray
    detect_t: np.ndarray  # last sample of the shortest rejecting Y span (else the longest)
    x_start_t: np.ndarray
    z: np.ndarray
    auc: np.ndarray  # AUC test only (NaN for the GLR)
    sd: np.ndarray
    rms_deg: np.ndarray
    coef: np.ndarray  # (p, q, r, s) per X span (see _fit_relative; s = 0 without the
    # observer's positions), or the quadratic's
    windows: Windows = field(repr=False)
    t: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    u: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)  # unwrapped, rad
    params: "BearingParams | None" = field(default=None, repr=False)
    # GLR: smallest bearing-rate change (rad/s) reaching z_crit over the longest Y span
    min_rate: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    z_peak: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)  # max |z|
    # the observer's positions (x, y, m) when they enter the fit, else None
    observer: "tuple[np.ndarray, np.ndarray] | None" = field(default=None, repr=False)
    # per boundary: X's fit pins the range down (s known to 30 %: the observer maneuvered)
    range_known: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool), repr=False)
    # per boundary and Y span (shortest first): |z| (0 where the span is not tested) and
    # the time of the span's last sample
    z_span: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)), repr=False)
    y_end_span: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)), repr=False)


def observer_xy(obs_lon: np.ndarray, obs_lat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The observer's positions in local metres (east, north)."""
    return geo.to_local(obs_lon, obs_lat, *geo.centre_deg(obs_lon, obs_lat))


def models_observer(params: BearingParams, observer) -> bool:
    """True when the observer's positions enter the motion fit (given, moving, and the
    relative-motion model without the exclusion option)."""
    if observer is None or params.exclude_observer_turns or not params.relative_motion:
        return False
    ox, oy = observer
    return bool(len(ox) and np.isfinite(ox).all() and np.isfinite(oy).all()) and bool(
        np.ptp(ox) + np.ptp(oy) > 1.0
    )


def statistic(
    t: np.ndarray,
    bearing_deg: np.ndarray,
    params: BearingParams,
    excluded: np.ndarray | None = None,
    sigma_deg: float | None = None,
    observer: tuple[np.ndarray, np.ndarray] | None = None,
) -> Statistic:
    """z (and its parts) for every tested boundary; see the module docstring.

    ``sigma_deg`` replaces the noise estimated from X's residuals (GLR): with noise-free
    bearings it gives the expected z of a maneuver (what the geometry lets be seen).
    ``observer``: its positions (x, y in m, one per bearing): a moving observer's motion
    then enters the fit and its turns are not excluded (unless
    ``exclude_observer_turns``, when ``excluded`` marks them)."""
    params = windows_for(params, np.asarray(t, dtype=float))
    use_obs = models_observer(params, observer)
    if use_obs:
        observer = (np.asarray(observer[0], float), np.asarray(observer[1], float))
    win = _windows(t, params, None if use_obs else excluded)
    ok = win.reason == ""
    k, xs, ye, cover = win.k[ok], win.xs[ok], win.ye[ok], win.y_cover[ok]
    nb = len(k)
    keys = ("boundary_t", "detect_t", "x_start_t", "z", "auc", "sd", "rms", "min_rate", "z_peak")
    out = {key: np.zeros(nb) for key in keys}
    coef = np.zeros((nb, 4))
    known = np.zeros(nb, dtype=bool)
    spans = y_spans(params)
    z_span = np.zeros((nb, len(spans)))
    y_end_span = np.zeros((nb, len(spans)))
    obs_kept = observer if use_obs else None
    if nb == 0:
        return Statistic(
            *(out[c] for c in keys[:7]),
            coef,
            win,
            t,
            np.zeros(0),
            params,
            *keys_after(out),
            obs_kept,
            known,
            z_span,
            y_end_span,
        )
    u = np.unwrap(np.radians(bearing_deg))
    x_s = float(params.window_x_s)
    if use_obs:  # boundaries whose Y holds an observer maneuver
        man = excluded if excluded is not None else _maneuvering_xy(t, *observer, 1.0)
        cm = np.concatenate([[0], np.cumsum(man)])
        y_man = cm[ye] > cm[k]
    chunk = max(1, int(1.5e6 // max(int((ye - xs).max()), 1)))
    for a in range(0, nb, chunk):  # blocks of boundaries bound the memory, not a per-window loop
        sl = slice(a, a + chunk)
        tau, w, mx, my, idx = _padded(t, u, k[sl], xs[sl], ye[sl], x_s)
        prior = None
        if params.relative_motion:
            obs = _observer_frame((*observer, t), u, k[sl], idx, x_s) if use_obs else None
            f, jac, gram, c, prior = _fit_relative(tau, w, mx, spans[-1] / x_s, 1, obs, mx | my)
            lin = c
        else:
            f, jac, gram, c = _fit_poly(tau, w, mx)
            lin = c
        m = mx.sum(axis=1)
        resid = w - f
        dof = np.maximum(m - c.shape[1] + (1 if use_obs else 0), 1)
        rms = np.sqrt((np.where(mx, resid, 0.0) ** 2).sum(axis=1) / dof)
        sigma = np.full(len(m), math.radians(sigma_deg)) if sigma_deg else np.maximum(rms, 1e-9)
        if use_obs:  # s to 30 % (1 sd): X's fit sees the range
            ridge = 1e-9 * (np.trace(gram, axis1=1, axis2=2)[:, None, None] + 1e-12)
            var_s = np.linalg.inv(gram + ridge * np.eye(4))[:, 3, 3]
            known[sl] = sigma * np.sqrt(np.maximum(var_s, 0.0)) < 0.3 * c[:, 3]
            # Where X leaves the range open and the observer maneuvers within Y, the GLR's
            # one step from X's fit would meet the maneuver's effect, nonlinear in s, far
            # from X's s: linearize there about the fit over X and the whole Y instead.
            r = np.flatnonzero(y_man[sl] & ~known[sl])
            if len(r):
                sub = tuple(o[r] for o in obs)
                f_r, jac_r, _, lin_r, _ = _fit_relative(
                    tau[r], w[r], mx[r] | my[r], spans[-1] / x_s, 1, sub, mx[r] | my[r]
                )
                f[r], lin = f_r, lin.copy()
                lin[r] = lin_r
                for col, col_r in zip(jac, jac_r, strict=True):
                    col[r] = col_r
        best_z = np.zeros(len(m))
        best_t = np.full(len(m), np.inf)
        full_t = t[k[sl]]
        last = np.full(len(m), False)
        n_span = np.stack([(my & (tau * x_s < span - 1e-9)).sum(axis=1) for span in spans], 1)
        if params.glr:
            resid = w - f
            z_all, rate_all = _glr(
                tau, resid, mx, my, n_span, jac, lin, prior, sigma, params.z_crit
            )
        for si in range(len(spans) - 1, -1, -1):  # nested Y spans: shorter ones react sooner
            span, n = spans[si], n_span[:, si]
            valid = (cover[sl] >= span - 1e-9) & (n >= params.min_samples)
            y_end = t[np.minimum(k[sl] + n - 1, len(t) - 1)]
            if params.glr:
                z, min_rate = z_all[:, si], rate_all[:, si]
            else:
                myf = my & (tau * x_s < span - 1e-9)
                z, auc, sd = _auc_z(resid, mx, myf, m, n, jac, gram)
            z = np.where(valid, z, 0.0)
            first = valid & ~last  # the longest valid span of each boundary
            full_t = np.where(first, y_end, full_t)
            if params.glr:
                out["min_rate"][sl] = np.where(first, min_rate / x_s, out["min_rate"][sl])
                out["auc"][sl] = np.nan
            else:
                out["auc"][sl] = np.where(first, auc, out["auc"][sl])
                out["sd"][sl] = np.where(first, sd, out["sd"][sl])
            last |= valid
            out["z_peak"][sl] = np.maximum(out["z_peak"][sl], np.abs(z))
            z_span[sl, si], y_end_span[sl, si] = np.abs(z), y_end
            hit = np.abs(z) > params.z_crit
            best_t = np.where(hit, y_end, best_t)  # shortest rejecting span wins
            best_z = np.where(hit | (first & (best_z == 0)), z, best_z)
        out["z"][sl] = best_z
        out["detect_t"][sl] = np.where(np.isfinite(best_t), best_t, full_t)
        out["rms"][sl] = np.degrees(rms)
        coef[sl, : c.shape[1]] = c
    out["boundary_t"], out["x_start_t"] = t[k], t[xs]
    if params.auc_mean and not params.glr:
        out["z"] = _auc_mean_z(out["boundary_t"], out["auc"], out["sd"], params.mean_span_s)
    return Statistic(
        *(out[c] for c in keys[:7]),
        coef,
        win,
        t,
        u,
        params,
        *keys_after(out),
        obs_kept,
        known,
        z_span,
        y_end_span,
    )


def keys_after(out: dict) -> tuple[np.ndarray, np.ndarray]:
    return out["min_rate"], out["z_peak"]


def _glr(tau, resid, mx, my, n_span, jac, theta, prior, sigma, z_crit):
    """GLR z of a bearing-rate change at the boundary for every Y span (columns of
    ``n_span``: Y samples in the span): a ramp max(τ, 0) added to the motion model and
    fitted with it over X and the span (one Gauss–Newton step from X's fit). Sums over
    the span come from cumulative sums along the samples, so all spans cost one pass.
    ``prior``: the motion parameters' prior weights (or None). Also the smallest ramp
    slope (rad per X span) reaching ``z_crit``."""
    cols = [*jac, np.maximum(tau, 0.0)]
    q = len(cols)
    m = mx.sum(axis=1)
    end = np.maximum(m[:, None] + n_span - 1, 0)  # (B, S): last column of X + span
    gram = np.empty((*end.shape, q, q))
    g = np.empty((*end.shape, q))
    mall = mx | my
    for i in range(q):  # q ≤ 5 columns: a handful of cumulative sums over (B, L)
        ci = np.where(mall, cols[i], 0.0)
        for j in range(i, q):
            cs = np.take_along_axis(np.cumsum(ci * cols[j], axis=1), end, axis=1)
            gram[..., i, j] = gram[..., j, i] = cs
        g[..., i] = np.take_along_axis(np.cumsum(ci * resid, axis=1), end, axis=1)
    if prior is not None:  # (B, q−1, q−1): the motion parameters' prior
        nq = prior.shape[1]
        gram[..., :nq, :nq] += prior[:, None]
        g[..., :nq] -= np.einsum("bij,bj->bi", prior, theta)[:, None, :]
    ridge = 1e-9 * (np.trace(gram, axis1=-2, axis2=-1)[..., None, None] + 1e-12)
    inv = np.linalg.inv(gram + ridge * np.eye(q))
    slope = np.einsum("bsj,bsj->bs", inv[..., -1, :], g)
    se = sigma[:, None] * np.sqrt(np.maximum(inv[..., -1, -1], 1e-300))
    return slope / se, z_crit * se


def _auc_z(resid, mx, myf, m, n, jac, gram):
    """Seed 002's AUC of X's against Y's residuals, its null sd with the fit's
    extrapolation (module docstring) and z."""
    r = np.where(mx | myf, resid, np.nan)
    hbar = np.stack([np.where(myf, c, 0.0).sum(axis=1) for c in jac], axis=1)
    hbar /= np.maximum(n, 1)[:, None]
    lever = np.einsum("bj,bj->b", hbar, _solve(gram, hbar))
    var = (m + n + 1) / (12.0 * m * np.maximum(n, 1)) + lever / (4.0 * math.pi)
    auc = auc_windows(r, m)
    sd = np.sqrt(var)
    return (auc - 0.5) / sd, auc, sd


def _auc_mean_z(bt: np.ndarray, auc: np.ndarray, sd: np.ndarray, span_s: float) -> np.ndarray:
    """Seed 002 eq. 15: |mean of the last N AUCs − ½| / (σ/√N), N the boundaries within
    ``span_s`` before each one (causal)."""
    start = np.searchsorted(bt, bt - span_s)
    ca = np.concatenate([[0.0], np.cumsum(auc)])
    cs = np.concatenate([[0.0], np.cumsum(sd)])
    end = np.arange(1, len(bt) + 1)
    n = end - start
    mean = (ca[end] - ca[start]) / n
    sigma = (cs[end] - cs[start]) / n
    return (mean - 0.5) / (sigma / np.sqrt(n))


def auc_statistic(
    t: np.ndarray,
    bearing_deg: np.ndarray,
    params: BearingParams | None = None,
    obs_lon: np.ndarray | None = None,
    obs_lat: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Boundary times (s) and z for every tested boundary (for plots), with the
    observer's positions when given (as :func:`detect_with_report` takes them)."""
    params = (params or BearingParams()).checked()
    excluded = xy = None
    if obs_lon is not None and obs_lat is not None:
        obs_lon, obs_lat = np.asarray(obs_lon, float), np.asarray(obs_lat, float)
        if np.isfinite(obs_lon).all() and np.isfinite(obs_lat).all():
            excluded = observer_maneuvering(t, obs_lon, obs_lat, params.observer_dv_ms)
            xy = observer_xy(obs_lon, obs_lat)
    st = statistic(t, bearing_deg, params, excluded, observer=xy)
    return st.boundary_t, st.z


@dataclass(frozen=True)
class Detection:
    detect_time_s: float
    maneuver_time_s: float
    z: float


def detections_from(st: Statistic, z_crit: float) -> list[Detection]:
    """One detection per run of rejecting boundaries (a skipped boundary ends a run)."""
    if len(st.z) == 0:
        return []
    reject = np.abs(st.z) > z_crit
    if not reject.any():
        return []
    # consecutive tested boundaries: a skipped boundary breaks a run
    pos = np.flatnonzero(st.windows.reason == "")
    brk = np.concatenate([[True], np.diff(pos) > 1])
    prev = np.concatenate([[False], reject[:-1]])
    starts = np.flatnonzero(reject & (brk | ~prev))
    stops = np.flatnonzero(~reject | brk)
    ends = np.append(stops, len(reject))[np.searchsorted(stops, starts, side="right")]
    out: list[Detection] = []
    for a, b in zip(starts, ends, strict=True):  # one entry per detection, not per sample
        if out:
            # A window X that still holds the last detected maneuver misfits its trend:
            # those rejections are the same maneuver, not a new one.
            clear = np.flatnonzero(st.x_start_t[a:b] > out[-1].maneuver_time_s)
            if len(clear) == 0:
                # ... but if one of its short spans rejected before the detection's own
                # (a run that started early, on long Y spans), the alarm came then: the
                # detection takes that time and that boundary's maneuver time (causal)
                hit = a + np.flatnonzero(np.abs(st.z[a:b]) > z_crit)
                j = int(hit[np.argmin(st.detect_t[hit])])
                if st.detect_t[j] < out[-1].detect_time_s:
                    when = maneuver_time(st, j) if len(st.u) else float(st.boundary_t[j])
                    z = max(out[-1].z, float(st.z[j]), key=abs)
                    out[-1] = Detection(float(st.detect_t[j]), when, z)
                continue
            a = a + int(clear[0])
        kk = a + int(np.argmax(np.abs(st.z[a:b])))
        when = maneuver_time(st, a) if len(st.u) else float(st.boundary_t[kk])
        first = float(st.detect_t[a:b][np.abs(st.z[a:b]) > z_crit].min())
        out.append(Detection(first, when, float(st.z[kk])))
    return out


def maneuver_time(st: Statistic, i: int) -> float:
    """Estimated turn time (s) for a detection at tested boundary ``i``: X's motion fit
    plus a bearing-rate change (a ramp) starting at t_c, the t_c over the last 2·Y' of the
    samples up to the detection (Y' = detection − boundary) that explains most of the
    residuals (causal). (The largest |z| of the run, seed 002's estimate, comes late here:
    once X holds the turn its misfit keeps |z| growing.)"""
    p = st.params
    pos = np.flatnonzero(st.windows.reason == "")[i]
    k, xs = st.windows.k[pos : pos + 1], st.windows.xs[pos : pos + 1]
    ye = np.minimum(st.windows.ye[pos : pos + 1], np.searchsorted(st.t, st.detect_t[i], "right"))
    ye = np.maximum(ye, k + 1)
    tau, w, mx, my, idx = _padded(st.t, st.u, k, xs, ye, float(p.window_x_s))
    if p.relative_motion:
        obs = None
        if st.observer is not None:
            obs = _observer_frame((*st.observer, st.t), st.u, k, idx, float(p.window_x_s))
        f = _fit_relative(tau, w, mx, y_spans(p)[-1] / p.window_x_s, 1, obs, mx | my)[0]
    else:
        f = _fit_poly(tau, w, mx)[0]
    tt = st.t[xs[0] : ye[0]]
    r = (w - f)[0][: len(tt)]
    y_eff = max(float(st.detect_t[i] - st.boundary_t[i]), float(y_spans(p)[0]))
    cand = tt[tt >= tt[-1] - 2.0 * y_eff][:-2]
    if len(cand) == 0:
        return float(st.boundary_t[i])
    ramp = np.maximum(tt[None, :] - cand[:, None], 0.0)  # (candidates, samples)
    ramp -= ramp.mean(axis=1, keepdims=True)
    score = (ramp @ r) ** 2 / np.maximum((ramp**2).sum(axis=1), 1e-12)
    return float(cand[int(np.argmax(score))])


def detect_sequence(
    t: np.ndarray,
    bearing_deg: np.ndarray,
    params: BearingParams,
    excluded: np.ndarray | None = None,
    observer: tuple[np.ndarray, np.ndarray] | None = None,
) -> list[Detection]:
    """All detections in one sequence: one per run of rejecting boundaries (``excluded``
    and ``observer`` as in :func:`statistic`)."""
    st = statistic(t, bearing_deg, params, excluded, observer=observer)
    return detections_from(st, params.z_crit)


def observer_maneuvering(
    t: np.ndarray,
    obs_lon: np.ndarray,
    obs_lat: np.ndarray,
    dv_ms: float,
    span_s: float = 60.0,
    lag_s: float = 5.0,
) -> np.ndarray:
    """Samples where the observer's velocity vector changed by more than ``dv_ms`` (m/s)
    within ``span_s`` seconds: its own turns and speed changes. Velocities are taken over
    ``lag_s`` (at least one sample) so position jitter of a slow or docked observer does
    not count."""
    if len(t) < 3 or np.all(np.isnan(obs_lon)):
        return np.zeros(len(t), dtype=bool)
    x, y = geo.to_local(obs_lon, obs_lat, *geo.centre_deg(obs_lon, obs_lat))
    return _maneuvering_xy(t, x, y, dv_ms, span_s, lag_s)


def _maneuvering_xy(t, x, y, dv_ms, span_s=60.0, lag_s=5.0):
    """:func:`observer_maneuvering` on local positions (m)."""
    n = len(t)
    if n < 3:
        return np.zeros(n, dtype=bool)
    back = np.minimum(np.searchsorted(t, t - lag_s, side="right") - 1, np.arange(n) - 1)
    back = np.maximum(back, 0)
    dt = np.maximum(t - t[back], 1e-9)
    vx, vy = (x - x[back]) / dt, (y - y[back]) / dt
    vx[np.arange(n) == back] = np.nan
    vx[t - t[0] < lag_s] = np.nan  # no velocity before a full lag
    first = int(np.argmax(np.isfinite(vx))) if np.isfinite(vx).any() else n - 1
    earlier = np.maximum(np.searchsorted(t, t - span_s), first)  # the first velocity early on
    dv = np.hypot(vx - vx[earlier], vy - vy[earlier])
    return np.isfinite(dv) & (dv > dv_ms)


# --------------------------------------------------------------------------------------
# what the data can show


def min_detectable(st: Statistic, params: BearingParams, observer_static: bool) -> dict:
    """Smallest bearing-rate change (deg/min) and, where the range is known, smallest turn
    (deg) the data can show at its noise and geometry (medians over the tested windows).

    GLR: the rate change whose fitted ramp slope reaches z_crit standard errors over the
    longest Y span (σ from X's residuals, the slope's variance from the fit). AUC: a
    bearing-rate change Δω at the boundary drifts Y's residuals by Δω·Y/2 on average;
    a shift δ between two samples of noise σ gives AUC − ½ = Φ(δ/(σ√2)) − ½, so the
    smallest Δω meets z_crit·sd. With a static observer the fit's relative velocity is
    the target's, over range; with a moving observer whose positions enter the fit, the
    fit's (q, r) are the target's own velocity over range wherever X's fit pins the range
    down (the observer maneuvered within X: ``range_known``). A turn Δc rotates (w_r, w_c)
    and changes the bearing rate by w_r·sin Δc + w_c·(cos Δc − 1); the smallest |Δc|
    reaching Δω is reported. On a moving observer's steady legs the range is unobservable,
    so only Δω is given."""
    if len(st.z) == 0:
        return {"noise_deg": None, "min_rate_change_deg_min": None, "min_turn_deg": None}
    sigma = float(np.median(st.rms_deg))
    if params.glr:
        # z_crit · σ · sd of the fitted ramp slope (rad/s), where Y has its full span
        sel = st.windows.y_cover[st.windows.reason == ""] >= params.window_y_s - 1e-9
        sel = sel if sel.any() else np.ones(len(sel), dtype=bool)
        rate = st.min_rate
    else:
        need = params.z_crit * st.sd
        frac = np.clip(0.5 + need, None, 1 - 1e-12)
        sel = np.ones(len(need), dtype=bool)
        from scipy.stats import norm  # lazy: scipy.stats is slow to import

        delta = np.radians(sigma) * math.sqrt(2.0) * norm.ppf(frac)
        rate = np.where(need < 0.5, delta / (params.window_y_s / 2.0), np.inf)  # rad/s
    out = {
        "noise_deg": round(sigma, 4),
        "min_rate_change_deg_min": _finite(np.degrees(np.median(rate[sel])) * 60.0),
        "min_turn_deg": None,
    }
    if not params.relative_motion:
        return out
    if not observer_static:
        if st.observer is None or len(st.range_known) != len(sel):
            return out
        sel = sel & st.range_known
        if not sel.any():
            return out
    turns = np.radians(np.arange(1.0, 181.0))
    coef = st.coef[sel]
    wc, wr = coef[:, 1:2] / params.window_x_s, coef[:, 2:3] / params.window_x_s
    wc = wc / (1.0 + coef[:, 0:1] ** 2)  # bearing rate at the boundary
    change = np.maximum(
        np.abs(wr * np.sin(turns) + wc * (np.cos(turns) - 1)),
        np.abs(-wr * np.sin(turns) + wc * (np.cos(turns) - 1)),
    )
    ok = change >= rate[sel][:, None]
    first = np.where(ok.any(axis=1), np.argmax(ok, axis=1) + 1.0, np.inf)
    out["min_turn_deg"] = _finite(np.median(first))
    return out


def _finite(x: float) -> float | None:
    return round(float(x), 3) if math.isfinite(x) else None


# --------------------------------------------------------------------------------------
# tables


def detect_with_report(
    bearings: pd.DataFrame, params: BearingParams | None = None
) -> tuple[pd.DataFrame, list[dict]]:
    """Detections for every batch (``batch, detect_time, maneuver_time, z``) and, per
    batch, what was tested and why windows were skipped."""
    table, report, _ = detect_with_statistic(bearings, params)
    return table, report


def detect_with_statistic(
    bearings: pd.DataFrame, params: BearingParams | None = None
) -> tuple[pd.DataFrame, list[dict], pd.DataFrame]:
    """:func:`detect_with_report`'s detections and report, and the statistic they came
    from: per tested boundary of every batch, ``batch``, ``boundary_s`` (s since 1970)
    and ``z`` (the Detail panel's curve, not computed again)."""
    params = (params or BearingParams()).checked()
    rows, report = [], []
    stat_batch, stat_t, stat_z = [], [], []
    for batch, g in bearings.groupby("batch", sort=True):  # one pass per target
        g = g.sort_values("time", kind="stable")
        t = time_seconds(g["time"])
        left_out = 0
        if np.any(np.diff(t) <= 0):
            first = np.r_[True, np.diff(t) > 0]  # the first bearing (in file order) per time
            repeated = int((~first[1:] & first[:-1]).sum())  # times holding more than one
            if repeated > REPEATED_TIMES_TESTED * int(first.sum()):
                report.append(several_per_time(str(batch), t, params))
                continue
            left_out = int((~first).sum())  # a rare glitch: test the first bearing per time
            g, t = g[first], t[first]
        excluded, static, observer = None, True, "not given (taken as static)"
        xy, maneuvering = None, 0
        if {"obs_lon", "obs_lat"} <= set(g.columns):
            olon, olat = g["obs_lon"].to_numpy(float), g["obs_lat"].to_numpy(float)
            if np.isfinite(olon).all() and np.isfinite(olat).all():
                excluded = observer_maneuvering(t, olon, olat, params.observer_dv_ms)
                maneuvering = int(excluded.sum())
                xy = observer_xy(olon, olat)
                x, y = xy
                speed = float(np.hypot(x[-1] - x[0], y[-1] - y[0]) / max(t[-1] - t[0], 1e-9))
                static = speed < 0.5
                observer = f"{speed / geo.KN_MS:.1f} kn mean" + (" (static)" if static else "")
            else:
                observer = "position missing on some rows: no observer exclusion"
        used = windows_for(params, t)  # the spans this sequence is tested with
        st = statistic(t, g["bearing"].to_numpy(float), used, excluded, observer=xy)
        if st.observer is not None:
            observer += (
                f"; its positions enter the fit, {maneuvering} maneuvering samples "
                "modelled, not excluded"
                if maneuvering
                else "; its positions enter the fit"
            )
        stat_batch.append(np.full(len(st.z), str(batch), dtype=object))
        stat_t.append(np.asarray(st.boundary_t, dtype="float64"))
        stat_z.append(np.asarray(st.z, dtype="float64"))
        found = detections_from(st, used.z_crit)
        for d in found:
            rows.append((str(batch), d.detect_time_s, d.maneuver_time_s, d.z))
        win = st.windows
        counts = {r: int((win.reason == r).sum()) for r in EXCLUSION_REASONS}
        report.append(
            {
                "batch": str(batch),
                "test": "GLR" if params.glr else "AUC-mean (eq. 15)" if params.auc_mean else "AUC",
                "x_s": round(float(used.window_x_s), 1),
                "min_x_s": round(float(used.min_window_x_s), 1),
                "y_spans_s": [round(float(v), 1) for v in y_spans(used)],
                "window_rule": params.windows
                + ("" if used.window_y_s == params.window_y_s else " (shrunk to the sequence)"),
                "samples": int(len(t)),
                "duration_s": round(float(t[-1] - t[0]), 3) if len(t) else 0.0,
                "median_interval_s": round(float(np.median(np.diff(t))), 3) if len(t) > 1 else None,
                "observer": observer,
                "windows": int(len(win.k)),
                "tested": int((win.reason == "").sum()),
                "excluded": counts,
                "too_short": win.too_short or None,
                "detections": len(found),
                "repeated_left_out": left_out,
                **min_detectable(st, used, static),
            }
        )
    out = pd.DataFrame(rows, columns=["batch", "detect_s", "maneuver_s", "z"])
    table = pd.DataFrame(
        {
            "batch": out["batch"].astype("str"),
            "detect_time": seconds_to_time(out["detect_s"].to_numpy()).to_numpy(),
            "maneuver_time": seconds_to_time(out["maneuver_s"].to_numpy()).to_numpy(),
            "z": out["z"].to_numpy(),
        }
    )
    cat = lambda xs, dtype: np.concatenate(xs) if xs else np.zeros(0, dtype)  # noqa: E731
    statistic_table = pd.DataFrame(
        {
            "batch": pd.Series(cat(stat_batch, object), dtype="str"),
            "boundary_s": cat(stat_t, "float64"),
            "z": cat(stat_z, "float64"),
        }
    )
    return table, report, statistic_table


REPEATED_TIMES_TESTED = 0.01
"""A series with bearings at a repeated time is still tested when at most this fraction
of its distinct times hold more than one bearing (a logging glitch, not a camera frame's
several targets): the first bearing at each time is tested, the others left out and
counted in the report (``repeated_left_out``). More repeats than that: not one target's
sequence, not tested (:func:`several_per_time`)."""


def several_per_time(batch: str, t: np.ndarray, params: BearingParams) -> dict:
    """The report of a series holding several bearings at one time (a camera frame's
    several targets or clutter): not one target's sequence (SPEC §4's input), so not
    tested; the reason says how many times and what splits it."""
    _, counts = np.unique(t, return_counts=True)
    shared = counts[counts > 1]
    why = (
        f"{int(shared.sum()):,} of its {len(t):,} bearings share a time with another "
        f"({len(shared):,} times, up to {int(shared.max())} at one time): not one target's "
        "sequence; split it by a target column (--map target=COLUMN) or gate it on the "
        "targets' tracks (--tracks FILE)"
    )
    return {
        "batch": batch,
        "test": "GLR" if params.glr else "AUC-mean (eq. 15)" if params.auc_mean else "AUC",
        "x_s": round(float(params.window_x_s), 1),
        "min_x_s": round(float(params.min_window_x_s), 1),
        "y_spans_s": [round(float(v), 1) for v in y_spans(params)],
        "window_rule": params.windows,
        "samples": int(len(t)),
        "duration_s": round(float(t[-1] - t[0]), 3) if len(t) else 0.0,
        "median_interval_s": None,
        "observer": "",
        "windows": 0,
        "tested": 0,
        "excluded": {r: 0 for r in EXCLUSION_REASONS},
        "too_short": why,
        "several_per_time": int(len(shared)),
        "detections": 0,
        "noise_deg": None,
        "min_rate_change_deg_min": None,
        "min_turn_deg": None,
    }


def detect(bearings: pd.DataFrame, params: BearingParams | None = None) -> pd.DataFrame:
    """Detections for every batch: ``batch, detect_time, maneuver_time, z``."""
    return detect_with_report(bearings, params)[0]


def report_lines(report: list[dict]) -> list[str]:
    """One readable line per batch: windows tested, skipped and why, what can be seen."""
    lines = []
    for r in report:
        if r["too_short"]:
            lines.append(f"batch {r['batch']}: no window tested, {r['too_short']}")
            continue
        skipped = ", ".join(f"{v} {k.replace('_', ' ')}" for k, v in r["excluded"].items() if v)
        turn = f", smallest turn ≈ {r['min_turn_deg']:.0f}°" if r["min_turn_deg"] else ""
        rate = r["min_rate_change_deg_min"]
        see = f"smallest bearing-rate change ≈ {rate:.2f}°/min" if rate else "nothing detectable"
        if not r["tested"]:  # no window: no noise, nothing to see (not "noise ≈ None°")
            what = "noise and detectable change not estimated: no window tested"
        elif r["noise_deg"] is None:
            what = f"noise not estimated, {see}{turn}"
        else:
            what = f"noise ≈ {r['noise_deg']}°, {see}{turn}"
        rep = r.get("repeated_left_out") or 0
        lines.append(
            f"batch {r['batch']}: {r['detections']} detection(s); {r['tested']} of "
            f"{r['windows']} windows tested"
            + (f" (skipped: {skipped})" if skipped else "")
            + f"; {what}"
            + (
                f"; {rep} bearing(s) at an already-taken time left out (first per time tested)"
                if rep
                else ""
            )
        )
    return lines


def __getattr__(name: str):  # the simulator and evaluation live in bearing_eval
    if name in ("simulate_table", "simulate_bearings", "Scenario", "SCENARIOS"):
        from wakeline.core import bearing_eval

        return getattr(bearing_eval, name)
    raise AttributeError(name)
