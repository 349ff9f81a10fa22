"""A denser real AIS test bed: the Saronic capture's days overlaid on one day (issue 15 goal
3a; docs/evaluation.md, "Saronic days overlaid on one day").

    python bench/overlay_days.py                          # density, association, maneuver
    python bench/overlay_days.py --seeds 0 --bands 300 900 --methods 1
    python bench/overlay_days.py --write /tmp/overlay.csv --only-write   # for the CLI:
    wakeline evaluate associate --real /tmp/overlay.csv --gaps 300 900 --gaps-every 7200
    python bench/overlay_days.py --source mtad            # MTAD's 10 scenes overlaid in one
    python bench/overlay_days.py --why                    # every wrong join and miss

Saronic (``greece-ais-annotated/vessels.csv``, GPL v3: read from $WAKELINE_SHARED/data/real,
else ../shared/data/real; never copied into this repository, and ``--write`` only to a path
you give, outside it): each (vessel, UTC day) becomes its own ship (batch ``v<id>d<day>``,
the identity scored), moved onto the first day (time − d days) and by a random time of day
offset of U(−OFFSET, +OFFSET) h per ship (``--offset-h``, default 2; ``--seed-overlay``), so a
ferry's daily runs do not lie on top of each other exactly. Every fix keeps its position:
the real motion, GPS jitter and moored spans are all there — and the ships that lie at the
same berth every day lie on top of each other (within their jitter), which no real harbour
has; ``--spread-m M`` moves each ship as a whole by a random offset of up to M metres (a
berth of its own; default 0, the brief's overlay). ``--alone``: the control, every ship
of the overlay moved on by 2 days × its number (no other ship within any reach of the
association), so the same ships get the same cuts and the same true pairs: what differs
from the overlay is the traffic around them.

MTAD (``--source mtad``): the 10 scenes of mtad-dtwcm/original, each moved as a whole so
its median position is the first scene's (in metres, east/north) and its clock starts at
0; batch ``scene:MMSI`` with the ``-k`` sub-track suffix dropped (one ship); ``--alone`` as
for Saronic. MTAD is open sea (its scenes are separate areas): the overlay puts ~270 ships
at once in one scene's area, ten times a scene's traffic, none moored.

Printed: the density (ships present at once: a fix within ±5 min of each 10-min tick; the
median distance from a present ship to its nearest present neighbour at a tick, positions
the nearest fix within ±5 min; the share of fixes < 1 kn over the legs either side), then
association as ``wakeline evaluate associate --real FILE --gaps LO HI --gaps-every S``
scores it (``evaluate_association.scene_scores``: ours, optimal, and the CLI's three other
rows) per gap band and seed, and at own cuts (``--cut-s``), then the maneuver detector's
slow share and compression against Douglas–Peucker as ``wakeline evaluate maneuver --real``
counts them. ``--why``: the anatomy of every wrong join and miss of ours (gap band, wrong
kind, piece sizes, moored or moving ends, distance between the ships).
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np
import pandas as pd

from wakeline.core import geo, real_sets
from wakeline.core.associate import LinkParams, counted_gap
from wakeline.core.evaluate_association import (
    _reachable_scores,
    consecutive_true_pairs,
    cut_at_gaps,
    cut_known_gaps,
    error_breakdown,
    real_files,
    run_method,
    score_association,
    within_t_gap,
)
from wakeline.core.evaluate_real import compression_against_dp, slow_share
from wakeline.core.io import read_points
from wakeline.core.maneuver import ManeuverParams, detect
from wakeline.core.schema import time_seconds

#: ../shared, or $WAKELINE_SHARED (as the tests read it)
SHARED = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
REAL = SHARED / "data" / "real"

METHODS = (
    "ours, optimal",
    "ours, pair by pair",
    "ours, greedy",
    "seed 003 (min-max, greedy)",
)
#: (lo, hi) s, one window every S s of track (Saronic's protocol: every 2 h)
BANDS = ((60.0, 300.0), (300.0, 900.0), (600.0, 1800.0))
DAY = 86400.0


def overlay_saronic(
    offset_h: float = 2.0, seed: int = 0, spread_m: float = 0.0, alone: bool = False
) -> pd.DataFrame:
    """Saronic's (vessel, UTC day) tracks as ships of one day (module docstring);
    ``alone``: the control, each ship in a 2-day slot of its own."""
    pts = real_sets.read_greece(REAL / "greece-ais-annotated")
    t = time_seconds(pts["time"])
    day = np.floor(t / DAY).astype("int64")
    ship = "v" + pts["batch"].astype(str) + "d" + (day - day.min()).astype(str)
    keys, inv = np.unique(ship.to_numpy(), return_inverse=True)
    rng = np.random.default_rng(seed)
    off = rng.uniform(-offset_h, offset_h, len(keys)) * 3600.0
    t_new = t - (day - day.min()) * DAY + off[inv] + (2 * DAY * inv if alone else 0.0)
    out = pts.assign(batch=ship.to_numpy(), time=real_sets._times(t_new))
    return _spread(out, inv, len(keys), spread_m, rng)


def overlay_mtad(spread_m: float = 0.0, seed: int = 0, alone: bool = False) -> pd.DataFrame:
    """MTAD's scenes moved onto the first one's median position and clock (docstring)."""
    frames = []
    lon0 = lat0 = None
    for f in real_files(REAL / "mtad-dtwcm" / "original"):
        df = read_points(f).points
        t = time_seconds(df["time"])
        lon_m, lat_m = float(df["lon"].median()), float(df["lat"].median())
        if lon0 is None:
            lon0, lat0 = lon_m, lat_m
        # the scene as a whole, in metres east / north of its median, placed at the first's
        x, y = geo.to_local(df["lon"].to_numpy(), df["lat"].to_numpy(), lon_m, lat_m)
        lon, lat = geo.from_local(x, y, lon0, lat0)
        ship = f.stem + ":" + df["batch"].astype(str).str.split("-").str[0]
        frames.append(df.assign(batch=ship, lon=lon, lat=lat, time=real_sets._times(t - t.min())))
    out = pd.concat(frames, ignore_index=True)
    keys, inv = np.unique(out["batch"].to_numpy(), return_inverse=True)
    if alone:
        t = time_seconds(out["time"]) + 2 * DAY * inv
        out = out.assign(time=real_sets._times(t))
    return _spread(out, inv, len(keys), spread_m, np.random.default_rng(seed))


def _spread(df: pd.DataFrame, inv, n: int, spread_m: float, rng) -> pd.DataFrame:
    """Each ship moved as a whole by up to ``spread_m`` metres (uniform in a disc)."""
    if spread_m <= 0:
        return df
    r = spread_m * np.sqrt(rng.uniform(0, 1, n))
    a = rng.uniform(0, 2 * np.pi, n)
    lat = df["lat"].to_numpy()
    dlat = (r * np.cos(a))[inv] / 111_320.0
    dlon = (r * np.sin(a))[inv] / (111_320.0 * np.cos(np.radians(lat)))
    return df.assign(lon=df["lon"].to_numpy() + dlon, lat=lat + dlat)


def _legs_kn(df: pd.DataFrame) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Sorted (batch, t, x, y, speed over the legs either side kn) of ``df``."""
    d = df.sort_values(["batch", "time"], kind="stable").reset_index(drop=True)
    t = time_seconds(d["time"])
    lon0, lat0 = float(d["lon"].median()), float(d["lat"].median())
    x, y = geo.to_local(d["lon"].to_numpy(), d["lat"].to_numpy(), lon0, lat0)
    b = d["batch"].to_numpy()
    v = np.full(len(d), np.nan)
    same = (b[2:] == b[:-2]) & (t[2:] > t[:-2])
    with np.errstate(invalid="ignore", divide="ignore"):
        v[1:-1] = np.where(
            same, np.hypot(x[2:] - x[:-2], y[2:] - y[:-2]) / (t[2:] - t[:-2]), np.nan
        )
    return b, t, x, y, v / geo.KN_MS


def density(df: pd.DataFrame, tick_s: float = 600.0, near_s: float = 300.0) -> dict:
    """Ships present at once, median nearest-neighbour distance, share of fixes < 1 kn."""
    b, t, x, y, v = _legs_kn(df)
    ticks = np.arange(np.floor(t.min() / tick_s) * tick_s, t.max() + tick_s, tick_s)
    # per fix its nearest tick; per (ship, tick) the fix nearest the tick within near_s
    k = np.rint((t - ticks[0]) / tick_s).astype("int64")
    off = np.abs(t - ticks[k])
    ok = off <= near_s
    tab = pd.DataFrame({"b": b[ok], "k": k[ok], "off": off[ok], "x": x[ok], "y": y[ok]})
    tab = tab.sort_values("off", kind="stable").drop_duplicates(["b", "k"]).sort_values("k")
    present = tab.groupby("k").size().reindex(np.arange(len(ticks)), fill_value=0).to_numpy()
    nn = []
    moored_nn = []
    vk = pd.Series(v).groupby([b, k]).median()  # speed near each (ship, tick)
    for _, g in tab.groupby("k"):  # a tick at a time (a bench: ~150 ticks)
        if len(g) < 2:
            continue
        gx, gy = g["x"].to_numpy(), g["y"].to_numpy()
        d = np.hypot(gx[:, None] - gx[None], gy[:, None] - gy[None])
        np.fill_diagonal(d, np.inf)
        nn.append(d.min(axis=1))
        slow = vk.reindex(list(zip(g["b"], g["k"], strict=True))).to_numpy() < 1.0
        moored_nn.append(d.min(axis=1)[slow])
    nn = np.concatenate(nn) if nn else np.array([np.nan])
    moored_nn = np.concatenate(moored_nn) if moored_nn else np.array([])
    busy = present[present > 0]
    return {
        "ships": int(len(np.unique(b))),
        "fixes": int(len(b)),
        "present_median": float(np.median(busy)),
        "present_p90": float(np.percentile(busy, 90)),
        "present_max": int(busy.max()),
        "nn_median_m": float(np.median(nn)),
        "nn_p10_m": float(np.percentile(nn, 10)),
        "nn_moored_median_m": float(np.median(moored_nn)) if moored_nn.size else np.nan,
        "nn_under_100m": float(np.mean(nn < 100)),
        "slow_fix_share": float(np.nanmean(v < 1.0)),
        "median_step_s": float(np.median(np.diff(t)[(b[1:] == b[:-1])])),
    }


def cut(df: pd.DataFrame, band, every, seed: int, cut_s: float | None = None) -> pd.DataFrame:
    if "truth" not in df.columns:
        df = df.assign(truth=df["batch"].astype(str))
    if cut_s is not None:
        return cut_at_gaps(df, min_gap_s=cut_s, seed=seed)
    return cut_known_gaps(df, *band, seed=seed, every_s=every)


def score(cut_df: pd.DataFrame, methods, params: LinkParams) -> list[dict]:
    rows = []
    for label in methods:
        a = run_method(cut_df, label, params)
        rows.append(
            {
                "method": label,
                **score_association(a),
                **_reachable_scores(a, params),
                **error_breakdown(a, params),
            }
        )
    return rows


def anatomy(df_cut: pd.DataFrame, params: LinkParams, label: str, slow_kn: float = 1.0):
    """Every wrong join and every missed true pair (any gap) of ours, one row each: the
    band of the gap as the time limits count it (``first`` ≤ ``max_gap_s`` < ``soft`` ≤
    ``soft_gap_s`` < ``long``; ``none``: no candidate), the kind (wrong: ``skip`` same ship,
    ``loose`` the end has no true successor or the start no true predecessor at any gap,
    ``swap`` both have one; miss: ``beyond`` no candidate and beyond T_gap as counted,
    ``no candidate`` within it, ``taken`` a piece went to a wrong join, ``left loose``),
    the raw gap, the fixes of the smaller piece, ``moored`` / ``moving`` / ``mixed`` by
    the speed over each end's last / first five fixes (< ``slow_kn``), the distance from
    the end's last fix to the start's first and, for a wrong join, to the end's true
    successor's first."""
    a = run_method(df_cut, "ours, optimal", params)
    seg = a.segments
    truth = seg.column("truth").astype(str).to_numpy()[seg.index.starts]
    true = consecutive_true_pairs(truth, seg.t0)
    succ, pred = {i for i, _ in true}, {j for _, j in true}
    pi, pj = a.pairs.i, a.pairs.j
    ch = a.chosen
    out = {(int(pi[k]), int(pj[k])): int(k) for k in ch}
    key = {(int(x), int(y)): k for k, (x, y) in enumerate(zip(pi, pj, strict=True))}
    counted = counted_gap(a.pairs)
    # per piece: end / start position and speed (the last / first two fixes, m/s -> kn)
    lon = seg.column("lon").to_numpy()
    lat = seg.column("lat").to_numpy()
    t = time_seconds(seg.points["time"])
    s, e = seg.index.starts, seg.index.ends - 1
    lon0, lat0 = float(np.median(lon)), float(np.median(lat))
    x, y = geo.to_local(lon, lat, lon0, lat0)

    def spd(r0, r1):
        dt = t[r1] - t[r0]
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(dt > 0, np.hypot(x[r1] - x[r0], y[r1] - y[r0]) / dt / geo.KN_MS, np.nan)

    # speed over up to 5 fixes at each end
    n = seg.index.ends - seg.index.starts
    v_end = spd(np.maximum(e - 4, s), e)
    v_start = spd(s, np.minimum(s + 4, e))

    def band(k):
        if k is None:
            return "none"
        c = counted[k]
        if c <= params.max_gap_s:
            return "first"
        return "soft" if c <= max(params.soft_gap_s, params.max_gap_s) else "long"

    def moored(i, j):
        a_, b_ = v_end[i] < slow_kn, v_start[j] < slow_kn
        return "moored" if a_ and b_ else ("moving" if not (a_ or b_) else "mixed")

    def dist(i, j):
        return float(np.hypot(x[s[j]] - x[e[i]], y[s[j]] - y[e[i]]))

    rows = []
    for (i, j), k in out.items():
        if (i, j) in true:
            continue
        kind = (
            "skip"
            if truth[i] == truth[j]
            else ("loose" if i not in succ or j not in pred else "swap")
        )
        # the true partner's distance: how far the right continuation was
        ti_j = [jj for ii, jj in true if ii == i]
        rows.append(
            {
                "case": label,
                "what": "wrong",
                "kind": kind,
                "band": band(k),
                "gap_s": float(t[s[j]] - t[e[i]]),
                "n_small": int(min(n[i], n[j])),
                "motion": moored(i, j),
                "dist_m": dist(i, j),
                "true_dist_m": dist(i, ti_j[0]) if ti_j else np.nan,
                "ships": f"{truth[i]}>{truth[j]}",
            }
        )
    used_i = {i for i, _ in out}
    used_j = {j for _, j in out}
    reach = within_t_gap(seg, true, params)
    for i, j in sorted(true - set(out)):
        k = key.get((i, j))
        why = (
            "beyond"
            if (i, j) not in reach and k is None
            else "no candidate"
            if k is None
            else "taken"
            if i in used_i or j in used_j
            else "left loose"
        )
        rows.append(
            {
                "case": label,
                "what": "miss",
                "kind": why,
                "band": band(k),
                "gap_s": float(t[s[j]] - t[e[i]]),
                "n_small": int(min(n[i], n[j])),
                "motion": moored(i, j),
                "dist_m": dist(i, j),
                "true_dist_m": dist(i, j),
                "ships": f"{truth[i]}",
            }
        )
    return rows


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--source", choices=("saronic", "mtad"), default="saronic")
    ap.add_argument("--offset-h", type=float, default=2.0)
    ap.add_argument("--seed-overlay", type=int, default=0)
    ap.add_argument("--spread-m", type=float, default=0.0)
    ap.add_argument("--alone", action="store_true", help="control: each ship 2 days apart")
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    ap.add_argument("--bands", type=float, nargs="+", default=None, help="LO HI [LO HI ...]")
    ap.add_argument("--every", type=float, default=7200.0, help="0: one window per track")
    ap.add_argument("--cut-s", type=float, nargs="*", default=[600.0, 120.0])
    ap.add_argument("--methods", type=int, default=len(METHODS), help="first N of the four")
    ap.add_argument("--no-maneuver", action="store_true")
    ap.add_argument("--why", action="store_true", help="anatomy of ours' errors")
    ap.add_argument("--write", type=Path, help="also write the overlay as CSV (outside the repo)")
    ap.add_argument("--only-write", action="store_true")
    ap.add_argument("--set", action="append", default=[], help="LinkParams NAME=VALUE")
    a = ap.parse_args(argv)
    t_start, c_start = time.time(), time.process_time()
    params = LinkParams().replace(**dict(kv.split("=", 1) for kv in a.set))
    if a.source == "saronic":
        df = overlay_saronic(a.offset_h, a.seed_overlay, a.spread_m, a.alone)
    else:
        df = overlay_mtad(a.spread_m, a.seed_overlay, a.alone)
    if a.write:
        df.to_csv(a.write, index=False)
        print(f"wrote {a.write} ({len(df)} fixes)")
        if a.only_write:
            return
    d = density(df)
    print(
        f"{a.source} {'ships alone' if a.alone else 'overlay'} (offset ±{a.offset_h:g} h, seed {a.seed_overlay}, "
        f"spread {a.spread_m:g} m): {d['ships']} ships, {d['fixes']} fixes, "
        f"median step {d['median_step_s']:.0f} s"
    )
    print(
        f"  ships present at once (10-min ticks): median {d['present_median']:.0f}, "
        f"p90 {d['present_p90']:.0f}, max {d['present_max']}"
    )
    print(
        f"  nearest neighbour at a tick: median {d['nn_median_m']:.0f} m, p10 "
        f"{d['nn_p10_m']:.0f} m, share < 100 m {d['nn_under_100m']:.3f}; ships < 1 kn: "
        f"median {d['nn_moored_median_m']:.0f} m"
    )
    print(f"  share of fixes < 1 kn: {d['slow_fix_share']:.3f}")
    methods = METHODS[: a.methods]
    bands = BANDS if a.bands is None else tuple(zip(a.bands[::2], a.bands[1::2], strict=True))
    every = a.every or None
    cases = [(f"{lo:g}-{hi:g} s", (lo, hi), None) for lo, hi in bands]
    cases += [(f"own cuts {c:g} s", None, c) for c in a.cut_s]
    rows, why = [], []
    for label, band, cut_s in cases:
        for sd in a.seeds if cut_s is None else a.seeds[:1]:  # own cuts: seeds only renumber
            c = cut(df, band, every, sd, cut_s)
            for r in score(c, methods, params):
                rows.append({"case": label, "seed": sd, "pieces": c["batch"].nunique(), **r})
            if a.why:
                why += anatomy(c, params, f"{label} seed {sd}")
    tab = pd.DataFrame(rows)
    often = f"one window every {every:g} s" if every else "one window per track"
    print(f"\nAssociation (known gaps: {often}; P_CA / P_FA / true pairs / within T_gap):")
    print(f"{'case':<16} {'method':<27} " + "  ".join(f"seed {s:<14}" for s in a.seeds))
    for (label, m), g in tab.groupby(["case", "method"], sort=False):
        cells = "  ".join(
            f"{r.p_ca:.3f}/{r.p_fa:.3f} {r.true_pairs:3.0f} {r.reachable:3.0f}"
            for r in g.itertuples()
        )
        print(f"{label:<16} {m:<27} {cells}")
    kinds = [c for c in tab.columns if c.startswith(("wrong_", "miss_"))]
    ours = tab[tab["method"] == "ours, optimal"]
    print("\nours, optimal: wrong joins and misses within T_gap, summed over seeds")
    for label, g in ours.groupby("case", sort=False):
        print(f"  {label:<16} " + "  ".join(f"{k} {int(g[k].sum())}" for k in kinds))
    if why:
        w = pd.DataFrame(why)
        w["case"] = w["case"].str.replace(r" seed \d+", "", regex=True)
        w["size"] = np.where(w["n_small"] == 1, "1", np.where(w["n_small"] <= 3, "2-3", "4+"))
        for what in ("wrong", "miss"):
            part = w[w["what"] == what]
            print(f"\nAnatomy, {what} ({len(part)}, all seeds):")
            if not len(part):
                continue
            for col in ("kind", "band", "motion", "size"):
                print(f"  by {col}:")
                print(
                    "    "
                    + part.groupby(["case", col])
                    .size()
                    .unstack(fill_value=0)
                    .to_string()
                    .replace("\n", "\n    ")
                )
            q = part.groupby("case")[["gap_s", "dist_m", "true_dist_m"]].median()
            print("  medians (gap s, distance of the join m, to the true partner m):")
            print("    " + q.round(0).to_string().replace("\n", "\n    "))
            if what == "wrong":
                pair = part["ships"].str.replace(r"d\d+", "", regex=True)
                print(
                    "  vessel > vessel: "
                    + pair.value_counts().head(8).to_string().replace("\n", ", ")
                )
    if not a.no_maneuver:
        res = detect(df, ManeuverParams())
        comp = compression_against_dp(res)
        print(
            f"\nManeuver (defaults): {int(res.is_maneuver.sum())} maneuver points, slow share "
            f"{slow_share(res):.3f}; compression ours {comp['ours_kept']} / DP "
            f"{comp['dp_kept']} at Dis_e {comp['ours_dis_e_m']:.1f} m"
        )
    la = os.getloadavg()
    print(
        f"CPU {time.process_time() - c_start:.0f} s, wall {time.time() - t_start:.0f} s, "
        f"load average {la[0]:.2f} {la[1]:.2f} {la[2]:.2f}"
    )


if __name__ == "__main__":
    main()
