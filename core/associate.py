"""Single-sensor track association (SPEC §5): segments of one ship, interrupted tracks.

Two problems, one set of building blocks:

- *Segment association* (seed 001 §5): agglomerative clustering of track segments under a
  combined distance D = (w₁·S′ + w₂·l′)·σ, where S is the area of the polygon made by two
  segments, l the difference of their linear directional means and σ = −1 when their
  time spans overlap (such clusters never merge).
- *Interrupted-track association* (seed 003 §3.1–3.2): old track i ended, new track j of
  the same sensor started within T_gap; distance from i's end to j's start by position,
  course and speed, and a one-to-one assignment (greedy as in the paper, or optimal).

Candidate pairs are never a dense n×n matrix: they come from a grid of track ends and
starts with a sweep on time (a k-d tree where the grid does not fit), filtered by the gap
and the speed needed to cover it. Everything per pair is vectorized; only the final assignment walks the sorted pairs.
"""

from dataclasses import dataclass, replace

import numpy as np
import pandas as pd

from wakeline.core import geo
from wakeline.core.errors import InputError
from wakeline.core.params import Params, param
from wakeline.core.progress import Progress, null_progress
from wakeline.core.schema import seconds_to_time
from wakeline.core.segments import Segments, chain_refit, ecef, order_by, segment_stats
from wakeline.core.sorted_sets import member, repeat_runs
from wakeline.core.tracks import concat_ranges, track_seconds
from wakeline.core.words import count as count_of

SEGMENT_METHODS = ("motion", "area", "dtw", "hausdorff")
INTERRUPT_METHODS = ("optimal", "greedy")


@dataclass(frozen=True)
class LinkParams(Params):
    """Which pairs of tracks may be the same ship, and how they are scored."""

    max_gap_s: float = param(
        720.0,
        "s",
        "T_gap: longest gap between an old track's end and a new track's start",
        1.0,
        86400.0 * 7,
        "seed 003 tuned 70 s / 90 s on MTAD; 720 s covers 10 min gaps plus a sampling period",
    )
    step_allowance_s: float = param(
        120.0,
        "s",
        "T_gap in sampling steps: the two sampling steps (the old end's and the new start's, "
        "summed) that max_gap_s allows for — a 10-min outage of 1-min AIS is a gap of up to "
        "10 + 2 × 1 min. A pair whose ends' median steps sum to more has the excess taken "
        "off its gap wherever the gap meets a time limit (max_gap_s, soft_gap_s, long_gap_s "
        "and the gap price), so the limits hold the same outage at any sampling: at 3-min "
        "sampling T_gap is 600 + 2 × 180 = 960 s; each end's step counts up to max_gap_s, and "
        "nothing when it is over twice max_gap_s (a longer step is an outage of its own, not "
        "sampling); the second look's searches count it up to their own reach, long_gap_s "
        "(0 = off: the gap as it is, whatever the sampling)",
        0.0,
        86400.0,
        "ours (issue 15, sampling sweep; max_gap_s 720 = a 600 s outage plus two 60 s "
        "steps): docs/evaluation.md",
    )
    soft_gap_s: float = param(
        1200.0,
        "s",
        "soft T_gap: the assignment also sees pairs across a gap longer than max_gap_s, up to "
        "this long, between moving pieces (above rest_kn) of at least soft_min_fixes each that have "
        "no candidate within max_gap_s cheaper than long_margin, when the gap is at least "
        "one time step of each; such a pair costs gap_price more per max_gap_s beyond "
        "max_gap_s and is joined only where it is each piece's cheapest candidate not "
        "claimed more cheaply, by long_margin (0, or any value up to max_gap_s: the hard "
        "wall of earlier versions; the second look still reaches to long_gap_s)",
        0.0,
        86400.0 * 7,
        "ours (issue 15): MTAD at known gaps of 300-900 s; docs/evaluation.md",
    )
    soft_min_fixes: int = param(
        2,
        "fixes",
        "soft T_gap: the fewest fixes each piece of a pair beyond max_gap_s needs (two show "
        "its motion, its noise then its sensor's median; at 3-min sampling two fixes are "
        "the track time three are at 1 min)",
        1,
        100,
        "ours (issue 15, sampling sweep; 3 before): docs/evaluation.md",
    )
    gap_price: float = param(
        0.75,
        "",
        "soft T_gap: what a pair beyond max_gap_s pays in the assignment per max_gap_s of gap "
        "beyond it (a ship is silent that long less often)",
        0.0,
        10.0,
        "ours (issue 15)",
    )
    v_max_kn: float = param(
        30.0, "kn", "fastest plausible ship: the gap must be coverable at this speed", 1.0, 100.0
    )
    position_tol_m: float = param(
        200.0, "m", "position error allowed on top of v_max when checking reachability", 0.0
    )
    end_points: int = param(10, "points", "points of each end fitted for position and motion", 1)
    end_points_max: int = param(
        40,
        "points",
        "longest end fit: an end whose fixes show no acceleration (1 % test) over 2x, 4x ... "
        "end_points is fitted over that many, up to this (a long steady track's velocity is "
        "known better; a turning one's is not averaged over the turn); end_points: never. "
        "Interrupted-track association only (segment clustering keeps end_points)",
        1,
        1000,
    )
    end_span_s: float = param(
        450.0,
        "s",
        "end fits in track time: an end is fitted over 1 + end_span_s / its median step "
        "fixes, rounded (at least 3, at most end_points; end_points_max shrinks in proportion; the "
        "chain pass's refits alike), so the fit spans about the same time at any sampling "
        "(0 = end_points fixes whatever the sampling, SPEC §5's last 10 points)",
        0.0,
        86400.0,
        "ours (issue 15, sampling sweep): docs/evaluation.md",
    )
    alpha: float = param(
        0.5, "", "α: weight of the position distance", 0.0, 1.0, "seed 003 eq. (position)"
    )
    beta: float = param(0.25, "", "β: weight of the course difference", 0.0, 1.0, "seed 003")
    gamma: float = param(0.25, "", "γ: weight of the speed difference", 0.0, 1.0, "seed 003")
    predict: bool = param(
        True,
        "",
        "measure position distance to the dead-reckoned end (either end's velocity, one course change in the gap)",
    )
    gate: float = param(
        1.5,
        "",
        "largest combined distance accepted (scaled units: 1 = one tolerance on every term)",
        0.0,
    )
    drift_ms: float = param(
        1.0,
        "m/s",
        "growth of the position tolerance with the gap (turns and speed changes unseen); "
        "with uncertainty_gate, the velocity change that bounds ½·accel·gap²",
        0.0,
    )
    uncertainty_gate: bool = param(
        True,
        "",
        "position tolerance from the prediction's uncertainty (each end's own noise and "
        "velocity error, unknown acceleration over the gap); false: the fixed "
        "position_tol_m + drift_ms × gap of earlier versions",
    )
    accel_ms2: float = param(
        0.001,
        "m/s²",
        "unknown acceleration during a gap (speed changes, turns beyond the one allowed): "
        "adds ½·a·gap² to the position uncertainty, at most drift_ms × gap",
        0.0,
        5.0,
    )
    measured_accel: bool = param(
        True,
        "",
        "the unknown acceleration of a gap is at least what either end shows beyond its "
        "noise (a quadratic fit over its end points, significant at 1 %): a ship seen "
        "speeding up, slowing down or turning gets the wider gate; false: accel_ms2 alone",
    )
    sigmas: float = param(
        3.0, "σ", "position miss worth one unit of distance, in standard deviations", 0.5, 20.0
    )
    no_join: float = param(
        1.5,
        "",
        "cost of leaving an old end and a new start loose: a pair is joined only when it "
        "costs less (at most the gate)",
        0.0,
    )
    margin: float = param(
        0.25,
        "",
        "margin test: a join is dropped when a rival that overlaps it in time (another "
        "start for the old end, another end for the new start), not claimed more cheaply "
        "by someone else, costs less than this much more",
        0.0,
    )
    blind_order: float = param(
        0.01,
        "",
        "a pair of which neither end shows its motion (single fixes) costs no_join less "
        "the margin, plus this much × the speed it implies (distance / gap) over v_max_kn, "
        "so that among such pairs the slower is taken; 0: all alike, the assignment's "
        "order decides",
        0.0,
        0.25,
    )
    chain_passes: int = param(
        1,
        "",
        "chain evidence: after an assignment, refit the ends of pieces shorter than "
        "end_points over the chain they were joined into (a single fix borrows its "
        "neighbours' motion) and assign again, this many times; 0: pair by pair only",
        0,
        5,
    )
    long_gap_s: float = param(
        3600.0,
        "s",
        "second look: after the assignment, an old end and a new start both left loose are "
        "joined across a gap longer than max_gap_s, up to this long, when each is the "
        "other's cheapest candidate among all within reach (joined or not) by long_margin "
        "(0, or any value up to max_gap_s, turns it off)",
        0.0,
        86400.0 * 7,
    )
    long_margin: float = param(
        0.25,
        "",
        "second look: how much cheaper than every rival of either piece a long-gap join must be",
        0.0,
    )
    long_margin_moving: float = param(
        0.1,
        "",
        "second look: the margin instead when both pieces are seen moving (the old end's and "
        "the new start's fitted speed above rest_kn): their motion is evidence a loose posit "
        "lacks (= long_margin: one margin for all)",
        0.0,
    )
    min_gap_steps: float = param(
        0.5,
        "",
        "a pair's gap must be at least this many of its pieces' time steps (the smaller "
        "of the two ends' median steps): a ship seen every 30 min does not reappear after "
        "3 min (0 = off)",
        0.0,
        10.0,
    )
    mmsi_apart: bool = param(
        True,
        "",
        "AIS identities: two tracks whose batch ids are different MMSIs (nine digits whose "
        "first three, the maritime identification digits, are 201-775; alone or before a "
        "separator as in 413801163-1) are two ships and never a candidate pair; pieces of "
        "one MMSI and ids of any other form are paired as before. A sensor whose own track "
        "numbers look like MMSIs (nine digits such as a date-coded 240101001) needs it off "
        "(False = MMSIs are paired like any track numbers)",
        source="ours (session 24: on the uncut ATD example every one of the 13 joins tied two "
        "different MMSIs)",
    )
    long_rivals: bool = param(
        True,
        "",
        "second look: a join of the assignment gives way where a loose piece beyond "
        "max_gap_s (up to rivals_reach times it) would continue either of its pieces cheaper by "
        "long_margin (the assignment cannot see it), and comes back if the second look "
        "does not take it",
    )
    rest_kn: float = param(
        0.5,
        "kn",
        "at rest: an end whose speed and speed error are both below this; between two ends "
        "at rest the ship is expected where it lay (free within sigmas x rest_drift_m, "
        "charged beyond), not anywhere an unknown acceleration could take it (0 = off)",
        0.0,
        5.0,
    )
    rest_drift_m: float = param(
        50.0,
        "m",
        "between two ends at rest: how far a ship lying at a berth or at anchor may seem to "
        "move (GPS wander, swinging at anchor), per axis; free within sigmas times this",
        0.0,
        1e4,
    )
    rest_drift_s: float = param(
        0.0,
        "s",
        "between two ends at rest: the gap over which the allowance reaches rest_drift_m; a "
        "shorter gap allows rest_drift_m x sqrt(gap / rest_drift_s) (0 = rest_drift_m "
        "whatever the gap; measured and not taken: docs/evaluation.md)",
        0.0,
        86400.0 * 7,
        "ours; Saronic AIS at rest: 90 % of ships within 15 m of their end after 5 min, "
        "37 m after 1 h",
    )
    rest_seen_s: float = param(
        300.0,
        "s",
        "between two ends at rest: when each end's own fit (3 fixes or more) spans at least "
        "this long, its scatter shows how much the ship wanders at its spot: the pair costs "
        "the cheaper of lying within rest_wander x that scatter (every metre off the "
        "prediction charged) and having moved within the rest_drift_m allowance (rest_move "
        "more); shorter ends say nothing of a swing and keep the allowance (0 = off)",
        0.0,
        86400.0,
        "ours; Saronic AIS at rest (bench/moored_harbour.py --wander); 600 s until "
        "session 22, when end fits span about end_span_s (450 s): docs/evaluation.md",
    )
    rest_wander: float = param(
        3.0,
        "",
        "between two ends seen at rest for rest_seen_s: how far the ship may seem to move, "
        "per axis, in units of its ends' own scatter",
        0.0,
        100.0,
        "ours; Saronic AIS at rest, ends scattered <= 2 m: 1.7-4.2 (5 min to 1 h)",
    )
    rest_move: float = param(
        1.0,
        "",
        "between two ends seen at rest for rest_seen_s: what it costs that the ship moved "
        "within the rest_drift_m allowance rather than lay where it was seen (a ship "
        "re-berthed or drifting), on top of that allowance's price",
        0.0,
        10.0,
        "ours",
    )
    log_sigma: float = param(
        0.5,
        "",
        "spread of the prediction: a pair pays this × ln(σ / σ_best) on its position term, "
        "σ its predicted position's standard deviation and σ_best the tightest among the "
        "plausible candidates of its old end and of its new start (none without "
        "uncertainty_gate), so a ship's next piece beats a "
        "later one that skips it (0 = off: the scaled miss alone)",
        0.0,
        5.0,
        "the 1/σ² of a position likelihood",
    )
    motion_shown: float = param(
        0.0,
        "",
        "an end not at rest (rest_kn) whose fitted speed is below this many standard errors "
        "of its velocity (per axis) shows no motion of its own to the pricing: its course and "
        "speed terms are unknown and the prediction takes the other end's velocity where "
        "that one shows its motion, as for a single fix (1: a course error of 45° or more; "
        "0 = off: every fitted velocity counts)",
        0.0,
        10.0,
        "ours (session 26, MTAD decimated: two fixes 180 s apart at 450-700 m noise fit a "
        "course of noise at an inflated speed): docs/prereg/session26_mtad_sparse.md",
    )
    course_debias: bool = param(
        True,
        "",
        "the course tolerance's angle arctan(velocity error / speed) takes the fitted speed "
        "less its noise, sqrt(max(speed² - 2·error², 0)) (a fitted speed's expected square "
        "is the true one's plus twice the error's), so a course of noise gets the wide "
        "tolerance its error allows (False: the fitted speed, the rule before)",
        source="ours (session 26, adopted by its pre-set rule: MTAD tuning half at 180 s "
        "0.906 / 0.027 -> 0.910 / 0.021, 600 s 0.838 / 0.093 -> 0.842 / 0.090): "
        "docs/prereg/session26_mtad_sparse.md",
    )
    margin_displaced: float = param(
        0.4,
        "",
        "margin test: a rival that another join claims (more dearly than the rival costs) "
        "counts only when taking it would cost the assignment less than this much more: "
        "the rival's cost, plus the cheaper of leaving its claimer and the freed piece "
        "loose (no_join) or joining the two (a candidate within the gate), less the two "
        "joins it undoes; unclaimed rivals count as before (0 = off: every such rival "
        "within margin counts, the rule before)",
        0.0,
        10.0,
        "ours (session 27, MTAD decimated: joins dropped for a rival whose taking would "
        "undo a cheaper join elsewhere; 0.6 with the no_join charge failed its pre-set "
        "rule, docs/prereg/session27_mtad.md; 0.4 with the alternative charge adopted by "
        "it: MTAD tuning half at 600 s 0.842 / 0.090 -> 0.854 / 0.086, hard very dense "
        "P_FA 0.088 -> 0.090 at the bound; with rivals_reach 5 as well 0.851 / 0.090 and "
        "0.088): docs/prereg/session27_mtad_b.md",
    )
    margin_displaced_charge: str = param(
        "alternative",
        "",
        "what margin_displaced charges for the two pieces a rearrangement frees when they "
        "are not joined to each other: no_join (both loose), or alternative (each half of "
        "its own cheapest other candidate within the gate, or half of no_join if it has "
        "none or a dearer one; no_join: each freed piece charged no_join)",
        source="ours (session 27, h169: no_join overprices leaving a piece loose that has "
        "another reading; adopted with margin_displaced 0.4): docs/prereg/session27_mtad_b.md",
        choices=("no_join", "alternative"),
    )
    speed_change_ms2: float = param(
        0.0,
        "m/s²",
        "the speed tolerance grows with the gap: a ship may change speed by this much per "
        "second of gap (it arrived at or left a berth unseen), added in squares to "
        "speed_tol_kn and the ends' velocity errors; pairs at rest at both ends keep no "
        "speed term (0 = off: the tolerance whatever the gap)",
        0.0,
        1.0,
        "ours (session 27, Saronic's days overlaid: true pairs across 600-1,800 s gaps "
        "left loose at speed differences of 15-31 kn): docs/prereg/session27_overlay.md",
    )
    rivals_reach: float = param(
        5.0,
        "",
        "long_rivals: how far beyond a join's end and start a loose piece is looked for as "
        "a cheaper continuation, in max_gap_s (at most long_gap_s): 5 = long_gap_s at the "
        "defaults, the second look's own reach (2: twice max_gap_s, the rule before)",
        1.0,
        100.0,
        "ours (session 27, adopted by its pre-set rule: Saronic's days overlaid, tuning "
        "split at 600-1,800 s 0.810 / 0.069 -> 0.828 / 0.056; moored ends joined within "
        "T_gap to another ship's berth while their own next piece lay 1,440-2,000 s on): "
        "docs/prereg/session27_overlay.md",
    )
    course_tol_deg: float = param(45.0, "deg", "course difference worth one unit of distance", 1.0)
    speed_tol_kn: float = param(5.0, "kn", "speed difference worth one unit of distance", 0.1)
    w1: float = param(
        0.5, "", "w₁: weight of the area S (segment association)", 0.0, 1.0, "seed 001 Table 2"
    )
    w2: float = param(
        0.5,
        "",
        "w₂: weight of the direction term l (segment association)",
        0.0,
        1.0,
        "seed 001 Table 2",
    )
    limit: float = param(
        1.0,
        "",
        "segment association (area/dtw/hausdorff): largest min-max normalized D merged; "
        "with w₁ + w₂ = 1 the default merges while any D > 0 is left, as seed 001 does",
        0.0,
        source="seed 001 §5",
    )
    rivals_rounds: int = param(
        2,
        "",
        "long_rivals: how many times the release test is made, each time with the pieces "
        "that the rounds before released counted loose (a moored end joined to another "
        "ship's berth whose own continuation was itself joined wrongly, and released, in "
        "the round before); 1 = once, the rule before",
        1,
        10,
        "ours (session 28, adopted by its pre-set rule: Saronic's days overlaid, tuning "
        "split at 600-1,800 s 0.828 / 0.056 -> 0.834 / 0.051; swapped joins at one berth "
        "that free each other's true continuation only in turn): "
        "docs/prereg/session28_overlay.md",
    )
    min_gap_least_steps: float = param(
        0.0,
        "",
        "a pair's gap must also be at least this many of the shortest time step either "
        "piece shows between its own end fixes (the old end's last end_points fixes, the "
        "new start's first; a single fix shows none, the other's counts): a ship seen "
        "again every 600 s at the soonest does not reappear after 300 s, while sampling "
        "that jitters shows its short steps and is held to them (0 = off: min_gap_steps "
        "on the median step alone)",
        0.0,
        10.0,
        "ours (session 28, MTAD decimated to 600 s: wrong joins across gaps of 0.5-0.8 "
        "of a step, the median rule's 0.5 kept for jittered sampling; adopted by its pre-set "
        "rule: MTAD tuning half 600 s 0.851 / 0.090 -> 0.858 / 0.081, 180 s unchanged; "
        "Oresund 180 s +-30 % lost 1 of 10 pairs, at rule 6's bound; held out, once, P_FA "
        "+0.009 / +0.017, so returned to an option by the lead; 0.9 is the candidate): "
        "docs/prereg/session28_mtad.md",
    )
    slow_change_ms2: float = param(
        0.0,
        "m/s²",
        "where one end of a moving pair is slow (fitted speed below slow_end_kn: the ship "
        "arriving at or leaving a berth), the speed tolerance grows with the gap by this "
        "acceleration × the gap, added in squares to speed_tol_kn and the ends' velocity "
        "errors; pairs with both ends faster keep the tolerance whatever the gap (0 = off)",
        0.0,
        1.0,
        "ours (session 28, Saronic's days overlaid: a fast ferry slowing into or leaving "
        "port across 15-30 min gaps, the slower end under 5 kn in 57 of the 74 misses "
        "over 10 kn apart; 0.01 failed its pre-set rule 2, MTAD held-out own cuts P_CA "
        "0.919 -> 0.905 at 5 kn, 0.904 at 10 kn): docs/prereg/session28_overlay_b.md",
    )
    slow_end_kn: float = param(
        5.0,
        "kn",
        "slow_change_ms2: an end slower than this (fitted speed) lets the speed change with "
        "the gap",
        0.0,
        50.0,
        "ours (session 28, Saronic's days overlaid: the slower end of the misses over 10 kn "
        "apart, median 1.9 kn, under 5 kn in 57 of 74): docs/prereg/session28_overlay_b.md",
    )


@dataclass(frozen=True)
class Pairs:
    """Candidate pairs (old ``i`` → new ``j``) with their features, arrays of length m."""

    i: np.ndarray
    j: np.ndarray
    gap_s: np.ndarray
    dist_m: np.ndarray
    miss_m: np.ndarray
    dcourse_deg: np.ndarray
    dspeed_kn: np.ndarray
    #: Seconds of the gap that sparse sampling explains beyond what the time limits allow
    #: for (``step_allowance_s``; :func:`counted_gap`); None: none.
    allow_s: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.i)

    def _field(self, f: str) -> np.ndarray:
        v = getattr(self, f)
        return np.zeros(len(self.i)) if v is None else v

    def concat(self, other: "Pairs") -> "Pairs":
        """These pairs followed by ``other``'s."""
        return Pairs(
            *(
                None
                if getattr(self, f) is None and getattr(other, f) is None
                else np.concatenate([self._field(f), other._field(f)])
                for f in self.__dataclass_fields__
            )
        )

    def take(self, keep: np.ndarray) -> "Pairs":
        return Pairs(
            *(
                None if getattr(self, f) is None else getattr(self, f)[keep]
                for f in self.__dataclass_fields__
            )
        )


def counted_gap(pairs: Pairs) -> np.ndarray:
    """Per pair: its gap (s) as the time limits count it — less the part its ends' sparse
    sampling explains (``step_allowance_s``, :func:`_step_allowance`)."""
    return pairs.gap_s if pairs.allow_s is None else pairs.gap_s - pairs.allow_s


def _step_allowance(
    seg: Segments, i: np.ndarray, j: np.ndarray, allowance_s: float, step_cap_s: float
) -> np.ndarray:
    """Per pair (old ``i`` → new ``j``): the seconds by which the old end's and the new
    start's median time steps (``step1`` / ``step0``, each counted up to ``step_cap_s``)
    sum to more than ``allowance_s`` (0 where not, or when ``allowance_s`` is 0: off).

    The cap is T_gap itself (``max_gap_s``), and a step beyond twice it counts nothing
    (:func:`_sampling_step`): a step longer than T_gap is an outage of its own, not
    sampling, so one piece reported every few hours neither makes any gap of its own
    "within T_gap" nor widens every piece's candidate search (ATD's 12 h steps did: 33 s
    and 1.6 GB at its own cuts, against 2.4 s); and a track reported every 30 min does not
    reach every other ship's start one report later (ATD at known 30–60 min gaps: 1,346
    wrong joins with the cap alone, 418 so)."""
    if allowance_s <= 0 or seg.step1 is None or seg.step0 is None:
        return np.zeros(len(i))
    steps = _sampling_step(seg.step1[i], step_cap_s) + _sampling_step(seg.step0[j], step_cap_s)
    return np.maximum(steps - allowance_s, 0.0)


def _sampling_step(step_s: np.ndarray, cap_s: float) -> np.ndarray:
    """Per end: how much of its median time step (s) counts as sampling — all of it up to
    ``cap_s`` (T_gap), ``cap_s`` up to twice it (one report missed in the end's few steps),
    nothing beyond: a piece reported more sparsely than that is outside the design (every
    gap of its own is an outage; ATD's 30-min posits), not sampling to allow for."""
    step = np.nan_to_num(step_s)
    return np.where(step <= 2.0 * cap_s, np.fmin(step, cap_s), 0.0)


def _largest_allowance(seg: Segments, params: LinkParams) -> float:
    """The most (s) :func:`_step_allowance` gives any pair of ``seg``: how much further in
    time a candidate search must look (at most 2 × ``max_gap_s`` − ``step_allowance_s``)."""
    if params.step_allowance_s <= 0 or seg.step1 is None or seg.step0 is None or not len(seg):
        return 0.0
    top = sum(float(_sampling_step(s, params.max_gap_s).max()) for s in (seg.step1, seg.step0))
    return max(top - params.step_allowance_s, 0.0)


def _grid_pairs(
    seg: Segments,
    params: LinkParams,
    ends: np.ndarray | None = None,
    starts: np.ndarray | None = None,
    min_gap_s: float = 0.0,
) -> tuple[np.ndarray, np.ndarray] | None:
    """(end i, start j) of one sensor with ``t0[j] − t1[i]`` in (``min_gap_s``,
    ``max_gap_s``] and the straight-line (chord) distance within ``v_max·gap +
    position_tol_m``, or None when the grid's keys do not fit in 64 bits. ``ends`` /
    ``starts``: masks of the tracks whose end / start may take part (default all).

    Earth-centred positions are binned in cubes of side ``reach`` (the distance coverable
    in the longest gap): the starts reachable from an end lie in the 3×3×3 cubes about
    it, so 27 look-ups per end (per cube of ends). Starts are sorted by (cube, start time);
    each look-up is a ``searchsorted`` for the cube's starts in the end's time window (from
    when that cube could be reached), the ranges are
    expanded into pairs with ``np.repeat`` and cut to the reachability cone at once —
    no Python loop per track or per pair, work linear in the pairs looked at.
    """
    gmax = float(params.max_gap_s)
    v = params.v_max_kn * geo.KN_MS
    tol = params.position_tol_m
    side = v * gmax + tol
    pe, ps = seg.ecef1, seg.ecef0
    if not (np.isfinite(pe).all() and np.isfinite(ps).all() and side > 0):
        return None  # the k-d tree path handles (or reports) what a grid cannot bin
    origin = np.floor(np.minimum(pe.min(axis=0), ps.min(axis=0)) / side) - 2
    cs = (np.floor(ps / side) - origin).astype("int64")
    ce = (np.floor(pe / side) - origin).astype("int64")
    bits = max(int(max(cs.max(), ce.max()) + 2).bit_length(), 1)
    sens = seg.sensor_code.astype("int64")
    if 3 * bits + max(int(sens.max()).bit_length(), 1) > 62:
        return None

    def key(c: np.ndarray) -> np.ndarray:
        return (((sens << bits | c[:, 0]) << bits | c[:, 1]) << bits) | c[:, 2]

    t0, t1 = seg.t0, seg.t1
    tmin = float(min(t0.min(), t1.min()))
    ks = key(cs)
    # Only the starts (ends) that may take part are sorted: a stable sort of the subset
    # gives the order the whole one would, filtered.
    sub = np.flatnonzero(starts) if starts is not None else slice(None)
    order = np.arange(len(ks))[sub][order_by(ks[sub], seg.t0_rank[sub])]
    n_s = len(order)
    if n_s == 0:
        return np.zeros(0, dtype="int64"), np.zeros(0, dtype="int64")
    cells, first = np.unique(ks[order], return_index=True)
    width = float(max(t0.max(), t1.max()) - tmin) + gmax + 10.0
    if len(cells) * width > 2.0**52 / 1e3:  # millisecond resolution of the sweep key
        return None
    sweep = repeat_runs(None, np.diff(np.append(first, n_s))) * width + (t0[order] - tmin)
    # Ends in (cube, time) order too: the queries of each look-up come sorted and every
    # gather below walks both tables forwards (the cache decides the speed at 100 k).
    ke = key(ce)
    sub = np.flatnonzero(ends) if ends is not None else slice(None)
    e_order = np.arange(len(ke))[sub][order_by(ke[sub], seg.t1_rank[sub])]
    ke, ce_s, tq = ke[e_order], ce[e_order], t1[e_order] - tmin
    # Positions by axis (one gather per axis per pair; the squares summed x, y, z in turn
    # as a row sum does).
    pe_s, ps_s, t0_s = pe[e_order].T.copy(), ps[order].T.copy(), t0[order]
    slack = 2e-3  # s: the sweep key's rounding; the exact gap test follows
    # Each end's place in its cube (0..1 per axis): a start in the next cube over is at
    # least the way to that cube's face (edge, corner) away, so it is reachable only after
    # (that way − position_tol_m)/v. Looking no earlier there (a metre to spare for the
    # rounding, far above it) skips only pairs the distance test below refuses.
    frac = (np.clip(pe_s.T / side - (ce_s + origin), 0.0, 1.0) * side).T.copy()
    # The cube look-ups once per cube the ends lie in (ends come sorted by cube).
    if len(ke) == 0:
        return np.zeros(0, dtype="int64"), np.zeros(0, dtype="int64")
    first_of_cube = np.r_[True, ke[1:] != ke[:-1]]
    head, cube = np.flatnonzero(first_of_cube), np.cumsum(first_of_cube) - 1
    ku, cu = ke[head], ce_s[head]
    out_i, out_j = [], []
    for off in np.stack(np.meshgrid([-1, 0, 1], [-1, 0, 1], [-1, 0, 1]), -1).reshape(-1, 3):
        kq = ((ku >> (3 * bits)) << bits | cu[:, 0] + off[0]) << bits | cu[:, 1] + off[1]
        kq = kq << bits | cu[:, 2] + off[2]
        cq = np.searchsorted(cells, kq)
        hit = (cq < len(cells)) & (cells[np.minimum(cq, len(cells) - 1)] == kq)
        e = np.flatnonzero(hit[cube])
        soon = np.full(len(e), float(min_gap_s))
        if off.any() and v > 0:
            way = np.zeros(len(e))
            for k in np.flatnonzero(off):
                way += (side - frac[k][e] if off[k] > 0 else frac[k][e]) ** 2
            soon = np.fmax(soon, (np.sqrt(way) - tol - 1.0) / v)
            live = soon <= gmax + 2.0 * slack  # the others' windows are empty
            e, soon = e[live], soon[live]
        base = cq[cube[e]] * width + tq[e]
        lo = np.searchsorted(sweep, base + soon - slack, side="left")
        cnt = np.maximum(np.searchsorted(sweep, base + gmax + slack, side="right") - lo, 0)
        i = repeat_runs(e, cnt)  # np.repeat holds the GIL (sorted_sets)
        j = concat_ranges(lo, cnt)
        gap = t0_s[j] - (tq[i] + tmin)
        d2 = (pe_s[0][i] - ps_s[0][j]) ** 2
        d2 += (pe_s[1][i] - ps_s[1][j]) ** 2
        d2 += (pe_s[2][i] - ps_s[2][j]) ** 2
        ok = (gap > min_gap_s) & (gap <= gmax) & (d2 <= (v * gap + tol) ** 2)
        i, j = e_order[i[ok]], order[j[ok]]
        keep = i != j
        out_i.append(i[keep])
        out_j.append(j[keep])
    return np.concatenate(out_i), np.concatenate(out_j)


def _tree_pairs(seg: Segments, params: LinkParams) -> tuple[np.ndarray, np.ndarray]:
    """The same pairs as :func:`_grid_pairs` (a superset) from a k-d tree: ends and starts
    as points in (x, y, z, scaled time, sensor) space, the starts shifted back by half the
    longest gap, so that a reachable pair lies within √2·reach (one
    ``sparse_distance_matrix`` query, arrays out)."""
    from scipy.spatial import cKDTree  # lazy: keeps `wakeline --help` fast

    t_ref = float(min(seg.t0.min(), seg.t1.min()))
    reach = params.v_max_kn * geo.KN_MS * params.max_gap_s + params.position_tol_m
    scale = 2.0 * reach / params.max_gap_s
    sensor_far = 4.0 * geo.EARTH_RADIUS_M + 4.0 * reach
    ends = np.column_stack(
        [ecef(seg.lon1, seg.lat1), scale * (seg.t1 - t_ref), sensor_far * seg.sensor_code]
    )
    mid = seg.t0 - t_ref - params.max_gap_s / 2.0
    starts = np.column_stack([ecef(seg.lon0, seg.lat0), scale * mid, sensor_far * seg.sensor_code])
    near = cKDTree(ends).sparse_distance_matrix(
        cKDTree(starts), np.sqrt(2.0) * reach * (1.0 + 1e-9), output_type="ndarray"
    )
    return near["i"].astype("int64"), near["j"].astype("int64")


#: A batch id that is an MMSI (nine digits, the first 2-7: ships' maritime identification
#: digits 201-775), alone or followed by a separator and a piece number.
_MMSI_ID = r"^\s*((?:20[1-9]|2[1-9]\d|[3-6]\d\d|7[0-6]\d|77[0-5])\d{6})(?:\s*$|[^0-9])"


def mmsi_identity(batches: pd.Series) -> np.ndarray:
    """The MMSI each batch id names (int64), or -1 where it names none: ``"367128730"`` and
    ``"413801163-1"`` give their MMSIs (maritime identification digits 201-775 first);
    ``"17"``, ``"p3"``, ``"1234567890"``, ``"200000001"`` give -1."""
    found = batches.astype(str).str.extract(_MMSI_ID, expand=False)
    return pd.to_numeric(found, errors="coerce").fillna(-1).to_numpy(dtype="int64")


def _track_identities(seg: Segments) -> np.ndarray:
    """:func:`mmsi_identity` of a segment table's tracks, once per table (the candidate
    searches of one run ask it several times)."""
    out = seg.__dict__.get("_mmsi_identity")
    if out is None:
        out = mmsi_identity(seg.index.keys["batch"])
        object.__setattr__(seg, "_mmsi_identity", out)  # a cache on the frozen table
    return out


def candidate_pairs(
    seg: Segments,
    params: LinkParams,
    ends: np.ndarray | None = None,
    starts: np.ndarray | None = None,
    min_gap_s: float = 0.0,
    apart: list | None = None,
) -> Pairs:
    """Pairs of one sensor with ``min_gap_s < start(j) − end(i) ≤ max_gap_s`` (``min_gap_s``
    0 by default; the gap as the time limits count it, :func:`counted_gap`: less the
    part sparse sampling explains, ``step_allowance_s``) and reachable at
    ``v_max_kn`` — or at :data:`FAST_FACTOR` × the speed the faster end was seen at, when
    that is more (:func:`_seen_speed_kn`) — plus ``position_tol_m``; features per pair,
    ordered by (i, j). ``ends`` /
    ``starts``: masks of the tracks whose end / start may take part (default all).

    A reachable pair is at most ``reach = v·max_gap_s + position_tol_m`` apart, so
    :func:`_grid_pairs` finds them with a grid and a sweep on time (arrays end to end,
    work linear in the pairs it looks at); a k-d tree over (position, scaled time)
    stands in when the grid's cell keys would not fit in 64 bits (tracks spread over
    the globe with a short reach).

    ``apart``: a list to which the pairs ``mmsi_apart`` refused are appended, as int64
    keys ``i·n + j`` (pairs otherwise candidates, reachable, whose batch ids are different
    MMSIs): :func:`apart_count` counts them, each pair once however many searches met it.
    """
    n = len(seg)
    if n < 2:
        e = np.zeros(0)
        return Pairs(e.astype("int64"), e.astype("int64"), e, e, e, e, e)
    fast_end, fast_start = _seen_speed_kn(seg)
    # The search reaches as far as the fastest end seen (a high-speed ferry), each pair
    # as far as its own ends: max(v_max_kn, FAST_FACTOR × the faster end's speed).
    seen = float(max(fast_end.max(), fast_start.max(), 0.0))
    wide = (
        replace(params, v_max_kn=max(params.v_max_kn, seen)) if seen > params.v_max_kn else params
    )
    # Sparse sampling: the gaps are counted less each pair's step allowance, so the search
    # looks as much further as the largest allowance (the exact test per pair follows).
    extra = _largest_allowance(seg, params)
    if extra > 0:
        wide = replace(wide, max_gap_s=params.max_gap_s + extra)
    found = _grid_pairs(seg, wide, ends, starts, min_gap_s)
    i, j = found if found is not None else _tree_pairs(seg, wide)
    gap = seg.t0[j] - seg.t1[i]
    allow = _step_allowance(seg, i, j, params.step_allowance_s, params.max_gap_s)
    counted = gap - allow
    keep = (i != j) & (gap > 0.0) & (counted <= params.max_gap_s)
    if min_gap_s > 0:
        keep &= counted > min_gap_s
    if found is None and ends is not None:
        keep &= ends[i]
    if found is None and starts is not None:
        keep &= starts[j]
    if params.min_gap_steps > 0 and seg.step1 is not None and seg.step0 is not None:
        with np.errstate(invalid="ignore"):
            keep &= ~(gap < params.min_gap_steps * np.fmin(seg.step1[i], seg.step0[j]))
    keep &= ~_sooner_than_seen(seg, i, j, gap, params)
    i, j, gap = i[keep], j[keep], gap[keep]
    dist = geo.haversine_m(seg.lon1[i], seg.lat1[i], seg.lon0[j], seg.lat0[j])
    v = np.maximum(params.v_max_kn, np.maximum(fast_end[i], fast_start[j])) * geo.KN_MS
    keep = dist <= v * gap + params.position_tol_m
    if params.mmsi_apart and len(i):
        # after the reach test, so that what it refused is counted as pairs it kept apart
        ident = _track_identities(seg)
        two_ships = (ident[i] >= 0) & (ident[j] >= 0) & (ident[i] != ident[j])
        if apart is not None:
            refused = keep & two_ships
            apart.append(i[refused].astype("int64") * n + j[refused])
        keep &= ~two_ships
    i, j, dist = i[keep], j[keep], dist[keep]
    order = np.argsort(i * n + j)  # (i, j) order; keys are unique
    return pair_features(
        seg, i[order], j[order], dist[order], params.step_allowance_s, params.max_gap_s
    )


def _sooner_than_seen(
    seg: Segments, i: np.ndarray, j: np.ndarray, gap: np.ndarray, params: LinkParams
) -> np.ndarray:
    """Per pair: its gap is shorter than ``min_gap_least_steps`` × the shortest time
    step either piece shows at the ends that meet (the smaller of the two; a piece that
    shows none, a single fix, is judged by the other's; neither shows one: no test). All
    False when off."""
    k = params.min_gap_least_steps
    if k <= 0 or seg.least_step1 is None or seg.least_step0 is None or len(i) == 0:
        return np.zeros(len(i), dtype=bool)
    least = np.fmin(seg.least_step1[i], seg.least_step0[j])  # NaN only when neither shows
    with np.errstate(invalid="ignore"):
        return gap < k * least


def apart_count(apart: list) -> int:
    """How many different pairs the searches that filled ``apart`` (:func:`candidate_pairs`)
    kept apart: a pair the first pass and the second look both met counts once."""
    keys = [k for k in apart if len(k)]
    return int(len(np.unique(np.concatenate(keys)))) if keys else 0


def _narrowed(
    seg: Segments,
    params: LinkParams,
    ends: np.ndarray | None,
    starts: np.ndarray | None,
    before: tuple | None,
    apart: list | None = None,
) -> tuple[Pairs, tuple]:
    """:func:`candidate_pairs` (``seg``, ``params``, ``ends``, ``starts``) with the help of
    ``before``, what this returned for an earlier search on the same ``seg`` and
    ``params`` (or None): a search finds each end's pairs on its own (its look-ups, then
    exact tests per pair), so the pairs of ends and starts that the earlier search had
    are its pairs, filtered; ends (or starts) it did not have are searched apart and
    merged in, in (i, j) order. The same pairs, features and order as a new search.
    Returns the pairs and what to pass as ``before`` next time. ``apart``: as
    :func:`candidate_pairs`' (the pairs a reused search refused were counted when it ran)."""
    n = len(seg)
    e = np.ones(n, dtype=bool) if ends is None else ends.copy()
    s = np.ones(n, dtype=bool) if starts is None else starts.copy()
    if before is None:
        found = candidate_pairs(seg, params, ends, starts, apart=apart)
        return found, (e, s, found)
    e0, s0, p0 = before
    new_e, new_s = e & ~e0, s & ~s0
    if new_e.any() and new_s.any():
        found = candidate_pairs(seg, params, ends, starts, apart=apart)
        return found, (e, s, found)
    if np.array_equal(e, e0) and np.array_equal(s, s0):
        return p0, before  # the same search: the same pairs (the same object)
    found = p0.take(e[p0.i] & s[p0.j])
    if new_e.any() or new_s.any():
        more = (
            candidate_pairs(seg, params, new_e, starts, apart=apart)
            if new_e.any()
            else candidate_pairs(seg, params, ends, new_s, apart=apart)
        )
        found = found.concat(more)
        found = found.take(np.argsort(found.i * n + found.j, kind="stable"))
    return found, (e, s, found)


def _soft_gap(params: LinkParams) -> float:
    """The longest gap the first pass's assignment sees (``soft_gap_s``, at least
    ``max_gap_s``; ``max_gap_s`` when the soft T_gap is off)."""
    return max(params.max_gap_s, params.soft_gap_s)


def _soft_ends(seg: Segments, params: LinkParams) -> tuple[np.ndarray, np.ndarray]:
    """Per track: its end, its start may take part in a pair beyond ``max_gap_s`` in the
    first pass (soft T_gap) — a piece of at least ``soft_min_fixes`` fixes whose fit
    there is moving (above ``rest_kn``)."""
    fit = seg.n >= params.soft_min_fixes
    slow = params.rest_kn * geo.KN_MS
    return fit & (np.hypot(seg.vx1, seg.vy1) > slow), fit & (np.hypot(seg.vx0, seg.vy0) > slow)


def _fitted(seg: Segments, pairs: Pairs, params: LinkParams) -> np.ndarray:
    """Per pair: both pieces may take part beyond ``max_gap_s`` (:func:`_soft_ends`), and
    its gap is at least one time step of each piece (a ship reported every 30 min is
    not missing after 20)."""
    end, start = _soft_ends(seg, params)
    ok = end[pairs.i] & start[pairs.j]
    if seg.step1 is not None and seg.step0 is not None:
        with np.errstate(invalid="ignore"):
            ok &= ~(pairs.gap_s < np.fmax(seg.step1[pairs.i], seg.step0[pairs.j]))
    return ok


def _in_first(gap_s: np.ndarray, fitted: np.ndarray | None, params: LinkParams) -> np.ndarray:
    """Per pair: one the first pass's assignment may see — its gap within ``max_gap_s``,
    or within the soft T_gap (``soft_gap_s``) between pieces that may take part there
    (``fitted``, :func:`_fitted`; the assignment sees those of them whose pieces are open,
    :func:`first_pass_pairs`). The others are the second look's only."""
    inside = gap_s <= params.max_gap_s
    soft = _soft_gap(params)
    if soft <= params.max_gap_s or fitted is None:
        return inside
    return inside | ((gap_s <= soft) & fitted)


def first_pass_pairs(
    seg: Segments, params: LinkParams, normalize: str = "scaled", apart: list | None = None
) -> "tuple[Pairs, _Priced, np.ndarray]":
    """The first pass's candidates, their pricing and costs: :func:`candidate_pairs`
    within ``max_gap_s`` and, with the soft T_gap (``soft_gap_s``), the pairs up to it
    between pieces that may take part (:func:`_fitted`) and are **open**: whose cheapest
    candidate within ``max_gap_s`` costs at least ``long_margin`` (or who have none). A
    piece with a cheaper one has nothing to gain from a longer look (a join beyond
    ``max_gap_s`` must be its cheapest by ``long_margin``, :func:`soft_gap_test`), and
    leaving it out keeps the search near the size of the hard wall's. Ordered by (i, j);
    min-max (seed 003 as written) keeps its hard T_gap. ``apart``: as
    :func:`candidate_pairs`' (both searches: the pairs they kept apart, none twice)."""
    n = len(seg)
    pairs = candidate_pairs(seg, params, apart=apart)
    priced = _pricing(pairs, params, normalize, seg)
    cost = priced.total(pairs, params, n)
    soft = _soft_gap(params)
    if normalize == "minmax" or soft <= params.max_gap_s or n < 2:
        return pairs, priced, cost
    best_end = np.full(n, np.inf)
    best_start = np.full(n, np.inf)
    np.minimum.at(best_end, pairs.i, cost)
    np.minimum.at(best_start, pairs.j, cost)
    ends, starts = _soft_ends(seg, params)
    ends &= best_end >= params.long_margin
    starts &= best_start >= params.long_margin
    more = candidate_pairs(
        seg,
        replace(params, max_gap_s=soft),
        ends=ends,
        starts=starts,
        min_gap_s=params.max_gap_s,
        apart=apart,
    )
    more = more.take(_fitted(seg, more, params))
    extra = _pricing(more, params, normalize, seg)
    # Only pairs that could sway a decision are kept: a pair priced (before the spread
    # term, which only adds) beyond the gate and the larger margin, gap price included,
    # can neither be joined nor be anyone's rival (about 4 % are kept in the bench scene).
    limit = min(params.gate, params.no_join) + max(params.margin, params.long_margin)
    keep = extra.cost + _gap_price(more, params) <= limit
    if not keep.any():
        return pairs, priced, cost
    more, extra = more.take(keep), extra.take(keep)
    # Pairs the first pass sees take their spread against candidates within max_gap_s
    # (_spread): the short pairs' costs do not change.
    refs = _references(pairs, priced, params, n) if priced.log_sd is not None else None
    both = pairs.concat(more)
    order = np.argsort(both.i * n + both.j, kind="stable")
    cost = np.concatenate([cost, extra.total(more, params, n, refs)])[order]
    return both.take(order), priced.concat(extra).take(order), cost


def _gap_price(pairs: Pairs, params: LinkParams) -> np.ndarray:
    """Per pair: what the assignment adds for a gap beyond ``max_gap_s`` (soft T_gap):
    ``gap_price`` per ``max_gap_s`` beyond it."""
    beyond = np.maximum(counted_gap(pairs) - params.max_gap_s, 0.0)
    return params.gap_price * beyond / max(params.max_gap_s, 1e-9)


def soft_gap_test(
    pairs: Pairs, cost: np.ndarray, chosen: np.ndarray, params: LinkParams, n: int
) -> np.ndarray:
    """The chosen pairs (indices into ``pairs``) less the joins across a gap beyond
    ``max_gap_s`` (soft T_gap) that are not each piece's cheapest candidate by
    ``long_margin`` — among all its candidates here, not only those overlapping in time
    (the margin test's), a rival whose other piece is claimed more cheaply excepted.
    A long join is held to the second look's standard; both pieces stay loose."""
    long = counted_gap(pairs)[chosen] > params.max_gap_s
    if not long.any():
        return chosen
    claim_end = np.full(n, np.inf)
    claim_start = np.full(n, np.inf)
    claim_end[pairs.i[chosen]] = cost[chosen]
    claim_start[pairs.j[chosen]] = cost[chosen]
    mine = np.zeros(len(pairs), dtype=bool)
    mine[chosen] = True
    lc = chosen[long]
    # Only the rivals of the long joins' pieces are looked at (27 of 65,723 joins are long
    # in the bench's 100 k scene): the pairs of their old ends, of their new starts.
    of_end = np.zeros(n, dtype=bool)
    of_start = np.zeros(n, dtype=bool)
    of_end[pairs.i[lc]] = True
    of_start[pairs.j[lc]] = True
    ri = np.flatnonzero(of_end[pairs.i])
    rj = np.flatnonzero(of_start[pairs.j])
    rival_i = np.where(mine[ri] | (claim_start[pairs.j[ri]] < cost[ri]), np.inf, cost[ri])
    rival_j = np.where(mine[rj] | (claim_end[pairs.i[rj]] < cost[rj]), np.inf, cost[rj])
    best_i = np.full(n, np.inf)
    best_j = np.full(n, np.inf)
    np.minimum.at(best_i, pairs.i[ri], rival_i)
    np.minimum.at(best_j, pairs.j[rj], rival_j)
    c = cost[lc] + params.long_margin
    keep = np.ones(len(chosen), dtype=bool)
    keep[np.flatnonzero(long)] = ~((best_i[pairs.i[lc]] < c) | (best_j[pairs.j[lc]] < c))
    return chosen[keep]


#: A pair may be as far apart as this times the speed its faster end was seen at, when
#: that is above ``v_max_kn`` (high-speed craft: the Saronic ferries at 32-40 kn).
FAST_FACTOR = 1.2
#: ... but never beyond this (kn), and only from ends whose speed is known to 2 kn.
FAST_CAP_KN = 60.0
FAST_SD_KN = 2.0


def _seen_speed_kn(seg: Segments) -> tuple[np.ndarray, np.ndarray]:
    """Per track: the reach speed (kn) its end and its start allow, FAST_FACTOR × the speed
    seen there — fitted where known to FAST_SD_KN, or reported — at most FAST_CAP_KN."""
    out = []
    for speed, sd, known, sog in (
        (seg.speed1_kn, seg.vel_sd1, seg.motion1, seg.sog1),
        (seg.speed0_kn, seg.vel_sd0, seg.motion0, seg.sog0),
    ):
        with np.errstate(invalid="ignore"):
            sure = known & (sd < FAST_SD_KN * geo.KN_MS) & np.isfinite(speed)
        seen = np.where(sure, speed, 0.0)
        if sog is not None:  # a reported speed counts without a course (AIS to 0.1 kn)
            seen = np.fmax(seen, np.nan_to_num(sog))
        out.append(np.minimum(FAST_FACTOR * seen, FAST_CAP_KN))
    return out[0], out[1]


def pair_features(
    seg: Segments,
    i: np.ndarray,
    j: np.ndarray,
    dist: np.ndarray | None = None,
    step_allowance_s: float = 0.0,
    step_cap_s: float = np.inf,
) -> Pairs:
    """The features of the pairs (old ``i`` → new ``j``) of ``seg``: gap, end-to-start
    distance (m; ``dist`` when the caller has it), dead-reckoning miss, course and speed
    differences, and the gap's step allowance (s; ``step_allowance_s``, each end's step
    counted up to ``step_cap_s``, :func:`_step_allowance`; None when no pair has one)."""
    gap = seg.t0[j] - seg.t1[i]
    if dist is None:
        dist = geo.haversine_m(seg.lon1[i], seg.lat1[i], seg.lon0[j], seg.lat0[j])
    px, py = geo.to_local(seg.lon0[j], seg.lat0[j], seg.lon1[i], seg.lat1[i])
    # the new piece's velocity and course in the old end's plane (turned by the meridians'
    # convergence between the ends: 0.5° over a 20 km gap at 72° N)
    turn = geo.plane_turn(seg.lon0[j], seg.lat0[j], seg.lon1[i], seg.lat1[i])
    vxj, vyj = geo.turn_into_plane(seg.vx0[j], seg.vy0[j], turn)
    miss = _miss_one_turn(px, py, seg.vx1[i] * gap, seg.vy1[i] * gap, vxj * gap, vyj * gap)
    # Course over ground means nothing for a ship at rest: the difference counts in full
    # only when both ends move at 2 kn or more.
    slow = np.minimum(seg.speed1_kn[i], seg.speed0_kn[j])
    course_j = seg.course0_deg[j] + np.degrees(np.arctan2(*turn))
    dcourse = geo.angle_diff(seg.course1_deg[i], course_j) * np.clip(slow / 2.0, 0, 1)
    dspeed = np.abs(seg.speed1_kn[i] - seg.speed0_kn[j])
    allow = (
        _step_allowance(seg, i, j, step_allowance_s, step_cap_s) if step_allowance_s > 0 else None
    )
    if allow is not None and not allow.any():
        allow = None  # the common case (steps within the allowance): no array kept
    return Pairs(i, j, gap, dist, miss, dcourse, dspeed, allow)


def _miss_one_turn(
    px: np.ndarray, py: np.ndarray, ax: np.ndarray, ay: np.ndarray, bx: np.ndarray, by: np.ndarray
) -> np.ndarray:
    """Distance (m) from the observed displacement p to the displacements possible with one
    course change in the gap: old velocity for τ, new velocity for the rest, τ ∈ [0, gap].

    Those form the segment from ``b`` (new velocity × gap) to ``a`` (old velocity × gap);
    a ship that kept its course gives a = b and the plain dead-reckoning miss.
    """
    dx, dy = ax - bx, ay - by
    den = dx * dx + dy * dy
    with np.errstate(invalid="ignore", divide="ignore"):
        u = np.where(den > 0, ((px - bx) * dx + (py - by) * dy) / den, 0.0)
    u = np.clip(np.nan_to_num(u), 0.0, 1.0)
    return np.hypot(px - (bx + u * dx), py - (by + u * dy))


def _minmax(x: np.ndarray) -> np.ndarray:
    if len(x) == 0:
        return x
    lo, hi = float(np.min(x)), float(np.max(x))
    return (x - lo) / (hi - lo) if hi > lo else np.zeros_like(x)


def _seen_at_rest(seg: Segments, pairs: Pairs, params: LinkParams) -> np.ndarray:
    """Per pair: both ends' own fixes (three or more each) span at least ``rest_seen_s``."""
    if params.rest_seen_s <= 0 or seg.span0 is None or seg.span1 is None:
        return np.zeros(len(pairs), dtype=bool)
    i, j = pairs.i, pairs.j
    return (
        (seg.n[i] >= 3)
        & (seg.n[j] >= 3)
        & (seg.span1[i] >= params.rest_seen_s)
        & (seg.span0[j] >= params.rest_seen_s)
    )


def _both_moving(seg: Segments, pairs: Pairs, params: LinkParams) -> np.ndarray:
    """Per pair: the old end's and the new start's fitted speeds are above ``rest_kn``."""
    slow = params.rest_kn * geo.KN_MS
    return (np.hypot(seg.vx1[pairs.i], seg.vy1[pairs.i]) > slow) & (
        np.hypot(seg.vx0[pairs.j], seg.vy0[pairs.j]) > slow
    )


def rest_drift_m(gap_s: np.ndarray, params: LinkParams) -> np.ndarray:
    """How far (m, per axis) a ship at rest at both ends of a gap of ``gap_s`` seconds
    may seem to have moved: ``rest_drift_m`` once the gap reaches ``rest_drift_s``, less
    (as the square root of the gap) before — GPS wander and swinging at anchor take time."""
    if params.rest_drift_s <= 0:
        return np.full(np.shape(gap_s), params.rest_drift_m)
    share = np.clip(np.asarray(gap_s, dtype="float64") / params.rest_drift_s, 0.0, 1.0)
    return params.rest_drift_m * np.sqrt(share)


def at_rest_pairs(seg: Segments, pairs: Pairs, params: LinkParams) -> np.ndarray:
    """Per pair: its old end and its new start are at rest — each end's speed and the
    speed's standard error below ``rest_kn`` — or one is and the other shows no motion of
    its own (a single fix borrows the other end's velocity, so it is at rest too). Never
    when ``rest_kn`` is 0."""
    if params.rest_kn <= 0:
        return np.zeros(len(pairs), dtype=bool)
    i, j = pairs.i, pairs.j
    slow = params.rest_kn * geo.KN_MS
    known_i, known_j = seg.motion1[i], seg.motion0[j]
    with np.errstate(invalid="ignore"):
        still_i = known_i & (np.hypot(seg.vx1[i], seg.vy1[i]) < slow) & (seg.vel_sd1[i] < slow)
        still_j = known_j & (np.hypot(seg.vx0[j], seg.vy0[j]) < slow) & (seg.vel_sd0[j] < slow)
    return (still_i & still_j) | (still_i & ~known_j) | (still_j & ~known_i)


def _gap_accel(
    seg: Segments, i: np.ndarray, j: np.ndarray, params: LinkParams
) -> np.ndarray | float:
    """Per pair: the unknown acceleration (m/s²) allowed in the gap: ``accel_ms2``, or
    with ``measured_accel`` the larger of it and what either end shows (a ship seen
    speeding up, slowing down or turning at an end may go on doing so in the gap)."""
    if not params.measured_accel or seg.accel0 is None or seg.accel1 is None:
        return params.accel_ms2
    return np.fmax(params.accel_ms2, np.fmax(seg.accel1[i], seg.accel0[j]))


def _motion_shown(seg: Segments, params: LinkParams) -> tuple[np.ndarray, np.ndarray]:
    """Per track: whether its start and its end show their motion to the pricing —
    the motion flags, less (``motion_shown`` > 0) ends not at rest whose fitted speed is
    below ``motion_shown`` standard errors of their velocity (a course of noise)."""
    if params.motion_shown <= 0:
        return seg.motion0, seg.motion1
    slow = params.rest_kn * geo.KN_MS
    out = []
    for vx, vy, sd, known in (
        (seg.vx0, seg.vy0, seg.vel_sd0, seg.motion0),
        (seg.vx1, seg.vy1, seg.vel_sd1, seg.motion1),
    ):
        speed = np.hypot(vx, vy)
        with np.errstate(invalid="ignore"):
            still = (speed < slow) & (sd < slow)
            noise = ~still & ~(speed >= params.motion_shown * sd)
        out.append(known & ~noise)
    return out[0], out[1]


def _speed_change_kn2(pairs: Pairs, params: LinkParams) -> np.ndarray | float:
    """Per pair: the square (kn²) of the speed change its gap allows
    (``speed_change_ms2`` × the gap), added to the speed tolerance's square; 0 when off."""
    if params.speed_change_ms2 <= 0:
        return 0.0
    return (params.speed_change_ms2 * pairs.gap_s / geo.KN_MS) ** 2


def _slow_change_kn2(seg: Segments, pairs: Pairs, params: LinkParams) -> np.ndarray | float:
    """Per pair: the square (kn²) of the speed change its gap allows where one end is slow
    (``slow_change_ms2`` × the gap, where the end's or the start's fitted speed is below
    ``slow_end_kn``), added to the speed tolerance's square; 0 elsewhere and when off."""
    if params.slow_change_ms2 <= 0:
        return 0.0
    slow = np.minimum(seg.speed1_kn[pairs.i], seg.speed0_kn[pairs.j]) < params.slow_end_kn
    return np.where(slow, (params.slow_change_ms2 * pairs.gap_s / geo.KN_MS) ** 2, 0.0)


def _debiased_speed(speed_ms: np.ndarray, sd_ms: np.ndarray) -> np.ndarray:
    """The fitted speed (m/s) less its noise's share: sqrt(max(speed² − 2·sd², 0))."""
    sd = np.nan_to_num(sd_ms, nan=0.0, posinf=0.0)
    return np.sqrt(np.fmax(speed_ms**2 - 2.0 * sd**2, 0.0))


def prediction_miss(seg: Segments, pairs: Pairs, params: LinkParams) -> tuple[np.ndarray, ...]:
    """Position miss (m) of each pair against the one-course-change prediction, its
    standard deviation (m), and whether neither end shows its motion (``blind``).

    An end without motion (one fix, or fixes at one instant) borrows the other end's
    velocity; the standard deviation combines both ends' fitted-position errors, the
    velocity error over the gap and the unseen manoeuvres: ½·a·gap² (a: ``accel_ms2``, or
    what an end shows, :func:`_gap_accel`), which for long gaps becomes ``drift_ms``·gap
    (an acceleration does not last for hours; a velocity change of ``drift_ms`` does) —
    all per axis, added in squares.
    """
    i, j, gap = pairs.i, pairs.j, pairs.gap_s
    known_i, known_j = seg.motion1[i], seg.motion0[j]
    blind = ~known_i & ~known_j
    if params.motion_shown > 0:
        # An end whose velocity is noise borrows the other end's where that one shows its
        # motion (both such: each keeps its own, as before).
        shown0, shown1 = _motion_shown(seg, params)
        one = shown1[i] ^ shown0[j]
        known_i = np.where(one, shown1[i], known_i)
        known_j = np.where(one, shown0[j], known_j)
    # the new piece's velocity in the old end's plane (:func:`pair_features`)
    turn = geo.plane_turn(seg.lon0[j], seg.lat0[j], seg.lon1[i], seg.lat1[i])
    vx0j, vy0j = geo.turn_into_plane(seg.vx0[j], seg.vy0[j], turn)
    vxi = np.where(known_i, seg.vx1[i], vx0j)
    vyi = np.where(known_i, seg.vy1[i], vy0j)
    vxj = np.where(known_j, vx0j, vxi)
    vyj = np.where(known_j, vy0j, vyi)
    px, py = geo.to_local(seg.lon0[j], seg.lat0[j], seg.lon1[i], seg.lat1[i])
    miss = _miss_one_turn(px, py, vxi * gap, vyi * gap, vxj * gap, vyj * gap)
    vsd_i = np.where(known_i, seg.vel_sd1[i], np.nan)
    vsd_j = np.where(known_j, seg.vel_sd0[j], np.nan)
    vsd = np.sqrt(np.where(known_i & known_j, (vsd_i**2 + vsd_j**2) / 2, 0.0))
    vsd = np.where(known_i & ~known_j, vsd_i, np.where(known_j & ~known_i, vsd_j, vsd))
    var = (
        seg.pos_sd1[i] ** 2
        + seg.pos_sd0[j] ** 2
        + (vsd * gap) ** 2
        + np.minimum(0.5 * _gap_accel(seg, i, j, params) * gap**2, params.drift_ms * gap) ** 2
    )
    # Never below a sampling-grid metre: exact synthetic positions still carry rounding.
    sigma = np.sqrt(np.maximum(var, 1.0))
    return miss, sigma, blind


@dataclass(frozen=True)
class _Priced:
    """A pricing before the spread term (:func:`_spread`), which compares each pair with
    the other candidates of its ends and so is added over a whole candidate set."""

    cost: np.ndarray  # without the spread term, before the price of blind pairs
    share: np.ndarray | None  # the position term's part of the weights
    log_sd: np.ndarray | None  # ln σ of the predicted position (m)
    blind: np.ndarray
    fitted: np.ndarray | None = None  # both pieces may take part in the soft T_gap

    def _fields(self) -> tuple:
        return (self.cost, self.share, self.log_sd, self.blind, self.fitted)

    def take(self, keep: np.ndarray) -> "_Priced":
        return _Priced(*(None if v is None else v[keep] for v in self._fields()))

    def concat(self, other: "_Priced") -> "_Priced":
        """These pairs' pricing followed by ``other``'s."""
        return _Priced(
            *(
                None if v is None else np.concatenate([v, w])
                for v, w in zip(self._fields(), other._fields(), strict=True)
            )
        )

    def put(self, where: np.ndarray, new: "_Priced") -> "_Priced":
        """A copy with the pairs at ``where`` priced as ``new``."""
        out = []
        for v, w in zip(self._fields(), new._fields(), strict=True):
            if v is not None:
                v = v.copy()
                v[where] = w
            out.append(v)
        return _Priced(*out)

    def refusing(self, pairs: Pairs, n: int, blocked: np.ndarray | None) -> "_Priced":
        """The refused pairs (keys ``i·n + j``) priced ∞: no join, and no reference of
        their ends' other candidates in the spread term."""
        return replace(self, cost=_blocked_cost(pairs, self.cost, n, blocked))

    def total(
        self, pairs: Pairs, params: LinkParams, n: int, refs: tuple | None = None
    ) -> np.ndarray:
        """The costs: plus the spread term (against ``refs``, :func:`_references`, by
        default those of these pairs), blind pairs at ``no_join`` less the margin."""
        cost = self.cost
        if self.log_sd is not None and len(pairs):
            refs = refs if refs is not None else _references(pairs, self, params, n)
            cost = cost + self.share * _spread(pairs, self.log_sd, refs, params, self.fitted)
        blind = max(params.no_join - params.margin, 0.0)
        if params.blind_order > 0 and self.blind.any():
            # Never more than half the room left below the price of staying loose (and
            # the gate): the order settles ties, it must not push a pair out of reach
            # (with margin 0 there is no room: all alike, as before).
            room = max(min(params.gate, params.no_join) - blind, 0.0) / 2.0
            step = min(params.blind_order, room)
            blind = blind + step * _blind_order(pairs, params)
        return np.where(self.blind, blind, cost)


def _blind_order(pairs: Pairs, params: LinkParams) -> np.ndarray:
    """Per pair, 0..1: the speed its two fixes imply (distance / gap) over ``v_max_kn``
    (1 beyond). With no motion at either end this is all the pair shows, and a ship is
    found slower far more often than near v_max."""
    v_max = max(params.v_max_kn * geo.KN_MS, 1e-9)
    with np.errstate(invalid="ignore", divide="ignore"):
        level = pairs.dist_m / np.fmax(pairs.gap_s, 1e-9) / v_max
    return np.clip(np.nan_to_num(level, nan=1.0, posinf=1.0), 0.0, 1.0)


def pair_cost(
    pairs: Pairs, params: LinkParams, normalize: str = "scaled", seg: Segments | None = None
) -> np.ndarray:
    """Combined distance α·d′ + β·c′ + γ·v′ of every pair.

    ``normalize="minmax"`` is seed 003's min-max over the candidate set; ``"scaled"``
    divides each term by a tolerance (course: ``course_tol_deg``; speed: ``speed_tol_kn``;
    position: ``sigmas`` standard deviations of the predicted end when ``uncertainty_gate``
    and ``seg`` are given, else ``position_tol_m + drift_ms·gap``), so a cost means the
    same in every scene and a gate can be absolute. Weights are renormalized to sum to 1
    over the terms that are known for the pair (course and speed mean nothing at an end
    without motion). A pair of which neither end shows its motion has only reachability
    as evidence and costs ``no_join`` less the margin (plus ``blind_order`` × the speed it
    implies over v_max: the slower first): it is taken only when nothing else claims either
    piece. With ``log_sigma`` the position term also pays the spread of its
    prediction against the plausible candidates within ``max_gap_s`` in ``pairs`` of the
    same ends (:func:`_spread`); ``uncertainty_gate`` off, there is no σ and no spread.
    """
    return _pricing(pairs, params, normalize, seg).total(
        pairs, params, 0 if seg is None else len(seg)
    )


def _pricing(
    pairs: Pairs, params: LinkParams, normalize: str = "scaled", seg: Segments | None = None
) -> _Priced:
    """:func:`pair_cost` of every pair on its own, the spread term apart."""
    wsum = params.alpha + params.beta + params.gamma
    if wsum <= 0:
        raise InputError("alpha + beta + gamma must be positive")
    if normalize == "minmax":
        d = pairs.miss_m if params.predict else pairs.dist_m
        a, b, g = params.alpha / wsum, params.beta / wsum, params.gamma / wsum
        terms = (_minmax(d), _minmax(pairs.dcourse_deg), _minmax(pairs.dspeed_kn))
        cost = a * terms[0] + b * np.nan_to_num(terms[1]) + g * np.nan_to_num(terms[2])
        return _Priced(cost, None, None, np.zeros(len(pairs), dtype=bool))
    blind = np.zeros(len(pairs), dtype=bool)
    dcourse, dspeed = pairs.dcourse_deg, pairs.dspeed_kn
    log_sd = None
    if params.uncertainty_gate and seg is not None:
        miss, sigma, blind = prediction_miss(seg, pairs, params)
        d = (miss if params.predict else pairs.dist_m) / (params.sigmas * sigma)
        i, j = pairs.i, pairs.j
        # Both ends at rest: the ship lay still before and after the gap. Within
        # ``sigmas`` standard deviations of its spot (its ends' noise and rest_drift_m:
        # GPS wander, swinging at anchor) it is priced as any other pair; beyond, it
        # must have left and stopped again, and the rest model charges every further
        # sigmas·σ one unit, however long the gap (two ships moored 400 m apart are not
        # one ship that crossed the harbour and stopped again).
        rest = at_rest_pairs(seg, pairs, params)
        if rest.any():
            drift = rest_drift_m(pairs.gap_s, params)
            # Ends seen at rest long enough show the ship's wander: a ship lying within
            # 4 m for an hour is at a berth and is not expected 40 m off (its neighbour's
            # spot); every metre off the spot is charged. A short end (a few fixes) says
            # nothing of a swing at anchor: the allowance and its free zone.
            seen = _seen_at_rest(seg, pairs, params) & rest
            ends_sd2 = seg.pos_sd1[i] ** 2 + seg.pos_sd0[j] ** 2
            spot = params.sigmas * np.sqrt(np.fmax(ends_sd2 + drift**2, 1.0))
            loose = np.fmax(d, pairs.dist_m / spot - 1.0)  # within the allowance, free
            d = np.where(rest, loose, d)
            if seen.any():
                # Two hypotheses: it lay where it was seen lying (the spot its scatter
                # shows, every metre off the prediction charged: a ship creeping below
                # rest_kn is expected where its velocity takes it), or it moved within the
                # allowance (re-berthed, drifted: rest_move more). The scatter is taken as
                # at least a metre (a GPS holding one position shows none).
                scatter = params.rest_wander * np.fmax(np.fmax(seg.noise1[i], seg.noise0[j]), 1.0)
                vel2 = (seg.vel_sd1[i] ** 2 + seg.vel_sd0[j] ** 2) / 2 * pairs.gap_s**2
                # Never below a metre, as the moving-ship sigma (rest_wander may be 0).
                tight = params.sigmas * np.sqrt(
                    np.fmax(
                        ends_sd2 + np.fmin(drift, scatter) ** 2 + np.where(seen, vel2, 0.0), 1.0
                    )
                )
                lay = np.fmax(d, (miss if params.predict else pairs.dist_m) / tight)
                moved = loose + params.rest_move
                d = np.where(seen, np.fmin(lay, moved), d)
                # The tight spread only where lying still is the price taken: a pair priced
                # as "moved" is spread as widely as any rest pair, and must not become the
                # tightest reference of its ends' other candidates (the spread term).
                spot = np.where(seen & (lay <= moved), tight, spot)
            # At rest the ship is expected at its spot, not spread by unknown motion.
            sigma = np.where(rest, np.fmin(sigma, spot / params.sigmas), sigma)
        if params.log_sigma > 0:
            log_sd = np.log(sigma)
        known = seg.motion1[i] & seg.motion0[j]
        if params.motion_shown > 0:
            shown0, shown1 = _motion_shown(seg, params)
            known = known & shown1[i] & shown0[j]
        # Course and speed tolerances grow with the ends' velocity errors (noisy tracks
        # give noisy velocities): the error in knots, and in degrees as seen at the speed
        # (with course_debias, at the speed less its noise).
        vi, vj = seg.vel_sd1[i], seg.vel_sd0[j]
        si, sj = seg.speed1_kn[i] * geo.KN_MS, seg.speed0_kn[j] * geo.KN_MS
        if params.course_debias:
            si, sj = _debiased_speed(si, vi), _debiased_speed(sj, vj)
        with np.errstate(invalid="ignore", divide="ignore"):
            v_kn2 = np.where(known, vi**2 + vj**2, 0.0) / geo.KN_MS**2
            c_deg2 = np.where(
                known,
                np.degrees(np.arctan2(vi, si)) ** 2 + np.degrees(np.arctan2(vj, sj)) ** 2,
                0.0,
            )
        course_tol = np.sqrt(params.course_tol_deg**2 + c_deg2)
        speed_tol = np.sqrt(
            params.speed_tol_kn**2
            + v_kn2
            + _speed_change_kn2(pairs, params)
            + _slow_change_kn2(seg, pairs, params)
        )
        # At rest at both ends, course means nothing and equal (zero) speeds are the
        # premise, not evidence: the position alone decides.
        dcourse = np.where(known & ~rest, dcourse, np.nan)
        dspeed = np.where(known & ~rest, dspeed, np.nan)
    else:
        d = (pairs.miss_m if params.predict else pairs.dist_m) / (
            params.position_tol_m + params.drift_ms * pairs.gap_s
        )
        course_tol, speed_tol = params.course_tol_deg, params.speed_tol_kn
    cost, share = _weighted_mean(
        (d, dcourse / course_tol, dspeed / speed_tol), (params.alpha, params.beta, params.gamma)
    )
    if log_sd is None:
        share = None
    return _Priced(cost, share, log_sd, blind, None if seg is None else _fitted(seg, pairs, params))


def _weighted_mean(terms: tuple, weights: tuple) -> tuple[np.ndarray, np.ndarray]:
    """Per pair: the weighted mean of its finite ``terms`` (inf when none is) and the first
    term's share of the weights used (0 when none is).

    Column by column, the weights' sum taken once (an m × 3 stack and three row sums
    were ~50 ms at 100 k segments): the sums of numpy's row sum, which starts from +0.0
    — the trailing ``+ 0.0`` gives its sign of zero — so the same bits."""
    w = [a * np.isfinite(t) for a, t in zip(weights, terms, strict=True)]
    wx = [wk * np.nan_to_num(t) for wk, t in zip(w, terms, strict=True)]
    wsum = w[0] + w[1] + w[2] + 0.0
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        cost = (wx[0] + wx[1] + wx[2] + 0.0) / wsum
        share = np.nan_to_num(w[0] / wsum)
    return np.where(wsum > 0, cost, np.inf), share


def _references(pairs: Pairs, priced: _Priced, params: LinkParams, n: int) -> tuple:
    """Per track (0..n−1): ln σ of the tightest plausible candidate of its old end and of
    its new start (inf when none) — among the candidates within ``max_gap_s`` (the first
    pass's, which is all it sees), and among all of ``pairs`` (for a second-look pair,
    whose rivals include the other long candidates). Plausible: priced within the gate
    and ``no_join`` before the spread term, with motion at one end at least."""
    ok = (
        (priced.cost <= min(params.gate, params.no_join))
        & ~priced.blind
        & np.isfinite(priced.log_sd)
    )
    out = []
    for use in (ok & (counted_gap(pairs) <= params.max_gap_s), ok):
        # The others as inf, which no minimum takes: one pass, not three gathers of the
        # pairs used.
        log_sd = np.where(use, priced.log_sd, np.inf)
        tight_i = np.full(n, np.inf)
        tight_j = np.full(n, np.inf)
        np.minimum.at(tight_i, pairs.i, log_sd)
        np.minimum.at(tight_j, pairs.j, log_sd)
        out.append((tight_i, tight_j))
    return tuple(out)


def _spread(
    pairs: Pairs,
    log_sd: np.ndarray,
    refs: tuple,
    params: LinkParams,
    fitted: np.ndarray | None = None,
) -> np.ndarray:
    """Per pair: ``log_sigma`` × ln(σ / σ_best), added to its position term.

    A position likelihood is the scaled miss's *and* 1/σ²: a prediction spread wider than
    a rival's explains a start there less, so a ship's next piece beats a later one that
    skips it. σ_best is the tightest σ among the plausible candidates (``refs``,
    :func:`_references`: within ``max_gap_s`` for a pair the first pass may see — within
    ``max_gap_s``, or the soft T_gap's (``fitted``, :func:`_in_first`) — any for a
    second-look one) of the pair's old end and of its new start, the pair itself
    included: never a bonus, and a lone candidate pays nothing however long its gap.
    """
    (short_i, short_j), (all_i, all_j) = refs
    i, j = pairs.i, pairs.j
    # A pair the first pass may see (within max_gap_s, or the soft T_gap's) is compared
    # with its ends' candidates within max_gap_s: every candidate set holds those, so the
    # cost is the same whichever set it is priced in.
    first = _in_first(counted_gap(pairs), fitted, params)
    best = np.where(
        first,
        np.minimum(short_i[i], short_j[j]),
        np.minimum(all_i[i], all_j[j]),
    )
    return params.log_sigma * np.nan_to_num(log_sd - np.fmin(best, log_sd))


def greedy_assign(
    i: np.ndarray, j: np.ndarray, cost: np.ndarray, gate: float, unmatched: float | None = None
) -> np.ndarray:
    """Seed 003's greedy minimum: take the smallest cost, blank its row and column, repeat.

    Returns the indices of the chosen pairs (cost ≤ ``gate`` and below ``unmatched``, the
    price of leaving both loose, when given)."""
    limit = gate if unmatched is None else min(gate, unmatched)
    order = np.argsort(cost, kind="stable")
    order = order[cost[order] <= limit]
    used_i: set[int] = set()
    used_j: set[int] = set()
    chosen = []
    for k, a, b in zip(order.tolist(), i[order].tolist(), j[order].tolist(), strict=True):
        if a in used_i or b in used_j:
            continue
        used_i.add(a)
        used_j.add(b)
        chosen.append(k)
    return np.asarray(chosen, dtype="int64")


def optimal_assign(
    i: np.ndarray, j: np.ndarray, cost: np.ndarray, gate: float, unmatched: float | None = None
) -> np.ndarray:
    """One-to-one assignment of least total cost over the pairs with cost ≤ ``gate``,
    leaving a row and a column unmatched at the price ``unmatched`` (default ``gate``);
    sparse, so thousands of tracks never build a dense matrix.

    Rows are the old tracks plus one dummy per new track, columns the new tracks plus one
    dummy per old track: (old i, new j) costs c_ij, (old i, its dummy) and (dummy of j, new j)
    cost ``gate``/2 each, and (dummy of j, dummy of i) is free for every candidate (i, j),
    so a pair is worth using when its cost is below the ``gate`` paid by leaving both
    unmatched.
    A constant is added to every edge (the matching is full, so it does not change the
    optimum) to keep zero costs as edges.
    """
    from scipy import sparse
    from scipy.sparse.csgraph import min_weight_full_bipartite_matching

    ok = (cost <= gate) & np.isfinite(cost)
    idx = np.flatnonzero(ok)
    if len(idx) == 0:
        return np.zeros(0, dtype="int64")
    ui, ri = np.unique(i[idx], return_inverse=True)
    uj, rj = np.unique(j[idx], return_inverse=True)
    n_old, n_new = len(ui), len(uj)
    shift = 1.0
    half = (
        gate if unmatched is None else unmatched
    ) / 2.0  # each side's unmatched price: together a pair is worth keeping if c < gate
    # A price of staying loose above what every real pair together can cost changes
    # nothing (the most pairs, then the least cost): capped there, so that an infinite
    # gate still leaves finite whole numbers below.
    half = min(half, 2.0 * min(n_old, n_new) * (float(cost[idx].max()) + shift) + 1.0)
    rows = np.concatenate([ri, np.arange(n_old), n_old + np.arange(n_new), n_old + rj])
    cols = np.concatenate([rj, n_new + np.arange(n_old), np.arange(n_new), n_new + ri])
    vals = np.concatenate(
        [
            cost[idx] + shift,
            np.full(n_old, half + shift),
            np.full(n_new, half + shift),
            np.full(len(idx), shift),
        ]
    )
    size = n_old + n_new
    # In whole numbers (micro-units of cost): scipy's LAPJVsp can loop for ever on float
    # costs (seen on 500 single-fix pieces with near-equal costs: no answer after 2 min;
    # 3 ms in whole numbers; tests/test_associate.py). Exact while sums stay below 2**53.
    scale = min(1e6, 2.0**52 / (float(vals.max()) * size))
    vals = np.maximum(np.round(vals * scale), 1.0)
    graph = sparse.csr_matrix((vals, (rows, cols)), shape=(size, size))
    r, c = min_weight_full_bipartite_matching(graph)
    # Chosen real edges: row r < n_old matched to a column c < n_new.
    real = (r < n_old) & (c < n_new)
    lookup = pd.Series(np.arange(len(idx)), index=pd.MultiIndex.from_arrays([ri, rj]))
    lookup = lookup[~lookup.index.duplicated()]
    picked = lookup.reindex(pd.MultiIndex.from_arrays([r[real], c[real]])).to_numpy()
    return idx[picked.astype("int64")]


def margin_test(
    seg: Segments,
    pairs: Pairs,
    cost: np.ndarray,
    chosen: np.ndarray,
    margin: float,
    displaced: tuple[float, float, float, bool] | None = None,
) -> np.ndarray:
    """The chosen pairs that pass the margin test (indices into ``pairs``).

    A rival of a chosen pair (i, j) is another candidate (i, j′) whose j′ overlaps j in
    time — the two cannot both be this ship's continuation — or (i′, j) with i′
    overlapping i, that is not claimed by a chosen pair of lower cost. A join whose rival
    costs less than ``margin`` more is ambiguous and dropped: both ends stay loose.
    ``displaced`` (``no_join``, ``gate``, ``margin_displaced``, charge by alternatives): a
    rival another chosen
    pair claims counts only where taking it would cost the assignment less than
    ``margin_displaced`` more (:func:`_displacement_holds`).
    """
    if len(chosen) == 0 or margin <= 0:
        return chosen
    # Cheapest chosen claim on each new start and each old end (inf where unclaimed).
    claim_j = np.full(len(seg), np.inf)
    claim_i = np.full(len(seg), np.inf)
    claim_j[pairs.j[chosen]] = cost[chosen]
    claim_i[pairs.i[chosen]] = cost[chosen]
    bad = np.zeros(len(chosen), dtype=bool)
    at = np.full(len(seg), -1, dtype=np.int64)
    c_all = cost[chosen]
    for own, other, claim in ((pairs.i, pairs.j, claim_j), (pairs.j, pairs.i, claim_i)):
        mine = own[chosen]
        # Not one-to-one (a count per track, not a sort of the chosen ends): every claim
        # row apart.
        if len(mine) and np.bincount(mine, minlength=len(seg)).max() > 1:
            return _margin_test_joined(seg, pairs, cost, chosen, margin, claim_i, claim_j)
        # Every candidate sharing its ``own`` end with a chosen pair (k: that pair).
        at[mine] = np.arange(len(chosen))
        k = at[own]
        at[mine] = -1
        sel = np.flatnonzero(k >= 0)
        k = k[sel]
        r, o, c_r = other[sel], other[chosen[k]], cost[sel]
        lo = np.maximum(seg.t0[r], seg.t0[o])
        hi = np.minimum(seg.t1[r], seg.t1[o])
        rival = (r != o) & (hi >= lo) & (c_r < c_all[k] + margin) & ~(claim[r] < c_r)
        if displaced is not None:
            rival &= ~_displacement_holds(
                seg, pairs, cost, chosen, own is pairs.i, sel, k, r, o, displaced
            )
        bad[k[rival]] = True
    return chosen[~bad]


def _displacement_holds(
    seg: Segments,
    pairs: Pairs,
    cost: np.ndarray,
    chosen: np.ndarray,
    old_side: bool,
    sel: np.ndarray,
    k: np.ndarray,
    r: np.ndarray,
    o: np.ndarray,
    prices: tuple[float, float, float, bool],
) -> np.ndarray:
    """Per rival row of :func:`margin_test` (candidate ``sel`` sharing its end with chosen
    pair ``chosen[k]``; ``r`` the rival's other piece, ``o`` the chosen pair's): whether a
    rival that another chosen pair claims is outweighed by what taking it would displace
    (``margin_displaced``). Taking the rival (cost c_r instead of the chosen c) frees
    ``o`` and takes ``r`` from its claimer x (claim c_x): x then goes loose with ``o``
    (the two halves of ``no_join``) or takes ``o`` (the candidate x–o, within the gate),
    whichever is cheaper. The rival holds as ambiguous only when that rearrangement costs
    less than ``prices[2]`` (``margin_displaced``) more than the assignment's:
    c_r + min(no_join, c_xo) − c − c_x < margin_displaced. ``prices``: (``no_join``,
    ``gate``, ``margin_displaced``, ``alternative``). With ``alternative``
    (``margin_displaced_charge``) the loose reading charges each freed piece half of
    min(no_join, its cheapest other candidate within the gate — partners other than the
    four pieces of the rearrangement) instead of half of ``no_join``: a piece with a cheap
    other reading loses little by being freed. Unclaimed rivals are not looked at (they
    hold, as before); nor is the margin test of joins that share an end
    (:func:`_margin_test_joined`)."""
    no_join, gate, need, alternative = prices
    n = len(seg)
    holder = np.full(n, -1, dtype=np.int64)
    # who claims r: the chosen pair whose piece on the rival's side is r
    side_of = pairs.j if old_side else pairs.i
    holder[side_of[chosen]] = chosen
    h = holder[r]
    claimed = h >= 0
    out = np.zeros(len(sel), dtype=bool)
    if not claimed.any():
        return out
    idx = np.flatnonzero(claimed)
    hc = h[idx]
    x = (pairs.i if old_side else pairs.j)[hc]  # the claimer's other piece
    # the candidate x–o (x old and o new when the rival shares the old end)
    a, b = (x, o[idx]) if old_side else (o[idx], x)
    keys = pairs.i.astype(np.int64) * n + pairs.j
    order = np.argsort(keys, kind="stable")
    want = a.astype(np.int64) * n + b
    at = np.searchsorted(keys[order], want)
    at = np.minimum(at, len(order) - 1)
    hit = keys[order][at] == want
    c_xo = np.where(hit, cost[order[at]], np.inf)
    c_xo = np.where(c_xo <= gate, c_xo, np.inf)
    loose = no_join
    if alternative:
        own_piece = (pairs.i if old_side else pairs.j)[sel[idx]]
        rr = r[idx]
        oo = o[idx]
        # x on the claimer's side, o on the chosen pair's; each excludes the four pieces
        x_old = old_side
        ax = _best_alternative(pairs, cost, gate, n, x, x_old, (rr, oo))
        ao = _best_alternative(pairs, cost, gate, n, oo, not x_old, (own_piece, x))
        loose = 0.5 * (np.fmin(no_join, ax) + np.fmin(no_join, ao))
    rearranged = cost[sel[idx]] + np.fmin(loose, c_xo)
    assigned = cost[chosen[k[idx]]] + cost[hc]
    out[idx] = rearranged >= assigned + need
    return out


def _margin_test_joined(
    seg: Segments,
    pairs: Pairs,
    cost: np.ndarray,
    chosen: np.ndarray,
    margin: float,
    claim_i: np.ndarray,
    claim_j: np.ndarray,
) -> np.ndarray:
    """:func:`margin_test` for chosen pairs that share an end (not one-to-one): each
    chosen row is compared with every candidate of its end by a join."""
    ch = pd.DataFrame({"k": chosen, "i": pairs.i[chosen], "j": pairs.j[chosen], "c": cost[chosen]})
    cand = pd.DataFrame({"i": pairs.i, "j": pairs.j, "c": cost})
    bad = np.zeros(len(chosen), dtype=bool)
    for own, other, claim in (("i", "j", claim_j), ("j", "i", claim_i)):
        ch["row"] = np.arange(len(chosen))
        m = ch.merge(cand, on=own, suffixes=("", "_r"))
        r, o = m[f"{other}_r"].to_numpy(), m[other].to_numpy()
        lo = np.maximum(seg.t0[r], seg.t0[o])
        hi = np.minimum(seg.t1[r], seg.t1[o])
        rival = (
            (r != o)
            & (hi >= lo)
            & (m["c_r"].to_numpy() < m["c"].to_numpy() + margin)
            & ~(claim[r] < m["c_r"].to_numpy())
        )
        bad[m["row"].to_numpy()[rival]] = True
    return chosen[~bad]


def insert_skipped(
    seg: Segments, pairs: Pairs, cost: np.ndarray, chosen: np.ndarray, limit: float
) -> np.ndarray:
    """Route a chosen join (i, j) through a loose piece p that lies in its gap when both
    (i, p) and (p, j) are candidates cheaper than ``limit``: a short piece between two
    ends of one ship is that ship's, and leaving it out would leave a loose piece and a
    join that skips a step. The cheapest such p (by c(i, p) + c(p, j)) is taken."""
    if len(chosen) == 0:
        return chosen
    used_old = np.zeros(len(seg), dtype=bool)
    used_new = np.zeros(len(seg), dtype=bool)
    used_old[pairs.i[chosen]] = True
    used_new[pairs.j[chosen]] = True
    ok = cost < limit
    cand = pd.DataFrame(
        {"k": np.flatnonzero(ok), "i": pairs.i[ok], "j": pairs.j[ok], "c": cost[ok]}
    )
    free = ~used_old & ~used_new
    first = cand[free[cand["j"].to_numpy()]].rename(columns={"j": "p", "k": "k1", "c": "c1"})
    second = cand[free[cand["i"].to_numpy()]].rename(columns={"i": "p", "k": "k2", "c": "c2"})
    ch = pd.DataFrame({"k": chosen, "i": pairs.i[chosen], "j": pairs.j[chosen]})
    m = ch.merge(first, on="i").merge(second, on=["p", "j"])
    if m.empty:
        return chosen
    m["s"] = m["c1"] + m["c2"]
    m = m.sort_values("s", kind="stable")
    m = m.drop_duplicates("k").drop_duplicates("p")
    keep = np.setdiff1d(chosen, m["k"].to_numpy())
    return np.concatenate([keep, m["k1"].to_numpy(), m["k2"].to_numpy()]).astype("int64")


def components(n: int, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Connected-component label of each of ``n`` tracks linked by pairs (a, b)."""
    from scipy import sparse
    from scipy.sparse.csgraph import connected_components

    g = sparse.coo_matrix((np.ones(len(a)), (a, b)), shape=(n, n))
    return connected_components(g, directed=False)[1]


@dataclass(frozen=True)
class Association:
    """Result: the pairs chosen, the target of every track and of every point."""

    segments: Segments
    pairs: Pairs  # all candidates
    cost: np.ndarray  # per candidate
    chosen: np.ndarray  # indices into ``pairs``
    target_of_track: np.ndarray  # per track: target label (str)
    method: str
    #: What the assignment started from, so that it can run again without some pairs
    #: (:meth:`without`): the summaries before any chain refit, the candidates of the
    #: first pass and their costs, the parameters and the normalization.
    base: Segments | None = None
    base_pairs: Pairs | None = None
    base_cost: np.ndarray | None = None
    params: LinkParams | None = None
    normalize: str = "scaled"
    #: Candidate pairs that ``mmsi_apart`` kept apart (different MMSIs), each once: the
    #: first pass's (within ``max_gap_s``, and the soft T_gap's look) and the second
    #: look's across long gaps, its rivals' searches included (h179; until then the first
    #: pass's only).
    mmsi_apart_pairs: int = 0
    #: Their keys ``i·n + j`` from the first pass's searches (:meth:`without` runs the
    #: second look again and counts with them).
    mmsi_apart_first: np.ndarray | None = None

    def without(self, blocked: np.ndarray) -> "Association":
        """The association run again with the pairs ``blocked`` refused (int64 keys
        ``i·n + j`` of track indices, old i → new j): the same candidates, costs,
        chain passes and second look, so the remaining tracks may find other partners."""
        if self.base is None or self.base_pairs is None or self.base_cost is None:
            raise InputError("this association cannot be run again (no starting state kept)")
        apart: list = [] if self.mmsi_apart_first is None else [self.mmsi_apart_first]
        seg, pairs, cost, chosen = assign_interrupted(
            self.base,
            self.base_pairs,
            self.base_cost,
            self.params or LinkParams(),
            self.method,
            self.normalize,
            blocked,
            apart=apart,
        )
        targets = _targets(seg, pairs.i[chosen], pairs.j[chosen])
        return replace(
            self,
            segments=seg,
            pairs=pairs,
            cost=cost,
            chosen=chosen,
            target_of_track=targets,
            mmsi_apart_pairs=apart_count(apart),
        )

    def points(self) -> pd.DataFrame:
        """Every input row (sorted by track and time) with a ``target`` column."""
        pts = self.segments.full_points().copy()
        pts["target"] = self.target_of_track[self.segments.index.track_of_row]
        return pts

    def pair_table(self) -> pd.DataFrame:
        """The chosen pairs: sensor, batch_a (old), batch_b (new), gap_s, distance_m, cost."""
        keys = self.segments.index.keys
        p = self.pairs
        k = self.chosen
        return pd.DataFrame(
            {
                "sensor": keys["sensor"].to_numpy()[p.i[k]],
                "batch_a": keys["batch"].to_numpy()[p.i[k]],
                "batch_b": keys["batch"].to_numpy()[p.j[k]],
                "gap_s": np.round(p.gap_s[k], 3),
                "distance_m": np.round(p.dist_m[k], 1),
                "miss_m": np.round(p.miss_m[k], 1),
                "cost": np.round(self.cost[k], 4),
            }
        )

    def long_joins(self) -> np.ndarray:
        """Per chosen pair: joined across a gap beyond ``max_gap_s`` (by the second look, or
        by the assignment within the soft T_gap, ``soft_gap_s``)."""
        limit = self.params.max_gap_s if self.params is not None else np.inf
        return counted_gap(self.pairs)[self.chosen] > limit

    def report(self) -> dict:
        n_targets = len(np.unique(self.target_of_track))
        return {
            "method": self.method,
            "tracks": len(self.segments),
            "candidate_pairs": len(self.pairs),
            "pairs_chosen": len(self.chosen),
            "long_gap_joins": int(self.long_joins().sum()),
            "rest_joins": int(self.rest_joins().sum()),
            "targets": n_targets,
            "single_fix_tracks": int((self.segments.n == 1).sum()),
            "mmsi_apart_pairs": self.mmsi_apart_pairs,
        }

    def rest_joins(self) -> np.ndarray:
        """Per chosen pair: priced as a ship lying still at both ends (:func:`at_rest_pairs`)."""
        if self.params is None or self.normalize != "scaled" or not len(self.chosen):
            return np.zeros(len(self.chosen), dtype=bool)
        return at_rest_pairs(self.segments, self.pairs.take(self.chosen), self.params)


def _targets(seg: Segments, links_i: np.ndarray, links_j: np.ndarray) -> np.ndarray:
    """Target label per track: the batch of the earliest track of its linked group —
    ``sensor:batch`` when the table holds several sensors, so batch 7 of R1 and batch 7
    of R2 never become one target."""
    comp = components(len(seg), links_i, links_j)
    leader = group_leaders(comp, order_by(comp, seg.t0_rank))
    keys = seg.index.keys
    label = keys["batch"].to_numpy().astype(str)
    # One sensor code, one sensor (the text of each is compared only when there are more).
    codes = seg.sensor_code
    if len(codes) and codes.min() != codes.max():
        sensors = keys["sensor"].to_numpy().astype(str)
        if len(np.unique(sensors)) > 1:
            label = np.char.add(np.char.add(sensors, ":"), label)
    return label[leader]


def group_leaders(comp: np.ndarray, order: np.ndarray) -> np.ndarray:
    """Per item, the index of its group's first item in ``order`` (a permutation sorting
    the items by their group ``comp`` first, then by what makes a leader: the earliest
    track names a target in association, review and fusion alike)."""
    if not len(order):
        return np.zeros(0, dtype="int64")
    first = np.ones(len(order), dtype=bool)
    first[1:] = comp[order][1:] != comp[order][:-1]
    leader = np.empty(comp.max() + 1, dtype="int64")
    leader[comp[order][first]] = order[first]
    return leader[comp]


def _best_alternative(
    pairs: Pairs,
    cost: np.ndarray,
    gate: float,
    n: int,
    p: np.ndarray,
    as_old: bool,
    exclude: tuple[np.ndarray, np.ndarray],
) -> np.ndarray:
    """Per query piece ``p`` (an old end when ``as_old``, else a new start): the cost of
    its cheapest candidate within ``gate`` whose other piece is neither of ``exclude``
    (inf when none). From each piece's three cheapest candidates (two exclusions), over the
    pairs of the asked pieces only."""
    mine, other = (pairs.i, pairs.j) if as_old else (pairs.j, pairs.i)
    asked = np.zeros(n, dtype=bool)
    asked[p] = True
    ok = np.flatnonzero(asked[mine] & np.isfinite(cost) & (cost <= gate))
    top_c = np.full((n, 3), np.inf)
    top_p = np.full((n, 3), -1, dtype=np.int64)
    if len(ok):
        # by piece, then by cost (two stable sorts of the asked pieces' pairs, no lexsort)
        order = ok[np.argsort(cost[ok], kind="stable")]
        order = order[np.argsort(mine[order], kind="stable")]
        m = mine[order]
        start = np.r_[0, np.flatnonzero(np.diff(m)) + 1]
        rank = np.arange(len(m)) - np.repeat(start, np.diff(np.r_[start, len(m)]))
        keep = rank < 3
        top_c[m[keep], rank[keep]] = cost[order[keep]]
        top_p[m[keep], rank[keep]] = other[order[keep]]
    c = top_c[p]
    q = top_p[p]
    c = np.where((q == exclude[0][:, None]) | (q == exclude[1][:, None]), np.inf, c)
    return c.min(axis=1)


def _assign_scaled(seg: Segments, pairs: Pairs, cost: np.ndarray, params: LinkParams, assign):
    """Assignment with the loose-end price, the short-piece rule and the margin test; pairs
    beyond ``max_gap_s`` (soft T_gap) pay the gap price and must pass
    :func:`soft_gap_test`."""
    if len(pairs) and (counted_gap(pairs) > params.max_gap_s).any():
        cost = cost + _gap_price(pairs, params)
    chosen = assign(pairs.i, pairs.j, cost, params.gate, params.no_join)
    chosen = insert_skipped(seg, pairs, cost, chosen, min(params.gate, params.no_join))
    chosen = margin_test(
        seg,
        pairs,
        cost,
        chosen,
        params.margin,
        (
            params.no_join,
            params.gate,
            params.margin_displaced,
            params.margin_displaced_charge == "alternative",
        )
        if params.margin_displaced > 0
        else None,
    )
    return soft_gap_test(pairs, cost, chosen, params, len(seg))


def _two_cheapest(owner: np.ndarray, cost: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Per track (0..n−1): the index of its cheapest pair among those it ``owner``s (−1
    when none; the first of equal ones) and the cost of its second cheapest (inf when
    none).

    Three scatter-minima over the pairs, no sort (a lexsort of the pairs was 16 ms of
    100 k segments' second look, growing 15× per 10×); costs with NaN take the sort."""
    if not np.isnan(cost).any():
        m = len(owner)
        low = np.full(n, np.inf)
        np.minimum.at(low, owner, cost)
        k = np.flatnonzero(cost == low[owner])
        best = np.full(n, m, dtype="int64")
        np.minimum.at(best, owner[k], k)
        best[best == m] = -1
        rest = cost.copy()
        rest[best[best >= 0]] = np.inf
        second = np.full(n, np.inf)
        np.minimum.at(second, owner, rest)
        return best, second
    order = np.lexsort((cost, owner))
    o = owner[order]
    first = np.flatnonzero(np.r_[True, o[1:] != o[:-1]]) if len(o) else np.zeros(0, "int64")
    best = np.full(n, -1, dtype="int64")
    best[o[first]] = order[first]
    second = np.full(n, np.inf)
    nxt = first + 1
    has = nxt < len(o)
    has[has] = o[nxt[has]] == o[first[has]]
    second[o[first[has]]] = cost[order[nxt[has]]]
    return best, second


def _blocked_cost(pairs: Pairs, cost: np.ndarray, n: int, blocked: np.ndarray | None):
    if blocked is None or len(blocked) == 0 or len(pairs) == 0:
        return cost
    return np.where(member(pairs.i * n + pairs.j, blocked), np.inf, cost)


def _skips(
    cand: Pairs,
    links: Pairs,
    link_cost: np.ndarray,
    limit: float,
    chain: np.ndarray,
    head: np.ndarray,
    tail: np.ndarray,
) -> np.ndarray:
    """Per pair (i, j) of ``cand``: it skips a loose piece, or a chain of joined pieces,
    lying in its gap — ``links`` hold (i, p) into the chain's first start p (``head``)
    and (q, j) out of its last end q (``tail``), each costing at most ``limit``. The
    route i → p … q → j explains the pair, so it is no rival of (i, p) or (q, j): one
    ship may have left all of them.

    The route's links are not compared with the pair's own cost: scaled costs shrink
    with the gap, so a ship's own short links cost more than its long skip, and asking
    the route to cost at most ``long_margin`` more lost more true joins on the hard
    simulated scenes than it saved (docs/evaluation.md). The price: a lone piece of
    another ship lying in a ship's gap, within reach of both ends, is taken as a step of
    its route."""
    ok = link_cost <= limit
    first = ok & head[links.j]
    second = ok & tail[links.i]
    if not (first.any() and second.any() and len(cand)):
        return np.zeros(len(cand), dtype=bool)
    a = pd.DataFrame({"i": links.i[first], "p": chain[links.j[first]]})
    b = pd.DataFrame({"p": chain[links.i[second]], "j": links.j[second]})
    m = a.merge(b, on="p")
    n = len(chain)
    keys = m["i"].to_numpy() * n + m["j"].to_numpy()
    return member(cand.i * n + cand.j, keys)


def long_gap_pass(
    seg: Segments,
    pairs: Pairs,
    cost: np.ndarray,
    chosen: np.ndarray,
    params: LinkParams,
    blocked: np.ndarray | None = None,
    priced: _Priced | None = None,
    apart: list | None = None,
) -> tuple[Pairs, np.ndarray, np.ndarray]:
    """Second look across long gaps (``long_gap_s``): an old end and a new start that the
    assignment left loose are joined across a gap in (``max_gap_s``, ``long_gap_s``] when
    the pair costs at most the gate and ``no_join`` and is each one's cheapest candidate
    among *all* candidates within ``long_gap_s`` — joined ones included — by at least
    ``long_margin``. A ship that went silent for half an hour is found again when nothing
    else could be it; in dense traffic, where a loose end has many rivals, it stays loose.

    Returns the candidates with the long candidates of the pieces looked at appended,
    their costs and the chosen indices with the accepted ones added (mutually cheapest
    pairs never conflict). ``priced``: the pricing of ``pairs`` on ``seg`` (the spread
    term's references come from it; priced here when not given). ``apart``: as
    :func:`candidate_pairs`' (every search of this look and of its rivals).
    """
    n = len(seg)
    if params.long_gap_s <= params.max_gap_s or n < 2:
        return pairs, cost, chosen
    free_end, free_start = _free(pairs, chosen, n)
    if not (free_end.any() and free_start.any()):
        return pairs, cost, chosen
    wide = replace(params, max_gap_s=params.long_gap_s)
    limit = min(params.gate, params.no_join)
    margin = params.long_margin
    main = None
    if params.log_sigma > 0:
        main = priced if priced is not None else _pricing(pairs, params, "scaled", seg)
        main = main.refusing(pairs, n, blocked)
        if main.log_sd is None:  # no σ (uncertainty_gate off): no spread term
            main = None

    # The references of the first pass's candidates, taken once: a set's references are
    # the least over its parts (_references).
    main_refs = None if main is None else _references(pairs, main, params, n)

    def price(p: Pairs) -> np.ndarray:
        # The spread of a pair is taken among the first pass's candidates and the long
        # ones looked at (pair_cost over the candidates returned gives the same).
        parts = _pricing(p, wide, "scaled", seg).refusing(p, n, blocked)
        refs = None
        if main_refs is not None:
            long = counted_gap(p) > params.max_gap_s
            own = _references(p.take(long), parts.take(long), params, n)
            refs = tuple(
                (np.minimum(a_i, b_i), np.minimum(a_j, b_j))
                for (a_i, a_j), (b_i, b_j) in zip(main_refs, own, strict=True)
            )
        return _blocked_cost(p, parts.total(p, params, n, refs), n, blocked)

    # The searches of the first look, for the second: that one has fewer loose pieces
    # (released joins came back), so its searches are mostly the first's, filtered.
    searched: dict[str, tuple] = {}

    def search(name: str, ends: np.ndarray | None = None, starts: np.ndarray | None = None):
        found, searched[name] = _narrowed(seg, wide, ends, starts, searched.get(name), apart=apart)
        return found

    def look(joined: np.ndarray) -> tuple[Pairs, np.ndarray, np.ndarray]:
        """The second look with ``joined`` (indices into ``pairs``) as the joins: the long
        candidates of the pieces it looked at, their costs, and which it joins."""
        free_end, free_start = _free(pairs, joined, n)
        none = (pairs.take(np.zeros(0, dtype="int64")), np.zeros(0), np.zeros(0, dtype=bool))

        def mutual(cand: Pairs, c: np.ndarray, c_i: np.ndarray, c_j: np.ndarray):
            """Loose pairs beyond max_gap_s, each piece's cheapest by the margin (rivals
            of the end priced ``c_i``, of the start ``c_j``)."""
            best_i, second_i = _two_cheapest(cand.i, c_i, n)
            best_j, second_j = _two_cheapest(cand.j, c_j, n)
            k = np.arange(len(cand))
            m = np.where(_both_moving(seg, cand, params), params.long_margin_moving, margin)
            return (
                free_end[cand.i]
                & free_start[cand.j]
                & (counted_gap(cand) > params.max_gap_s)
                & (c <= limit)
                & (best_i[cand.i] == k)
                & (best_j[cand.j] == k)
                & (second_i[cand.i] >= c + m)
                & (second_j[cand.j] >= c + m)
            )

        # First among the loose pieces only (few pairs: a necessary condition), then
        # against every rival of the pieces that pass. A pair that skips a loose piece of
        # its own chain (i → p → j all cheap) is no rival: a ship moored for hours whose
        # AIS comes and goes leaves pieces at one spot, and every later one is "as cheap"
        # as the next.
        loose = search("loose", free_end, free_start)
        c_loose = price(loose)
        chain = components(n, pairs.i[joined], pairs.j[joined])
        skip = _skips(loose, loose, c_loose, limit, chain, free_start, free_end)
        c = np.where(skip, np.inf, c_loose)
        ok = mutual(loose, c, c, c)
        if not ok.any():
            return none
        ends = np.zeros(n, dtype=bool)
        ends[loose.i[ok]] = True
        starts = np.zeros(n, dtype=bool)
        starts[loose.j[ok]] = True
        a = search("a", ends=ends)
        b = search("b", starts=starts)
        if searched.get("cand", (None,))[0] is a and searched["cand"][1] is b:
            cand, c = searched["cand"][2:]  # the same searches: the same pairs and prices
        else:
            cand = a.concat(b.take(~ends[b.i]))
            c = price(cand)
            searched["cand"] = (a, b, cand, c)
        # A route through loose pieces runs on loose links only (a joined start belongs
        # to the chain that claimed it), so the loose pairs found first tell every skip.
        skip = _skips(cand, loose, c_loose, limit, chain, free_start, free_end)
        rank = np.where(skip, np.inf, c)
        # A joined track competes for a start once, through its last end: its inner ends
        # (already continued) are no rivals when that last end is a candidate too — and
        # likewise for an end, through a joined track's first start.
        key_j = cand.j * n + chain[cand.i]
        inner_i = ~free_end[cand.i] & member(key_j, key_j[free_end[cand.i]])
        key_i = cand.i * n + chain[cand.j]
        inner_j = ~free_start[cand.j] & member(key_i, key_i[free_start[cand.j]])
        ok = mutual(cand, rank, np.where(inner_j, np.inf, rank), np.where(inner_i, np.inf, rank))
        ok &= ends[cand.i] & starts[cand.j]
        if not ok.any():
            return none
        # Every long candidate of the pieces looked at is kept (their rivals beyond
        # T_gap: the review shows the runner-up of a long join).
        long = counted_gap(cand) > params.max_gap_s
        return cand.take(long), c[long], ok[long]

    released = np.zeros(0, dtype="int64")
    if params.long_rivals:
        released = _released_rounds(
            seg, pairs, cost, chosen, params, price, free_end, free_start, apart
        )
    joined = chosen[~member(chosen, released)]
    found, c_found, ok = look(joined)
    if len(released):
        # A join gives way only to a long join the second look makes: the others come
        # back, and the second look runs again with them joined (as loose pieces they
        # were rivals they never were).
        left_i, left_j = _free(found, np.flatnonzero(ok), n)
        kept = released[~left_i[pairs.i[released]] | ~left_j[pairs.j[released]]]
        if len(kept) < len(released):
            released = kept
            joined = chosen[~member(chosen, released)]
            found, c_found, ok = look(joined)
    if not ok.any():
        return pairs, cost, chosen
    # Pairs within the soft T_gap that the first pass saw already (and left loose) are
    # joined where they are, not listed twice.
    key = pairs.i * n + pairs.j
    order = np.argsort(key, kind="stable")
    key_f = found.i * n + found.j
    key = key[order]
    at = np.minimum(np.searchsorted(key, key_f), max(len(key) - 1, 0))
    seen = (key[at] == key_f) if len(key) else np.zeros(len(found), dtype=bool)
    again = order[at[seen & ok]]
    found, c_found, ok = found.take(~seen), c_found[~seen], ok[~seen]
    out = np.concatenate([joined, again, len(pairs) + np.flatnonzero(ok)])
    every = pairs.concat(found)  # once: 7 arrays of every candidate (42 MB at 100 k)
    if len(released):
        # What the last look did not take after all, comes back.
        end_free, start_free = _free(every, out, n)
        back = released[end_free[pairs.i[released]] & start_free[pairs.j[released]]]
        out = np.concatenate([out, back])
    return every, np.concatenate([cost, c_found]), out


def _free(pairs: Pairs, chosen: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Per track (0..n−1): its end is not continued, its start does not continue, by
    ``chosen`` (indices into ``pairs``)."""
    free_end = np.ones(n, dtype=bool)
    free_end[pairs.i[chosen]] = False
    free_start = np.ones(n, dtype=bool)
    free_start[pairs.j[chosen]] = False
    return free_end, free_start


def _released(
    seg: Segments,
    pairs: Pairs,
    cost: np.ndarray,
    chosen: np.ndarray,
    params: LinkParams,
    price,
    free_end: np.ndarray,
    free_start: np.ndarray,
    apart: list | None = None,
) -> np.ndarray:
    """``long_rivals``: the joins of ``chosen`` that a loose piece beyond max_gap_s (up to
    ``rivals_reach`` times it, at most ``long_gap_s``) would continue cheaper by
    ``long_margin`` — the assignment could not see it — priced by ``price`` (the second
    look's; its spread reference among the candidates up to that reach). Only a join
    dearer than the margin can be beaten (a rival costs at least 0)."""
    n = len(seg)
    m = params.long_margin
    near = replace(params, max_gap_s=min(params.long_gap_s, params.rivals_reach * params.max_gap_s))
    open_ = chosen[cost[chosen] >= m]
    end_open = np.zeros(n, dtype=bool)
    end_open[pairs.i[open_]] = True
    start_open = np.zeros(n, dtype=bool)
    start_open[pairs.j[open_]] = True
    rivals = candidate_pairs(seg, near, ends=end_open, starts=free_start, apart=apart).concat(
        candidate_pairs(seg, near, ends=free_end, starts=start_open, apart=apart)
    )
    # A join across the soft T_gap is itself long: its pieces' rivals are looked for as
    # far as the second look reaches (few joins, so few searches).
    far = open_[counted_gap(pairs)[open_] > params.max_gap_s]
    if len(far) and params.long_gap_s > near.max_gap_s:
        wide = replace(params, max_gap_s=params.long_gap_s)
        end_far = np.zeros(n, dtype=bool)
        end_far[pairs.i[far]] = True
        start_far = np.zeros(n, dtype=bool)
        start_far[pairs.j[far]] = True
        beyond = near.max_gap_s
        more = candidate_pairs(seg, wide, end_far, free_start, beyond, apart).concat(
            candidate_pairs(seg, wide, free_end, start_far, beyond, apart)
        )
        rivals = rivals.concat(more)
    rivals = rivals.take(counted_gap(rivals) > params.max_gap_s)
    if not len(rivals):
        return np.zeros(0, dtype="int64")
    c_riv = price(rivals)
    of_end = np.full(n, np.inf)
    of_start = np.full(n, np.inf)
    joined_i = ~free_end[rivals.i]
    np.minimum.at(of_end, rivals.i[joined_i], c_riv[joined_i])
    np.minimum.at(of_start, rivals.j[~joined_i], c_riv[~joined_i])
    beaten = np.minimum(of_end[pairs.i[chosen]], of_start[pairs.j[chosen]]) + m
    return chosen[beaten <= cost[chosen]]


def _released_rounds(
    seg: Segments,
    pairs: Pairs,
    cost: np.ndarray,
    chosen: np.ndarray,
    params: LinkParams,
    price,
    free_end: np.ndarray,
    free_start: np.ndarray,
    apart: list | None = None,
) -> np.ndarray:
    """:func:`_released` made ``rivals_rounds`` times: each round looks again at the joins
    still made, with the pieces the rounds before released counted loose (a join whose
    cheaper continuation was itself joined wrongly gives way once that one has)."""
    released = _released(seg, pairs, cost, chosen, params, price, free_end, free_start, apart)
    for _ in range(params.rivals_rounds - 1):
        if not len(released):
            break
        kept = chosen[~member(chosen, released)]
        fe, fs = _free(pairs, kept, len(seg))
        more = _released(seg, pairs, cost, kept, params, price, fe, fs, apart)
        if not len(more):
            break
        released = np.concatenate([released, more])
    return released


def assign_interrupted(
    base: Segments,
    pairs: Pairs,
    cost: np.ndarray,
    params: LinkParams,
    method: str = "optimal",
    normalize: str = "scaled",
    blocked: np.ndarray | None = None,
    priced: _Priced | None = None,
    apart: list | None = None,
) -> tuple[Segments, Pairs, np.ndarray, np.ndarray]:
    """The assignment stage of :func:`associate_interrupted`, from the candidates and
    their costs: one-to-one assignment with the loose-end price, the short-piece rule and
    the margin test, the chain passes, then the second look across long gaps.
    ``blocked``: pairs refused (keys ``i·n + j``; the operator's rejections).
    ``priced``: the pricing of ``pairs`` on ``base`` behind ``cost``, when the caller has
    it (the chain passes price only the pairs they touch; without it, every pair once).
    ``apart``: as :func:`candidate_pairs`' (the second look's searches).

    Returns the summaries (chain-refitted), the candidates (long pairs appended), their
    costs and the indices of the chosen pairs.
    """
    n = len(base)
    spread = normalize != "minmax" and params.log_sigma > 0
    refused = blocked is not None and len(blocked) > 0

    if spread and refused:
        priced = (priced or _pricing(pairs, params, normalize, base)).refusing(pairs, n, blocked)
        cost = priced.total(pairs, params, n)
    cost = _blocked_cost(pairs, cost, n, blocked)
    assign = optimal_assign if method == "optimal" else greedy_assign
    if normalize == "minmax":  # seed 003 as written: a gate, no loose-end price, no margin
        return base, pairs, cost, assign(pairs.i, pairs.j, cost, params.gate)
    seg = base
    chosen = _assign_scaled(seg, pairs, cost, params, assign)
    before = np.zeros(n, dtype=bool)  # refitted in the previous pass
    for _ in range(params.chain_passes):
        chain = components(n, pairs.i[chosen], pairs.j[chosen])
        seg, changed = chain_refit(
            base,
            chain,
            params.end_points,
            params.accel_ms2,
            params.drift_ms,
            params.end_span_s,
        )
        moved = changed | before
        before = changed
        touched = moved[pairs.i] | moved[pairs.j]
        if not touched.any():
            break
        # Only pairs with an end refitted now or in the previous pass change.
        # The steps are the base's (a refit end is seen at the sampling it was).
        new = replace(
            pair_features(seg, pairs.i[touched], pairs.j[touched]),
            allow_s=None if pairs.allow_s is None else pairs.allow_s[touched],
        )
        fields = {}
        for f in Pairs.__dataclass_fields__:
            v = getattr(pairs, f)
            if v is not None:
                v = v.copy()
                v[touched] = getattr(new, f)
            fields[f] = v
        pairs = Pairs(**fields)
        if spread:
            # The spread term compares each pair with its ends' other candidates, so the
            # total is taken over all of them; only the touched ones are priced again.
            if priced is None:
                priced = _pricing(pairs, params, normalize, base).refusing(pairs, n, blocked)
            priced = priced.put(touched, _pricing(new, params, normalize, seg))
            priced = priced.refusing(pairs, n, blocked)
            cost = priced.total(pairs, params, n)
        else:
            cost = cost.copy()
            cost[touched] = pair_cost(new, params, normalize, seg)
        cost = _blocked_cost(pairs, cost, n, blocked)
        chosen = _assign_scaled(seg, pairs, cost, params, assign)
    pairs, cost, chosen = long_gap_pass(
        seg, pairs, cost, chosen, params, blocked, priced if spread else None, apart
    )
    return seg, pairs, cost, chosen


def associate_interrupted(
    points: pd.DataFrame,
    params: LinkParams | None = None,
    method: str = "optimal",
    normalize: str = "scaled",
    progress: Progress | None = None,
) -> Association:
    """Join interrupted tracks of each sensor (SPEC §5b).

    ``method``: ``optimal`` (least total cost, sparse) or ``greedy`` (seed 003).
    ``normalize``: ``scaled`` (absolute tolerances) or ``minmax`` (seed 003).
    """
    params = (params or LinkParams()).checked()
    if method not in INTERRUPT_METHODS:
        raise InputError(f"unknown method {method!r}; choose one of {', '.join(INTERRUPT_METHODS)}")
    progress = progress or null_progress
    progress(0.0, "summarizing tracks")
    base = segment_stats(
        points,
        params.end_points,
        end_points_max=params.end_points_max,
        end_span_s=params.end_span_s,
    )
    progress(0.3, "finding candidate pairs")
    apart: list = []
    pairs0, priced, cost0 = first_pass_pairs(base, params, normalize, apart)
    first = [k for k in apart if len(k)]
    first_keys = np.unique(np.concatenate(first)) if first else np.zeros(0, dtype="int64")
    progress(0.6, f"assigning {len(pairs0):,} candidate pairs")
    seg, pairs, cost, chosen = assign_interrupted(
        base, pairs0, cost0, params, method, normalize, priced=priced, apart=apart
    )
    targets = _targets(seg, pairs.i[chosen], pairs.j[chosen])
    progress(1.0, f"{count_of(len(chosen), 'pair')} joined")
    return Association(
        seg,
        pairs,
        cost,
        chosen,
        targets,
        method,
        base,
        pairs0,
        cost0,
        params,
        normalize,
        apart_count(apart),
        first_keys,
    )


# --------------------------------------------------------------------------------------
# seed 001: segment association by clustering


def polygon_area(seg: Segments, pairs: Pairs) -> np.ndarray:
    """S_ij (m²): area of the polygon made by the points of i followed by those of j
    (seed 001 eq. 8), from each track's open shoelace sum, in a frame at i's origin."""
    i, j = pairs.i, pairs.j
    lon_o, lat_o = seg.origin_lon[i], seg.origin_lat[i]
    # j's own frame → i's frame: turned by the meridians' convergence between the origins
    # (geo.plane_turn), shifted by j's origin seen from i's origin.
    ojx, ojy = geo.to_local(seg.origin_lon[j], seg.origin_lat[j], lon_o, lat_o)
    turn = geo.plane_turn(seg.origin_lon[j], seg.origin_lat[j], lon_o, lat_o)
    fj = np.column_stack([*geo.turn_into_plane(*seg.first_xy[j].T, turn)])
    lj = np.column_stack([*geo.turn_into_plane(*seg.last_xy[j].T, turn)])
    fj += np.column_stack([ojx, ojy])
    lj += np.column_stack([ojx, ojy])
    cross_j = seg.cross[j] + ojx * (lj[:, 1] - fj[:, 1]) - ojy * (lj[:, 0] - fj[:, 0])
    fi, li = seg.first_xy[i], seg.last_xy[i]
    total = (
        seg.cross[i]
        + (li[:, 0] * fj[:, 1] - li[:, 1] * fj[:, 0])
        + cross_j
        + (lj[:, 0] * fi[:, 1] - lj[:, 1] * fi[:, 0])
    )
    return 0.5 * np.abs(total)


def _resampled(seg: Segments, tracks: np.ndarray, m: int) -> tuple[np.ndarray, np.ndarray]:
    """Each listed track as ``m`` points evenly spaced in index (lon, lat), (tracks × m)."""
    pts = seg.points
    lon = pts["lon"].to_numpy(dtype="float64")
    lat = pts["lat"].to_numpy(dtype="float64")
    s = seg.index.starts[tracks]
    size = seg.index.sizes[tracks]
    pos = np.round(np.linspace(0.0, 1.0, m)[None, :] * (size - 1)[:, None]).astype("int64")
    rows = s[:, None] + pos
    return lon[rows], lat[rows]


def shape_distance(seg: Segments, pairs: Pairs, kind: str, m: int = 32) -> np.ndarray:
    """DTW (mean matched distance) or Hausdorff distance, metres, between i and j of each
    pair, on ``m`` points of each; vectorized over pairs in blocks."""
    out = np.empty(len(pairs))
    block = max(1, 200_000 // (m * m))
    for a in range(0, len(pairs), block):
        i = pairs.i[a : a + block]
        j = pairs.j[a : a + block]
        lon_i, lat_i = _resampled(seg, i, m)
        lon_j, lat_j = _resampled(seg, j, m)
        d = geo.haversine_m(
            lon_i[:, :, None], lat_i[:, :, None], lon_j[:, None, :], lat_j[:, None, :]
        )
        if kind == "hausdorff":
            out[a : a + block] = np.maximum(d.min(axis=2).max(axis=1), d.min(axis=1).max(axis=1))
        else:
            out[a : a + block] = dtw_batch(d) / (2 * m)
    return out


def dtw_batch(cost: np.ndarray) -> np.ndarray:
    """Dynamic time warping total cost of a batch of cost matrices (b × n × m).

    Anti-diagonal recursion: each diagonal depends only on the two before it, so one
    numpy step per diagonal serves the whole batch (n + m − 1 steps, no loop per cell).
    """
    b, n, m = cost.shape
    inf = np.inf
    acc = np.full((b, n + 1, m + 1), inf)
    acc[:, 0, 0] = 0.0
    for k in range(2, n + m + 1):  # k = i + j with 1-based i, j
        i = np.arange(max(1, k - m), min(n, k - 1) + 1)
        j = k - i
        best = np.minimum(np.minimum(acc[:, i - 1, j], acc[:, i, j - 1]), acc[:, i - 1, j - 1])
        acc[:, i, j] = cost[:, i - 1, j - 1] + best
    return acc[:, n, m]


def _cluster(
    seg: Segments,
    pairs: Pairs,
    dist: np.ndarray,
    limit: float,
    params: LinkParams,
) -> np.ndarray:
    """Agglomerative single-linkage clustering over candidate links with ``dist ≤ limit``,
    smallest first; clusters whose members overlap in time never merge, and each member
    must be reachable from the one before it. Returns the chosen link indices."""
    n = len(seg)
    parent = np.arange(n)
    members: dict[int, np.ndarray] = {}  # a cluster's members in time order (roots only)
    v = params.v_max_kn * geo.KN_MS
    tol = params.position_tol_m

    def find(a: int) -> int:
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    order = np.argsort(dist, kind="stable")
    order = order[dist[order] <= limit]
    chosen = []
    t0, t1 = seg.t0, seg.t1
    lon0, lat0, lon1, lat1 = seg.lon0, seg.lat0, seg.lon1, seg.lat1

    def reachable(p: np.ndarray, q: np.ndarray) -> bool:
        """Every q starts after its p ends and within reach of it."""
        gap = t0[q] - t1[p]
        if (gap <= 0).any():
            return False
        d = geo.haversine_m(lon1[p], lat1[p], lon0[q], lat0[q])
        return bool((d <= v * gap + tol).all())

    for k in order.tolist():
        ra, rb = find(int(pairs.i[k])), find(int(pairs.j[k]))
        if ra == rb:
            continue
        ma = members.get(ra)
        mb = members.get(rb)
        ma = np.array([ra]) if ma is None else ma
        mb = np.array([rb]) if mb is None else mb
        # Each cluster is a valid chain already: when one lies wholly before the other only
        # the junction is new; else the merged chain is checked link by link (arrays).
        if t0[mb[0]] >= t0[ma[-1]]:
            merged, ok = np.concatenate([ma, mb]), reachable(ma[-1:], mb[:1])
        elif t0[ma[0]] >= t0[mb[-1]]:
            merged, ok = np.concatenate([mb, ma]), reachable(mb[-1:], ma[:1])
        else:
            both = np.concatenate([ma, mb])
            merged = both[np.argsort(t0[both], kind="stable")]
            ok = reachable(merged[:-1], merged[1:])
        if not ok:
            continue
        parent[rb] = ra
        members[ra] = merged
        members.pop(rb, None)
        chosen.append(k)
    return np.asarray(chosen, dtype="int64")


def associate_segments(
    points: pd.DataFrame,
    params: LinkParams | None = None,
    method: str = "motion",
    progress: Progress | None = None,
) -> Association:
    """Cluster the segments of each sensor into targets (SPEC §5a).

    ``method``: ``area`` — seed 001's D = (w₁·S′ + w₂·l′)·σ; ``dtw`` / ``hausdorff`` — its
    baselines, the shape distance in place of l; ``motion`` — ours: the interrupted-track
    distance (dead-reckoned position, course, speed; scaled) as D. All share the candidate
    pairs (non-overlapping, within T_gap, reachable) and the clustering.
    """
    params = (params or LinkParams()).checked()
    if method not in SEGMENT_METHODS:
        raise InputError(f"unknown method {method!r}; choose one of {', '.join(SEGMENT_METHODS)}")
    progress = progress or null_progress
    progress(0.0, "summarizing segments")
    # Seed 001's features as the paper has them: ends over end_points fixes, not longer.
    seg = segment_stats(points, params.end_points)
    progress(0.2, "finding candidate pairs")
    apart: list = []
    pairs = candidate_pairs(seg, params, apart=apart)
    progress(0.4, f"scoring {len(pairs):,} candidate pairs")
    if method == "motion":
        dist = pair_cost(pairs, params, "scaled")
        limit = params.gate
    else:
        area = polygon_area(seg, pairs)
        if method == "area":
            # j's mean course seen from i's origin (turned by the meridians' convergence)
            i, j = pairs.i, pairs.j
            sg, cg = geo.plane_turn(
                seg.origin_lon[j], seg.origin_lat[j], seg.origin_lon[i], seg.origin_lat[i]
            )
            second = geo.angle_diff(seg.ldm_deg[i], seg.ldm_deg[j] + np.degrees(np.arctan2(sg, cg)))
            # a piece without a moving leg has no direction (it was taken as north): the
            # mean difference of unrelated directions, 90°
            second = np.where(np.isnan(second), 90.0, second)
        else:
            second = shape_distance(seg, pairs, method)
        dist = params.w1 * _minmax(area) + params.w2 * _minmax(second)
        limit = params.limit
    progress(0.7, "clustering")
    chosen = _cluster(seg, pairs, dist, limit, params)
    targets = _targets(seg, pairs.i[chosen], pairs.j[chosen])
    progress(
        1.0,
        f"{count_of(len(np.unique(targets)), 'target')} from {count_of(len(seg), 'segment')}",
    )
    return Association(
        seg, pairs, dist, chosen, targets, method, mmsi_apart_pairs=apart_count(apart)
    )


# --------------------------------------------------------------------------------------
# seed 003 §4.1: stitching


FILLS = ("line", "hermite")


def _line_fill(
    seg: Segments, i: np.ndarray, j: np.ndarray, owner: np.ndarray, tau: np.ndarray, k: int
) -> tuple[np.ndarray, ...]:
    """Seed 003 §4.1's gap fill: a straight line x(t), y(t) fitted by least squares to
    the last ``k`` points of old track i and the first ``k`` of new track j together,
    evaluated ``tau`` seconds after i's end. Returns x, y (m, in the frame of i's last
    fix, as fitted by :func:`segment_stats`) and vx, vy (m/s)."""
    idx = seg.index
    pts = seg.points
    lon = pts["lon"].to_numpy(dtype="float64")
    lat = pts["lat"].to_numpy(dtype="float64")
    t = track_seconds(pts)
    offs = np.arange(k)
    tail = np.maximum(idx.ends[i][:, None] - 1 - offs, idx.starts[i][:, None])
    head = np.minimum(idx.starts[j][:, None] + offs, idx.ends[j][:, None] - 1)
    rows = np.concatenate([tail, head], axis=1)
    valid = np.concatenate(
        [offs[None, :] < idx.sizes[i][:, None], offs[None, :] < idx.sizes[j][:, None]], axis=1
    ).astype("float64")
    x, y = geo.to_local(lon[rows], lat[rows], seg.lon1[i][:, None], seg.lat1[i][:, None])
    tt = t[rows] - seg.t1[i][:, None]
    sw = valid.sum(axis=1)
    mt, mx, my = ((valid * v).sum(axis=1) / sw for v in (tt, x, y))
    dt = (tt - mt[:, None]) * valid
    var = (dt * dt).sum(axis=1)
    bx = np.where(var > 0, (dt * (x - mx[:, None])).sum(axis=1) / np.maximum(var, 1e-9), 0.0)
    by = np.where(var > 0, (dt * (y - my[:, None])).sum(axis=1) / np.maximum(var, 1e-9), 0.0)
    ax, ay = mx - bx * mt, my - by * mt
    return ax[owner] + bx[owner] * tau, ay[owner] + by[owner] * tau, bx[owner], by[owner]


def stitch(
    assoc: Association, period_s: float | None = None, fill: str = "line", fit_points: int = 10
) -> pd.DataFrame:
    """Join every associated pair into one track and fill its gap (seed 003 §4.1).

    The gap is filled at the sensor's period (the old track's median sampling interval,
    or ``period_s``). ``fill="line"`` (seed 003, the default: the better of the two on
    our scenes, docs/evaluation.md): a straight line fitted to ``fit_points`` points on
    each side — except in a gap where the line would have the ship jump onto or off it,
    or run along it, faster than ``v_max_kn`` (it did not go straight there), which takes
    the Hermite curve; ``"hermite"``: a cubic Hermite curve between the position and velocity
    fitted to the old track's last points and the new track's first points, leaving and
    joining both tracks smoothly. Returns all input rows plus the filled ones: ``batch``
    is the target (one id per stitched track), the original batch is kept in
    ``source_batch``, and ``interpolated`` marks filled rows.
    """
    if fill not in FILLS:
        raise InputError(f"unknown gap fill {fill!r}; choose one of {', '.join(FILLS)}")
    seg = assoc.segments
    pts = assoc.points()
    pts["source_batch"] = pts["batch"]
    pts["batch"] = pts["target"]
    pts["interpolated"] = False
    k = assoc.chosen
    i, j = assoc.pairs.i[k], assoc.pairs.j[k]
    if len(k) == 0:
        return pts
    gap = seg.t0[j] - seg.t1[i]
    period = np.full(len(k), float(period_s)) if period_s else seg.period_s[i]
    period = np.where(np.isfinite(period) & (period > 0), period, seg.period_s[j])
    period = np.where(np.isfinite(period) & (period > 0), period, gap)
    count = np.maximum(np.ceil(gap / period - 0.5).astype("int64") - 1, 0)
    owner = np.repeat(np.arange(len(k)), count)
    step = concat_ranges(np.ones(len(count)), count)
    tau = step * period[owner]  # seconds after the old track's end
    g = gap[owner]
    s = tau / g
    h10 = s**3 - 2 * s**2 + s
    h01 = -2 * s**3 + 3 * s**2
    h11 = s**3 - s**2
    ii, jj = i[owner], j[owner]
    ex, ey = geo.to_local(seg.lon0[jj], seg.lat0[jj], seg.lon1[ii], seg.lat1[ii])
    # the new piece's velocity in the old end's plane (geo.plane_turn)
    turn = geo.plane_turn(seg.lon0[j], seg.lat0[j], seg.lon1[i], seg.lat1[i])
    vxj, vyj = (v[owner] for v in geo.turn_into_plane(seg.vx0[j], seg.vy0[j], turn))
    x = h10 * g * seg.vx1[ii] + h01 * ex + h11 * g * vxj
    y = h10 * g * seg.vy1[ii] + h01 * ey + h11 * g * vyj
    # The old track's end is the frame's origin, so its basis term h00 vanishes.
    # Velocity from the derivative of the Hermite basis (per second).
    d10 = (3 * s**2 - 4 * s + 1) * seg.vx1[ii], (3 * s**2 - 4 * s + 1) * seg.vy1[ii]
    d01 = (-6 * s**2 + 6 * s) / g
    d11 = 3 * s**2 - 2 * s
    vx = d10[0] + d01 * ex + d11 * vxj
    vy = d10[1] + d01 * ey + d11 * vyj
    if fill == "line":
        lx, ly, lvx, lvy = _line_fill(seg, i, j, owner, tau, max(int(fit_points), 1))
        # The paper's line assumes the ship went straight. Where it did not (a U-turn,
        # a stop, a turn in a long gap) the line misses the ends, and a ship would jump
        # onto or off it, or run along it, faster than v_max: that gap keeps the Hermite
        # curve, which meets both ends.
        v_max = (assoc.params or LinkParams()).v_max_kn * geo.KN_MS
        first = np.r_[0, np.cumsum(count)[:-1]]
        has = count > 0
        f, last = first[has], first[has] + count[has] - 1
        jump_in = np.hypot(lx[f], ly[f]) / tau[f]
        with np.errstate(invalid="ignore", divide="ignore"):
            jump_out = np.hypot(ex[last] - lx[last], ey[last] - ly[last]) / (gap[has] - tau[last])
        run = np.hypot(lvx[f], lvy[f])
        bad = np.zeros(len(k), dtype=bool)
        bad[has] = ~((jump_in <= v_max) & (jump_out <= v_max) & (run <= v_max))
        line = ~bad[owner]
        x, y = np.where(line, lx, x), np.where(line, ly, y)
        vx, vy = np.where(line, lvx, vx), np.where(line, lvy, vy)
    lon, lat = geo.from_local(x, y, seg.lon1[ii], seg.lat1[ii])
    # the course at each filled point from north there (the plane's +y turns away from it)
    sg, cg = geo.plane_turn(lon, lat, seg.lon1[ii], seg.lat1[ii])
    course = np.degrees(np.arctan2(vx, vy) - np.arctan2(sg, cg))
    keys = seg.index.keys
    fill = pd.DataFrame(
        {
            "sensor": keys["sensor"].to_numpy()[ii],
            "batch": assoc.target_of_track[ii],
            "time": seconds_to_time(seg.t1[ii] + tau).dt.round("ms").to_numpy(),
            "lon": np.round(lon, 6),
            "lat": np.round(lat, 6),
            "speed": np.round(np.hypot(vx, vy) / geo.KN_MS, 2),
            "course": np.round(geo.wrap360(course), 1),
            "target": assoc.target_of_track[ii],
            "source_batch": "",
            "interpolated": True,
        }
    )
    fill["time"] = pd.to_datetime(fill["time"], utc=True).astype(pts["time"].dtype)
    out = pd.concat([pts, fill], ignore_index=True)
    out["interpolated"] = out["interpolated"].astype(bool)
    return out.sort_values(["sensor", "batch", "time"], kind="stable").reset_index(drop=True)
