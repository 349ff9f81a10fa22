"""Peak resident memory of ``wakeline import`` and ``wakeline clean`` against the file size.

Generates a canonical CSV of about ``--size-gb`` GB in a temporary folder (in chunks, so
the generator itself stays small), runs ``wakeline import`` and ``wakeline clean`` on it,
each in its own process, and prints each run's peak RSS (``resource.getrusage``, the
child's ``ru_maxrss``) divided by the file size. Goals (issue 14): import ≤ 1.5×,
clean ≤ 2.5× on a 1 GB file (exit status 1 when over). Rows are in time order across the
tracks of each million-row chunk (every track's rows spread through its chunk). The folder is deleted afterwards unless ``--keep``.

Run: ``python bench/bench_memory.py`` (1 GB, a few minutes on 2 cores) or
``python bench/bench_memory.py --size-gb 0.1`` (quick). ``--bad-value`` also measures
``wakeline clean`` after one longitude in the middle of the file is mistyped (``12O.5``:
the streamed reader gives up and the file is read again in pieces, session 16).
"""

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.csv as pacsv

_RUN = (
    "import resource, sys\n"
    "from wakeline.app.cli import main\n"
    "code = main(sys.argv[1:])\n"
    "peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024\n"
    "print(f'PEAK_RSS {peak}', file=sys.stderr)\n"
    "sys.exit(code)\n"
)


#: Peak RSS over the file size allowed (issue 14) per command.
LIMITS = {"import": 1.5, "clean": 2.5}


def _load() -> str:
    try:
        return " ".join(Path("/proc/loadavg").read_text().split()[:3])
    except OSError:
        return "?"


def make_csv(path: Path, size_bytes: float, seed: int = 0, chunk_rows: int = 1_000_000) -> int:
    """A canonical CSV of about ``size_bytes``; returns the rows written."""
    rng = np.random.default_rng(seed)
    path.write_text("sensor,batch,time,lon,lat,speed,course\n")
    rows = 0
    per_track = 1_000
    with open(path, "ab") as fh:
        while fh.tell() < size_bytes:
            tracks = chunk_rows // per_track
            first = rows // per_track
            track = np.repeat(np.arange(first, first + tracks), per_track)
            k = np.tile(np.arange(per_track), tracks)
            t = np.datetime64("2024-05-01T00:00:00", "ms") + (k * 10_000).astype("timedelta64[ms]")
            lon0 = rng.uniform(120, 125, tracks).repeat(per_track)
            lat0 = rng.uniform(28, 33, tracks).repeat(per_track)
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
            # rows in time order, as a radar writes them: every track spread over the chunk
            table = table.take(pa.array(np.argsort(k, kind="stable")))
            pacsv.write_csv(
                table, fh, pacsv.WriteOptions(include_header=False, quoting_style="none")
            )
            rows += n
    return rows


def mistype_middle_longitude(path: Path) -> int:
    """Mistype the longitude of the line in the middle of the file in place (its first
    digit becomes the letter O: only the careful parse reads the column then); returns
    that line's number."""
    size = path.stat().st_size
    with open(path, "r+b") as fh:
        fh.seek(size // 2)
        fh.readline()  # to the next line's start
        start = fh.tell()
        line = fh.readline()
        fields = line.split(b",")
        at = start + sum(len(f) + 1 for f in fields[:3])
        fh.seek(at)
        fh.write(b"O")
    return _line_of(path, start)


def _line_of(path: Path, offset: int) -> int:
    """The 1-based line number of the line starting at byte ``offset``."""
    lines = 1
    with open(path, "rb") as fh:
        while offset > 0:
            block = fh.read(min(1 << 24, offset))
            lines += block.count(b"\n")
            offset -= len(block)
    return lines


def peak_rss(args: list[str]) -> tuple[int, float]:
    """Peak RSS (bytes) and wall time (s) of ``wakeline ARGS`` in a fresh process."""
    t0 = time.perf_counter()
    res = subprocess.run(
        [sys.executable, "-c", _RUN, *args], capture_output=True, text=True, check=False
    )
    wall = time.perf_counter() - t0
    if res.returncode != 0:
        sys.exit(f"wakeline {' '.join(args)} failed:\n{res.stderr}")
    line = next(x for x in res.stderr.splitlines() if x.startswith("PEAK_RSS"))
    return int(line.split()[1]), wall


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--size-gb", type=float, default=1.0, help="file size (default 1 GB)")
    ap.add_argument("--keep", action="store_true", help="keep the generated files")
    ap.add_argument("--skip-clean", action="store_true", help="measure import only")
    ap.add_argument(
        "--bad-value",
        action="store_true",
        help="also measure clean with one longitude in the middle mistyped (read in pieces)",
    )
    args = ap.parse_args()

    folder = Path(tempfile.mkdtemp(prefix="wakeline-membench-"))
    failed = False
    try:
        src = folder / "points.csv"
        t0 = time.perf_counter()
        rows = make_csv(src, args.size_gb * 1e9)
        size = src.stat().st_size
        print(
            f"file: {size / 1e9:.3f} GB ({size:,} bytes), {rows:,} rows "
            f"({time.perf_counter() - t0:.0f} s; load {_load()})"
        )
        runs = [("import", ["import", str(src), "-o", str(folder / "imported.csv")])]
        if not args.skip_clean:
            out = ["-o", str(folder / "cleaned.csv"), "--rejected", str(folder / "rejected.csv")]
            runs.append(("clean", ["clean", str(src), *out]))
            if args.bad_value:
                runs.append(("clean, bad value", ["clean", str(src), *out]))
        for name, command in runs:
            if name == "clean, bad value":
                print(f"mistyped the longitude on line {mistype_middle_longitude(src):,}")
            peak, wall = peak_rss(command)
            ratio = peak / size
            limit = LIMITS[name.split(",")[0]]
            ok = ratio <= limit
            failed |= not ok
            print(
                f"{name + ':':8s}peak RSS {peak / 1e9:.3f} GB = {ratio:.2f}x file "
                f"(limit {limit}x: {'ok' if ok else 'OVER'}; {wall:.0f} s; "
                f"load {_load()})"
            )
    finally:
        if args.keep:
            print(f"kept {folder}")
        else:
            shutil.rmtree(folder, ignore_errors=True)
    if failed:
        sys.exit("peak memory over the limit")


if __name__ == "__main__":
    main()
