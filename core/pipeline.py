"""The step registry: every pipeline step is ONE core function with its parameters.

The command line (``wakeline clean|maneuvers|compress|associate|fuse``), the desktop
application (through :class:`wakeline.core.session.Session`) and saved pipeline presets
(:class:`Pipeline`, JSON) all run the steps of :data:`STEPS`, so the same input and
parameters give the same tables everywhere. A step's command-line flags are generated
from its parameter dataclasses (``core/params.py``).

A step takes a point table, a dict of parameter sets keyed as in :attr:`Step.params`, and
a progress callback; it returns a :class:`StepResult` holding new layers (for the
session and the map), named tables (what the command line writes: ``points`` with ``-o``,
``rejected``, ``pairs``, ``maneuvers`` …) and a report.
"""

import dataclasses
import json
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from wakeline.core.errors import InputError
from wakeline.core.params import Params, finite_number, param
from wakeline.core.progress import Progress, null_progress, sub_progress
from wakeline.core.timeline import format_elapsed, is_relative_time
from wakeline.core.words import Phrase, Text, joined, phrase


@dataclass(frozen=True)
class NewLayer:
    """A layer a step makes: ``suffix`` is its role (``cleaned``, ``compressed`` …)."""

    suffix: str
    kind: str
    points: pd.DataFrame
    meta: dict = field(default_factory=dict)
    #: side tables that belong to the layer (``maneuvers``, ``rejected``, ``pairs``)
    tables: dict[str, pd.DataFrame] = field(default_factory=dict)


@dataclass(frozen=True)
class StepResult:
    step: str
    layers: list[NewLayer]
    report: dict
    tables: dict[str, pd.DataFrame] = field(default_factory=dict)
    #: for a pipeline: each stage's result, in order (its layers are the stages' layers)
    stages: list["StepResult"] = field(default_factory=list)
    #: a re-run of a reviewed step in a session: what it carries over from the review of
    #: the layer it replaces (:class:`wakeline.core.review_session.Carry`)
    carry: Any = None
    #: a pipeline's stage: the parameter sets it ran with (its layers' lineage records
    #: them, :meth:`wakeline.core.session.Session.apply_result`)
    params: dict | None = None


# -- step options (choices beside the algorithms' parameters) --------------------------


@dataclass(frozen=True)
class ManeuverOptions(Params):
    """Which detector ``maneuvers`` runs."""

    method: str = param(
        "pca",
        "",
        "detector: pca (seed 000) or the baselines imm, entropy",
        choices=("pca", "imm", "entropy"),
    )
    sigma: float = param(300.0, "m", "imm: position noise std", 0.001)
    k: int = param(0, "", "entropy: maneuvers per track (0: from the true_turn column)", 0)


@dataclass(frozen=True)
class CompressOptions(Params):
    """Which points ``compress`` keeps."""

    method: str = param(
        "maneuver",
        "",
        "keep maneuver points (seed 000) or Douglas-Peucker points",
        choices=("maneuver", "dp"),
    )
    dp_distance: str = param(
        "segment",
        "",
        "dp: a point's distance to the chord segment (GEOS, shapely) or to its infinite "
        "line (the classic textbook form)",
        choices=("segment", "line"),
    )


@dataclass(frozen=True)
class AssociateOptions(Params):
    """Which association ``associate`` runs and what it writes."""

    mode: str = param(
        "interrupted",
        "",
        "interrupted tracks (seed 003) or segment clustering (seed 001)",
        choices=("interrupted", "segments"),
    )
    method: str = param(
        "",
        "",
        "interrupted: optimal (default) | greedy; segments: motion (default) | area | dtw | hausdorff",
        choices=("", "optimal", "greedy", "motion", "area", "dtw", "hausdorff"),
    )
    normalize: str = param(
        "scaled",
        "",
        "interrupted: divide each term by its tolerance, or seed 003's min-max",
        choices=("scaled", "minmax"),
    )
    stitch: bool = param(False, "", "one batch per target, gaps filled at the sensor period")
    fill: str = param(
        "line",
        "",
        "stitch gap fill: line (seed 003: a straight line fitted to 10 points each side; "
        "better on our scenes) or hermite (a cubic joining both ends' positions and velocities)",
        choices=("line", "hermite"),
    )


@dataclass(frozen=True)
class FuseOptions(Params):
    """Distance and assignment of ``fuse``."""

    distance: str = param(
        "sync",
        "",
        "synchronized distance, DTW over the common span, or seed 003's whole-track DTW",
        choices=("sync", "dtw", "dtw_whole"),
    )
    method: str = param(
        "optimal",
        "",
        "one-to-one assignment: optimal or seed 003's greedy",
        choices=("optimal", "greedy"),
    )


# -- the steps -------------------------------------------------------------------------


def _p(params: dict[str, Any], key: str, default_cls: type) -> Any:
    value = params.get(key)
    return (value if value is not None else default_cls()).checked()


#: The columns of a cleaned layer's ``at_rest`` table (one row per span; times as text).
AT_REST_COLUMNS = ("sensor", "batch", "start", "end", "duration_s", "points", "lon", "lat")


def run_clean(points: pd.DataFrame, params: dict, progress: Progress = null_progress):
    from wakeline.core.clean import CleanParams, clean

    res = clean(points, _p(params, "clean", CleanParams), progress=progress)
    rep = res.report
    # The at-rest spans the stationary rule found, beside the layer (the Statistics panel
    # counts them; the project keeps them with the layer's other side tables).
    rest = pd.DataFrame(rep.get("at_rest_spans", []), columns=AT_REST_COLUMNS)
    return StepResult(
        "clean",
        [
            NewLayer(
                "cleaned",
                "cleaned",
                res.points,
                # per action and rule, so the Statistics dock reads it, not the table
                {"rejected": int(len(res.rejected)), "clean_counts": clean_counts(rep)},
                {"rejected": res.rejected, "at_rest": rest},
            )
        ],
        rep,
        {"points": res.points, "rejected": res.rejected},
    )


def clean_counts(report: dict) -> dict[str, dict[str, int]]:
    """A clean report's points per action (``removed``, ``changed`` — kept, with new
    values — ``replaced``) and rule, in the rules' order; actions and rules without
    points left out."""
    out = {}
    for action in ("removed", "changed", "replaced"):
        per = {rule: int(v.get(action, 0)) for rule, v in report["rules"].items()}
        per = {rule: n for rule, n in per.items() if n}
        if per:
            out[action] = per
    return out


def _rule_count(rule: str, n: int):
    """A clean rule's name and count, "speed 23" (the rule's name as the command line and
    the report say it; a phrase of its own, so the window shows the rule's name in its
    language)."""
    known = {
        "duplicates": phrase("duplicates {n:,}", n=n),
        "same_time": phrase("same_time {n:,}", n=n),
        "stationary": phrase("stationary {n:,}", n=n),
        "speed": phrase("speed {n:,}", n=n),
        "turn": phrase("turn {n:,}", n=n),
        "speed_outliers": phrase("speed_outliers {n:,}", n=n),
        "isolated": phrase("isolated {n:,}", n=n),
        "short_tracks": phrase("short_tracks {n:,}", n=n),
        "bspline": phrase("bspline {n:,}", n=n),
        "resample": phrase("resample {n:,}", n=n),
        "smooth": phrase("smooth {n:,}", n=n),
    }
    return known.get(rule) or phrase("{rule} {n:,}", rule=rule, n=n)


def joined_counts(parts: list) -> list:
    """``parts`` with a ", " phrase between each two."""
    out: list = []
    for k, part in enumerate(parts):
        if k:
            out.append(phrase(", "))
        out.append(part)
    return out


def _said_time(text: str) -> str:
    """A report's time as a summary says it: ``T+h:mm:ss`` for a scene-relative time (MTAD,
    Øresund: seconds from a scene start, as the window shows them), else the UTC time."""
    try:
        stamp = pd.Timestamp(text)
    except (ValueError, TypeError):
        return str(text)
    if pd.isna(stamp):
        return str(text)
    seconds = stamp.value / 1e9
    if is_relative_time(np.array([seconds])):
        return format_elapsed(seconds)
    return str(text).removesuffix("+00:00")


def _break_phrases(speed: dict) -> list:
    """The speed rule's breaks (an impossible leg followed by plausible ones: another ship,
    or a clock set back), whatever the rule removed: how many split the track, and the
    impossible legs left inside a track with the fastest (operator test 7, D3)."""
    out: list = []
    splits = int(speed.get("splits", 0) or 0)
    if splits:
        out.append(phrase("; {n:#break} split into new tracks (batch#2 …)", n=splits))
    legs = speed.get("break_legs") or []
    if legs:
        worst = legs[0]
        values = dict(
            km=worst["km"],
            s=worst["s"],
            kn=worst["kn"] if worst["kn"] is not None else float("inf"),
            track=f"{worst['sensor']}:{worst['batch']}",
            time=_said_time(worst["from_time"]),
        )
        n_kept = int(speed.get("breaks_kept", len(legs)) or len(legs))
        # a jump at one time (no speed), or within what "{s:,.0f} s" shows as 0 s (two
        # ships under one id, rows 0.03 s apart: "0.3 km in 0 s, 18,143 kn", operator test 10)
        same_time = worst["kn"] is None or not worst["s"] or worst["s"] < 0.5
        if same_time and n_kept == 1:
            out.append(
                phrase(
                    "; 1 break kept: {km:,.1f} km at the same time, track {track} at {time}",
                    **values,
                )
            )
        elif same_time:
            out.append(
                phrase(
                    "; {n:#break} kept, the fastest {km:,.1f} km at the same time, track "
                    "{track} at {time}",
                    n=n_kept,
                    **values,
                )
            )
        elif n_kept == 1:
            out.append(
                phrase(
                    "; 1 break kept: {km:,.1f} km in {s:,.0f} s, {kn:,.0f} kn, track {track} "
                    "at {time}",
                    **values,
                )
            )
        else:
            out.append(
                phrase(
                    "; {n:#break} kept, the fastest {km:,.1f} km in {s:,.0f} s, {kn:,.0f} kn, "
                    "track {track} at {time}",
                    n=n_kept,
                    **values,
                )
            )
        if not speed.get("params", {}).get("split_at_breaks", False):
            out.append(phrase(" (--set speed.split_at_breaks=true splits there)"))
    return out


def _summary_clean(res: StepResult) -> Text:
    """Where the points went: kept, then removed, changed (kept, with new values) and
    replaced, each with its rules (the removed add up to what was not kept)."""
    rep = res.report
    parts = [
        phrase(
            "kept {kept:,} of {points:#point} in {tracks:#track}",
            kept=rep["points_out"],
            points=rep["points_in"],
            tracks=rep["tracks_out"],
        )
    ]
    for action, per in clean_counts(rep).items():
        rules = Text(joined_counts([_rule_count(rule, n) for rule, n in per.items()]))
        n = sum(per.values())
        if action == "removed":
            parts.append(phrase("; removed {n:,} ({rules})", n=n, rules=rules))
        elif action == "changed":
            parts.append(phrase("; changed {n:,} ({rules})", n=n, rules=rules))
        else:
            parts.append(phrase("; replaced {n:,} ({rules})", n=n, rules=rules))
    parts += _break_phrases(rep["rules"].get("speed", {}))
    same_time = rep["rules"].get("same_time", {})
    if same_time.get("removed"):
        parts.append(
            phrase(
                "; same time, another place: {rows:#row}, median {m:,.0f} m from the row kept "
                "(several targets in one batch, or times cut to the minute?)",
                rows=same_time["removed"],
                m=same_time.get("median_m", 0.0),
            )
        )
    return Text(parts)


def _detect(points: pd.DataFrame, params: dict, progress: Progress):
    """The maneuver detector (or a baseline) → ManeuverResult over the sorted points."""
    from wakeline.core.maneuver import ManeuverParams, ManeuverResult, detect

    opts = _p(params, "maneuver_options", ManeuverOptions)
    result = detect(points, _p(params, "maneuver", ManeuverParams), progress)
    if opts.method == "pca":
        return result
    from wakeline.core import baselines
    from wakeline.core.schema import time_seconds
    from wakeline.core.tracks import local_xy

    pts, index = result.points, result.index
    if opts.method == "entropy" and opts.k == 0 and "true_turn" not in pts.columns:
        raise InputError(
            "--method entropy needs the number of maneuvers per track: give --k N "
            "(or a true_turn column, as simulations have)"
        )
    x, y = local_xy(pts, index)
    t = time_seconds(pts["time"])
    turns = pd.to_numeric(pts.get("true_turn", pd.Series(dtype=float)), errors="coerce").to_numpy()
    mask = np.zeros(len(pts), dtype=bool)
    # The baselines are per-track recursions (IMM) or clusterings (entropy): one call per track.
    for a, b in zip(index.starts, index.ends, strict=True):
        if opts.method == "imm":
            found = baselines.imm_detect(x[a:b], y[a:b], t[a:b], opts.sigma)
        else:
            k = opts.k if opts.k else int((turns[a:b] == 1).sum())
            found = baselines.entropy_detect(x[a:b], y[a:b], k)
        mask[a + found] = True
    return ManeuverResult(pts, index, np.full(len(pts), np.nan), mask, result.window_p)


def _factor_layer(res) -> pd.DataFrame:
    pts = res.points.copy(deep=False)  # copy-on-write: the new columns do not touch the input
    pts["maneuver_factor"] = res.factor
    pts["is_maneuver"] = res.is_maneuver
    return pts


def run_maneuvers(points: pd.DataFrame, params: dict, progress: Progress = null_progress):
    from wakeline.core.maneuver import MANEUVER_COLUMNS, ManeuverParams

    res = _detect(points, params, progress)
    table = res.table()[list(MANEUVER_COLUMNS)]
    mp = _p(params, "maneuver", ManeuverParams)
    method = _p(params, "maneuver_options", ManeuverOptions).method
    return StepResult(
        "maneuvers",
        [
            NewLayer(
                "maneuvers",
                "maneuvers",
                _factor_layer(res),
                {"threshold_deg": mp.threshold_deg},
                {"maneuvers": table},
            )
        ],
        {"maneuvers": int(len(table)), "tracks": int(res.index.n_tracks), "method": method},
        {"maneuvers": table},
    )


def _summary_maneuvers(res: StepResult) -> Text:
    r = res.report
    return Text(
        [
            phrase(
                "{maneuvers:#maneuver point} in {tracks:#track} ({method})",
                maneuvers=r["maneuvers"],
                tracks=r["tracks"],
                method=r["method"],
            )
        ]
    )


def run_compress(points: pd.DataFrame, params: dict, progress: Progress = null_progress):
    from wakeline.core.compress import CompressParams, compress_with, douglas_peucker_mask
    from wakeline.core.maneuver import MANEUVER_COLUMNS, ManeuverParams
    from wakeline.core.tracks import local_xy, sort_points, track_index

    cp = _p(params, "compress", CompressParams)
    opts = _p(params, "compress_options", CompressOptions)
    layers = []
    from wakeline.core.clean import without_position

    # rows without a position (a table not read by import nor cleaned): left out, counted
    no_position = without_position(points)
    if no_position:
        lon = pd.to_numeric(points["lon"], errors="coerce").to_numpy(dtype="float64")
        lat = pd.to_numeric(points["lat"], errors="coerce").to_numpy(dtype="float64")
        points = points[np.isfinite(lon) & np.isfinite(lat)].reset_index(drop=True)
    if opts.method == "dp":
        pts = sort_points(points)
        index = track_index(pts)
        x, y = local_xy(pts, index)
        keep = douglas_peucker_mask(x, y, index, cp.dp_tolerance_m, distance=opts.dp_distance)
        refine = False
    else:
        from wakeline.core.compress import turning_keep

        res = _detect(points, params, sub_progress(progress, 0.0, 0.7))
        pts, keep, refine = res.points, turning_keep(res, cp), cp.refine
        mp = _p(params, "maneuver", ManeuverParams)
        table = res.table()[list(MANEUVER_COLUMNS)]
        layers.append(
            NewLayer(
                "maneuvers",
                "maneuvers",
                _factor_layer(res),
                {"threshold_deg": mp.threshold_deg},
                {"maneuvers": table},
            )
        )
    progress(0.7, "compressing")
    comp = compress_with(None, keep, refine=refine, sorted_points=pts, keep_ends=cp.keep_ends)
    report = comp.report()
    report["method"] = opts.method
    report["refined_vertices"] = refine
    if no_position:
        report["rows_without_position"] = no_position
    if opts.method != "dp":  # the turning points it kept around, as the maneuvers layer has
        report["maneuvers"] = int(len(table))
        _add_error_bounds(report, res, cp)
    # legs no ship makes (clean's speed test): a raw table's two ships under one id gave
    # bounds of thousands of km with no word of why (operator test 10); said, not changed
    from wakeline.core.clean import CleanParams, track_jumps

    jumps = track_jumps(pts, _p(params, "clean", CleanParams).speed)  # sorted once, above
    if jumps is not None:
        report["jumps"] = jumps
    kept = comp.kept_points()
    per_track = {f"{t['sensor']}\x1f{t['batch']}": t["dis_e_m"] for t in report["tracks"]}
    layers.append(
        NewLayer(
            "compressed",
            "compressed",
            kept,
            {"dis_e_m": report["overall"]["dis_e_m"], "dis_e_by_track": per_track},
        )
    )
    progress(1.0, "compressed")
    return StepResult("compress", layers, report, {"points": kept})


#: Tracks with the largest error bound named in the compress report's ``error_bound``.
WORST_BOUNDS = 5


def _add_error_bounds(report: dict, res, cp) -> None:
    """Each track's noise estimate and the error bound used between kept points
    (``noise_m``, ``error_tol_m`` in ``tracks``), and their spread with the tracks of
    the largest bound in ``error_bound`` (operator test 7, D9: on 30-min posits the
    bound is kilometres)."""
    from wakeline.core.compress import error_bounds

    bounds = error_bounds(res, cp)
    if cp.error_sigmas <= 0 or not len(bounds):
        report["error_bound"] = None
        return
    by_key = {
        (str(s), str(b)): (n, tol)
        for s, b, n, tol in zip(
            bounds["sensor"], bounds["batch"], bounds["noise_m"], bounds["error_tol_m"], strict=True
        )
    }
    for row in report["tracks"]:
        n, tol = by_key.get((str(row["sensor"]), str(row["batch"])), (np.nan, np.nan))
        row["noise_m"] = float(n) if np.isfinite(n) else None  # None: too short to tell
        row["error_tol_m"] = float(tol)
    tol = bounds["error_tol_m"].to_numpy(dtype="float64")
    # the tracks of the largest bound, among those with a noise estimate (a track of one
    # or two points has the floor and no noise to show)
    known = np.isfinite(bounds["noise_m"].to_numpy(dtype="float64"))
    worst = bounds.assign(_t=tol)[known].sort_values("_t", ascending=False, kind="stable")
    dis = {(str(r["sensor"]), str(r["batch"])): r for r in report["tracks"]}
    report["error_bound"] = {
        "error_sigmas": cp.error_sigmas,
        "error_floor_m": cp.error_floor_m,
        "error_cap_m": cp.error_cap_m,
        "capped_tracks": int((cp.error_sigmas * bounds["noise_m"] > tol + 1e-9).sum()),
        "tol_m": {
            "min": float(tol.min()),
            "median": float(np.median(tol)),
            "p90": float(np.quantile(tol, 0.9)),
            "max": float(tol.max()),
        },
        "largest": [
            {
                "sensor": str(r.sensor),
                "batch": str(r.batch),
                "noise_m": float(r.noise_m),
                "error_tol_m": float(r.error_tol_m),
                "max_error_m": float(dis[(str(r.sensor), str(r.batch))]["max_error_m"]),
            }
            for r in worst.head(WORST_BOUNDS).itertuples()
        ],
    }


def _summary_compress(res: StepResult) -> Text:
    o = res.report["overall"]
    found = res.report.get("maneuvers")
    return Text(
        [
            None if found is None else phrase("{n:#maneuver point}; ", n=found),
            phrase(
                "kept {kept:,} of {points:#point} ({ratio:.1%})",
                kept=o["kept"],
                points=o["points"],
                ratio=o["ratio"],
            ),
            phrase(
                " ({rows:#row} repeating the time and place of the row before set aside)",
                rows=o["repeated_rows"],
            )
            if o.get("repeated_rows")
            else None,
            phrase(
                " ({rows:#row} without a position left out)",
                rows=res.report["rows_without_position"],
            )
            if res.report.get("rows_without_position")
            else None,
            phrase("; Dis_e {dis_e:.1f} m", dis_e=o["dis_e_m"]),
            phrase(", Dis_e against truth {dis_e:.1f} m", dis_e=o["dis_e_true_m"])
            if "dis_e_true_m" in o
            else None,
            *_bound_phrases(res.report.get("error_bound"), o),
            _jump_phrase(res.report.get("jumps")),
        ]
    )


def _jump_phrase(jumps: dict | None):
    """Tracks with legs no ship makes (:func:`~wakeline.core.clean.track_jumps`): clean
    first, which splits them (the compressed result is left as it is)."""
    if not jumps:
        return None
    return phrase(
        "; {n:#track} with jumps no ship can make ({legs:#leg} beyond {v:,.0f} kn; {k:,} in "
        "track {track}): clean first (wakeline clean; Clean in the window): it splits such "
        "tracks, and the error bounds then measure noise, not the jumps",
        n=jumps["tracks"],
        legs=jumps["legs"],
        v=jumps["v_max_kn"],
        k=jumps["track_legs"],
        track=f"{jumps['sensor']}:{jumps['batch']}",
    )


def _bound_phrases(bound: dict | None, overall: dict) -> list:
    """The largest error bound used between kept points and the farthest point left off
    the compressed track (operator test 7, D9)."""
    if not bound or not bound.get("largest"):
        return []
    top = bound["largest"][0]
    out = [
        phrase(
            "; largest error bound {tol:,.0f} m (track {track}, noise {noise:,.0f} m; "
            "median {median:,.0f} m), farthest point {far:,.0f} m off",
            tol=top["error_tol_m"],
            track=f"{top['sensor']}:{top['batch']}",
            noise=top["noise_m"],
            median=bound["tol_m"]["median"],
            far=overall.get("max_error_m", 0.0),
        )
    ]
    if bound.get("error_cap_m"):
        out.append(
            phrase(
                " (capped at {cap:,.0f} m on {n:#track})",
                cap=max(bound["error_cap_m"], bound["error_floor_m"]),
                n=bound["capped_tracks"],
            )
        )
    return out


def run_associate(
    points: pd.DataFrame,
    params: dict,
    progress: Progress = null_progress,
    rejected: set[tuple[str, str]] | frozenset = frozenset(),
    split: set[tuple[str, str]] | frozenset = frozenset(),
):
    """The associate step. ``rejected``: pairs of track labels (``sensor:batch``) the
    operator rejected in an earlier run's review, kept out of this one (the session
    passes them when the step runs again on the same layer); ``split``: pairs the
    operator split, kept out the same way (and named in the layer's meta, so a later run
    keeps them out too)."""
    from wakeline.core.associate import (
        LinkParams,
        associate_interrupted,
        associate_segments,
        stitch,
    )

    lp = _p(params, "associate", LinkParams)
    opts = _p(params, "associate_options", AssociateOptions)
    if opts.mode == "segments":
        method = opts.method or "motion"
        if method not in ("motion", "area", "dtw", "hausdorff"):
            raise InputError(
                f"--mode segments takes --method motion|area|dtw|hausdorff, not {method}"
            )
        assoc = associate_segments(points, lp, method=method)
    else:
        method = opts.method or "optimal"
        if method not in ("optimal", "greedy"):
            raise InputError(f"--mode interrupted takes --method optimal|greedy, not {method}")
        assoc = associate_interrupted(
            points, lp, method=method, normalize=opts.normalize, progress=progress
        )
    from wakeline.core.review import association_proposals, mark_plot_tracks
    from wakeline.core.tracks import plot_tracks

    proposals, assoc = association_proposals(assoc, lp, set(rejected) | set(split))
    plots, _ = plot_tracks(points)
    proposals = mark_plot_tracks(proposals, plots)
    out = stitch(assoc, fill=opts.fill) if opts.stitch else assoc.points()
    pairs = assoc.pair_table()
    report = {**assoc.report(), "method": method}
    if plots:
        report["plot_tracks"] = len(plots)
    if rejected:
        report["rejected_kept_out"] = len(rejected)
    if split:
        report["split_kept_out"] = len(split)
    if opts.stitch:
        report["points_filled"] = int(out["interpolated"].sum())
    role = "stitched" if opts.stitch else "associated"
    return StepResult(
        "associate",
        [
            NewLayer(
                role,
                "associated",
                out,
                {"pairs": int(len(pairs))}
                | ({"split_kept_out": sorted(map(list, split))} if split else {}),
                {"pairs": pairs, "proposals": proposals},
            )
        ],
        report,
        {"points": out, "pairs": pairs, "proposals": proposals},
    )


def _summary_associate(res: StepResult) -> Text:
    rep = res.report
    parts = [
        phrase(
            "{tracks:#track} -> {targets:#target} ({joins:#join} of "
            "{candidates:#candidate pair}, {method})",
            tracks=rep["tracks"],
            targets=rep["targets"],
            joins=rep["pairs_chosen"],
            candidates=rep["candidate_pairs"],
            method=option_word(rep["method"]),
        )
    ]
    if rep.get("mmsi_apart_pairs"):
        # Said, so that "0 joins of 0 candidate pairs" on AIS does not read as nothing found.
        parts.append(
            phrase(
                "; {n:#pair} of different MMSIs kept apart (mmsi_apart; off with --set "
                "mmsi_apart=false if the ids are a sensor's own numbers)",
                n=rep["mmsi_apart_pairs"],
            )
        )
    parts.extend(_review_kept(res))
    if rep.get("long_gap_joins"):
        parts.append(
            phrase(
                "; {n:,} of the joins across gaps beyond T_gap (second look)",
                n=rep["long_gap_joins"],
            )
        )
    if rep.get("rest_joins"):
        parts.append(
            phrase("; {n:,} between ends at rest (moored or at anchor)", n=rep["rest_joins"])
        )
    if "points_filled" in rep:
        parts.append(phrase("; {n:#point} filled", n=rep["points_filled"]))
    if rep.get("plot_tracks"):
        parts.append(
            phrase(
                "; warning: {plots:,} of the {tracks:,} tracks are plots, not tracks (several "
                "positions at one time: detections of several targets and clutter): their "
                "joins rest on points of different targets; join the plots into tracks first "
                "(a tracker), or read the file with batch from a column that names one target",
                plots=rep["plot_tracks"],
                tracks=rep["tracks"],
            )
        )
    single = rep.get("single_fix_tracks", 0)
    if rep["tracks"] >= 100 and single > 0.5 * rep["tracks"]:
        parts.append(
            phrase(
                "; warning: {single:,} of the {tracks:,} tracks are single fixes (a file of "
                "radar plots?): each join rests on distance and time alone, so expect wrong "
                "joins where ships are close; a tracker belongs before this step",
                single=single,
                tracks=rep["tracks"],
            )
        )
    return Text(parts)


def kept_out_phrases(rejected: int, split: int) -> list[Phrase]:
    """The words for the pairs a re-run kept out (rejected, split in an earlier review):
    the summaries' and a re-run's carry (:meth:`~wakeline.core.review_session.Carry.text`)."""
    parts = []
    if rejected:
        parts.append(phrase("{n:#pair} rejected in an earlier review kept out", n=rejected))
    if split:
        parts.append(phrase("{n:#pair} split in an earlier review kept out", n=split))
    return parts


def _review_kept(res: StepResult) -> list[Phrase]:
    """The summary's words on an earlier review: what a re-run kept out and carried
    over (:class:`wakeline.core.review_session.Carry`), or the pairs kept out."""
    carry = getattr(res, "carry", None)
    if carry is not None and getattr(carry, "reviewed", True):
        return [phrase("; review of the earlier run: {carry}", carry=carry.text())]
    rep = res.report
    kept = kept_out_phrases(rep.get("rejected_kept_out", 0), rep.get("split_kept_out", 0))
    return [p for k in kept for p in (phrase("; "), k)]


def run_fuse(
    points: pd.DataFrame,
    params: dict,
    progress: Progress = null_progress,
    rejected: set[tuple[str, str]] | frozenset = frozenset(),
    split: set[tuple[str, str]] | frozenset = frozenset(),
):
    """The fuse step. ``rejected``, ``split``: pairs of track labels the operator
    rejected or split in an earlier run's review, kept out of this one as
    :func:`run_associate` keeps them (the fused points are made without them)."""
    from wakeline.core.fuse import FuseParams, associate_sensors, fuse

    fp = _p(params, "fuse", FuseParams)
    opts = _p(params, "fuse_options", FuseOptions)
    assoc = associate_sensors(
        points,
        fp,
        distance=opts.distance,
        method=opts.method,
        progress=sub_progress(progress, 0.0, 0.6),
    )
    from wakeline.core.review import fusion_proposals, mark_plot_tracks
    from wakeline.core.tracks import plot_tracks

    proposals, assoc = fusion_proposals(assoc, fp, set(rejected) | set(split))
    plots, _ = plot_tracks(points)
    proposals = mark_plot_tracks(proposals, plots)
    base = {}
    fused = fuse(assoc, fp, sub_progress(progress, 0.6, 1.0), base)
    pairs = assoc.pair_table()
    if plots:
        # fused and said (operator test 8, D1): a fused track of plots holds several
        # points at one time; the summary counts them and names what to do
        base["plot_tracks"] = len(plots)
        several = fused.duplicated(["batch", "time"], keep=False)
        base["fused_times"] = int(len(fused) - fused.duplicated(["batch", "time"]).sum())
        base["fused_shared_times"] = int(
            (several & ~fused.duplicated(["batch", "time"], keep="first")).sum()
        )
    report = {
        **base,
        **assoc.report(),
        "points_in": int(len(points)),
        "max_distance_m": float(fp.max_distance_m),
        "max_interp_s": float(fp.max_interp_s),
        "min_overlap_s": float(fp.min_overlap_s),
        "min_overlap_fixes": int(fp.min_overlap_fixes),
        "fused_points": int(len(fused)),
        "distance": opts.distance,
        "method": opts.method,
    }
    if rejected:
        report["rejected_kept_out"] = len(rejected)
    if split:
        report["split_kept_out"] = len(split)
    return StepResult(
        "fuse",
        [
            NewLayer(
                "fused",
                "fused",
                fused,
                {"pairs": int(len(pairs))}
                | ({"split_kept_out": sorted(map(list, split))} if split else {}),
                {"pairs": pairs, "proposals": proposals},
            )
        ],
        report,
        {"points": fused, "pairs": pairs, "proposals": proposals},
    )


#: The option values a summary names (associate's and fuse's method, fuse's distance and
#: time_base), each a phrase so that the window says it in its language (operator test 6,
#: D-i18n-2); the command line prints the value itself.
_OPTION_WORDS = {
    "optimal": phrase("optimal"),
    "greedy": phrase("greedy"),
    "sync": phrase("sync"),
    "dtw": phrase("dtw"),
    "dtw_whole": phrase("dtw_whole"),
    "weight": phrase("weight"),
    "densest": phrase("densest"),
    "union": phrase("union"),
}


def option_word(value) -> "Text | str":
    """``value`` (an option's value in a report) as a summary names it: a Text the window
    translates when it is one of :data:`_OPTION_WORDS`, else the value as it is."""
    word = _OPTION_WORDS.get(value) if isinstance(value, str) else None
    return Text([word]) if word is not None else value


def _and_names(names: list[str]) -> "Text | str":
    """Names joined as a sentence does ("AIS and radar", "A, B and C"), the "and" a phrase."""
    if len(names) < 2:
        return "".join(names)
    return Text([phrase("{first} and {last}", first=", ".join(names[:-1]), last=names[-1])])


def _summary_fuse(res: StepResult) -> Text:
    rep = res.report
    parts = [
        phrase(
            "{tracks:#track} of {sensors:#sensor} -> {targets:#target} ({pairs:#pair} of "
            "{candidates:#candidate}, {distance}, {method}); {fused:#fused point}",
            tracks=rep["tracks"],
            sensors=rep["sensors"],
            targets=rep["targets"],
            pairs=rep["pairs_chosen"],
            candidates=rep["candidate_pairs"],
            distance=option_word(rep["distance"]),
            method=option_word(rep["method"]),
            fused=rep["fused_points"],
        )
    ]
    if "points_in" in rep:
        parts.append(phrase(" from {n:#input point}", n=rep["points_in"]))
    if "time_base" in rep:
        parts.extend(_time_base_phrases(rep))
    elif rep.get("points_in", 0) > rep["fused_points"]:
        parts.append(phrase(" (points of two sensors at one time become one)"))
    parts.extend(_review_kept(res))
    if rep.get("repeated_rows"):
        parts.append(
            phrase(
                "; {rows:#row} repeating the time and place of the row before set aside",
                rows=rep["repeated_rows"],
            )
        )
    if not rep.get("pairs_chosen") and "max_distance_m" in rep:
        parts.extend(_no_pair_reason(rep))
    if rep.get("plot_tracks"):
        parts.append(
            phrase(
                "; warning: {plots:,} of the {tracks:,} tracks are plots, not tracks (several "
                "positions at one time: detections of several targets and clutter), so the "
                "fused tracks zig-zag between them and hold several points at {shared:,} of "
                "their {times:,} times; join the plots into tracks first (a tracker), or read "
                "the file with batch from a column that names one target",
                plots=rep["plot_tracks"],
                tracks=rep["tracks"],
                shared=rep.get("fused_shared_times", 0),
                times=rep.get("fused_times", 0),
            )
        )
    return Text(parts)


def _time_base_phrases(rep: dict) -> list[Phrase]:
    """Whose times the fused points take where sensors overlap, and the fixes of the
    other sensors between them that were not kept: '; fused on AIS's 30 s times: 20,880
    RADAR1 fixes between them not kept (--time-base union keeps them)'."""
    base = rep.get("base_fixes") or {}
    if not base:
        return []
    if rep["time_base"] == "union":
        return [phrase("; fused on every sensor's times (time_base union)")]
    interval = rep.get("base_interval_s") or {}
    if len(base) == 1:
        (name,) = base
        dt = interval.get(name, float("nan"))
        on = (
            phrase("{sensor}'s {dt:g} s times", sensor=name, dt=round(dt, 1))
            if np.isfinite(dt)
            else phrase("{sensor}'s times", sensor=name)
        )
    else:
        on = phrase("the times of {sensors}", sensors=_and_names(sorted(base)))
    dropped = rep.get("not_kept") or {}
    if not dropped:
        return [phrase("; fused on {on}", on=Text([on]))]
    lost = " + ".join(f"{n:,} {s}" for s, n in sorted(dropped.items()))
    values = {"on": Text([on]), "rule": option_word(rep["time_base"]), "lost": lost}
    if sum(dropped.values()) == 1:
        return [
            phrase(
                "; fused on {on} (time_base {rule}): {lost} fix between them not kept "
                "(--time-base union keeps it)",
                **values,
            )
        ]
    return [
        phrase(
            "; fused on {on} (time_base {rule}): {lost} fixes between them not kept "
            "(--time-base union keeps them)",
            **values,
        )
    ]


def _short_overlap_text(rep: dict, n: int) -> Phrase:
    """The ``n`` pairs the overlap gate refused, as the summary names the gate:
    min_overlap_s, and min_overlap_fixes over a span of at least half of it (values when
    the report has them)."""
    span = rep.get("min_overlap_s")
    fixes = rep.get("min_overlap_fixes")
    s = Text([phrase(" ({span:g} s)", span=span)]) if span is not None else ""
    if fixes == 0:
        return phrase("{n:,} for a common span under min_overlap_s{span}", n=n, span=s)
    half = Text([phrase(" ({span:g} s)", span=span / 2)]) if span is not None else ""
    fx = f" ({fixes:,})" if fixes is not None else ""
    return phrase(
        "{n:,} for a common span under min_overlap_s{span} without min_overlap_fixes{fixes} "
        "of each track in at least half of it{half}",
        n=n,
        span=s,
        fixes=fx,
        half=half,
    )


def _no_pair_reason(rep: dict) -> list[Phrase]:
    """Why fusion paired nothing: the gate that refused the pairs found near each other."""
    probed = rep.get("probed_pairs", 0)
    if not probed:
        return [
            phrase(
                "; no candidate was close enough: the tracks of different sensors are farther "
                "apart than max_distance_m ({max_distance:g} m) or their times are further "
                "apart than max_interp_s ({max_interp:g} s) — raise them with --set if the "
                "sensors are that noisy or sparse",
                max_distance=rep["max_distance_m"],
                max_interp=rep["max_interp_s"],
            )
        ]
    parts = []
    if rep.get("refused_short_overlap"):
        parts.append(_short_overlap_text(rep, rep["refused_short_overlap"]))
    if rep.get("refused_count_ratio"):
        parts.append(
            phrase(
                "{n:,} for a point-count ratio over count_ratio_max (or under 2 points in the "
                "common span)",
                n=rep["refused_count_ratio"],
            )
        )
    refused = Text(joined(parts) if parts else [phrase("none by the gates")])
    out = [
        phrase(
            "; {probed:#pair} of tracks came within max_distance_m ({max_distance:g} m) of "
            "each other, refused: {refused}",
            probed=probed,
            max_distance=rep["max_distance_m"],
            refused=refused,
        )
    ]
    rest = probed - rep.get("refused_short_overlap", 0) - rep.get("refused_count_ratio", 0)
    if rest:
        if rest == 1 and probed == 1:
            out.append(phrase("; it was farther apart on average than the gate"))
        elif rest == 1:
            out.append(phrase("; the other one was farther apart on average than the gate"))
        elif rest == probed:
            out.append(phrase("; all {n:,} were farther apart on average than the gate", n=rest))
        else:
            out.append(
                phrase("; the other {n:,} were farther apart on average than the gate", n=rest)
            )
        if rep.get("nearest_m") is not None:
            out.append(
                phrase(
                    " (the nearest {nearest:,.0f} m apart on average: raise max_distance_m "
                    "with --set if the sensors are that noisy)",
                    nearest=rep["nearest_m"],
                )
            )
    return out


@dataclass(frozen=True)
class Step:
    """One pipeline step: its function, parameter sets and command-line outputs."""

    name: str  # the CLI subcommand and the session's step name
    title: str
    params: tuple[tuple[str, type], ...]  # (key, parameter class), as run() reads them
    run: Callable[[pd.DataFrame, dict, Progress], StepResult]
    summary: Callable[[StepResult], Text]  # English as a str; phrases for a translator
    output: str = "points"  # the table written with -o
    outputs: tuple[tuple[str, str], ...] = ()  # (table, flag) written on request
    primary: str = ""  # the role of the layer the next pipeline stage reads
    many_inputs: bool = False  # takes several files (one per sensor) on the command line
    #: its output keeps a few points per track (compress): a later stage that joins
    #: tracks does not read it (see ``joins_tracks``)
    simplifies: bool = False
    #: joins tracks (associate, fuse): in a pipeline it reads the tracks whole, the output
    #: of the last stage before it that does not simplify (the cleaned tracks after clean
    #: → compress), not a compressed layer (operator test 7, D5: associate on the
    #: compressed tracks joined worse)
    joins_tracks: bool = False

    def defaults(self) -> dict[str, Any]:
        return {key: cls() for key, cls in self.params}

    def __call__(
        self, points: pd.DataFrame, params: dict | None = None, progress: Progress | None = None
    ) -> StepResult:
        return self.run(points, {**self.defaults(), **(params or {})}, progress or null_progress)


def _clean_cls():
    from wakeline.core.clean import CleanParams

    return CleanParams


def _steps() -> dict[str, Step]:
    from wakeline.core.associate import LinkParams
    from wakeline.core.compress import CompressParams
    from wakeline.core.fuse import FuseParams
    from wakeline.core.maneuver import ManeuverParams

    maneuver = (("maneuver", ManeuverParams), ("maneuver_options", ManeuverOptions))
    return {
        s.name: s
        for s in (
            Step(
                "clean",
                "Clean",
                (("clean", _clean_cls()),),
                run_clean,
                _summary_clean,
                outputs=(("rejected", "--rejected"),),
                primary="cleaned",
            ),
            Step(
                "maneuvers",
                "Maneuvers",
                maneuver,
                run_maneuvers,
                _summary_maneuvers,
                output="maneuvers",
                primary="maneuvers",
            ),
            Step(
                "compress",
                "Compress",
                (*maneuver, ("compress", CompressParams), ("compress_options", CompressOptions)),
                run_compress,
                _summary_compress,
                primary="compressed",
                simplifies=True,
            ),
            Step(
                "associate",
                "Associate",
                (("associate", LinkParams), ("associate_options", AssociateOptions)),
                run_associate,
                _summary_associate,
                outputs=(("pairs", "--pairs"), ("proposals", "--proposals")),
                primary="associated",
                joins_tracks=True,
            ),
            Step(
                "fuse",
                "Fuse",
                (("fuse", FuseParams), ("fuse_options", FuseOptions)),
                run_fuse,
                _summary_fuse,
                outputs=(("pairs", "--pairs"), ("proposals", "--proposals")),
                primary="fused",
                many_inputs=True,
                joins_tracks=True,
            ),
        )
    }


class _Registry(dict):
    """``STEPS``: filled on first use so that importing this module stays light."""

    def _fill(self) -> None:
        if not dict.__len__(self):
            self.update(_steps())

    def __getitem__(self, key: str) -> Step:
        self._fill()
        if not dict.__contains__(self, key):
            raise InputError(f"unknown step {key!r}; steps: {', '.join(self)}")
        return dict.__getitem__(self, key)

    def __iter__(self):
        self._fill()
        return dict.__iter__(self)

    def __len__(self) -> int:
        self._fill()
        return dict.__len__(self)

    def __contains__(self, key: object) -> bool:
        self._fill()
        return dict.__contains__(self, key)

    def items(self):
        self._fill()
        return dict.items(self)

    def values(self):
        self._fill()
        return dict.values(self)

    def keys(self):
        self._fill()
        return dict.keys(self)


#: Every step by name (the CLI's subcommand names).
STEPS: dict[str, Step] = _Registry()


# -- parameters as JSON (presets, project, pipeline files) -------------------------------


def params_to_json(params: dict[str, Any]) -> dict[str, dict]:
    """Parameter sets as plain dicts (CleanParams nests one dict per rule)."""
    return {key: dataclasses.asdict(value) for key, value in params.items()}


#: Pipeline file version. 2 (h79): ``max_window_s`` of the maneuver detector is the longest
#: window itself; in version 1 windows doubled from ``window_s`` while within it.
PIPELINE_VERSION = 2


def _ladder_top_v1(values: dict) -> dict:
    """A version-1 maneuver parameter dict with ``max_window_s`` turned into the window its
    ladder ended with then (``window_s`` doubled while within it), so the file's detector
    runs the windows it ran: 600 s from 10 s windows is 320 s."""
    from wakeline.core.maneuver import ManeuverParams

    if not isinstance(values, dict) or "max_window_s" not in values:
        return values
    try:  # a value that is no finite number is left for the parameters' own check
        w = finite_number(values.get("window_s", ManeuverParams().window_s), "window_s")
        top = finite_number(values["max_window_s"], "max_window_s")
    except ValueError:
        return values
    if w <= 0 or top <= 0 or top > 1e7:  # 1e7: the field's range (a 2**k loop stays short)
        return values
    last = w
    while last * 2 <= top:  # version 1's rule, exactly
        last *= 2
    return {**values, "max_window_s": last}


#: Version of a saved parameter table in the panel's form (group -> field -> value: a
#: parameter preset, a project's ``params``). 2: ``max_window_s`` is the longest window
#: itself (see :data:`PIPELINE_VERSION`); a table without a version is version 1.
PARAMS_VERSION = 2


def params_from_version(data: dict, version: int) -> dict:
    """A saved parameter table (the panel's form) read as today's: version 1's maneuver
    ``max_window_s`` becomes the window its ladder ended with (:func:`_ladder_top_v1`)."""
    if version >= PARAMS_VERSION or not isinstance(data, dict):
        return data
    return {k: _ladder_top_v1(v) if k == "maneuver" else v for k, v in data.items()}


def params_from_json(step: str, data: dict[str, dict]) -> dict[str, Any]:
    """The parameter sets of ``step`` from :func:`params_to_json` output (checked)."""
    out = STEPS[step].defaults()
    for key, value in (data or {}).items():
        if key not in out:
            raise InputError(f"step {step}: unknown parameter set {key!r}; known: {', '.join(out)}")
        default = out[key]
        if hasattr(default, "with_settings"):  # CleanParams: rule -> {param: value}
            settings = {
                f"{rule}.{name}": str(v).lower() if isinstance(v, bool) else str(v)
                for rule, values in value.items()
                for name, v in values.items()
            }
            out[key] = default.with_settings(settings).checked()
        else:
            out[key] = dataclasses.replace(default, **value).checked()
    return out


def _v1(step: str, data: dict, old: bool) -> dict:
    """``data`` (a step's parameter sets from a pipeline file) with version 1's maneuver
    ``max_window_s`` translated (:func:`_ladder_top_v1`) when ``old``."""
    if not old or not isinstance(data, dict):
        return data
    from wakeline.core.maneuver import ManeuverParams

    defaults = STEPS[step].defaults() if step in STEPS else {}
    return {
        key: _ladder_top_v1(value) if isinstance(defaults.get(key), ManeuverParams) else value
        for key, value in data.items()
    }


class StageChain:
    """What each stage of a pipeline reads: the previous stage's primary output, or, for
    a stage that joins tracks (``Step.joins_tracks``: associate, fuse), the output of the
    last stage before it that does not simplify the tracks (``Step.simplifies``:
    compress), so that clean → compress → associate associates the cleaned tracks
    (operator test 7, D5). Holds any kind of value: points (:meth:`Pipeline.run`, batch)
    or layer ids (the session)."""

    def __init__(self, start: Any) -> None:
        self.last = start
        self.whole = start

    def input(self, name: str) -> Any:
        """What stage ``name`` (next) reads."""
        return self.whole if STEPS[name].joins_tracks else self.last

    def done(self, name: str, output: Any) -> None:
        """Stage ``name`` made ``output`` (its primary output, or what it read)."""
        self.last = output
        if not STEPS[name].simplifies:
            self.whole = output


def stage_input(names: list[str] | tuple[str, ...], k: int) -> int:
    """The index of the stage whose output stage ``k`` of ``names`` reads (-1: the
    pipeline's input), by :class:`StageChain`'s rule."""
    chain = StageChain(-1)
    for j, name in enumerate(names[:k]):
        chain.done(name, j)
    return chain.input(names[k])


@dataclass(frozen=True)
class Pipeline:
    """A saved sequence of steps with their parameters (the GUI's presets, ``batch``)."""

    stages: tuple[tuple[str, dict[str, Any]], ...]

    @classmethod
    def default(cls) -> "Pipeline":
        """Clean, then find maneuvers and compress."""
        return cls(
            (("clean", STEPS["clean"].defaults()), ("compress", STEPS["compress"].defaults()))
        )

    def to_json(self) -> str:
        return json.dumps(
            {
                "wakeline_pipeline": PIPELINE_VERSION,
                "steps": [
                    {"step": name, "params": params_to_json(params)} for name, params in self.stages
                ],
            },
            indent=2,
        )

    @classmethod
    def from_json(cls, text: str) -> "Pipeline":
        try:
            data = json.loads(text)
            old = data.get("wakeline_pipeline", 1) == 1  # max_window_s: see PIPELINE_VERSION
            stages = tuple(
                (s["step"], params_from_json(s["step"], _v1(s["step"], s.get("params", {}), old)))
                for s in data["steps"]
            )
        except (ValueError, KeyError, TypeError) as exc:
            raise InputError(f"not a Wakeline pipeline: {exc}") from None
        return cls(stages)

    def run(
        self,
        points: pd.DataFrame,
        progress: Progress | None = None,
        run_stage: Callable[[str, dict, pd.DataFrame, Progress], StepResult] | None = None,
    ) -> StepResult:
        """Run the stages in order, each on the previous stage's primary output, except
        that a stage joining tracks (associate, fuse) reads the tracks whole: the output
        of the last stage before it that does not simplify them (:func:`stage_input`;
        clean → compress → associate associates the cleaned tracks, compress's layer
        stays beside them). ``run_stage(name, params, points, progress)``: runs one
        stage in place of the step itself (a session's, which keeps a reviewed stage's
        review: :meth:`wakeline.core.session.Session.run_pipeline`)."""
        progress = progress or null_progress
        stages = []
        chain = StageChain(points)
        n = len(self.stages)
        for k, (name, params) in enumerate(self.stages):
            step = STEPS[name]
            sub = sub_progress(progress, k / n, (k + 1) / n)
            current = chain.input(name)
            res = run_stage(name, params, current, sub) if run_stage else step(current, params, sub)
            stages.append(dataclasses.replace(res, params={**step.defaults(), **params}))
            nxt = [lay for lay in res.layers if lay.suffix == step.primary]
            chain.done(name, nxt[0].points if nxt else res.tables.get("points", current))
        return StepResult(
            "pipeline",
            [lay for res in stages for lay in res.layers],
            {res.step: res.report for res in stages},
            stages[-1].tables if stages else {},
            stages,
        )


# -- the old names (kept for callers that take one parameter set each) -------------------


def step_clean(points: pd.DataFrame, params, progress: Progress | None = None) -> StepResult:
    return STEPS["clean"](points, {"clean": params}, progress)


def step_maneuvers(points: pd.DataFrame, params, progress: Progress | None = None) -> StepResult:
    return STEPS["maneuvers"](points, {"maneuver": params}, progress)


def step_compress(
    points: pd.DataFrame, mparams, cparams, progress: Progress | None = None
) -> StepResult:
    return STEPS["compress"](points, {"maneuver": mparams, "compress": cparams}, progress)


def step_associate(points: pd.DataFrame, params, progress: Progress | None = None) -> StepResult:
    return STEPS["associate"](points, {"associate": params}, progress)


def step_fuse(points: pd.DataFrame, params, progress: Progress | None = None) -> StepResult:
    return STEPS["fuse"](points, {"fuse": params}, progress)


def default_pipeline(points, cleaning, mparams, cparams, progress=None) -> StepResult:
    """Clean, then find maneuvers and compress (what ``wakeline gui --screenshot`` runs)."""
    pipe = Pipeline(
        (("clean", {"clean": cleaning}), ("compress", {"maneuver": mparams, "compress": cparams}))
    )
    full = {name: {**STEPS[name].defaults(), **params} for name, params in pipe.stages}
    return Pipeline(tuple(full.items())).run(points, progress)


def step_bearing(bearings: pd.DataFrame, params, progress: Progress | None = None) -> StepResult:
    """Bearing-only maneuver detection (seed 002) on every sequence; no new layer. The
    report's ``report`` says per batch what was tested and why windows were skipped;
    ``why`` holds it as log lines. Tables: ``detections`` and ``statistic`` (the z of
    every tested boundary, :func:`~wakeline.core.bearing.detect_with_statistic`; the
    Detail panel's curves, not kept in a project)."""
    from wakeline.core.bearing import detect_with_statistic, report_lines

    (progress or null_progress)(0.0, "AUC detection")
    detections, report, statistic = detect_with_statistic(bearings, params)
    return StepResult(
        "bearing",
        [],
        {
            "sequences": int(bearings["batch"].nunique()),
            "detections": int(len(detections)),
            "report": report,
            "why": report_lines(report),
        },
        {"detections": detections, "statistic": statistic},
    )
