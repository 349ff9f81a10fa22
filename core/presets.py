"""Built-in parameter presets: measured settings an operator chooses by name (session 29).

Several settings measured on this project are options, not defaults: each failed a
pre-registered guard somewhere (docs/prereg/README.md), yet each is much better on some
kind of data. A preset names one of them: its purpose in a line, the evidence (the
figures and the docs/evaluation.md section), and its changes as a partial table in the
parameter panel's form (parameter set -> field -> value), applied over the defaults (or
over any values) and validated by the parameter dataclasses as every value is. The
command line (``--preset NAME``, ``wakeline presets``) and the parameter panel's
"Built-in presets" menu are generated from :data:`PRESETS` (:func:`presets`).

:func:`suggested_presets` says which preset suits a loaded layer, from the detector's own
noise estimate and the sampling (the panel's guidance paragraph).
"""

import dataclasses
import re
from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np
import pandas as pd

from wakeline.core.errors import InputError


@dataclass(frozen=True)
class Preset:
    """A named measured setting: ``changes`` by parameter set (the pipeline's keys:
    ``maneuver``, ``compress`` …) and field, over the defaults."""

    name: str  # the command line's name (``--preset noisy-tracks``)
    title: str  # the menu's
    purpose: str  # one line: what data it is for
    evidence: str  # the figures, and where they are
    changes: Mapping[str, Mapping[str, Any]]

    def table(self) -> dict[str, dict[str, Any]]:
        """The changes as a plain partial table (the panel's form)."""
        return {key: dict(values) for key, values in self.changes.items()}


#: The evaluation document's sections the evidence names.
NOISY_SECTIONS = '"A confirmation test per turn (session 29)", "Grown legs for gradual turns"'


def _paper_changes() -> dict[str, dict[str, Any]]:
    """Every parameter set with a ``paper()`` (seed 000 as written): its fields that
    differ from the defaults, by the pipeline's key."""
    from wakeline.core.pipeline import STEPS

    out: dict[str, dict[str, Any]] = {}
    for step in STEPS.values():
        for key, cls in step.params:
            if key in out or not hasattr(cls, "paper"):
                continue
            paper, default = cls.paper(), cls()
            out[key] = {
                f.name: getattr(paper, f.name)
                for f in dataclasses.fields(cls)
                if getattr(paper, f.name) != getattr(default, f.name)
            }
    return out


@lru_cache(maxsize=1)
def presets() -> dict[str, Preset]:
    """The built-in presets by name, in the menu's order."""
    items = (
        Preset(
            "noisy-tracks",
            "Noisy tracks",
            "tracks whose position noise is large for their sampling (radar, sparse or "
            "simulated AIS): far fewer false turns",
            "confirm_z 4 + confirm_grow 4: long noisy tracks 8,015 -> 17 false "
            "turns (207/207 found); hard scenes precision 0.401 -> 0.543 at recall 0.970; "
            "Autoferry radar precision 0.90 -> 1.00 at recall 0.86; MTAD maneuvers 1,297 -> "
            "341. Costs: seed 000's compression Dis_e up to +5.0 % (fewer points kept); slow "
            "share DMA 0.034 -> 0.037, MTAD 0.005 -> 0.012 (docs/evaluation.md "
            f"{NOISY_SECTIONS})",
            {"maneuver": {"confirm_z": 4.0, "confirm_grow": 4}},
        ),
        Preset(
            "paper",
            "Paper (as written)",
            "the seed papers' methods as written (seed 000: windows in points, one scale, "
            "no speed, noise or at-rest rules; raw vertices): for comparison",
            "each step's paper() parameters (seed 000 etc.); docs/evaluation.md tables "
            "give them as the 'paper' rows",
            _paper_changes(),
        ),
    )
    return {p.name: p for p in items}


@dataclass(frozen=True)
class Retired:
    """A built-in preset no longer offered whose name is still accepted (a command line or
    script naming it): it changes nothing and :attr:`note` says why."""

    name: str
    title: str
    #: the parameter sets it changed (the commands whose ``--preset`` took it)
    keys: tuple[str, ...]
    note: str


#: Retired presets by name. ``slow-radar`` (session 29, ``radius_s`` 15 + ``edge_s`` 12):
#: session 31 (h241, docs/prereg/session31_slow_scans_b.md) made these values the
#: defaults, gated by ``step_noise_max`` 0.15; the ungated pair measured worse than the
#: new default on every set (docs/evaluation.md "Session 31: slow scans, gated").
RETIRED: dict[str, Retired] = {
    "slow-radar": Retired(
        "slow-radar",
        "Slow radar scans (3-7 s)",
        ("maneuver",),
        "slow-radar: this preset was retired, its values (radius_s 15, edge_s 12) are now the defaults; nothing changed",
    ),
}


def _retired(name: str) -> Retired | None:
    """The retired preset of this name or title (any case); None for any other."""
    key = name.strip().lower()
    return next((r for r in RETIRED.values() if key in (r.name, r.title.lower())), None)


def retired_note(name: str) -> str | None:
    """The note for a retired preset's name or title (any case); None for any other."""
    r = _retired(name)
    return r.note if r is not None else None


def preset(name: str) -> Preset:
    """The preset called ``name`` (its name or its title, any case); a retired one
    (:data:`RETIRED`) as a preset that changes nothing; InputError naming the known ones
    otherwise."""
    table = presets()
    key = name.strip().lower()
    for p in table.values():
        if key in (p.name, p.title.lower()):
            return p
    r = _retired(name)
    if r is not None:
        return Preset(r.name, r.title, r.note, r.note, {})
    raise InputError(f"unknown preset {name!r}; presets: {', '.join(table)}")


def apply_preset(which: "Preset | str", params: Mapping[str, Any]) -> dict[str, Any]:
    """``params`` (parameter sets by the pipeline's key, e.g. a step's defaults) with the
    preset's changes for the sets they hold applied and checked; the others as given."""
    p = preset(which) if isinstance(which, str) else which
    out = dict(params)
    for key, values in p.changes.items():
        if key not in out or not values:
            continue
        current = out[key]
        if hasattr(current, "with_settings"):  # CleanParams: rule -> {param: value}
            settings = [f"{rule}.{n}={v}" for rule, vals in values.items() for n, v in vals.items()]
            out[key] = current.with_settings(settings).checked()
        else:
            out[key] = current.replace(**values).checked()
    return out


def menu_table(
    which: "Preset | str", current: Mapping[str, Mapping[str, Any]] | None = None
) -> dict[str, dict[str, Any]]:
    """What choosing the preset in the parameter panel sets: its changes, and each field
    another built-in preset changes back at its default where that preset is still in
    effect, i.e. where the ``current`` value (the panel's table, parameter set -> field ->
    value) is that preset's value (switching from one preset to another leaves nothing of
    the first); a value the operator set (any other) is kept, and so are the fields no
    preset touches. Without ``current`` every other preset's field is set back (review
    h216: with every field, choosing "Noisy tracks" after "Paper" was right but it also
    reset the operator's own window_s, 14 fields in all)."""
    from wakeline.core.pipeline import STEPS

    p = preset(which) if isinstance(which, str) else which
    if p.name in RETIRED:
        return {}  # changes nothing, not even another preset's values
    classes = {key: cls for step in STEPS.values() for key, cls in step.params}
    out = p.table()
    for other in presets().values():
        if other.name == p.name:
            continue
        for key, values in other.changes.items():
            default = classes[key]()
            for name, value in values.items():
                if name in out.get(key, {}):
                    continue  # the chosen preset's own value
                if current is not None:
                    now = current.get(key, {}).get(name, getattr(default, name))
                    if now != value:
                        continue  # the operator's value, or the default already
                out.setdefault(key, {})[name] = getattr(default, name)
    return out


def preset_pipeline(pipe, which: "Preset | str"):
    """A :class:`~wakeline.core.pipeline.Pipeline` with the preset applied to every
    stage's parameter sets (over the file's values: ``wakeline batch --preset``)."""
    from wakeline.core.pipeline import Pipeline

    p = preset(which) if isinstance(which, str) else which
    return Pipeline(tuple((name, apply_preset(p, params)) for name, params in pipe.stages))


def preset_lines() -> list[str]:
    """Every preset as text: name and title, purpose, changes, evidence (``wakeline
    presets``)."""
    lines = []
    for p in presets().values():
        changes = "; ".join(
            f"{key}: " + ", ".join(f"{n}={v}" for n, v in values.items())
            for key, values in p.changes.items()
            if values
        )
        lines += [
            f"{p.name}  ({p.title})",
            f"  purpose:  {p.purpose}",
            f"  changes:  {changes}",
            f"  evidence: {p.evidence}",
        ]
    return lines


# -- which preset suits the data -----------------------------------------------------------

#: Rows read for the noise estimate (whole tracks, in order, until this many).
SUGGEST_MAX_ROWS = 200_000
#: Above this median interval (s) the noise-tracks preset is not suggested: between fixes
#: this far apart the track's measured "noise" (its neighbours' interpolation) is the
#: ship's own motion (ATD's 30-min posits gave ratios 2.4–2.7 and the preset changed
#: little there: 1,422 → 1,387 maneuvers).
NOISY_MAX_INTERVAL_S = 600.0
#: A track's id that is an AIS MMSI (9 digits, 2-7 first: a ship station), alone or in a
#: longer name ("Scene-0.csv:209351000-0").
_MMSI = re.compile(r"(?:^|\D)[2-7]\d{8}(?:\D|$)")


@dataclass(frozen=True)
class Suggestion:
    """A preset suggested for the data, and the measured figures that suggest it."""

    name: str
    #: noisy-tracks: the median over tracks of k · σ_δ / threshold (above 1: the noise
    #: floor, not the threshold, decides which turns count)
    value: float


def looks_like_ais(points: pd.DataFrame) -> bool:
    """The points are AIS: a sensor named AIS, or at least half the tracks named by MMSI."""
    if points.empty:
        return False
    sensors = points["sensor"].astype(str).unique()
    if any("ais" in s.lower() for s in sensors):
        return True
    names = pd.Series(points["batch"].astype(str).unique())
    return bool(names.str.contains(_MMSI).mean() >= 0.5)


def noise_floor_ratio(points: pd.DataFrame, params=None) -> float:
    """The median over tracks of the detector's noise floor at the first scale over its
    threshold: :func:`noise_floor_deg` / threshold_deg (the threshold a scalar, the median
    of the ratio is the ratio of the median)."""
    from wakeline.core.maneuver import ManeuverParams

    mp = params or ManeuverParams()
    return noise_floor_deg(points, mp) / mp.threshold_deg


def noise_floor_deg(points: pd.DataFrame, params=None) -> float:
    """The median over tracks of the detector's noise floor at the first scale (°):
    k · σ_δ, σ_δ = √2 · σ √(12 / p) / L rad (the δ error of two
    windows of p points, :func:`~wakeline.core.maneuver._heading_noise_deg`), σ the track's
    position noise as the detector measures it (:func:`~wakeline.core.maneuver.position_noise_m`),
    p the first scale's points at the track's median interval, L the median over the
    track's windows of p points of the distance from first to last point (the detector's
    leg: not the path length, which noise lengthens), k ``noise_k`` (the default's 2 when
    off).
    Above 1 on a typical track: the noise, not the threshold, decides which turns count.
    Tracks of fewer than 2p − 1 points, or not moving, are not counted; NaN when none is.
    At most :data:`SUGGEST_MAX_ROWS` rows are read (whole tracks, in order)."""
    from wakeline.core.maneuver import ManeuverParams, _noise_lag, position_noise_m, window_points
    from wakeline.core.tracks import (
        local_xy,
        median_interval_s,
        sorted_with_index,
        track_seconds,
    )

    mp = params or ManeuverParams()
    if points.empty:
        return float("nan")
    pts, index = sorted_with_index(points)
    if len(pts) > SUGGEST_MAX_ROWS:
        last = int(np.searchsorted(index.ends, SUGGEST_MAX_ROWS, side="left"))
        pts = pts.iloc[: int(index.ends[min(last, index.n_tracks - 1)])]
        pts, index = sorted_with_index(pts)
    x, y = local_xy(pts, index)
    t = track_seconds(pts)
    med = median_interval_s(t, index)
    sigma = position_noise_m(x, y, t, index, _noise_lag(med if mp.window_s > 0 else None, mp))
    p = np.full(index.n_tracks, int(mp.window_p), dtype="float64")
    if mp.window_s > 0:
        with np.errstate(invalid="ignore", divide="ignore"):
            p = window_points(mp.window_s, med, mp.window_p, mp.window_max_s)
        p = p.astype("float64")
    # L: the distance a window of p points spans, first to last (the detector's, not the
    # track's path length, which the noise lengthens), its median per track
    tr = index.track_of_row
    p_row = p.astype("int64")[tr]
    row = np.arange(len(pts))
    far = row + p_row - 1
    inside = far < index.ends[tr]
    i, j = row[inside], far[inside]
    chord = np.hypot(x[j] - x[i], y[j] - y[i])
    leg = pd.Series(chord).groupby(tr[inside]).median().reindex(range(index.n_tracks))
    leg = leg.to_numpy(dtype="float64")
    with np.errstate(invalid="ignore", divide="ignore"):
        k = mp.noise_k if mp.noise_k > 0 else ManeuverParams().noise_k
        noise = k * np.degrees(np.sqrt(2.0) * sigma * np.sqrt(12.0 / p) / leg)
    ok = (index.sizes >= 2 * p - 1) & np.isfinite(noise) & (leg > 0)
    return float(np.median(noise[ok])) if ok.any() else float("nan")


#: The maneuver fields :func:`noise_floor_deg` reads (the threshold is not one of them):
#: a change of one of these needs :func:`suggest_inputs` again, of the threshold not.
NOISE_FIELDS = (
    "window_p",
    "window_s",
    "window_max_s",
    "noise_k",
    "noise_lag_s",
)


@dataclass(frozen=True)
class SuggestInputs:
    """What the suggestion reads of the points (:func:`suggest_inputs`, the slow part, run
    once per layer and set of :data:`NOISE_FIELDS`); :func:`suggest_from` compares it
    with a threshold (cheap)."""

    #: :func:`noise_floor_deg` (NaN: no track to judge)
    noise_deg: float
    #: the median over tracks of each one's median interval (s); NaN: none
    interval_s: float
    #: :func:`looks_like_ais` (no rule reads it since slow-radar was removed, h247; kept as
    #: a measured property of the layer)
    ais: bool


def suggest_inputs(points: pd.DataFrame, params=None) -> SuggestInputs:
    """The points' part of :func:`suggested_presets` (with maneuver parameters ``params``,
    default the defaults; only :data:`NOISE_FIELDS` matter)."""
    from wakeline.core.tracks import median_interval_s, sorted_with_index, track_seconds

    if points.empty:
        return SuggestInputs(float("nan"), float("nan"), False)
    noise = noise_floor_deg(points, params)
    pts, index = sorted_with_index(points)
    med = median_interval_s(track_seconds(pts), index)
    med = med[(index.sizes > 1) & np.isfinite(med)]
    interval = float(np.median(med)) if len(med) else float("nan")
    return SuggestInputs(noise, interval, looks_like_ais(points))


def suggest_from(inputs: SuggestInputs, threshold_deg: float) -> list[Suggestion]:
    """The presets :func:`suggested_presets` names, from the points' part ``inputs`` and
    the detector's threshold (°)."""
    out: list[Suggestion] = []
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = inputs.noise_deg / threshold_deg
    sparse = np.isfinite(inputs.interval_s) and inputs.interval_s > NOISY_MAX_INTERVAL_S
    if np.isfinite(ratio) and ratio >= 1.0 and not sparse:
        out.append(Suggestion("noisy-tracks", float(ratio)))
    return out


def suggested_presets(points: pd.DataFrame, params=None) -> list[Suggestion]:
    """The presets that suit ``points`` with maneuver parameters ``params`` (default:
    the defaults):

    - ``noisy-tracks`` where :func:`noise_floor_ratio` is at least 1: on a typical track
      the detector's noise floor at its first scale is above its threshold (not where the
      median interval is over :data:`NOISY_MAX_INTERVAL_S`).

    (``slow-radar``, suggested at 3-7 s for data not AIS until session 31, is retired:
    :data:`RETIRED`.)

    :func:`suggest_inputs` then :func:`suggest_from` (the panel runs the first off the GUI
    thread, once per layer). docs/evaluation.md "Built-in presets (session 29)" gives the
    real sets each fires on."""
    from wakeline.core.maneuver import ManeuverParams

    mp = params or ManeuverParams()
    if points.empty:
        return []
    return suggest_from(suggest_inputs(points, mp), mp.threshold_deg)
