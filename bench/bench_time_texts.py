"""Time texts: CPU seconds of ``parse_times`` per million rows for each written form (ISO,
day-first slashed dates, English month names, asctime, Chinese dates, times of day).

Run: ``python bench/bench_time_texts.py [--rows 1000000] [--repeat 2]``; the best of
``--repeat`` runs is printed. CPU time, not wall: on a shared machine it is the steadier.
docs/import.md "Month names, Chinese dates, times of day alone" quotes it.
"""

import argparse
import time

import pandas as pd
import pyarrow as pa

from wakeline.core.io.reader import parse_times

FORMS = (
    "%Y-%m-%dT%H:%M:%SZ",
    "%Y-%m-%d %H:%M:%S",
    "%d/%m/%Y %H:%M:%S",
    "%d-%b-%Y %H:%M:%S",
    "%a %b %d %H:%M:%S %Y",
    "%Y年%m月%d日 %H:%M:%S",
    "%H:%M:%S",
)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, default=1_000_000)
    ap.add_argument("--repeat", type=int, default=2)
    args = ap.parse_args()
    times = pd.date_range("2024-01-01", periods=args.rows, freq="s")
    for fmt in FORMS:
        arr = pa.chunked_array([pa.array(times.strftime(fmt))])
        best = float("inf")
        for _ in range(args.repeat):
            start = time.process_time()
            _ns, ok = parse_times(arr, "auto", info={})
            best = min(best, time.process_time() - start)
        print(f"{fmt!r:28} {best:6.2f} s CPU  {int(ok.sum()):,} of {args.rows:,} read")


if __name__ == "__main__":
    main()
