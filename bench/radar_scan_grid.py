"""The Autoferry radar decimated to many slower scans (2–7 s, regular and ±30 % jittered,
two seeds) and scored against its GNSS as ``bench/radar_scan_rates.py`` scores it: the tuning
grid behind ``window_max_s`` (docs/evaluation.md "Radar at slower scans (h131)").

    python bench/radar_scan_grid.py [--sensor radar] [--set window_max_s=20] [--set ...]

One line per cell: precision / recall of the defaults and of each ``--set`` row; then, per
row, F1 summed over the cells and the cells meeting goal 2a (recall ≥ 0.7 at precision ≥ 0.8).
The lidar is the blind check of these rules: do not tune on it.
"""

import argparse
import os
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "bench"))
from radar_scan_rates import _params, score  # noqa: E402
from sampling_sweep import decimate  # noqa: E402

from wakeline.core import real_sets  # noqa: E402
from wakeline.core.io import write_points  # noqa: E402

REAL = Path(os.environ.get("WAKELINE_SHARED", REPO.parent / "shared")) / "data" / "real"
RATES = [2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0, 5.5, 6.0, 7.0]
#: (jitter, seed) per rate: regular, and ±30 % with two seeds
VARIANTS = [(0.0, 0), (0.3, 1), (0.3, 2)]


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sensor", choices=("radar", "lidar"), default="radar")
    ap.add_argument("--rates", nargs="+", type=float, default=RATES)
    ap.add_argument("--set", nargs="+", action="append", default=[], metavar="FIELD=VALUE")
    a = ap.parse_args(argv)
    folder = REAL / "autoferry-fusion"
    if not folder.is_dir():
        sys.exit(f"{folder} not found (set WAKELINE_SHARED)")
    rows = {"defaults": []} | {" ".join(s): s for s in a.set}
    pts, truth = real_sets.read_autoferry(folder, exclusive=True, sensor=a.sensor)
    total = {k: [0.0, 0] for k in rows}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        write_points(truth, tmp / "gnss.csv")
        print(f"{a.sensor}: P/R per cell, columns " + " | ".join(rows))
        for rate in a.rates:
            for jitter, seed in VARIANTS:
                plots = decimate(pts, rate, jitter, seed)
                cells = []
                for name, pairs in rows.items():
                    s = score(plots, tmp / "gnss.csv", _params(pairs), tmp)
                    total[name][0] += s["F1"]
                    total[name][1] += s["R"] >= 0.7 and s["P"] >= 0.8
                    cells.append(f"{s['P']:.2f}/{s['R']:.2f}")
                label = f"{rate:g} s" + (f" ±{jitter:.0%} seed {seed}" if jitter else "")
                print(f"{label:>18} | " + " | ".join(cells), flush=True)
    n = len(a.rates) * len(VARIANTS)
    for name, (f1, met) in total.items():
        print(f"{name}: F1 summed {f1:.3f}, cells meeting 2a {met}/{n}")


if __name__ == "__main__":
    main()
