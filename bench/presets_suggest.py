"""Which built-in preset the parameter panel suggests for each real set (and a few
synthetic ones): ``core.presets.suggested_presets``, with the figure behind each rule.

    python bench/presets_suggest.py

One line per set: tracks, median interval (s), whether it looks like AIS, the noise
floor ratio (the median over tracks of k · σ_δ / threshold at the first scale; the
"Noisy tracks" preset is suggested at 1 or more) and the presets suggested. The Autoferry
radar and lidar are also decimated to one plot every 3-7 s (bench/sampling_sweep.py).
docs/evaluation.md "Built-in presets (session 29)".
"""

import os
import sys
from pathlib import Path

import numpy as np
import pandas as pd

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "bench"))
from long_noisy_tracks import make as long_noisy  # noqa: E402
from sampling_sweep import decimate  # noqa: E402

from wakeline.core import real_sets  # noqa: E402
from wakeline.core.evaluate_real import read_track_files  # noqa: E402
from wakeline.core.presets import looks_like_ais, noise_floor_ratio, suggested_presets  # noqa: E402
from wakeline.core.simulate import hard_maneuver_scene  # noqa: E402
from wakeline.core.tracks import median_interval_s, sorted_with_index, track_seconds  # noqa: E402

REAL = Path(os.environ.get("WAKELINE_SHARED", REPO.parent / "shared")) / "data" / "real"


def sets():
    yield "Saronic AIS (greece-ais-annotated)", real_sets.read_greece(REAL / "greece-ais-annotated")
    yield "DMA AIS (dma-single-ship)", real_sets.read_dma(REAL / "dma-single-ship")
    yield "Oresund AIS (oresund-encounters)", real_sets.read_oresund(REAL / "oresund-encounters")
    for f in ("example_truth.csv.gz", "dataset1_truth.csv.gz"):
        yield f"ATD AIS {f}", read_track_files(REAL / "atd2025-noaa" / f, None)[0]
    yield "MTAD original scenes", read_track_files(REAL / "mtad-dtwcm" / "original", None)[0]
    two = REAL / "mtad-dtwcm" / "two_sensor"
    for error in (0, 5, 10):
        for kind in ("radar", "AIS"):
            f = two / f"scene-0_error_{error}_{kind}.csv"
            yield f"MTAD two_sensor {f.stem}", read_track_files(f, None)[0]
    radar, _ = real_sets.read_autoferry(REAL / "autoferry-fusion", exclusive=True)
    lidar, _ = real_sets.read_autoferry(REAL / "autoferry-fusion", sensor="lidar")
    yield "Autoferry radar (1.68 s)", radar
    for rate in (3, 4, 5, 7):
        yield f"Autoferry radar every {rate} s", decimate(radar, rate)
    yield "Autoferry lidar (0.5 s)", lidar
    yield "Autoferry lidar every 5 s", decimate(lidar, 5)
    pts = pd.concat([long_noisy(s, 1.0, 15.0, 1.5)[0] for s in range(3)], ignore_index=True)
    yield "synthetic long noisy radar (1 s, 15 m)", pts
    scene = hard_maneuver_scene(0).points
    for rate in ("radar", "ais10", "ais30"):
        yield f"synthetic hard scene 0, {rate}", scene[scene["rate"] == rate]


def main() -> None:
    for name, pts in sets():
        srt, index = sorted_with_index(pts)
        med = median_interval_s(track_seconds(srt), index)
        interval = float(np.nanmedian(med[index.sizes > 1]))
        names = ", ".join(s.name for s in suggested_presets(pts)) or "-"
        print(
            f"{name:44s} tracks {index.n_tracks:5d}  interval {interval:8.2f} s  "
            f"AIS {'yes' if looks_like_ais(pts) else 'no ':3s}  "
            f"noise ratio {noise_floor_ratio(pts):6.2f}  suggests: {names}"
        )


if __name__ == "__main__":
    main()
