"""Rebuild world_coarse.npz from the Natural Earth raster shipped in the cartopy wheel.

Run: ``python make_world_coarse.py 50-natural-earth-1-downsampled.png`` (offscreen Qt).
Water is where blue clearly dominates; specks under 3 cells go; the 0.5 level of the
lightly smoothed land mask is traced with pyqtgraph's isocurve.
"""

import sys
from pathlib import Path

import numpy as np
import pyqtgraph as pg
from PySide6 import QtGui
from scipy import ndimage


def main(png: str) -> None:
    im = QtGui.QImage(png).convertToFormat(QtGui.QImage.Format.Format_RGB888)
    w, h = im.width(), im.height()
    raw = np.frombuffer(im.constBits(), dtype=np.uint8).reshape(h, im.bytesPerLine())
    a = raw[:, : w * 3].reshape(h, w, 3).astype(int)
    r, g, b = a[..., 0], a[..., 1], a[..., 2]
    land = ~((b > r + 25) & (b > g + 5))
    land = ndimage.binary_opening(land, iterations=1) | (
        ndimage.binary_closing(land, iterations=1) & land
    )
    lab, n = ndimage.label(land)
    sizes = ndimage.sum(land, lab, range(1, n + 1))
    land = np.isin(lab, 1 + np.flatnonzero(sizes >= 3))
    smooth = ndimage.gaussian_filter(land.astype(float), 0.6)
    lon, lat = [], []
    for line in pg.functions.isocurve(smooth.T, 0.5, connected=True):
        arr = np.asarray(line)
        if len(arr) < 4:
            continue
        lon.extend((arr[:, 0] + 0.5) * 360 / w - 180)
        lat.extend(90 - (arr[:, 1] + 0.5) * 180 / h)
        lon.append(np.nan)
        lat.append(np.nan)
    out = Path(__file__).with_name("world_coarse.npz")
    np.savez_compressed(
        out,
        lon=np.round(np.array(lon), 3).astype("float32"),
        lat=np.round(np.array(lat), 3).astype("float32"),
    )


if __name__ == "__main__":
    main(sys.argv[1])
