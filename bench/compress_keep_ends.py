"""Compression with each track's first and last point kept where observed
(``CompressParams.keep_ends``, SPEC §3) against the least-squares placement of every knot
(the default): Dis_e before/after on seed 000's protocol and on real AIS.

Seed 000: the evaluation's tracks (``simulate.maneuver_tracks``, seeds ``seed + 1000 k``
as ``wakeline evaluate maneuver --tracks N --seed S``), its "PCA + LS vertices" row
(maneuver points + ends, least-squares vertices), Dis_e against the true path and the
observed points. Real AIS: ``wakeline compress``'s pipeline (defaults) on the DMA ship,
the Saronic Gulf vessels and the ten MTAD scenes, Dis_e against the observed points.

Run: ``python bench/compress_keep_ends.py [--tracks 100] [--seed 0]``
"""

import argparse
import os
from pathlib import Path

from wakeline.core import simulate
from wakeline.core.compress import CompressParams, compress_with
from wakeline.core.io import read_points
from wakeline.core.maneuver import ManeuverParams, detect
from wakeline.core.pipeline import run_compress
from wakeline.core.real_sets import read_dma, read_greece

REAL = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
REAL = REAL / "data" / "real"


def seed000(n_tracks: int, seed: int) -> None:
    print("seed 000: Dis_e (m) of PCA + LS vertices, ends fitted (default) | ends kept")
    print(f"{'sigma':>5} {'class':<7} {'true':>7} {'true kept':>9} {'obs':>7} {'obs kept':>9}")
    cases = [(s, c) for s in (300.0, 600.0) for c in ("short", "medium", "long")]
    for k, (sigma, cls) in enumerate(cases):
        df = simulate.maneuver_tracks(n_tracks, cls, sigma, seed=seed + 1000 * k)
        res = detect(df, ManeuverParams())
        got = [
            compress_with(None, res.is_maneuver, True, res.points, keep_ends=e).report()["overall"]
            for e in (False, True)
        ]
        print(
            f"{sigma:5.0f} {cls:<7} {got[0]['dis_e_true_m']:7.1f} {got[1]['dis_e_true_m']:9.1f} "
            f"{got[0]['dis_e_m']:7.1f} {got[1]['dis_e_m']:9.1f}"
        )


def real_sets() -> dict[str, list]:
    """Name -> point tables (canonical)."""
    mtad = sorted((REAL / "mtad-dtwcm" / "original").glob("*.csv"))
    return {
        "DMA one ship": [read_dma(REAL / "dma-single-ship")],
        "Saronic Gulf": [read_greece(REAL / "greece-ais-annotated")],
        "MTAD 10 scenes": [read_points(f).points for f in mtad],
    }


def real() -> None:
    print("real AIS, `wakeline compress` defaults: kept, Dis_e (m) against the observed points")
    print(
        f"{'set':<16} {'points':>8} {'kept':>6} {'Dis_e':>7} {'ends kept':>9} {'max err':>8} {'kept':>8}"
    )
    for name, files in real_sets().items():
        rows = []
        for pts in files:
            out = []
            for e in (False, True):
                params = {"compress": CompressParams(keep_ends=e)}
                rep = run_compress(pts, params).report
                out.append(rep)
            rows.append(out)
        pts_n = sum(r[0]["overall"]["points"] for r in rows)
        kept = sum(r[0]["overall"]["kept"] for r in rows)
        mean = [
            sum(r[i]["overall"]["dis_e_m"] * r[i]["overall"]["points"] for r in rows) / pts_n
            for i in (0, 1)
        ]
        mx = [max(r[i]["overall"]["max_error_m"] for r in rows) for i in (0, 1)]
        print(
            f"{name:<16} {pts_n:8d} {kept:6d} {mean[0]:7.2f} {mean[1]:9.2f} {mx[0]:8.1f} {mx[1]:8.1f}"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tracks", type=int, default=100)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    seed000(args.tracks, args.seed)
    real()


if __name__ == "__main__":
    main()
