"""Peak memory and throughput of ``wakeline batch`` (issue 18), next to the single-process
command line on a size both can run.

Generates a canonical CSV of ``--size`` GB (default 5; tracks of 1000 points, radar and
AIS, as ``bench_memory.py`` makes them) in a temporary folder, runs ``wakeline batch`` with
the default pipeline (clean, compress) under ``/usr/bin/time -v`` and prints its peak
resident memory (goal: below 4 GB at 5 GB input) and rows/s. Then, on a ``--compare``
GB file, the same batch against ``wakeline clean`` followed by ``wakeline compress`` (the
single-process CLI; the figure is rows of input per second of the two commands together).
The machine's load (``/proc/loadavg``) is printed next to every figure. The folder is
deleted afterwards unless ``--keep``.

Run: ``python bench/bench_batch.py`` (5 GB: about an hour on 2 busy cores and 12 GB of
disk) or ``python bench/bench_batch.py --size 1 --compare 0.2``.
"""

import argparse
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_memory import make_csv  # noqa: E402

CLI = [sys.executable, "-m", "wakeline.app.cli"]


def _load() -> str:
    return Path("/proc/loadavg").read_text().split()[0] if Path("/proc/loadavg").exists() else "?"


def run_measured(args: list[str]) -> tuple[int, float]:
    """Peak RSS (bytes) and wall time (s) of ``wakeline ARGS`` under /usr/bin/time -v
    (the largest process: with the default local scheduler the whole batch is one)."""
    timer = shutil.which("time") or "/usr/bin/time"
    t0 = time.perf_counter()
    res = subprocess.run([timer, "-v", *CLI, *args], capture_output=True, text=True, check=False)
    wall = time.perf_counter() - t0
    if res.returncode not in (0, 3):  # 3: written, an input file refused (batch --help)
        sys.exit(f"wakeline {' '.join(args)} failed:\n{res.stderr[-3000:]}")
    kb = re.search(r"Maximum resident set size \(kbytes\): (\d+)", res.stderr)
    return (int(kb.group(1)) * 1024 if kb else -1), wall


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--size", type=float, default=5.0, help="batch input in GB (default 5)")
    ap.add_argument(
        "--compare", type=float, default=0.2, help="GB for batch vs single process (0: skip)"
    )
    ap.add_argument("--workers", type=int, default=0, help="batch --workers (default: threads)")
    ap.add_argument("--dir", type=Path, help="folder for the generated files (default /tmp)")
    ap.add_argument("--keep", action="store_true", help="keep the generated files")
    args = ap.parse_args()

    folder = Path(tempfile.mkdtemp(prefix="wakeline-batchbench-", dir=args.dir))
    pipe = folder / "pipe.json"
    subprocess.run([*CLI, "batch", "--print-pipeline"], stdout=open(pipe, "w"), check=True)
    extra = ["--workers", str(args.workers)] if args.workers else []
    try:
        if args.compare:
            src = folder / "small.csv"
            rows = make_csv(src, args.compare * 1e9)
            size = src.stat().st_size
            print(f"compare file: {size / 1e9:.3f} GB, {rows:,} rows")
            peak, wall = run_measured(["batch", str(pipe), str(src), "-o", str(folder / "sb")])
            print(
                f"  batch:          {rows / wall:>10,.0f} rows/s ({wall:.0f} s), "
                f"peak RSS {peak / 1e9:.2f} GB  [load {_load()}]"
            )
            p1, w1 = run_measured(["clean", str(src), "-o", str(folder / "c.csv")])
            p2, w2 = run_measured(["compress", str(folder / "c.csv"), "-o", str(folder / "cc.csv")])
            print(
                f"  clean+compress: {rows / (w1 + w2):>10,.0f} rows/s ({w1 + w2:.0f} s), "
                f"peak RSS {max(p1, p2) / 1e9:.2f} GB  [load {_load()}]"
            )
            print(f"  ratio batch/single throughput: {(w1 + w2) / wall:.2f}")
            for p in (src, folder / "c.csv", folder / "cc.csv"):
                p.unlink(missing_ok=True)
            shutil.rmtree(folder / "sb", ignore_errors=True)
        if args.size:
            src = folder / "big.csv"
            t0 = time.perf_counter()
            rows = make_csv(src, args.size * 1e9)
            size = src.stat().st_size
            print(
                f"batch file: {size / 1e9:.3f} GB, {rows:,} rows "
                f"(written in {time.perf_counter() - t0:.0f} s)"
            )
            peak, wall = run_measured(
                ["batch", str(pipe), str(src), "-o", str(folder / "out"), *extra]
            )
            verdict = "below" if peak < 4e9 else "ABOVE"
            print(
                f"  batch: peak RSS {peak / 1e9:.2f} GB ({verdict} the 4 GB goal), "
                f"{rows / wall:,.0f} rows/s ({wall:.0f} s)  [load {_load()}]"
            )
    finally:
        if args.keep:
            print(f"kept {folder}")
        else:
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
