"""The line decoder on a file wholly Windows-1252 (every row holds a non-ASCII byte, so
every line fails UTF-8): the line-by-line decoder before h148 (tests/decoding_reference.py)
against the one that finds the failing lines at once (core/io/decoding.py), both against
the baseline of the same run, the file decoded as latin-1 (``--encoding latin-1``).

Two measures: the decoding alone (4 MB chunks, as the whole-file reader feeds it), and
the whole import (``read_points``) with each decoder and with ``encoding="latin-1"``.
``--gb``: the same for a file wholly GB18030 (Chinese names on every row), whose lines the
decoder now looks at for UTF-8 ones (h148), against strict GB18030 decoding.

Run: ``python bench/bench_decoding.py [--rows 2000000] [--repeat 3] [--no-import] [--gb]``.
"""

import argparse
import codecs
import sys
import tempfile
import time
from pathlib import Path
from unittest import mock

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import decoding_reference as ref  # noqa: E402

from wakeline.core.io import read_points, reader  # noqa: E402
from wakeline.core.io.decoding import LineDecoder  # noqa: E402

NAMES = ["Bjørn", "Tromsø", "Ærøskøbing", "Málaga", "Façade", "Müller", "Åre", "Göteborg"]


def make_file(path: Path, rows: int) -> None:
    with open(path, "wb") as fh:
        fh.write(b"sensor,batch,time,lon,lat,name\n")
        step = 100_000
        for k in range(0, rows, step):
            fh.write(
                "".join(
                    f"{NAMES[i % 8]},{i % 50},2024-01-01T{i // 3600 % 24:02d}:{i // 60 % 60:02d}:"
                    f"{i % 60:02d}Z,{10 + i % 1000 * 1e-4:.4f},{60 + i % 777 * 1e-4:.4f},"
                    f"{NAMES[(i + 3) % 8]}\n"
                    for i in range(k, min(k + step, rows))
                ).encode("cp1252")
            )


def decode_all(path: Path, make) -> tuple[float, int]:
    dec = make()
    t = time.perf_counter()
    n = 0
    with open(path, "rb") as fh:
        while raw := fh.read(4 * 1024 * 1024):
            n += len(dec.decode(raw))
    n += len(dec.decode(b"", final=True))
    return time.perf_counter() - t, n


def best(fn, repeat: int):
    runs = [fn() for _ in range(repeat)]
    return min(runs, key=lambda r: r[0])


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rows", type=int, default=2_000_000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-import", action="store_true")
    ap.add_argument("--gb", action="store_true")
    args = ap.parse_args()
    if args.gb:
        gb(args)
        return
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "cp1252.csv"
        make_file(path, args.rows)
        size = path.stat().st_size
        print(f"{args.rows:,} rows, {size / 1e6:.1f} MB, every line Windows-1252")
        base = best(
            lambda: decode_all(path, lambda: codecs.getincrementaldecoder("latin-1")()),
            args.repeat,
        )
        old = best(lambda: decode_all(path, lambda: ref.LineDecoder("utf-8")), args.repeat)
        new = best(lambda: decode_all(path, lambda: LineDecoder("utf-8")), args.repeat)
        assert old[1] == new[1] == base[1]
        print(f"decoding alone (best of {args.repeat}):")
        print(f"  latin-1 (baseline)   {base[0]:7.3f} s")
        print(f"  line by line (old)   {old[0]:7.3f} s  {old[0] / base[0]:6.1f}x baseline")
        print(f"  fast (new)           {new[0]:7.3f} s  {new[0] / base[0]:6.1f}x baseline")
        print(f"  old / new            {old[0] / new[0]:7.1f}x")
        if args.no_import:
            return

        def imp(**kw):
            t = time.perf_counter()
            r = read_points(path, **kw)
            return time.perf_counter() - t, len(r.points), len(r.quarantine)

        base = best(lambda: imp(encoding="latin-1"), 1)
        new = best(imp, 1)

        def old_decoder(encoding: str, fail: bool = False):
            assert not fail  # a UTF-8 file: never read "strict-lines"
            return ref.LineDecoder(encoding)

        with mock.patch.object(reader, "LineDecoder", old_decoder):
            old = best(imp, 1)
        assert old[1:] == new[1:] == base[1:], (old, new, base)
        print("whole import, read_points (one run each):")
        print(f"  --encoding latin-1   {base[0]:7.3f} s")
        print(f"  line by line (old)   {old[0]:7.3f} s  {old[0] / base[0]:6.2f}x baseline")
        print(f"  fast (new)           {new[0]:7.3f} s  {new[0] / base[0]:6.2f}x baseline")


def gb(args) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "gb.csv"
        with open(path, "wb") as fh:
            fh.write("批号,时间,经度,纬度,船名\n".encode("gb18030"))
            for k in range(0, args.rows, 100_000):
                fh.write(
                    "".join(
                        f"{i % 50},2024-05-01 {i // 3600 % 24:02d}:{i // 60 % 60:02d}:"
                        f"{i % 60:02d},122.{i % 1000:03d},30.0,浙渔号{i % 97}\n"
                        for i in range(k, min(k + 100_000, args.rows))
                    ).encode("gb18030")
                )
        print(f"{args.rows:,} rows, {path.stat().st_size / 1e6:.1f} MB, GB18030")
        base = best(
            lambda: decode_all(path, lambda: codecs.getincrementaldecoder("gb18030")()),
            args.repeat,
        )
        new = best(lambda: decode_all(path, lambda: LineDecoder("gb18030")), args.repeat)
        print(f"decoding alone (best of {args.repeat}):")
        print(f"  strict gb18030 (baseline)  {base[0]:7.3f} s")
        print(f"  line decoder (new)         {new[0]:7.3f} s  {new[0] / base[0]:6.2f}x baseline")
        if args.no_import:
            return
        t = time.perf_counter()
        got = read_points(path, encoding="gb18030", tz="Asia/Shanghai")
        given = time.perf_counter() - t
        t = time.perf_counter()
        judged = read_points(path, tz="Asia/Shanghai")
        new = time.perf_counter() - t
        assert judged.report["encoding"] == "gb18030" and len(judged.points) == len(got.points)
        print("whole import, read_points (one run each):")
        print(f"  --encoding gb18030 (strict)  {given:7.3f} s")
        print(f"  judged (new: strict-lines)   {new:7.3f} s  {new / given:6.2f}x baseline")


if __name__ == "__main__":
    main()
