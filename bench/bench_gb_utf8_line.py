"""A GB18030 file with one UTF-8 line near its end (h157 (5)): ``wakeline import``
(:func:`import_to_csv`, streamed) and :func:`read_points` (whole) against the same file
without that line. Before h167 the UTF-8 line (not valid GB18030) failed the strict
first reading: the streamed import read the file again in pieces (strictly, then line by
line after the whole file's judgement) and the whole-file reader read it again line by
line. Now the decoder asks the judgement at that line and goes on. Prints the times, how
many file sizes went through the line decoder, and a digest of the output and warnings
(the same before and after). ``gb1_quoted.csv``: the same with every time quoted,
which the import reads in pieces.

Run: ``python bench/bench_gb_utf8_line.py [--rows 1000000] [--repeat 2] [--base DIR]``
(``--base``: a copy of an older tree, ``DIR/wakeline/{core,app,resources}``, to time it).
"""

import argparse
import hashlib
import json
import sys
import tempfile
import time
from pathlib import Path

NAMES = ["远洋一号", "海丰号", "中远之星"]
UTF8_LINE = "2024-01-02 00:00:00,u,37.5,23.6,Bjørn – Ålesund\n".encode()


def make(folder: Path, rows: int) -> tuple[Path, Path, Path]:
    clean, mixed = folder / "gb0.csv", folder / "gb1.csv"
    with open(clean, "wb") as fh:
        fh.write(b"time,id,lat,lon,name\n")
        for start in range(0, rows, 100_000):
            fh.write(
                "".join(
                    f"2024-01-01 {k // 3600 % 24:02d}:{k // 60 % 60:02d}:{k % 60:02d},{k % 50},"
                    f"37.{k % 1000:03d},23.60,{NAMES[k % 3]}\n"
                    for k in range(start, min(start + 100_000, rows))
                ).encode("gb18030")
            )
    mixed.write_bytes(clean.read_bytes() + UTF8_LINE)
    # every time quoted: the import reads it in pieces (quotes in the start)
    quoted = folder / "gb1_quoted.csv"
    lines = mixed.read_bytes().split(b"\n")
    body = [lines[0]] + [b'"' + line[:19] + b'"' + line[19:] for line in lines[1:] if line]
    quoted.write_bytes(b"\n".join(body) + b"\n")
    return clean, mixed, quoted


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, default=1_000_000)
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--base", type=Path, default=None)
    args = ap.parse_args()
    if args.base is not None:  # the older tree instead of the installed one
        sys.meta_path[:] = [f for f in sys.meta_path if "editable" not in repr(f)]
        sys.path_hooks[:] = [h for h in sys.path_hooks if "editable" not in repr(h)]
        sys.path.insert(0, str(args.base))
    import wakeline.core.io.decoding as decoding
    from wakeline.core.io import import_to_csv, read_points

    print("code:", Path(decoding.__file__).parents[2])
    count = {"bytes": 0}
    orig = decoding.LineDecoder.decode

    def counted(self, data=b"", final=False):
        count["bytes"] += len(data)
        return orig(self, data, final)

    decoding.LineDecoder.decode = counted
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        files = make(folder, args.rows)
        for name, fn in (
            ("import (streamed)", lambda p: import_to_csv(p, folder / "o.csv")),
            ("read_points (whole)", read_points),
        ):
            for path in files:
                best = float("inf")
                for _ in range(args.repeat):
                    count["bytes"] = 0
                    t = time.perf_counter()
                    got = fn(path)
                    best = min(best, time.perf_counter() - t)
                out = (folder / "o.csv").read_bytes() if name.startswith("import") else b""
                digest = hashlib.sha1(
                    out
                    + json.dumps(got.report["warnings"]).encode()
                    + got.quarantine.to_csv().encode()
                ).hexdigest()[:12]
                print(
                    f"{name:20s} {path.name}: {best:.2f} s, decoded "
                    f"{count['bytes'] / path.stat().st_size:.2f}x the file, "
                    f"{got.report['rows_imported']:,} rows, fallback "
                    f"{got.report.get('encoding_fallback')}, digest {digest}"
                )


if __name__ == "__main__":
    main()
