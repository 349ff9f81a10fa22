"""Dark ink for plot text on the white plot backgrounds.

pyqtgraph draws axes, tick labels, axis titles and legend text in its ``foreground``
option, a light grey meant for its black default background: on our white plots the
text read poorly (an operator's report). Every plot widget calls :func:`setup` before
it is built, so the CLI's renders, the window and the tests draw alike.
"""

import pyqtgraph as pg

#: Axes, ticks, titles and legend text.
INK = "#303030"


def setup() -> None:
    """Make the plots built from now on draw their text and axes in :data:`INK`."""
    if pg.getConfigOption("foreground") != INK:
        pg.setConfigOptions(foreground=INK)
