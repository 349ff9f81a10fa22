"""File ▸ Load ship names…: a vessel table (ship names and types by MMSI) joined to a
layer's points (:mod:`wakeline.core.io.vessels`), in the worker; the batch table's Name
and Type columns, the map's labels and the ``name:`` filter show them."""

from pathlib import Path

from PySide6 import QtWidgets

from wakeline.app.core_text import shown
from wakeline.app.layer_names import shown_name
from wakeline.core.session import BEARING_KIND


class VesselsMixin:
    """The main window's ship-name loading (a mixin of :class:`MainWindow`)."""

    TR_CONTEXT = "MainWindow"

    #: A vessel table to join to the source layers once the files being read are in
    #: (``wakeline gui --vessels FILE``).
    vessels_after_load: Path | None = None

    def load_vessels_dialog(self) -> None:
        """File ▸ Load ship names…: a vessel table joined to the active layer."""
        if self.active is None or self.session.get(self.active) is None:
            self.tell(self.tr("Load ship names"), self.tr("Open a track file first."))
            return
        path, _ = QtWidgets.QFileDialog.getOpenFileName(
            self,
            self.tr("Load ship names"),
            "",
            self.tr("Vessel tables (*.csv *.txt *.tsv *.gz);;All files (*)"),
        )
        if path:
            self.load_vessels(Path(path), [self.active])

    def load_vessels(self, path: Path, layer_ids: list[str] | None = None) -> int | None:
        """Read the vessel table ``path`` and join it to layers ``layer_ids`` (default: the
        active one) by their ship ids, in the worker; the layers' points get ``name`` and
        ``ship_type`` (saved in the project as any change of a layer)."""
        from wakeline.app.layer_view import prepare_view
        from wakeline.core.io.vessels import join_vessels, read_vessels

        ids = [
            i
            for i in (layer_ids if layer_ids is not None else [self.active])
            if i is not None
            and self.session.get(i) is not None
            and self.session.get(i).kind != BEARING_KIND
        ]
        if not ids:
            return None
        todo = []
        for lid in ids:
            layer, old = self.session.get(lid), self.views.get(lid)
            colors = old.colors if old is not None and layer.kind == "source" else None
            todo.append((lid, layer, layer.points, colors or None))
        view, size_px = self.canvas.current_view(), self.canvas.plot_size_px()

        def job(progress):
            progress(0.0, "reading the vessel table")
            table = read_vessels(path)
            out = []
            for k, (lid, layer, points, colors) in enumerate(todo):
                progress(k / len(todo), "joining the ship names")
                joined, join = join_vessels(points, table)
                lv = prepare_view(
                    joined, layer.kind, layer.color, layer.name, view, size_px, colors=colors
                )
                out.append((lid, points, lv, join))
            return ("vessels", path, table, out)

        return self._start("vessels", job, ("vessels", path))

    def _apply_vessels(self, path: Path, table, results: list) -> None:
        """The joined layers swapped in (a layer changed meanwhile is left as it is)."""
        self.log_message(f"{path.name}: {shown(table.report())}")
        for lid, points, view, join in results:
            layer = self.session.get(lid)
            if layer is None or layer.points is not points:
                self.log_message(
                    self.tr("{0}: the layer changed meanwhile; ship names not joined").format(
                        path.name
                    )
                )
                continue
            self._pending_views = {(layer.step, layer.role): view}
            if lid == self.active:
                self._restore_selection = self.selected_keys() or None
            try:
                self.session.replace_points(lid, view.points)
            finally:
                self._pending_views = {}
            self.log_message(f"{shown_name(layer.name)}: {shown(join.report())}")
        if table.bad:
            self.statusBar().showMessage(
                self.tr("{0}: some rows of the vessel table were not used (see the log)").format(
                    path.name
                ),
                8000,
            )

    def _vessels_after_import(self, layer_ids: list[str]) -> None:
        """``--vessels``: the table joined to the layers just read (once)."""
        path, self.vessels_after_load = self.vessels_after_load, None
        if path is not None and layer_ids:
            self.load_vessels(path, layer_ids)
