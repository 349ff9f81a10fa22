"""Autoferry radar (1.7 s) + lidar (0.5 s) fused per scenario (fuse departure 28): each
sensor's plots as one track per (scenario, target) (`read_autoferry`), cleaned with the
defaults, then `associate_sensors` with the defaults (or `--set NAME=VALUE`). A pair is
true when both tracks are the same (scenario, target). Prints every pair found, the true
pairs never compared, and the totals.

    python bench/fuse_autoferry.py [--set min_overlap_fixes=0 ...]
"""

import argparse
import os
from pathlib import Path

import pandas as pd

from wakeline.core import real_sets
from wakeline.core.clean import CleanParams, clean
from wakeline.core.fuse import FuseParams, associate_sensors


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    args = ap.parse_args(argv)
    changes = dict(s.split("=", 1) for s in args.set)
    params = FuseParams().replace(**changes).checked()
    folder = Path(os.environ.get("WAKELINE_SHARED", "/work/shared")) / "data/real/autoferry-fusion"
    radar = real_sets.read_autoferry(folder, sensor="radar")[0]
    lidar = real_sets.read_autoferry(folder, sensor="lidar")[0]
    both = pd.concat(
        [clean(radar, CleanParams()).points, clean(lidar, CleanParams()).points],
        ignore_index=True,
    )
    scen = both["batch"].astype(str).str.split("/").str[0]
    true_n = wrong_n = 0
    targets = set()
    for s in sorted(scen.unique(), key=lambda v: (len(v), v)):
        pts = both[scen == s]
        if pts["sensor"].nunique() < 2:
            continue
        rad = set(pts.loc[pts.sensor == "radar", "batch"])
        targets |= rad & set(pts.loc[pts.sensor == "lidar", "batch"])
        table = associate_sensors(pts, params).pair_table()
        for r in table.itertuples():
            ok = r.batch_a == r.batch_b
            true_n += ok
            wrong_n += not ok
            print(f"{s:>4} {r.batch_a:>8} {r.batch_b:>8} {r.distance:7.1f} m "
                  f"{r.overlap_s:6.1f} s {'true' if ok else 'WRONG'}")  # fmt: skip
    print(f"{len(targets)} boats seen by both sensors: {true_n} true pairs, {wrong_n} wrong")


if __name__ == "__main__":
    main()
