"""Act as the checker of real captures in unseen layouts (h111): the DMA ship, the Saronic
vessels, the Øresund encounters (../shared) and the ATD sample (tests/data) written in every
layout of ``tests/layout_variants.py``, each run through the command line as an owner would:

    wakeline import FILE -o OUT --quarantine Q --report R [--tz ZONE]
    wakeline evaluate maneuver  --real FILE --csv T [--tz ZONE]
    wakeline evaluate associate --real FILE --csv T [--tz ZONE]

and checked: points + quarantined + blank lines = the lines below the header, every point
imported; the two evaluations' figures equal those of the canonical file (rtol 2e-3); no
traceback. Also each named folder against its canonical file, and a folder of three
layouts (Saronic vessels split over them).

    python bench/unseen_layouts.py [OUT] [--sets dma,greece,oresund,atd]

One JSON line per (set, layout) on stdout and OUT/results.csv; about 10 min on 2 cores.
MarineCadastre, DMA, the ';' export and the 12-hour layout write whole seconds: the
Øresund encounters' milliseconds make their maneuver figures differ there, as they do for
the canonical file rounded to seconds.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests"))
import layout_variants as lv  # noqa: E402

from wakeline.core import real_sets  # noqa: E402
from wakeline.core.io import write_points  # noqa: E402

REAL = Path(os.environ.get("WAKELINE_SHARED", REPO.parent / "shared")) / "data" / "real"
NATIVE = {
    "dma": "dma-single-ship",
    "greece": "greece-ais-annotated",
    "oresund": "oresund-encounters",
}
FIGURES = {
    "maneuver": [
        "points",
        "maneuvers",
        "slow_share",
        "ours_kept",
        "ours_dis_e_m",
        "dp_kept",
        "dp_dis_e_m",
        "at_rest_spans",
    ],
    "associate": ["pieces", "true_pairs", "reachable", "p_ca", "p_fa", "f1", "p_ca_reachable"],
}


def bases(names):
    if "dma" in names:
        yield "dma", real_sets.read_dma(REAL / NATIVE["dma"])
    if "greece" in names:
        yield "greece", real_sets.read_greece(REAL / NATIVE["greece"])
    if "oresund" in names:  # the encounters a day apart, as association_tracks puts them
        o = real_sets.read_oresund(REAL / NATIVE["oresund"]).drop(columns="role")
        enc = o["batch"].str.split("/").str[0].astype(int)
        rel = o["time"].dt.round("ms") - pd.Timestamp(0, tz="UTC")
        start = pd.Timestamp("2023-06-01", tz="UTC")
        yield "oresund", o.assign(time=start + rel + pd.to_timedelta(enc * 86400, unit="s"))
    if "atd" in names:
        a = pd.read_csv(REPO / "tests" / "data" / "atd2025_example_sample.csv")
        yield (
            "atd",
            pd.DataFrame(
                {
                    "sensor": "AIS",
                    "batch": a["track_id"].astype(str),
                    "time": pd.to_datetime(a["time"], utc=True),
                    "lon": a["lon"],
                    "lat": a["lat"],
                    "speed": a["speed"],
                    "course": a["course"],
                }
            ),
        )


def run(args):
    p = subprocess.run(["wakeline", *map(str, args)], capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def failure(rc: int, err: str) -> str:
    last = err.strip().splitlines()[-1] if err.strip() else ""
    return f"rc={rc} {'TRACEBACK ' if 'Traceback' in err else ''}{last}"


def lines_below_header(path: Path) -> int:
    raw = path.read_bytes()
    for enc in ("utf-16", "utf-8-sig", "gb18030"):
        try:
            text = raw.decode(enc)
        except UnicodeDecodeError:
            continue
        if enc != "utf-16" or raw[:2] in (b"\xff\xfe", b"\xfe\xff"):
            break
    return len(text.splitlines()) - (0 if path.suffix == ".nmea" else 1)


def figures(kind, path, flags, out: Path):
    out.mkdir(parents=True, exist_ok=True)
    csv = out / f"{kind}.csv"
    rc, _, err = run(["evaluate", kind, "--real", path, "--csv", csv, *flags])
    return (None, failure(rc, err)) if rc else (pd.read_csv(csv), "")


def compare(kind, got, ref) -> str:
    cols = [c for c in FIGURES[kind] if c in ref.columns and c in got.columns]
    a, b = got.set_index("method")[cols], ref.set_index("method")[cols]
    diffs = []
    for m in b.index:
        if m not in a.index:
            diffs.append(f"no {m}")
            continue
        for c in cols:
            x, y = float(a.loc[m, c]), float(b.loc[m, c])
            if not np.isclose(x, y, rtol=2e-3, atol=2e-3):
                diffs.append(f"{m}.{c} {x:.4g}!={y:.4g}")
    return "same" if not diffs else "DIFF " + "; ".join(diffs[:4])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", nargs="?", type=Path, default=Path("unseen_layouts_out"))
    ap.add_argument("--sets", default="dma,greece,oresund,atd")
    args = ap.parse_args()
    names = args.sets.split(",")
    shutil.rmtree(args.out, ignore_errors=True)
    args.out.mkdir(parents=True)
    results = []

    def emit(row):
        results.append(row)
        print(json.dumps(row, ensure_ascii=False), flush=True)

    points = {}
    for name, pts in bases(names):
        points[name] = pts
        base = args.out / name
        base.mkdir()
        canon = base / "canonical.csv"
        write_points(pts, canon)
        refs = {k: figures(k, canon, [], base / "ref")[0] for k in FIGURES}
        for v in lv.write_variants(pts, base / "v"):
            d = v.path.parent
            row = {"set": name, "layout": v.name}
            rc, _, err = run(
                ["import", v.path, "-o", d / "imp.csv", "--quarantine", d / "q.csv"]
                + ["--report", d / "r.json", *v.flags]
            )
            if rc:
                row["import"] = failure(rc, err)
            else:
                rep = json.loads((d / "r.json").read_text())
                n, q, b = rep["rows_imported"], rep["rows_quarantined"], rep.get("blank_lines", 0)
                lines = lines_below_header(v.path)
                ok = n + q + b == lines and n == len(pts)
                row["import"] = f"{'ok' if ok else 'COUNT'} {n}+{q}q+{b}b/{lines}l"
                row["import_msg"] = err.strip().replace("\n", " | ")[:300]
            for kind in FIGURES:
                got, why = figures(kind, v.path, v.flags, d / kind)
                row[kind] = why if got is None else compare(kind, got, refs[kind])
            emit(row)
    for name, folder in NATIVE.items():
        if name not in points:
            continue
        row = {"set": name, "layout": "named folder, its own reader"}
        for kind in FIGURES:
            got, why = figures(kind, REAL / folder, [], args.out / name / "native")
            ref, _ = figures(kind, args.out / name / "canonical.csv", [], args.out / name / "ref")
            row[kind] = why if got is None else compare(kind, got, ref)
        emit(row)
    if "greece" in points:  # a folder of three layouts: the vessels split over them
        pts, d = points["greece"], args.out / "folder"
        parts = {
            "mc": (lv.marinecadastre, ["1", "2"]),
            "radar": (lv.radar, ["3"]),
            "eu": (lv.semicolon_comma, ["4", "5"]),
        }
        for key, (make, ids) in parts.items():
            sub = d / key
            sub.mkdir(parents=True)
            v = make(pts[pts["batch"].isin(ids)].reset_index(drop=True), sub)
            shutil.move(v.path, d / f"{key}.csv")
            sub.rmdir()
        row = {"set": "greece", "layout": "folder of 3 layouts"}
        ref, _ = figures("maneuver", args.out / "greece" / "canonical.csv", [], args.out / "r")
        got, why = figures("maneuver", d, [], args.out / "folder_out")
        row["maneuver"] = why if got is None else compare("maneuver", got, ref)
        got, why = figures("associate", d, [], args.out / "folder_out")
        ours = got is not None and got[got["method"] == "ours, optimal"]
        row["associate"] = (
            why
            if got is None
            else "ran: " + "; ".join(f"{r.file} {r.pieces} pieces" for r in ours.itertuples())
        )
        emit(row)
    pd.DataFrame(results).to_csv(args.out / "results.csv", index=False)


if __name__ == "__main__":
    main()
