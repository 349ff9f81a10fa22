"""Export ▸ "As it came in": the active layer written in the layout of the file its data
came from (issue 19), with no questions but the file name.

The main window calls :func:`export_as_it_came_in` from its Export menu; everything else
(finding the layout through the layer's lineage, target ids, the members table) is the
engine's (:mod:`wakeline.core.io.export_like`).
"""

from pathlib import Path

from PySide6 import QtWidgets

from wakeline.core.errors import InputError
from wakeline.core.io.export_like import export_like, layer_layout


def export_as_it_came_in(
    parent: QtWidgets.QWidget | None,
    layers,
    name: str,
    path: str | Path | None = None,
    log=None,
) -> dict | None:
    """Write layer ``name`` of ``layers`` (name → :class:`~wakeline.core.project.Layer`)
    in the layout it came in. Asks for the file when ``path`` is None (suggesting the
    original's name and suffix); a problem goes to a warning dialog and ``log`` (a
    callable taking one line). Returns the export report, or None when nothing was
    written."""
    try:
        layout = layer_layout(layers, name)
    except InputError as exc:
        _fail(parent, str(exc), log)
        return None
    if path is None:
        src = Path(layout.source) if layout.source else Path(name + ".csv")
        suggestion = f"{name.replace(' · ', '_')}{src.suffix or '.csv'}"
        path, _ = QtWidgets.QFileDialog.getSaveFileName(
            parent,
            parent.tr("Export as it came in") if parent else "Export as it came in",
            suggestion,
            f"{layout.name} ({layout.encoding}) (*{src.suffix or '.csv'});;All files (*)",
        )
        if not path:
            return None
    try:
        report = export_like(layers[name].points, layout, path)
    except (InputError, OSError) as exc:
        _fail(parent, str(exc), log)
        return None
    if log:
        line = f"exported {name} as {layout.name} ({layout.encoding}) to {path}"
        if report["members"]:
            line += f"; members of merged targets in {report['members']}"
        log(line)
    return report


def _fail(parent, text: str, log) -> None:
    if log:
        log(f"Error: {text}")
    QtWidgets.QMessageBox.warning(parent, "Export failed", text)
