"""Bundled data: the demo scene, the 1:50m world coastline, UI translations."""

from importlib import resources
from pathlib import Path


def resource_path(*parts: str) -> Path:
    """Path of a bundled resource file."""
    return Path(str(resources.files("wakeline.resources").joinpath(*parts)))


def demo_path() -> Path:
    """The bundled demo scene (canonical CSV: radar R1 with interrupted batches, AIS)."""
    return resource_path("demo", "demo.csv")


def coastline_path() -> Path:
    """The Natural Earth 1:50m world coastline (float32 lon/lat arrays, NaN-separated;
    see coastline/NOTICE.md)."""
    return resource_path("coastline", "ne_50m_coastline.npz")


def translations_dir() -> Path:
    """Folder of the Qt Linguist ``.ts`` translation files."""
    return resource_path("translations")
