"""GPX import: time and peak memory of ``read_points`` on a GPX written by our own
``export_gpx`` (N points in N/1000 tracks, both sensors), against the same points as CSV.

Run: ``python bench/bench_gpx.py --points 300000 [--folder DIR]`` (the files are kept in
the folder and reused). Each read runs in a fresh process; CPU is user + system time of that process (the
figure to compare on a shared, loaded machine); peak memory is that process's
peak RSS (VmHWM) minus its RSS after the imports.
"""

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd

CHILD = r"""
import json, os, sys, time
from wakeline.core.io import read_points
import wakeline.core.io.gpx, wakeline.core.io.reader  # noqa: imports before the baseline
def rss_kb():
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
def hwm_kb():
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith("VmHWM:"):
                return int(line.split()[1])
base = rss_kb()
t, c = time.perf_counter(), os.times()
r = read_points(sys.argv[1])
dt, c2 = time.perf_counter() - t, os.times()
cpu = (c2.user - c.user) + (c2.system - c.system)
peak = hwm_kb()
print(json.dumps({"s": dt, "cpu": cpu, "peak_mb": (peak - base) / 1024, "points": len(r.points),
                  "quarantined": len(r.quarantine)}))
"""


def make(folder: Path, n: int) -> tuple[Path, Path]:
    from wakeline.core.export_review import export_gpx

    gpx, csv = folder / f"p{n}.gpx", folder / f"p{n}.csv"
    if gpx.exists() and csv.exists():
        return gpx, csv
    rng = np.random.default_rng(0)
    per = 1000
    track = np.arange(n) // per
    k = np.arange(n) % per
    pts = pd.DataFrame(
        {
            "sensor": np.where(track % 3 == 0, "AIS", "R1"),
            "batch": track.astype(str),
            "time": pd.Timestamp("2024-05-01", tz="UTC") + pd.to_timedelta(k * 10, unit="s"),
            "lon": 10 + k * 1e-4 + rng.normal(0, 1e-4, n),
            "lat": 59 + k * 1e-4 + rng.normal(0, 1e-4, n),
        }
    )
    export_gpx(pts, gpx)
    out = pts.assign(time=pts["time"].dt.strftime("%Y-%m-%dT%H:%M:%SZ"))
    out.to_csv(csv, index=False)
    return gpx, csv


def run(path: Path) -> dict:
    out = subprocess.run([sys.executable, "-c", CHILD, str(path)], capture_output=True, text=True)
    if out.returncode:
        raise SystemExit(out.stderr)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--points", type=int, default=300_000)
    ap.add_argument("--folder", type=Path, default=None)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    folder = args.folder or Path(tempfile.mkdtemp(prefix="wakeline-gpx-"))
    folder.mkdir(parents=True, exist_ok=True)
    gpx, csv = make(folder, args.points)
    for path in (gpx, csv):
        runs = [run(path) for _ in range(args.repeat)]
        best = min(runs, key=lambda r: r["s"])
        print(
            f"{path.name}: {path.stat().st_size / 1e6:.0f} MB, {best['points']:,} points "
            f"({best['quarantined']} quarantined), best of {args.repeat}: {best['s']:.2f} s "
            f"(CPU {min(r['cpu'] for r in runs):.2f} s), "
            f"peak +{max(r['peak_mb'] for r in runs):.0f} MB"
        )


if __name__ == "__main__":
    main()
