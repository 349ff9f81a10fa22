"""Draw the application icon with Qt offscreen: resources/icons/wakeline.png (256 px) and
wakeline.ico (16-256 px). A wake line: a ship's track with turning points on a sea disc.

Run: ``QT_QPA_PLATFORM=offscreen python packaging/make_icon.py`` (the files are committed;
run it again only to change the drawing).
"""

import os
import sys
from pathlib import Path

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

from PySide6 import QtCore, QtGui  # noqa: E402

OUT = Path(__file__).resolve().parents[1] / "resources" / "icons"


def draw(size: int) -> QtGui.QImage:
    img = QtGui.QImage(size, size, QtGui.QImage.Format.Format_ARGB32)
    img.fill(QtCore.Qt.GlobalColor.transparent)
    p = QtGui.QPainter(img)
    p.setRenderHint(QtGui.QPainter.RenderHint.Antialiasing)
    s = size / 256.0
    grad = QtGui.QLinearGradient(0, 0, 0, size)
    grad.setColorAt(0.0, QtGui.QColor("#1f6fb2"))
    grad.setColorAt(1.0, QtGui.QColor("#0b3556"))
    p.setBrush(grad)
    p.setPen(QtCore.Qt.PenStyle.NoPen)
    p.drawRoundedRect(QtCore.QRectF(8 * s, 8 * s, 240 * s, 240 * s), 48 * s, 48 * s)
    pts = [(40, 190), (100, 150), (130, 175), (200, 70)]
    path = QtGui.QPainterPath(QtCore.QPointF(pts[0][0] * s, pts[0][1] * s))
    for x, y in pts[1:]:
        path.lineTo(x * s, y * s)
    pen = QtGui.QPen(QtGui.QColor("#f4f8fb"), max(1.5, 16 * s))
    pen.setCapStyle(QtCore.Qt.PenCapStyle.RoundCap)
    pen.setJoinStyle(QtCore.Qt.PenJoinStyle.RoundJoin)
    p.setPen(pen)
    p.setBrush(QtCore.Qt.BrushStyle.NoBrush)
    p.drawPath(path)
    p.setPen(QtCore.Qt.PenStyle.NoPen)
    p.setBrush(QtGui.QColor("#ffb000"))
    for x, y in pts[1:3]:
        p.drawEllipse(QtCore.QPointF(x * s, y * s), 18 * s, 18 * s)
    p.setBrush(QtGui.QColor("#f4f8fb"))
    p.drawEllipse(QtCore.QPointF(200 * s, 70 * s), 22 * s, 22 * s)
    p.end()
    return img


def main() -> int:
    from PySide6 import QtWidgets

    _app = QtWidgets.QApplication.instance() or QtWidgets.QApplication([])
    OUT.mkdir(parents=True, exist_ok=True)
    if not draw(256).save(str(OUT / "wakeline.png")):
        print("could not write the PNG", file=sys.stderr)
        return 1
    # One ICO with several sizes: Qt's ICO writer takes them through QImageWriter.
    writer = QtGui.QImageWriter(str(OUT / "wakeline.ico"), b"ico")
    if not writer.write(draw(256)):
        print(f"could not write the ICO: {writer.errorString()}", file=sys.stderr)
        return 1
    print(f"wrote {OUT / 'wakeline.png'} and {OUT / 'wakeline.ico'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
