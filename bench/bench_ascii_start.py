"""A file that starts ASCII and has lines that are not UTF-8 later (h179): Latin-1
(Windows-1252) ship names, or GB18030 Chinese names, in the second half of a 100 k-row
file. The start reads as UTF-8 (ASCII), so the first reading is UTF-8, strictly; before
h179 the first line that did not decode failed it, the whole file's judgement
(decide_file) read the file, and the file was read again line by line. Now the strict
reading's decoder asks the judgement at that line and goes on (as h167 did for GB18030
with a UTF-8 line). Prints, per file and reader (``wakeline import``'s streamed
:func:`import_to_csv` and the whole-file :func:`read_points`): the best time, how many
file sizes went through the line decoder and through Arrow's own UTF-8 reading, the
judgements asked, and a digest of the output, warnings and quarantine (the same before
and after).

Run: ``python bench/bench_ascii_start.py [--rows 100000] [--repeat 3] [--base DIR]``
(``--base``: a copy of an older tree, ``DIR/wakeline/{core,app,resources}``, to time it).
"""

import argparse
import hashlib
import json
import sys
import tempfile
import time
from pathlib import Path

LATIN = ["Bjørn", "Ålesund", "São Paulo", "Göteborg"]
CHINESE = ["远洋一号", "海丰号", "中远之星"]


def make(folder: Path, rows: int) -> list[Path]:
    out = []
    for name, names, enc in (
        ("ascii.csv", None, "ascii"),
        ("latin_late.csv", LATIN, "cp1252"),
        ("gb_late.csv", CHINESE, "gb18030"),
    ):
        lines = ["time,id,lat,lon,name\n"]
        for k in range(rows):
            ship = f"ship{k % 50}"
            if names is not None and k >= rows // 2 and k % 10 == 0:
                ship = names[k % len(names)]
            lines.append(
                f"2024-01-01 {k // 3600 % 24:02d}:{k // 60 % 60:02d}:{k % 60:02d},{k % 50},"
                f"37.{k % 1000:03d},23.60,{ship}\n"
            )
        p = folder / name
        p.write_bytes("".join(lines).encode(enc))
        out.append(p)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, default=100_000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--base", type=Path, default=None)
    args = ap.parse_args()
    if args.base is not None:  # the older tree instead of the installed one
        sys.meta_path[:] = [f for f in sys.meta_path if "editable" not in repr(f)]
        sys.path_hooks[:] = [h for h in sys.path_hooks if "editable" not in repr(h)]
        sys.path.insert(0, str(args.base))
    import wakeline.core.io.compressed as compressed
    import wakeline.core.io.decoding as decoding
    import wakeline.core.io.reader as reader
    from wakeline.core.io import import_to_csv, read_points

    print("code:", Path(decoding.__file__).parents[2])
    count = {"bytes": 0, "arrow": 0, "judged": 0}
    orig = decoding.LineDecoder.decode

    def counted(self, data=b"", final=False):
        count["bytes"] += len(data)
        return orig(self, data, final)

    decoding.LineDecoder.decode = counted
    arrow = compressed.open_for_arrow

    def arrow_counted(path, compression):
        count["arrow"] += Path(path).stat().st_size
        return arrow(path, compression)

    import wakeline.core.io.layout as layout

    for mod in (compressed, reader, layout):
        if hasattr(mod, "open_for_arrow"):
            mod.open_for_arrow = arrow_counted
    judge = decoding.decide_file

    def judged(*a, **k):
        count["judged"] += 1
        return judge(*a, **k)

    for mod in (decoding, reader):
        if hasattr(mod, "decide_file"):
            mod.decide_file = judged
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
                    getattr(reader, "_JUDGED", {}).clear()  # each run judges afresh
                    getattr(reader, "_VALID_UTF8", {}).clear()
                    count.update(bytes=0, arrow=0, judged=0)
                    t = time.perf_counter()
                    got = fn(path)
                    best = min(best, time.perf_counter() - t)
                if name.startswith("import"):
                    out = (folder / "o.csv").read_bytes()
                else:
                    out = got.points.to_csv(index=False).encode()
                digest = hashlib.sha1(
                    out
                    + json.dumps(got.report["warnings"]).encode()
                    + got.quarantine.to_csv().encode()
                ).hexdigest()[:12]
                size = path.stat().st_size
                print(
                    f"{name:20s} {path.name:15s}: {best:.3f} s, line decoder "
                    f"{count['bytes'] / size:.2f}x, arrow {count['arrow'] / size:.2f}x, "
                    f"judged {count['judged']}, {got.report['rows_imported']:,} rows, "
                    f"fallback {got.report.get('encoding_fallback')}, digest {digest}"
                )


if __name__ == "__main__":
    main()
