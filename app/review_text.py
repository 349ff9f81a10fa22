"""The review panel's texts, translated (issue 13): column titles, statuses, filters,
the counts line and the evidence of the current proposal.

Everything goes through ``QCoreApplication.translate`` in the ``ReviewPanel`` context of
``resources/translations/wakeline_<locale>.ts``; the texts are made when asked for, so a
language switch shows at the next redraw.
"""

import pandas as pd
from PySide6 import QtCore

TR_CONTEXT = "ReviewPanel"
#: Filter values of the status box, in its order ("" = all).
STATUS_FILTERS = ("", "pending", "accepted", "rejected", "split")


def tr(text: str) -> str:
    """``text`` in the current language (context :data:`TR_CONTEXT`)."""
    return QtCore.QCoreApplication.translate(TR_CONTEXT, text)


def column_titles(kind: str = "") -> dict[str, str]:
    """The queue's column titles; ``kind``: the queue's proposals' kind ("fuse": costs in
    metres; "associate": scaled costs; "": mixed or unknown, no unit)."""
    units = {
        "fuse": (tr("margin m"), tr("cost m")),
        "associate": (tr("margin (scaled)"), tr("cost (scaled)")),
    }
    margin, cost = units.get(kind, (tr("margin"), tr("cost")))
    return {
        "proposal": tr("proposal"),
        "status": tr("status"),
        "track_a": tr("track A"),
        "track_b": tr("track B"),
        "margin": margin,
        "cost": cost,
        "gap_s": tr("gap s"),
        "distance_m": tr("distance m"),
        "dcourse_deg": tr("Δcourse °"),
        "dspeed_kn": tr("Δspeed kn"),
        "runner_up": tr("runner-up"),
        "method": tr("method"),
        "target": tr("target"),
    }


def method_words() -> dict[str, str]:
    """The words of a proposal's ``method`` (``optimal``; ``optimal, second look (gap
    beyond T_gap)``; a fusion's ``sync/optimal``) in the current language; the core's
    values stay English (operator test 7, D11)."""
    return {
        "optimal": tr("optimal"),
        "greedy": tr("greedy"),
        "motion": tr("motion"),
        "area": tr("area"),
        "hausdorff": tr("hausdorff"),
        "dtw": "DTW",
        "dtw_whole": tr("DTW, whole tracks"),
        "sync": tr("sync"),
        "second look (gap beyond T_gap)": tr("second look (gap beyond T_gap)"),
    }


def method_text(value) -> str:
    """A proposal's ``method`` as the queue and the evidence show it: each of its words
    (between ", " and "/") said in the current language, an unknown one as it is."""
    words = method_words()
    return ", ".join(
        "/".join(words.get(w, w) for w in part.split("/")) for part in str(value).split(", ")
    )


def status_names() -> dict[str, str]:
    return {
        "pending": tr("pending"),
        "accepted": tr("accepted"),
        "rejected": tr("rejected"),
        "split": tr("split"),
    }


def status_name(status: str) -> str:
    return status_names().get(status, status)


def status_filter_items() -> list[str]:
    return [tr("all"), *(status_name(s) for s in STATUS_FILTERS[1:])]


def all_sensors() -> str:
    return tr("all sensors")


def sort_items() -> list[str]:
    return [tr("least margin first"), tr("highest cost first"), tr("id")]


def queue_hint() -> str:
    """The line over the queue: what its statuses and keys mean (h225 item 8)."""
    return tr(
        "Pending = joined for now. A keeps the join. R: two targets, never proposed again. "
        "S: track B leaves."
    )


def column_tips() -> dict[str, str]:
    """Tooltips of the queue's column titles (their units and meaning)."""
    return {
        "status": tr("pending: joined until you decide; accepted: joined; rejected: apart"),
        "margin": margin_tip(),
        "cost": tr(
            "the cost of this join: metres for a fusion (mean distance between the tracks), "
            "scaled for an association"
        ),
        "gap_s": tr("seconds between the end of track A and the start of track B"),
        "distance_m": tr("metres between the two tracks where they meet"),
        "dcourse_deg": tr(
            "degrees between the course at the end of track A and at the start of track B "
            "(counted in full when both move at 2 kn or more: a course means little at rest)"
        ),
        "dspeed_kn": tr(
            "knots between the speed at the end of track A and at the start of track B"
        ),
        "target": tr("the target track A belongs to now, as the decisions make it"),
    }


def decision_text(state, entry) -> str:
    """What a decision changed, for the log: "AIS:0 and radar:0 are two targets now
    (7 targets in all)"; "" when the log entry names no track."""
    tracks = [t for t in str(entry.tracks).split(" ") if t]
    if not tracks:
        return ""
    try:
        targets = dict.fromkeys(state.target(t) for t in tracks)
        total = len(set(state.target_of_track().tolist()))
    except Exception:  # noqa: BLE001 - a track the state no longer knows: say nothing
        return ""
    if len(tracks) == 1:
        target = next(iter(targets))
        members = state.members(target)
        if len(members) == 1:
            return tr("{0} is a target of its own now ({1} targets in all)").format(
                tracks[0], total
            )
        return tr("{0} is in target {1} now ({2} targets in all)").format(tracks[0], target, total)
    names = tr("{0} and {1}").format(", ".join(tracks[:-1]), tracks[-1])
    if len(targets) == 1:
        return tr("{0} are one target now ({1} targets in all)").format(names, total)
    return tr("{0} are {1} targets now ({2} targets in all)").format(names, len(targets), total)


def margin_tip() -> str:
    return tr("runner-up (or the gate) cost minus this cost: small = uncertain")


def counts_text(total: int, counts: dict) -> str:
    """ "N proposals: … pending, … accepted, … rejected, … split"."""
    return tr("{0} proposals: {1} pending, {2} accepted, {3} rejected, {4} split").format(
        total,
        counts.get("pending", 0),
        counts.get("accepted", 0),
        counts.get("rejected", 0),
        counts.get("split", 0),
    )


def cost_text(value) -> str:
    """A cost, gate or margin for reading: 3 significant digits below 100, whole numbers
    with thousands separators above (fusion costs are metres: "1,000", not "1e+03")."""
    v = float(value)
    if v != v:
        return "–"
    return f"{v:,.0f}" if abs(v) >= 100 else f"{v:.3g}"


def evidence_text(state, pid: str, p: pd.Series) -> str:
    """The evidence of proposal ``pid`` (row ``p`` of the proposals) as rich text."""
    unit = tr("m") if p["kind"] == "fuse" else tr("(scaled)")
    parts = []
    for name, label in (
        ("gap_s", tr("gap {0:.0f} s")),
        ("distance_m", tr("distance {0:.0f} m")),
        ("miss_m", tr("position misfit {0:.0f} m")),
        ("dcourse_deg", tr("Δcourse {0:.1f}°")),
        ("dspeed_kn", tr("Δspeed {0:.1f} kn")),
        ("spread", tr("spread of the prediction +{0:.2f}")),
        ("end_accel_ms2", tr("an end turns or changes speed ({0:.2g} m/s²): wider gate")),
        ("overlap_s", tr("overlap {0:.0f} s")),
    ):
        v = p[name]
        if name == "spread" and not (v is not None and v >= 0.005):
            continue  # the join's own prediction is the tightest: nothing to say
        if v == v and v is not None:  # not NaN
            parts.append(label.format(float(v)))
    plots = p.get("plot_tracks", "")
    if isinstance(plots, str) and plots:
        # operator test 8, D1: a pair of plots read as a comfortable join
        parts.insert(
            0,
            tr(
                "<b>plots, not tracks</b>: {0} (several positions at one time: several "
                "targets and clutter), so the distance and margin say little"
            ).format(", ".join(plots.split("+"))),
        )
    rival = (
        tr("runner-up {0} at {1}").format(p["runner_up"], cost_text(p["runner_up_cost"]))
        if p["runner_up"]
        else tr("no runner-up (the alternative is leaving both unmatched)")
    )
    target = state.target(p["track_a"])
    head = tr("<b>{0}</b> ({1}) {2} → {3}, {4}: cost {5} {6} (gate {7})").format(
        pid,
        status_name(state.status_of(pid)),
        p["track_a"],
        p["track_b"],
        method_text(p["method"]),
        cost_text(p["cost"]),
        unit,
        cost_text(p["gate"]),
    )
    tail = tr("margin {0}. Target {1}: {2}").format(
        cost_text(p["margin"]), target, " + ".join(state.members(target))
    )
    return tr("; ").join([head, *parts, rival, tail])
