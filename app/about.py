"""Help ▸ About Wakeline and Help ▸ Documentation (operator test 8, D10: the window had no
Help menu; nothing showed the version, the licence or the data credits).

The About dialog says: the version and licence of the installed package, the Qt, PySide6,
pyqtgraph and Python versions it runs on, the four papers its methods come from (the
seeds of ``../shared/SPEC.md``, cited as published), the notices of the data shipped in
``wakeline.resources`` (the coastline, the demo scene; each links its file) and the real
data sets Wakeline was tested on (not shipped). Documentation opens the README (which
links every page of ``docs/``) in the system's browser; on a screen without a desktop
(offscreen, tests) it only says where the documentation is.
"""

import importlib.metadata
import platform
from html import escape
from pathlib import Path

import pyqtgraph
import PySide6
from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.resources import resource_path

TR_CONTEXT = "About"


def tr(text: str) -> str:
    """``text`` in the current language (context :data:`TR_CONTEXT`)."""
    return QtCore.QCoreApplication.translate(TR_CONTEXT, text)


#: The papers the methods come from (SPEC.md's seeds), cited as published.
PAPERS = (
    (
        "000",
        "高原原, 王凯帅, 白立飞, 等. 基于先验知识的海上目标机动检测技术 (Maritime target "
        "maneuver detection based on the prior knowledge). 中国舰船研究 (Chinese Journal of "
        "Ship Research), 2026, 21(2): 435-444.",
    ),
    (
        "001",
        "张浩然, 王桂玲. 基于运动特征的多目标航迹生成方法 (Multi-target trajectory generation "
        "method based on motion features). 计算机科学 (Computer Science), 2025, 52(8): 154-161.",
    ),
    (
        "002",
        "张亚斌, 张逗逗, 吕祥伟, 王富明, 徐泽林. 一种基于AUC的纯方位目标机动检测算法 (An "
        "AUC-based bearing-only target maneuver detection algorithm). 舰船科学技术 (Ship "
        "Science and Technology), 2025, 47(22): 160-165. DOI 10.3404/j.issn.1672-7649.2025.22.023.",
    ),
    (
        "003",
        "陈晓慧, 刘建湘, 张匆, 张兵, 赵云鹏. 基于交互式分析的多源航迹关联融合方法 "
        "(Multi-source track association and fusion by interactive analysis). 信息工程大学学报 "
        "(Journal of Information Engineering University), 2025, 26(5): 608-616. "
        "DOI 10.3969/j.issn.1671-0673.2025.05.015.",
    ),
)

#: The real data sets of the tests and the evaluation (docs/evaluation.md; each one's
#: SOURCE.md in ``../shared/data/real/``): none is shipped with Wakeline.
REAL_SETS = (
    (
        "Autoferry sensor-fusion benchmark",
        "NTNU, github.com/Autoferry/sensor_fusion_dataset; Helgesen et al., Ocean Engineering 2022",
        "CC0 1.0",
    ),
    (
        "MTAD scenes and two-sensor samplings (DTWCM)",
        "github.com/SkiWWWW/Track-to-Track-Association-Algorithm-of-DTWCM; Wan, Mu, Han, "
        "Cheong, Xie, Int. J. Transportation Science and Technology 17 (2025) 95-108",
        "",
    ),
    (
        "MTAD V2 statistics",
        "崔亚奇等, 基于全球AIS的多源航迹关联数据集 (MTAD) V2, Science Data Bank, 2025",
        "",
    ),
    (
        "ATD 2025 challenge (anonymised NOAA/USCG AIS)",
        "Penn State ARL / NGA, atd2025 package",
        "MIT",
    ),
    (
        "Danish Maritime Authority AIS (one ship; Øresund encounters)",
        "DMA / HELCOM AIS via github.com/tadziqusky/ais-trajectory-simplification and "
        "github.com/UT-shunqiang/conditional-trajectory-prediction",
        "",
    ),
    (
        "Saronic Gulf annotated AIS",
        "Athena Research Center, github.com/M3-Archimedes/AIS-trajectory-annotation",
        "GPL-3.0",
    ),
)


def package_version() -> str:
    """The installed package's version ("?" when it is not installed)."""
    try:
        return importlib.metadata.version("wakeline")
    except importlib.metadata.PackageNotFoundError:
        return "?"


def package_licence() -> str:
    """The installed package's licence (its metadata; MIT, as LICENSE says)."""
    try:
        meta = importlib.metadata.metadata("wakeline")
    except importlib.metadata.PackageNotFoundError:
        return "MIT"
    return meta.get("License-Expression") or meta.get("License") or "MIT"


def versions() -> list[tuple[str, str]]:
    """(name, version) of what the window runs on."""
    return [
        ("Qt", QtCore.qVersion()),
        ("PySide6", PySide6.__version__),
        ("pyqtgraph", pyqtgraph.__version__),
        ("Python", platform.python_version()),
    ]


def _link(path: Path) -> str:
    url = QtCore.QUrl.fromLocalFile(str(path)).toString()
    return f'<a href="{escape(url)}">{escape(path.name)}</a>'


def about_html() -> str:
    """The About dialog's text (HTML) in the current language."""
    parts = [
        f"<h2>Wakeline {escape(package_version())}</h2>",
        "<p>"
        + escape(
            tr(
                "A desktop workbench for maritime track data: clean, detect maneuvers, "
                "compress, associate, fuse and review radar and AIS tracks."
            )
        )
        + "</p>",
        "<p>" + escape(tr("Licence: {0}").format(package_licence())) + "</p>",
        "<p>"
        + escape(tr("Runs on: {0}").format(", ".join(f"{n} {v}" for n, v in versions())))
        + "</p>",
        f"<h3>{escape(tr('The papers its methods come from'))}</h3><ul>",
    ]
    for seed, cite in PAPERS:
        parts.append(f"<li>{escape(tr('Seed {0}: {1}').format(seed, cite))}</li>")
    parts.append("</ul>")
    parts.append(f"<h3>{escape(tr('Data shipped with Wakeline'))}</h3><ul>")
    notices = (
        (
            resource_path("coastline", "NOTICE.md"),
            tr(
                "World coastline: Natural Earth 1:50m, public domain (no attribution "
                "required); made with Natural Earth."
            ),
        ),
        (
            resource_path("demo", "README.md"),
            tr("Demo scene: simulated (no real ships), made by wakeline simulate demo."),
        ),
    )
    for path, text in notices:
        parts.append(f"<li>{escape(text)} {_link(path)}</li>")
    parts.append("</ul>")
    parts.append(
        f"<h3>{escape(tr('Real data Wakeline was tested on (not shipped with it)'))}</h3><ul>"
    )
    for name, credit, licence in REAL_SETS:
        text = tr("{0}: {1}; licence: {2}").format(
            name, credit, licence or tr("none stated (kept out of the product)")
        )
        parts.append(f"<li>{escape(text)}</li>")
    parts.append("</ul>")
    return "".join(parts)


class AboutDialog(QtWidgets.QDialog):
    """Help ▸ About Wakeline: :func:`about_html` in a scrolling text, and Close."""

    def __init__(self, parent=None) -> None:
        super().__init__(parent)
        self.setObjectName("about")
        self.setWindowTitle(tr("About Wakeline"))
        self.text = QtWidgets.QTextBrowser()
        self.text.setOpenExternalLinks(True)
        self.text.setHtml(about_html())
        buttons = QtWidgets.QDialogButtonBox(QtWidgets.QDialogButtonBox.StandardButton.Close)
        buttons.rejected.connect(self.reject)
        close = buttons.button(QtWidgets.QDialogButtonBox.StandardButton.Close)
        close.setText(tr("Close"))
        lay = QtWidgets.QVBoxLayout(self)
        lay.addWidget(self.text)
        lay.addWidget(buttons)
        self.resize(720, 560)


def documentation_path() -> Path | None:
    """The README that links every page of ``docs/`` (a source checkout or an editable
    install; None when the package was installed without it)."""
    root = Path(__file__).resolve().parents[1]
    for path in (root / "README.md", root / "docs"):
        if path.exists():
            return path
    return None


def can_open_urls() -> bool:
    """Whether a browser may be asked to open a page: not on a screen without a desktop
    (``offscreen``, ``minimal``: tests and screenshots)."""
    name = QtGui.QGuiApplication.platformName()
    return name not in ("offscreen", "minimal", "")


def open_documentation() -> tuple[Path | None, bool]:
    """Open :func:`documentation_path` in the system's browser when it can: (the path,
    whether it was handed to the browser)."""
    path = documentation_path()
    if path is None or not can_open_urls():
        return path, False
    return path, bool(QtGui.QDesktopServices.openUrl(QtCore.QUrl.fromLocalFile(str(path))))
