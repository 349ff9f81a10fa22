"""Bearing-only maneuver detection by AUC (seed 002, SPEC §4).

Two adjacent windows slide over a target's bearing sequence: X (``m`` samples) and Y
(``n`` samples) meeting at a boundary. The Mann–Whitney statistic
AUC = (1/mn)·Σᵢ Σⱼ I(Xᵢ > Yⱼ) (ties ½) is computed from ranks for every boundary at once.

**The feature.** A raw bearing sequence trends even without a maneuver, so the AUC of
raw bearings is near 0 or 1 everywhere (measured: 100 % false alarms). The bearing rate
(first differences) is stationary but, at 1 s sampling and 0.6° noise, a 50° turn
changes the mean rate by ~0.013°/s against a differencing noise of 0.85°/s: no power
(measured: 0 % detection). We use **residuals from the trend fitted on X**: a straight
line is fitted to X's bearings against time; X's residuals and Y's residuals from that
line (Y: extrapolated) are compared. Without a maneuver both centre on zero; after a
change of bearing rate Y's residuals drift to one side.

**The null.** Y's residuals share the extrapolation error of X's line, so the textbook
null AUC ~ N(½, (m+n+1)/(12mn)) is too narrow (measured: 100 % false alarms). Near H0 a
common offset δ moves the AUC by δ / (σ√(4π)) and the offset's variance is
σ²·(1/m + (t̄_Y − t̄_X)²/Sxx), so σ cancels:
Var(AUC) = (m+n+1)/(12mn) + (1/m + (t̄_Y − t̄_X)²/Sxx) / (4π). We reject "no maneuver"
when |AUC − ½| / sd > z_{α/2}.

Detection time is when the first rejecting boundary's Y window is complete (causal);
the estimated maneuver time is the boundary with the largest |z| in that run of
rejections. Later rejections count as a new detection only once X no longer holds the
previous estimated maneuver time (X would misfit its trend until then). Bearings are unwrapped, so 359° → 1° is a 2° step. Boundaries whose windows
overlap a span where the observer itself maneuvers are skipped.
"""

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.lib.stride_tricks import sliding_window_view

from wakeline.core import geo
from wakeline.core.errors import InputError
from wakeline.core.params import Params, param
from wakeline.core.schema import seconds_to_time, time_seconds

DETECTION_COLUMNS = ("batch", "detect_time", "maneuver_time", "z")


@dataclass(frozen=True)
class BearingParams(Params):
    """AUC detector settings (ours; seed 002 leaves window sizes and α open)."""

    window_x: int = param(
        300, "samples", "m: samples in window X (trend reference)", lo=5, hi=100_000
    )
    window_y: int = param(90, "samples", "n: samples in window Y", lo=2, hi=100_000)
    alpha: float = param(0.00097, "", "significance level per boundary (z = 3.3)", lo=1e-12, hi=0.5)
    trend_order: int = param(
        2, "", "polynomial order of the trend fitted on X (1: a line)", lo=0, hi=3
    )
    observer_dv_ms: float = param(
        1.0,
        "m/s",
        "observer velocity change within 60 s that marks its own maneuver",
        lo=0,
        hi=1000,
    )

    @property
    def z_crit(self) -> float:
        from scipy.stats import norm  # lazy: scipy.stats is slow to import

        return float(norm.ppf(1.0 - self.alpha / 2.0))


def auc_windows(values: np.ndarray, m: int) -> np.ndarray:
    """AUC of the first ``m`` columns against the rest, for every row (ranks, ties ½)."""
    from scipy.stats import rankdata  # lazy: scipy.stats is slow to import

    ranks = rankdata(values, axis=1)
    n = values.shape[1] - m
    return (ranks[:, :m].sum(axis=1) - m * (m + 1) / 2.0) / (m * n)


def _trend_fit(tau: np.ndarray, w: np.ndarray, m: int, order: int):
    """Least-squares polynomial trend on the first m columns; residuals of all columns,
    the extrapolation lever h̄ᵀ(XᵀX)⁻¹h̄ over the rest, the coefficients and (XᵀX)⁻¹."""
    powers = np.stack([tau**k for k in range(order + 1)], axis=-1)  # (B, m+n, q+1)
    px = powers[:, :m, :]
    gram_inv = np.linalg.inv(np.einsum("bij,bik->bjk", px, px))
    coef = np.einsum("bjk,bk->bj", gram_inv, np.einsum("bij,bi->bj", px, w[:, :m]))
    resid = w - np.einsum("bij,bj->bi", powers, coef)
    hbar = powers[:, m:, :].mean(axis=1)
    lever = np.einsum("bj,bjk,bk->b", hbar, gram_inv, hbar)
    return resid, lever, coef, gram_inv


def auc_statistic(
    t: np.ndarray, bearing_deg: np.ndarray, m: int, n: int, order: int = 2
) -> tuple[np.ndarray, np.ndarray]:
    """Boundary times (s) and z for every boundary where both windows fit.

    The trend on X is a polynomial of ``order`` in time; the null variance adds
    h̄ᵀ(XᵀX)⁻¹h̄ / (4π), the variance of the trend's mean extrapolation over Y in units
    of σ² (h̄: the design row averaged over Y).
    """
    u = np.degrees(np.unwrap(np.radians(bearing_deg)))
    if len(u) < m + n:
        return np.zeros(0), np.zeros(0)
    w = sliding_window_view(u, m + n)
    tw = sliding_window_view(t, m + n)
    # time relative to the boundary, in units of the X span: well conditioned powers
    scale = max(float(np.median(tw[:, m - 1] - tw[:, 0])), 1e-9)
    tau = (tw - tw[:, m : m + 1]) / scale
    resid, lever, _, _ = _trend_fit(tau, w, m, order)
    auc = auc_windows(resid, m)
    var = (m + n + 1) / (12.0 * m * n) + lever / (4.0 * math.pi)
    return tw[:, m], (auc - 0.5) / np.sqrt(var)


@dataclass(frozen=True)
class Detection:
    detect_time_s: float
    maneuver_time_s: float
    z: float


def detect_sequence(
    t: np.ndarray,
    bearing_deg: np.ndarray,
    params: BearingParams,
    excluded: np.ndarray | None = None,
) -> list[Detection]:
    """All detections in one sequence: one per run of rejecting boundaries."""
    m, n = int(params.window_x), int(params.window_y)
    boundary_t, z = auc_statistic(t, bearing_deg, m, n, int(params.trend_order))
    if len(z) == 0:
        return []
    reject = np.abs(z) > params.z_crit
    if excluded is not None and excluded.any():
        # skip boundaries whose windows touch an excluded sample
        touched = sliding_window_view(excluded.astype(np.int8), m + n).any(axis=1)
        reject &= ~touched
    if not reject.any():
        return []
    edges = np.diff(np.concatenate([[0], reject.astype(np.int8), [0]]))
    starts = np.flatnonzero(edges == 1)
    ends = np.flatnonzero(edges == -1)
    out: list[Detection] = []
    x_start = t[: len(z)]  # time of the first sample of X at each boundary
    for a, b in zip(starts, ends, strict=True):  # one entry per detection, not per sample
        if out:
            # A window X that still holds the last detected maneuver misfits its trend:
            # those rejections are the same maneuver, not a new one.
            clear = np.flatnonzero(x_start[a:b] > out[-1].maneuver_time_s)
            if len(clear) == 0:
                continue
            a = a + int(clear[0])
        k = a + int(np.argmax(np.abs(z[a:b])))
        out.append(Detection(float(t[a + m + n - 1]), float(boundary_t[k]), float(z[k])))
    return out


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
    ``lag_s`` so position jitter of a slow or docked observer does not count."""
    n = len(t)
    if n < 3 or np.all(np.isnan(obs_lon)):
        return np.zeros(n, dtype=bool)
    x, y = geo.to_local(obs_lon, obs_lat, float(np.nanmean(obs_lon)), float(np.nanmean(obs_lat)))
    back = np.searchsorted(t, t - lag_s)
    dt = np.maximum(t - t[back], 1e-9)
    vx, vy = (x - x[back]) / dt, (y - y[back]) / dt
    vx[t - t[0] < lag_s] = np.nan  # no velocity before a full lag
    earlier = np.searchsorted(t, t - span_s)
    dv = np.hypot(vx - vx[earlier], vy - vy[earlier])
    return np.isfinite(dv) & (dv > dv_ms)


def read_bearings(path) -> pd.DataFrame:
    """Read ``batch,time,bearing[,obs_lon,obs_lat]`` (any delimiter/encoding import reads)."""
    from wakeline.core.io.reader import parse_times
    from wakeline.core.io.sniff import read_small_table

    df = read_small_table(path, ("batch", "time", "bearing"), "bearings", text_columns=("batch",))
    bearing = pd.to_numeric(df["bearing"], errors="coerce")
    bad = df.index[bearing.isna()]
    if len(bad):
        raise InputError(
            f"{path}: bearing is not a number on line(s) {', '.join(str(i + 2) for i in bad[:10])}"
        )
    import pyarrow as pa

    ns, ok = parse_times(pa.chunked_array([pa.array(df["time"].astype(str))]), "auto")
    if not ok.all():
        raise InputError(
            f"{path}: unreadable time on line(s) "
            f"{', '.join(str(i + 2) for i in np.flatnonzero(~ok)[:10])}"
        )
    df["time"] = pd.Series(ns.view("datetime64[ns]")).dt.tz_localize("UTC")
    df["bearing"] = bearing.to_numpy() % 360.0
    return df


def detect(bearings: pd.DataFrame, params: BearingParams | None = None) -> pd.DataFrame:
    """Detections for every batch: ``batch, detect_time, maneuver_time, z``."""
    params = (params or BearingParams()).checked()
    rows = []
    for batch, g in bearings.groupby("batch", sort=True):  # one pass per target
        g = g.sort_values("time", kind="stable")
        t = time_seconds(g["time"])
        if np.any(np.diff(t) <= 0):
            raise InputError(f"batch {batch}: repeated time stamps; bearings must be one per time")
        excluded = None
        if {"obs_lon", "obs_lat"} <= set(g.columns):
            excluded = observer_maneuvering(
                t,
                g["obs_lon"].to_numpy(float),
                g["obs_lat"].to_numpy(float),
                params.observer_dv_ms,
            )
        for d in detect_sequence(t, g["bearing"].to_numpy(float), params, excluded):
            rows.append((str(batch), d.detect_time_s, d.maneuver_time_s, d.z))
    out = pd.DataFrame(rows, columns=["batch", "detect_s", "maneuver_s", "z"])
    return pd.DataFrame(
        {
            "batch": out["batch"].astype("str"),
            "detect_time": seconds_to_time(out["detect_s"].to_numpy()).to_numpy(),
            "maneuver_time": seconds_to_time(out["maneuver_s"].to_numpy()).to_numpy(),
            "z": out["z"].to_numpy(),
        }
    )


# --------------------------------------------------------------------------------------
# simulation and evaluation


@dataclass(frozen=True)
class Scenario:
    """A bearing-only engagement: observer and target, seed 002 style."""

    name: str
    range_m: float = 20_000.0
    bearing_deg: float = 0.0  # initial bearing of the target from the observer
    speed_kn: float = 18.0
    course_deg: float = 30.0
    observer_speed_kn: float = 0.0
    observer_course_deg: float = 0.0
    observer_turns: tuple[
        tuple[float, float], ...
    ] = ()  # (time s, course change deg), instantaneous
    duration_s: float = 900.0
    period_s: float = 1.0


SCENARIOS = (
    Scenario("1 paper: 20 km, 18 kn, course 30, static"),
    Scenario("2 near: 10 km, 12 kn, course 200, static", 10_000, 45, 12, 200),
    Scenario("3 far fast: 30 km, 25 kn, course 270, static", 30_000, 300, 25, 270),
    Scenario("4 observer 10 kn on a leg", 20_000, 20, 18, 200, 10, 90),
    Scenario("5 observer turns at 120 s", 15_000, 350, 15, 330, 8, 0, ((120.0, 60.0),)),
)


def simulate_bearings(
    rng: np.random.Generator, sc: Scenario, turn_deg: float, t_m: float, sigma_deg: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Times (s), noisy bearings (deg), observer lon/lat for one run."""
    t = np.arange(0.0, sc.duration_s + 1e-9, sc.period_s)
    dt = sc.period_s

    def path(speed_kn, course0, changes, x0, y0):
        course = np.full(len(t), course0, dtype=float)
        for when, delta in changes:
            course[t >= when] += delta
        v = speed_kn * geo.KN_MS
        vx, vy = v * np.sin(np.radians(course)), v * np.cos(np.radians(course))
        x = x0 + np.concatenate([[0.0], np.cumsum(vx[:-1] * dt)])
        y = y0 + np.concatenate([[0.0], np.cumsum(vy[:-1] * dt)])
        return x, y

    ox, oy = path(sc.observer_speed_kn, sc.observer_course_deg, sc.observer_turns, 0.0, 0.0)
    b0 = np.radians(sc.bearing_deg)
    tx, ty = path(
        sc.speed_kn,
        sc.course_deg,
        ((t_m, turn_deg),) if turn_deg else (),
        sc.range_m * np.sin(b0),
        sc.range_m * np.cos(b0),
    )
    bearing = np.degrees(np.arctan2(tx - ox, ty - oy)) + rng.normal(0.0, sigma_deg, len(t))
    olon, olat = geo.from_local(ox, oy, 122.0, 30.0)
    return t, bearing % 360.0, olon, olat


def _metrics(rng, sc, params, runs, turn_deg, sigma_deg, t_m, max_delay_s):
    detected, reaction, error, false_alarm = 0, [], [], 0
    for _ in range(runs):  # Monte Carlo runs; each run is vectorized over boundaries
        t, b, olon, olat = simulate_bearings(rng, sc, turn_deg, t_m, sigma_deg)
        excl = observer_maneuvering(t, olon, olat, params.observer_dv_ms)
        hits = [
            d
            for d in detect_sequence(t, b, params, excl)
            if t_m <= d.detect_time_s <= t_m + max_delay_s
        ]
        if hits:
            detected += 1
            reaction.append(hits[0].detect_time_s - t_m)
            error.append(abs(hits[0].maneuver_time_s - t_m))
        t, b, olon, olat = simulate_bearings(rng, sc, 0.0, t_m, sigma_deg)
        excl = observer_maneuvering(t, olon, olat, params.observer_dv_ms)
        false_alarm += bool(detect_sequence(t, b, params, excl))
    return {
        "detection": detected / runs,
        "reaction_min": float(np.mean(reaction)) / 60 if reaction else float("nan"),
        "time_error_min": float(np.mean(error)) / 60 if error else float("nan"),
        "false_alarm": false_alarm / runs,
    }


def evaluate_bearing(
    runs: int = 1000,
    seed: int = 0,
    params: BearingParams | None = None,
    sweep_runs: int = 200,
    t_m: float = 450.0,
    max_delay_s: float = 300.0,
    progress=None,
) -> dict:
    """Seed 002's metrics on our five scenarios (σ 0.6°, 50° turn) and the noise/turn sweeps."""
    params = (params or BearingParams()).checked()
    rng = np.random.default_rng(seed)
    main = []
    for k, sc in enumerate(SCENARIOS):
        if progress:
            progress(k / (len(SCENARIOS) * 3), sc.name)
        main.append(
            {"scenario": sc.name, **_metrics(rng, sc, params, runs, 50.0, 0.6, t_m, max_delay_s)}
        )

    def sweep(label: str, values, turn_of, sigma_of) -> pd.DataFrame:
        return pd.DataFrame(
            [
                {
                    label: value,
                    "scenario": sc.name[:1],
                    **_metrics(
                        rng,
                        sc,
                        params,
                        sweep_runs,
                        turn_of(value),
                        sigma_of(value),
                        t_m,
                        max_delay_s,
                    ),
                }
                for value in values
                for sc in SCENARIOS
            ]
        )

    noise = sweep("sigma_deg", (0.1, 0.3, 0.6, 1.0, 1.5, 2.0), lambda v: 60.0, lambda v: v)
    turn = sweep("turn_deg", (10, 30, 50, 70, 90, 110), lambda v: float(v), lambda v: 0.6)
    return {
        "main": pd.DataFrame(main),
        "noise": noise,
        "turn": turn,
        "runs": runs,
        "sweep_runs": sweep_runs,
        "params": params,
    }


def simulate_table(
    seed: int = 0, turn_deg: float = 50.0, sigma_deg: float = 0.6, t_m: float = 450.0
) -> pd.DataFrame:
    """Every scenario twice — with a maneuver at ``t_m`` and without — as one table:
    ``batch,time,bearing,obs_lon,obs_lat,true_maneuver_time,true_turn_deg``."""
    rng = np.random.default_rng(seed)
    t0 = pd.Timestamp("2024-05-01T00:00:00Z")
    frames = []
    for k, sc in enumerate(SCENARIOS, start=1):
        for turn in (turn_deg, 0.0):
            t, b, olon, olat = simulate_bearings(rng, sc, turn, t_m, sigma_deg)
            frames.append(
                pd.DataFrame(
                    {
                        "batch": f"s{k}-{'m' if turn else 'straight'}",
                        "time": t0 + pd.to_timedelta(t, unit="s"),
                        "bearing": np.round(b, 4),
                        "obs_lon": np.round(olon, 7),
                        "obs_lat": np.round(olat, 7),
                        "true_maneuver_time": (t0 + pd.to_timedelta(t_m, unit="s"))
                        if turn
                        else pd.NaT,
                        "true_turn_deg": turn,
                    }
                )
            )
    return pd.concat(frames, ignore_index=True)


def format_evaluation(ev: dict) -> str:
    """Seed 002's metrics as tables: the five scenarios, then the noise and turn sweeps."""
    p: BearingParams = ev["params"]
    lines = [
        f"AUC detector: m = {p.window_x}, n = {p.window_y} samples, trend order {p.trend_order}, "
        f"z > {p.z_crit:.2f}; 1 s sampling, maneuver at 450 s; detection = a detection within 5 min after it.",
        "",
        f"Scenarios, bearing noise 0.6 deg, 50 deg turn, {ev['runs']} runs each (+ {ev['runs']} without maneuver)",
        f"{'scenario':<46} {'detect':>7} {'react min':>9} {'t err min':>9} {'false al':>8}",
    ]
    for _, r in ev["main"].iterrows():
        lines.append(
            f"{r.scenario:<46} {r.detection:7.1%} {r.reaction_min:9.2f} {r.time_error_min:9.2f} "
            f"{r.false_alarm:8.1%}"
        )
    m = ev["main"]
    lines.append(
        f"{'mean':<46} {m.detection.mean():7.1%} {m.reaction_min.mean():9.2f} "
        f"{m.time_error_min.mean():9.2f} {m.false_alarm.mean():8.1%}"
    )
    for key, label, unit in (
        ("noise", "sigma_deg", "deg noise (60 deg turn)"),
        ("turn", "turn_deg", "deg turn (0.6 deg noise)"),
    ):
        t = ev[key]
        lines += [
            "",
            f"Sweep over {unit}, {ev['sweep_runs']} runs per cell: detection / reaction min / time error min",
            f"{label:>9} "
            + " ".join(f"{'scenario ' + s:>22}" for s in sorted(t.scenario.unique())),
        ]
        for value, g in t.groupby(label):
            cells = [
                f"{r.detection:5.1%} {r.reaction_min:5.2f} {r.time_error_min:5.2f}"
                for _, r in g.iterrows()
            ]
            lines.append(f"{value:>9g} " + " ".join(f"{c:>22}" for c in cells))
    return "\n".join(lines)
