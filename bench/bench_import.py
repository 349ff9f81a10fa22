"""Import throughput: ``wakeline.core.io.read_points`` against ``pyarrow.csv.read_csv``.

Generates a canonical CSV (default 10 M rows in 10 k tracks), then times both readers on
the same file, alternating, best of ``--repeat`` runs each, and prints the ratio (the
goal is ≤ 1.5×). Run: ``python bench/bench_import.py [--rows 10000000] [--keep]``.
"""

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.csv as pacsv

from wakeline.core.io import read_points


def make_csv(path: Path, rows: int, tracks: int, seed: int = 0) -> None:
    rng = np.random.default_rng(seed)
    per = rows // tracks
    track = np.repeat(np.arange(tracks), per)
    k = np.tile(np.arange(per), tracks)
    t = np.datetime64("2024-05-01T00:00:00", "ms") + (k * 10_000 + track).astype("timedelta64[ms]")
    lon0 = rng.uniform(120, 125, tracks)[track]
    lat0 = rng.uniform(28, 33, tracks)[track]
    n = len(track)
    table = pa.table(
        {
            "sensor": pa.array(np.where(track % 3 == 0, "AIS", "R1")),
            "batch": pc.cast(pa.array(track), pa.string()),
            "time": pc.strftime(
                pa.array(t, pa.timestamp("ms", "UTC")), format="%Y-%m-%dT%H:%M:%SZ"
            ),
            "lon": np.round(lon0 + k * 1e-4 + rng.normal(0, 1e-4, n), 6),
            "lat": np.round(lat0 + k * 1e-4 + rng.normal(0, 1e-4, n), 6),
            "speed": np.round(rng.uniform(0, 20, n), 1),
            "course": np.round(rng.uniform(0, 360, n), 1),
        }
    )
    path.write_text("sensor,batch,time,lon,lat,speed,course\n")
    with open(path, "ab") as fh:
        pacsv.write_csv(table, fh, pacsv.WriteOptions(include_header=False, quoting_style="none"))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--rows", type=int, default=10_000_000)
    ap.add_argument("--tracks", type=int, default=10_000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--keep", action="store_true", help="keep the generated file")
    args = ap.parse_args()

    folder = Path(tempfile.mkdtemp(prefix="wakeline-bench-"))
    path = folder / "points.csv"
    t0 = time.perf_counter()
    make_csv(path, args.rows, args.tracks)
    size_mb = path.stat().st_size / 1e6
    print(
        f"generated {args.rows:,} rows, {size_mb:,.0f} MB in {time.perf_counter() - t0:.1f} s: {path}"
    )

    best = {
        "pyarrow.csv.read_csv": np.inf,
        "read_csv + to_pandas": np.inf,
        "wakeline read_points": np.inf,
    }
    for _ in range(args.repeat):
        t = time.perf_counter()
        table = pacsv.read_csv(path)
        best["pyarrow.csv.read_csv"] = min(best["pyarrow.csv.read_csv"], time.perf_counter() - t)
        del table
        t = time.perf_counter()
        frame = pacsv.read_csv(path).to_pandas()
        best["read_csv + to_pandas"] = min(best["read_csv + to_pandas"], time.perf_counter() - t)
        del frame
        t = time.perf_counter()
        result = read_points(path)
        best["wakeline read_points"] = min(best["wakeline read_points"], time.perf_counter() - t)
        assert len(result.points) == args.rows and len(result.quarantine) == 0
        del result
    for name, sec in best.items():
        print(f"{name:24s} {sec:6.2f} s  {args.rows / sec / 1e6:5.2f} M rows/s")
    ratio = best["wakeline read_points"] / best["pyarrow.csv.read_csv"]
    print(f"ratio wakeline / pyarrow.csv.read_csv: {ratio:.2f}x (goal <= 1.5x)")
    ratio = best["wakeline read_points"] / best["read_csv + to_pandas"]
    print(f"ratio wakeline / (read_csv + to_pandas): {ratio:.2f}x")
    if not args.keep:
        path.unlink()
        folder.rmdir()


if __name__ == "__main__":
    main()
