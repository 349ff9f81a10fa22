"""Speed-unit check (h191, D-import-14) on the real sets: each file's median ratio of its
speed column to the speed from the positions, rows compared, the standard error of the log
median, and the warning, if any. ``WAKELINE_SHARED=/work/shared python bench/speed_unit_real.py``"""

import glob
import os

from wakeline.core.io import read_points
from wakeline.core.io.speed_check import speed_ratio

R = os.path.join(os.environ.get("WAKELINE_SHARED", "../shared"), "data", "real", "")
files = sorted(
    glob.glob(R + "greece-ais-annotated/vessel_*_id_annotated.csv")
    + glob.glob(R + "dma-single-ship/*.csv")
    + [R + "oresund-encounters/encounters.csv"]
    + sorted(glob.glob(R + "mtad-dtwcm/original/*.csv"))[:40]
    + sorted(glob.glob(R + "mtad-dtwcm/two_sensor/*.csv"))[:40]
    + glob.glob(R + "atd2025-noaa/*.csv.gz")
)
bad = 0
for f in files:
    try:
        r = read_points(f)
    except Exception as e:
        print(f, "not read:", str(e)[:80])
        continue
    w = [x for x in r.report["warnings"] if "look like" in x]
    bad += bool(w)
    ratio, n, se = speed_ratio(r.points)
    print(f.replace(R, ""), r.report["columns"].get("speed"), f"{ratio:.3f}", n, f"{se:.3f}", w)
print("files", len(files), "warned", bad)
