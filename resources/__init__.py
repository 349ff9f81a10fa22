"""Bundled data: the demo scene (and later icons, coastline, translations)."""

from importlib import resources
from pathlib import Path


def resource_path(*parts: str) -> Path:
    """Path of a bundled resource file."""
    return Path(str(resources.files("wakeline.resources").joinpath(*parts)))


def demo_path() -> Path:
    """The bundled demo scene (canonical CSV: radar R1 with interrupted batches, AIS)."""
    return resource_path("demo", "demo.csv")
