"""The window's selection: batch-table rows and the map follow each other; the Detail
panel shows the first selected track; hover and map-image export.

Mixed into :class:`~wakeline.app.main_window.MainWindow`.
"""

from pathlib import Path

import numpy as np
from PySide6 import QtCore, QtWidgets

from wakeline.app.layer_view import maneuver_table
from wakeline.core import sorted_sets


class SelectionMixin:
    """Track selection, detail, hover and File ▸ Export map image."""

    #: The translation context of ``self.tr`` here: PySide looks a text up along
    #: ``type(self).__mro__``, which starts at the window (``MainWindow``).
    TR_CONTEXT = "MainWindow"

    def selected_keys(self) -> list[tuple[str, str]]:
        """(sensor, batch) of the selected rows, in table order. Read from the
        selection's ranges (whole rows: the table selects rows), not ``selectedRows()``,
        which asked the model for its size twice per row (1 s at 20,000 rows)."""
        ranges = self.batch_view.selectionModel().selection()
        parts = [np.arange(r.top(), r.bottom() + 1) for r in ranges if r.isValid()]
        if not parts:
            return []
        return self.batch_model.keys_of_rows(sorted_sets.distinct(np.concatenate(parts)))

    def select_tracks(self, keys: list[tuple[str, str]], add: bool = False) -> None:
        """Select rows of the batch table by (sensor, batch); the map follows. Rows next
        to each other are selected as one range (20,000 rows: one range when the table
        shows them in order, not 20,000)."""
        sel = self.batch_view.selectionModel()
        flags = QtCore.QItemSelectionModel.SelectionFlag
        selection = QtCore.QItemSelection()
        rows = self.batch_model.rows_of_keys(keys)
        if len(rows):
            cut = np.flatnonzero(np.diff(rows) != 1) + 1
            model = self.batch_model
            for a, b in zip(rows[np.r_[0, cut]], rows[np.r_[cut - 1, len(rows) - 1]], strict=True):
                selection.select(model.index(int(a), 0), model.index(int(b), 0))
        mode = flags.Select | flags.Rows
        sel.select(selection, mode if add else mode | flags.Clear)
        if len(rows):
            last = self.batch_model.rows_of_keys(keys[-1:])  # the last key's, when shown
            row = int(last[0]) if len(last) else int(rows[-1])
            self.batch_view.scrollTo(self.batch_model.index(row, 0))

    def show_name_columns(self) -> None:
        """The Name and Type columns shown when the tracks have ship names (types): a
        file's own, or a vessel table's (File ▸ Load ship names)."""
        keys = [k for k, _ in self.batch_model.COLUMNS]
        self.batch_view.setColumnHidden(keys.index("name"), not self.batch_model.has_names)
        self.batch_view.setColumnHidden(keys.index("ship_type"), not self.batch_model.has_types)

    def _reselect(self) -> None:
        """The batch table was reset (another layer's summary, a time window, a filter):
        Qt drops the rows' selection without a signal. The session's selection of the
        active layer is selected again where its rows are shown, and the map follows; the
        session keeps the tracks a window hides, selected again when it shows them."""
        self.show_name_columns()
        keys = [(s, b) for lid, s, b in self.session.selection if lid == self.active]
        if keys:
            self._selecting = True
            try:
                self.select_tracks(keys)
            finally:
                self._selecting = False

    def _table_selection_changed(self, *_args) -> None:
        view = self.views.get(self.active) if self.active else None
        if view is None:
            return
        keys = self.selected_keys()
        chosen = view.tracks(keys)
        gaps = view.draw.style.gaps if view.draw is not None else True
        west = view.draw.geometry.lon_west if view.draw is not None else -180.0
        layer = self.session.layers.get(self.active)
        if layer is not None and not layer.visible:
            # Its layer unticked: no selected track on the map nor in its legend (h181
            # D-map-2); the table keeps the selection, shown again with the layer.
            self.canvas.show_selection(chosen.iloc[:0])
        else:
            self.canvas.show_selection(chosen, maneuver_table(chosen), gaps, west)
            if not self._selecting and not getattr(self, "_from_map", False) and len(chosen):
                # h225 item 5: a track chosen in the table that is off the map is panned
                # into view (zoomed to when it would be a speck).
                self.canvas.bring_selection_into_view()
        # The Detail panel's plots follow on the next event-loop turn (its own paint).
        self._detail_key = (self.active, keys[0]) if keys else None
        if keys:
            QtCore.QTimer.singleShot(5, self._show_pending_detail)
        else:
            self.detail.clear()
        if not self._selecting:
            self.session.selection = [(self.active, s, b) for s, b in keys]
            self.project.put_state("selection", self.session.selection)

    def zoom_to_selection(self) -> None:
        self.canvas.zoom_to_selection()

    def select_filter_match(self) -> bool:
        """Enter in the batch table's filter: select the best match
        (:meth:`~wakeline.app.models.BatchTableModel.best_match_row`) and zoom the map to
        it; False when no row is shown."""
        row = self.batch_model.best_match_row()
        if row is None:
            self.statusBar().showMessage(self.tr("No track matches the filter"), 4000)
            return False
        self.select_tracks([self.batch_model.key_of_row(row)])
        self.zoom_to_selection()
        self.batch_view.setFocus(QtCore.Qt.FocusReason.OtherFocusReason)
        return True

    def export_map_image(self, path: Path | None = None) -> bool:
        """File ▸ Export map image: the map as drawn, offscreen, to PNG."""
        from wakeline.app.map_render import render_png

        if path is None:
            chosen, _ = QtWidgets.QFileDialog.getSaveFileName(
                self, self.tr("Export map image"), "map.png", "PNG (*.png)"
            )
            if not chosen:
                return False
            path = Path(chosen)
        ok = bool(render_png(self.canvas, path))
        text = self.tr("map image written to {0}") if ok else self.tr("map image not written: {0}")
        self.log_message(text.format(path))
        return ok

    def _show_pending_detail(self) -> None:
        pending, self._detail_key = self._detail_key, None
        if pending is not None and pending[0] in self.views:
            self._show_detail(*pending)

    def _show_detail(self, lid: str, key: tuple[str, str]) -> None:
        view = self.views[lid]
        man = self.session.related(lid, "maneuvers")
        comp = self.session.related(lid, "compressed")
        man_view = self.views.get(man.id) if man is not None else None
        comp_view = self.views.get(comp.id) if comp is not None else None
        factor = (man_view or view).tracks([key])
        threshold = man.meta.get("threshold_deg") if man is not None else None
        compressed = comp_view.tracks([key]) if comp_view is not None else None
        dis = None
        if comp is not None:
            dis = comp.meta.get("dis_e_by_track", {}).get(f"{key[0]}\x1f{key[1]}")
        draw = getattr(view, "draw", None)  # the band the map draws the layer in
        west = draw.geometry.lon_west if draw is not None else None
        fused = self.session.layers[lid].kind == "fused"
        self.detail.show_track(
            factor, threshold, compressed, factor, dis_e_m=dis, lon_west=west, fused=fused
        )

    def _track_clicked(self, lid: str, sensor: str, batch: str, add: bool) -> None:
        if lid not in self.session.layers:
            return  # a map layer of no session layer (the bearings): no batch to select
        if lid != self.active:
            self.select_layer(lid)
        self._from_map = True  # picked where it is drawn: the map stays where it is
        try:
            self.select_tracks([(sensor, batch)], add=add)
        finally:
            self._from_map = False
