"""Read every real file under $WAKELINE_SHARED/data/real (up to 30 MB) with read_points and
list those whose import warns of swapped lat/lon or quarantines rows as swapped (review h209,
finding 6: the judgement per sensor or track must not fire on real files)."""

import os
from pathlib import Path

from wakeline.core.errors import InputError
from wakeline.core.io import read_points
from wakeline.core.io.reader import SWAPPED_REASON


def main() -> None:
    root = Path(os.environ.get("WAKELINE_SHARED", "/work/shared")) / "data" / "real"
    read, hits = 0, []
    for p in sorted(root.rglob("*")):
        if p.is_dir() or p.suffix == ".md" or p.stat().st_size > 30e6:
            continue
        try:
            rep = read_points(p).report
        except (InputError, ValueError, OSError):
            continue
        read += 1
        if any("look swapped" in w for w in rep["warnings"]) or rep["quarantine_reasons"].get(
            SWAPPED_REASON
        ):
            hits.append(str(p.relative_to(root)))
    print(f"read {read} files; swapped warnings or quarantines: {hits}")


if __name__ == "__main__":
    main()
