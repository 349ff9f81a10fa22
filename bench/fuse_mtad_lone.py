"""MTAD two-sensor samplings (mtad-dtwcm/two_sensor, 4 scenes x 11 error levels): how far
the fused track's points of one sensor lie from that sensor's own fix (junction blends
included), per error level, with the test's set-up (batches renumbered, gate 50 km, sync,
optimal). MTAD's noise is about 1.28 km x level (p95 twice that); level 0 is the
original's ~460 m.

    WAKELINE_SHARED=/work/shared python bench/fuse_mtad_lone.py [--time-base union]
"""

import argparse
import glob
import os
import re

import numpy as np
import pandas as pd

from wakeline.core.evaluate_association import single_sensor_shifts
from wakeline.core.fuse import FuseParams, associate_sensors, fuse
from wakeline.core.io import read_points


def scene_shifts(path: str, time_base: str = "weight") -> dict:
    """Largest and 99th-percentile distance (m) of a one-sensor fused point from its fix."""
    parts = []
    for k, sensor in enumerate(("AIS", "radar")):
        d = read_points(path.replace("_AIS", f"_{sensor}"), sensor=sensor).points
        codes = pd.factorize(d["batch"])[0]
        perm = np.random.default_rng(k).permutation(codes.max() + 1) + 500 * k
        d["batch"] = perm[codes].astype(str)
        parts.append(d)
    params = FuseParams(max_distance_m=50_000.0, time_base=time_base)
    a = associate_sensors(pd.concat(parts, ignore_index=True), params)
    f = fuse(a, params)
    s = single_sensor_shifts(a.points, f)
    return {"max_m": s["single_shift_max"], "p99_m": s["single_shift_p99"]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--time-base", default="weight", help="FuseParams.time_base")
    args = ap.parse_args()
    shared = os.environ.get("WAKELINE_SHARED", "../shared")
    folder = os.path.join(shared, "data", "real", "mtad-dtwcm", "two_sensor")
    rows = []
    for path in sorted(glob.glob(os.path.join(folder, "scene-*_AIS.csv"))):
        scene, err = re.search(r"scene-(\d+)_error_(\d+)_AIS", path).groups()
        rows.append({"scene": int(scene), "level": int(err), **scene_shifts(path, args.time_base)})
    df = pd.DataFrame(rows)
    table = df.groupby("level").agg(
        largest_km=("max_m", lambda v: v.max() / 1000.0),
        p99_km=("p99_m", lambda v: v.median() / 1000.0),
    )
    print(
        f"time_base {args.time_base}: distance of a one-sensor fused point from its own "
        "fix, over the 4 scenes"
    )
    print("(largest; median over the scenes of each scene's 99th percentile)")
    print(table.round(2).to_string())


if __name__ == "__main__":
    main()
