"""Wakeline engine: track data, import, geometry, simulation and the algorithms.

Pure Python on numpy/scipy/pandas/pyarrow. This package never imports Qt.
"""

from wakeline.core.errors import Cancelled, InputError

__all__ = ["Cancelled", "InputError", "__version__"]
__version__ = "0.1.0"
