"""Pipeline steps as the application runs them: core calls bundled with their outputs.

Each step takes a point table and parameters and returns a :class:`StepResult`: new
layers (name suffix, kind, points), an optional maneuver table and a report. The GUI runs
these in its worker thread; the command line and tests call them directly.
"""

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from wakeline.core.associate import LinkParams, associate_interrupted
from wakeline.core.bearing import BearingParams, detect_with_report, report_lines
from wakeline.core.clean import CleanParams, clean
from wakeline.core.compress import CompressParams, compress_with
from wakeline.core.fuse import FuseParams, associate_sensors, fuse
from wakeline.core.maneuver import ManeuverParams, detect
from wakeline.core.progress import Progress, null_progress, sub_progress


@dataclass(frozen=True)
class NewLayer:
    suffix: str
    kind: str
    points: pd.DataFrame
    meta: dict = field(default_factory=dict)


@dataclass(frozen=True)
class StepResult:
    step: str
    layers: list[NewLayer]
    report: dict


def _with_factor(points: pd.DataFrame, params: ManeuverParams, progress: Progress):
    res = detect(points, params, progress)
    pts = res.points.copy()
    pts["maneuver_factor"] = np.round(res.factor, 3)
    pts["is_maneuver"] = res.is_maneuver
    return res, pts


def step_clean(points: pd.DataFrame, params: CleanParams, progress: Progress | None = None):
    res = clean(points, params, progress=progress)
    return StepResult(
        "clean",
        [NewLayer("cleaned", "cleaned", res.points, {"rejected": int(len(res.rejected))})],
        res.report,
    )


def step_maneuvers(
    points: pd.DataFrame, params: ManeuverParams, progress: Progress | None = None
) -> StepResult:
    res, pts = _with_factor(points, params, progress or null_progress)
    table = res.table()
    return StepResult(
        "maneuvers",
        [NewLayer("maneuvers", "maneuvers", pts, {"threshold_deg": params.threshold_deg})],
        {"maneuvers": int(len(table)), "tracks": int(res.index.n_tracks)},
    )


def step_compress(
    points: pd.DataFrame,
    mparams: ManeuverParams,
    cparams: CompressParams,
    progress: Progress | None = None,
) -> StepResult:
    progress = progress or null_progress
    res, pts = _with_factor(points, mparams, sub_progress(progress, 0.0, 0.7))
    progress(0.7, "compressing")
    comp = compress_with(pts, res.is_maneuver, refine=cparams.refine, sorted_points=pts)
    rep = comp.report()
    kept = comp.kept_points()
    kept["dis_e_m"] = np.repeat(
        [t["dis_e_m"] for t in rep["tracks"]], np.add.reduceat(comp.kept, comp.index.starts)
    )
    progress(1.0, "compressed")
    return StepResult(
        "compress",
        [
            NewLayer("maneuvers", "maneuvers", pts, {"threshold_deg": mparams.threshold_deg}),
            NewLayer("compressed", "compressed", kept, {"dis_e_m": rep["overall"]["dis_e_m"]}),
        ],
        rep["overall"],
    )


def step_associate(
    points: pd.DataFrame, params: LinkParams, progress: Progress | None = None
) -> StepResult:
    assoc = associate_interrupted(points, params, progress=progress)
    out = assoc.points()
    return StepResult(
        "associate",
        [
            NewLayer(
                "associated", "associated", out, {"pairs": assoc.pair_table().to_dict("records")}
            )
        ],
        assoc.report(),
    )


def step_fuse(points: pd.DataFrame, params: FuseParams, progress: Progress | None = None):
    progress = progress or null_progress
    assoc = associate_sensors(points, params, progress=sub_progress(progress, 0.0, 0.6))
    fused = fuse(assoc, params, sub_progress(progress, 0.6, 1.0))
    return StepResult(
        "fuse",
        [NewLayer("fused", "fused", fused, {"pairs": assoc.pair_table().to_dict("records")})],
        assoc.report(),
    )


def default_pipeline(
    points: pd.DataFrame,
    cleaning: CleanParams,
    mparams: ManeuverParams,
    cparams: CompressParams,
    progress: Progress | None = None,
) -> StepResult:
    """Clean, then find maneuvers and compress (what ``wakeline gui --screenshot`` runs)."""
    progress = progress or null_progress
    cleaned = step_clean(points, cleaning, sub_progress(progress, 0.0, 0.5))
    comp = step_compress(
        cleaned.layers[0].points, mparams, cparams, sub_progress(progress, 0.5, 1.0)
    )
    return StepResult(
        "pipeline",
        [cleaned.layers[0], *comp.layers],
        {"clean": cleaned.report, "compress": comp.report},
    )


def step_bearing(
    bearings: pd.DataFrame, params: BearingParams, progress: Progress | None = None
) -> StepResult:
    """Bearing-only maneuver detection (seed 002) on every sequence; no new layer. The
    summary's ``report`` says per batch what was tested and why windows were skipped;
    ``why`` holds it as log lines."""
    (progress or null_progress)(0.0, "AUC detection")
    detections, report = detect_with_report(bearings, params)
    return StepResult(
        "bearing",
        [],
        {
            "sequences": int(bearings["batch"].nunique()),
            "detections": int(len(detections)),
            "table": detections,
            "report": report,
            "why": report_lines(report),
        },
    )
