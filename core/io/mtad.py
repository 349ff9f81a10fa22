"""MTAD association tables (seed 003 §2.1): ground truth for MTAD measurement files.

An association table has one row per observed track piece, ``t_s, t_e, mmsi, source,
batch``: batch ``batch`` of sensor ``source`` belongs to target ``mmsi`` during
``[t_s, t_e]`` (seconds from scene start, like the measurement ``time``).
"""

from pathlib import Path

import numpy as np
import pandas as pd

from wakeline.core.io.sniff import read_small_table
from wakeline.core.schema import time_seconds

ASSOCIATION_COLUMNS = ("t_s", "t_e", "mmsi", "source", "batch")


def read_association_table(path: str | Path) -> pd.DataFrame:
    """Read an MTAD association table; columns as in ``ASSOCIATION_COLUMNS``."""
    df = read_small_table(
        path,
        ASSOCIATION_COLUMNS,
        "an MTAD association table",
        text_columns=("mmsi", "source", "batch"),
    )
    return df[list(ASSOCIATION_COLUMNS)]


def label_points(points: pd.DataFrame, table: pd.DataFrame) -> pd.Series:
    """The target of every point (``truth``) from an association table; "" where none applies.

    A point takes the ``mmsi`` of the table row with its ``(sensor, batch)`` whose
    ``[t_s, t_e]`` holds its time. MTAD times are seconds from scene start, which the
    importer reads as seconds since 1970-01-01.
    """
    t = time_seconds(points["time"])
    out = np.full(len(points), "", dtype=object)
    key_points = points["sensor"].astype("str") + "\x1f" + points["batch"].astype("str")
    key_table = table["source"].astype("str") + "\x1f" + table["batch"].astype("str")
    merged = pd.DataFrame(
        {"key": key_points.to_numpy(), "t": t, "row": np.arange(len(points))}
    ).merge(
        pd.DataFrame(
            {
                "key": key_table.to_numpy(),
                "t_s": table["t_s"].to_numpy(dtype="float64"),
                "t_e": table["t_e"].to_numpy(dtype="float64"),
                "mmsi": table["mmsi"].to_numpy(),
            }
        ),
        on="key",
        how="inner",
    )
    hit = merged[(merged["t"] >= merged["t_s"]) & (merged["t"] <= merged["t_e"])].drop_duplicates(
        "row"
    )
    out[hit["row"].to_numpy()] = hit["mmsi"].to_numpy()
    return pd.Series(out, index=points.index, dtype="str", name="truth")
