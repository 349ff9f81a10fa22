"""How many of the lines the window logs for a bearing file stay English in zh_CN
(operator test 8, D3): the file's read summary and the detector's line per batch, put in
the window's words and through ``resources/translations/core_zh_CN.json``.

    python bench/zh_bearing_lines.py [FILE] [--tracks TRACKS --origin LAT,LON]

FILE defaults to the Autoferry camera detections under ``$WAKELINE_SHARED``.
"""

import argparse
import os
import re
from pathlib import Path

from wakeline.app.core_text import translate
from wakeline.app.window_words import window_words
from wakeline.core.bearing import detect_with_report, report_lines
from wakeline.core.bearing_read import gate_lines, gate_to_tracks, read_bearing_file, summary_lines
from wakeline.core.io import read_points

REAL = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
#: An English phrase: a word of four letters or more followed by two more words.
ENGLISH = re.compile(r"[A-Za-z]{4,} [a-z]{3,} [a-z]{3,}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument(
        "file", nargs="?", default=REAL / "data/real/autoferry-fusion/detections.csv.gz"
    )
    ap.add_argument("--tracks", help="gate on this track file (as File ▸ Open bearings… does)")
    ap.add_argument("--origin", help="the tracks' origin of x/y metres, LAT,LON")
    args = ap.parse_args()
    got = read_bearing_file(args.file)
    bearings, lines = got.bearings, summary_lines(got.report)
    if args.tracks:
        tracks = read_points(args.tracks, origin=args.origin).points
        bearings, gated = gate_to_tracks(bearings, tracks, 3.0)
        lines += gate_lines(gated)
    _, report = detect_with_report(bearings)
    lines += report_lines(report)
    zh = [translate(window_words(t), "zh_CN") for t in lines]
    left = [t for t in zh if ENGLISH.search(t)]
    print(f"{len(lines)} lines, {len(left)} with English phrases left in zh_CN")
    for t in left[:5]:
        print("  ", t[:160])
    print("last:", zh[-1])


if __name__ == "__main__":
    main()
