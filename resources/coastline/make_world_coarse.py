import numpy as np, pyqtgraph as pg
from PySide6 import QtGui
from scipy import ndimage
im = QtGui.QImage('ne.png').convertToFormat(QtGui.QImage.Format.Format_RGB888)
w, h = im.width(), im.height()
a = np.frombuffer(im.constBits(), dtype=np.uint8).reshape(h, im.bytesPerLine())[:, : w * 3].reshape(h, w, 3).astype(int)
r, g, b = a[..., 0], a[..., 1], a[..., 2]
water = (b > r + 25) & (b > g + 5)
land = ~water
# drop specks
land = ndimage.binary_opening(land, iterations=1) | ndimage.binary_closing(land, iterations=1) & land
lab, n = ndimage.label(land)
sizes = ndimage.sum(land, lab, range(1, n + 1))
land = np.isin(lab, 1 + np.flatnonzero(sizes >= 3))
f = ndimage.gaussian_filter(land.astype(float), 0.6)
lines = pg.functions.isocurve(f.T, 0.5, connected=True)  # x = column index
lon, lat = [], []
for line in lines:
    arr = np.asarray(line)
    if len(arr) < 4:
        continue
    lon.extend((arr[:, 0] + 0.5) * 360 / w - 180); lat.extend(90 - (arr[:, 1] + 0.5) * 180 / h)
    lon.append(np.nan); lat.append(np.nan)
lon = np.round(np.array(lon), 3).astype('float32'); lat = np.round(np.array(lat), 3).astype('float32')
print(len(lines), len(lon))
np.savez_compressed('/work/main/resources/coastline/world_coarse.npz', lon=lon, lat=lat)
