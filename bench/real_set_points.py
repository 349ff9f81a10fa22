"""The points of the six real sets as ``wakeline evaluate maneuver --real`` reads them (one
helper for the bench scripts that loop over them: clean_breaks.py, compress_error_cap.py).

Saronic (greece-ais-annotated), DMA, Øresund and the Autoferry radar by their readers; MTAD
(original, every scene) and the two ATD files as import reads them.
"""

import os
from pathlib import Path

import pandas as pd

from wakeline.core import real_sets
from wakeline.core.evaluate_real import in_content_order, read_track_files

#: ../shared, or $WAKELINE_SHARED (as the tests read it)
SHARED = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
REAL = SHARED / "data" / "real"

SETS = {
    "saronic": "greece-ais-annotated",
    "dma": "dma-single-ship",
    "oresund": "oresund-encounters",
    "autoferry": "autoferry-fusion",
    "mtad": "mtad-dtwcm/original",
    "atd_example": "atd2025-noaa/example_truth.csv.gz",
    "atd_dataset1": "atd2025-noaa/dataset1_truth.csv.gz",
}


def set_points(name: str) -> pd.DataFrame:
    """Canonical points (sensor, batch, time, lon, lat[, speed …]) of the named set."""
    path = REAL / SETS[name]
    if name == "saronic":
        return in_content_order(real_sets.read_greece(path))
    if name == "dma":
        return in_content_order(real_sets.read_dma(path))
    if name == "oresund":
        return in_content_order(real_sets.read_oresund(path))
    if name == "autoferry":
        return real_sets.read_autoferry(path, exclusive=True, sensor="radar")[0]
    return read_track_files(path, None)[0]
