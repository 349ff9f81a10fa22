"""The map's view kept in the session, so the project brings the operator back to it.

Pan, zoom and resize move the view many times a second; the view is written to
:attr:`Session.map_view <wakeline.core.session.Session.map_view>` once it has settled
(:data:`SETTLE_MS` after the last change), and the project writer's thread stores it as
one small row (:class:`~wakeline.app.project_controller.ProjectController`). A view the
session gets otherwise (a script) is shown on the map; a project's saved view is shown
by the open job's plan, so its layers are decimated for it in the worker.

The map keeps the aspect of a kilometre, so a view asked for on a window of another
shape is shown widened along one axis (pyqtgraph's target range is the view asked for,
its view range the one shown). While the map's target is the session's view (a project
opened, a resize since) nothing is written: the wider view shown is that view fitted to
the window, and writing it back made the saved view grow with every open in a window
of another shape. A pan or zoom (a new target) writes the view shown.
"""

from PySide6 import QtCore

from wakeline.core.session import MapView, Session

#: The view is written this long (ms) after its last change: one write per pan or
#: zoom, not one per mouse move.
SETTLE_MS = 400
#: Views closer than this fraction of their span are the same (the aspect lock's
#: rounding is not a change worth a write).
SAME_FRACTION = 1e-9


def same_view(a: MapView | None, b: MapView | None) -> bool:
    """Whether two views show the same (every bound within :data:`SAME_FRACTION` of the
    view's width or height)."""
    if a is None or b is None:
        return a is b
    tx = SAME_FRACTION * max(a.x1 - a.x0, b.x1 - b.x0)
    ty = SAME_FRACTION * max(a.y1 - a.y0, b.y1 - b.y0)
    return (
        abs(a.x0 - b.x0) <= tx
        and abs(a.x1 - b.x1) <= tx
        and abs(a.y0 - b.y0) <= ty
        and abs(a.y1 - b.y1) <= ty
    )


class MapViewKeeper(QtCore.QObject):
    """Writes the map's settled view to the session; shows a view set on the session."""

    def __init__(self, canvas, session: Session, parent: QtCore.QObject | None = None) -> None:
        super().__init__(parent)
        self.canvas = canvas
        self.session = session
        self._storing = False
        self._timer = QtCore.QTimer(self)
        self._timer.setSingleShot(True)
        self._timer.setInterval(SETTLE_MS)
        self._timer.timeout.connect(self.store)
        canvas.vb.sigRangeChanged.connect(lambda *_: self._timer.start())
        session.subscribe(self._session_event)

    @property
    def pending(self) -> bool:
        """A view change waits to be written."""
        return self._timer.isActive()

    def store(self) -> None:
        """Write the map's view to the session now (Save as, closing, the timer)."""
        self._timer.stop()
        try:
            view = MapView.of(self.canvas.current_view())
            target = self._target()
        except ValueError:  # a view box not laid out yet (no width): nothing to keep
            return
        if same_view(view, self.session.map_view) or same_view(target, self.session.map_view):
            return  # the session's view, fitted to this window's shape: kept as it is
        self._storing = True
        try:
            self.session.set_map_view(view)
        finally:
            self._storing = False

    def _target(self) -> MapView:
        """The view the map was last asked for (before the aspect lock widened it)."""
        (x0, x1), (y0, y1) = self.canvas.vb.targetRange()
        return MapView(x0, x1, y0, y1)

    def _session_event(self, event: str, _lid: str) -> None:
        if event != "map_view" or self._storing or self.session.map_view is None:
            return
        view = self.session.map_view
        try:
            asked = self._target()
        except ValueError:
            asked = None
        if not same_view(view, asked):
            self.canvas.show_range(view.bounds())
