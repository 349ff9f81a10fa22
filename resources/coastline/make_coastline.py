"""Rebuild ne_50m_coastline.npz from Natural Earth's 1:50m coastline GeoJSON.

Run: ``python make_coastline.py ne_50m_coastline.geojson`` (the copy in
``../shared/data/coastline/``). Every vertex of every line is kept (no simplification);
lines (and the parts of the one MultiLineString) are separated by NaN; float32 degrees.
"""

import json
import sys
from pathlib import Path

import numpy as np


def main(geojson: str) -> None:
    with open(geojson, encoding="ascii") as f:
        data = json.load(f)
    lines = []
    for feature in data["features"]:
        geom = feature["geometry"]
        parts = [geom["coordinates"]] if geom["type"] == "LineString" else geom["coordinates"]
        lines.extend(np.asarray(p, dtype="float64") for p in parts)
    sep = np.full((1, 2), np.nan)
    xy = np.concatenate([a for line in lines for a in (line, sep)][:-1])
    out = Path(__file__).with_name("ne_50m_coastline.npz")
    np.savez_compressed(out, lon=xy[:, 0].astype("float32"), lat=xy[:, 1].astype("float32"))
    print(f"{out.name}: {len(lines)} lines, {int(np.isfinite(xy[:, 0]).sum())} vertices")


if __name__ == "__main__":
    main(sys.argv[1])
