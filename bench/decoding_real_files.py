"""Whether every real file decodes as before: each CSV/TXT file under
$WAKELINE_SHARED/data/real and tests/data, judged (``decide_file``) and decoded by the
line decoder as UTF-8 and as GB18030 (``decode_text``): a digest of each text and its
fallback lines, saved once and compared after a change.

``python bench/decoding_real_files.py chinese``: how often the GB18030 rule for UTF-8
lines misjudges real Chinese text (the zh_CN translations, line by line): lines that in
GB18030 are valid UTF-8 not pairing as GB2312 (would be misread as UTF-8), and lines that
in UTF-8 pair whole as GB2312 (would stay garbled as GB18030).

Run: ``python bench/decoding_real_files.py save before.json`` (before the change), then
``python bench/decoding_real_files.py compare before.json``: prints the files compared,
those whose reading changed (the encoding judged, the text in it, its fallback lines),
then those whose text decoded in the other encoding changed (not what is read; how the
two rules of h148 show) and the encodings judged.
"""

import hashlib
import json
import os
import sys
from collections import Counter
from pathlib import Path

from wakeline.core.io.decoding import decide_file, decode_text

ROOT = Path(__file__).resolve().parents[1]


def files() -> list[Path]:
    roots = [Path(os.environ.get("WAKELINE_SHARED", "/work/shared")) / "data/real"]
    roots.append(ROOT / "tests/data")
    out = []
    for root in roots:
        out += [p for p in root.rglob("*") if p.is_file() and p.suffix.lower() in (".csv", ".txt")]
    return sorted(out)


def digest(path: Path) -> dict:
    data = path.read_bytes()
    out = {"judged": decide_file(path, None)}
    for enc in ("utf-8", "gb18030"):
        text, dec = decode_text(data, enc)
        out[enc] = hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()[:16]
        out[enc + " fallbacks"] = {k: v for k, v in sorted(dec.fallbacks.counts.items())}
    return out


def chinese() -> None:
    import re

    from wakeline.core.io.decoding import _GB2312_PAIR, _high

    def pairs(data: bytes) -> bool:
        return 2 * len(_GB2312_PAIR.findall(data)) == _high(data)

    ts = (ROOT / "resources/translations/wakeline_zh_CN.ts").read_text(encoding="utf-8")
    texts = re.findall(r"<translation[^>]*>(.*?)</translation>", ts, re.S)
    lines = [x for t in texts for x in t.splitlines() if not x.isascii()]
    misread = stay = valid = 0
    for line in lines:
        gb, u8 = line.encode("gb18030"), line.encode("utf-8")
        try:
            gb.decode("utf-8")
            valid += 1
            misread += not pairs(gb)
        except UnicodeDecodeError:
            pass
        stay += pairs(u8)
    print(f"{len(lines)} lines of Chinese text; as GB18030 valid UTF-8: {valid}, of those read")
    print(f"as UTF-8 by the rule (wrong): {misread}; as UTF-8 pairing whole as GB2312 (left")
    print(f"as GB18030, garbled): {stay}")


def main() -> None:
    if sys.argv[1] == "chinese":
        chinese()
        return
    what, where = sys.argv[1], Path(sys.argv[2])
    got = {str(p): digest(p) for p in files()}
    if what == "save":
        where.write_text(json.dumps(got, indent=1))
        print(f"{len(got)} files saved to {where}")
        return
    before = json.loads(where.read_text())

    def read(d: dict) -> tuple:
        return d["judged"], d[d["judged"]], d[d["judged"] + " fallbacks"]

    changed = [p for p in got if p not in before or read(got[p]) != read(before[p])]
    print(
        f"{len(got)} files compared ({len(set(got) - set(before))} new), {len(changed)} read otherwise"
    )
    for p in changed:
        print(" ", p, before.get(p), "->", got[p])
    other = [p for p in got if p not in changed and got[p] != before[p]]
    print(f"{len(other)} files decode otherwise in the encoding not judged:")
    for p in other:
        was, now = before[p], got[p]
        enc = next(e for e in ("utf-8", "gb18030") if e != now["judged"])
        same = now[enc] == now[now["judged"]]
        print(
            f"  {p}: as {enc} {was[enc + ' fallbacks']} -> {now[enc + ' fallbacks']}"
            f"{' (now the text read)' if same else ''}"
        )
    print("judged:", dict(Counter(d["judged"] for d in got.values())))


if __name__ == "__main__":
    main()
