"""Dialogs of the main window: the import report with the quarantined rows (the import
dialog itself is app/import_dialog.py)."""

import json

import pandas as pd
from PySide6 import QtCore, QtWidgets

from wakeline.app.core_text import shown
from wakeline.app.layer_names import shown_name
from wakeline.app.models import FrameModel
from wakeline.core.words import CONTEXT, render

#: Quarantined rows kept with a source layer (and in the project) for viewing.
QUARANTINE_KEPT = 10_000


def summarize(report: dict) -> str:
    """A step's report as one readable line (key figures only; nested reports flattened)."""
    parts = []
    for key, value in report.items():
        if isinstance(value, dict):
            if key in ("rules", "params", "tracks_report"):
                continue
            parts.append(f"{key}: [{summarize(value)}]")
        elif isinstance(value, bool):
            continue
        elif isinstance(value, float):
            parts.append(f"{key} {value:,.3g}" if abs(value) < 1 else f"{key} {value:,.1f}")
        elif isinstance(value, int):
            parts.append(f"{key} {value:,}")
        elif isinstance(value, str):
            parts.append(f"{key} {value}")
    return ", ".join(parts)


def translated(text) -> str:
    """A core summary (:class:`~wakeline.core.words.Text`: English with its phrases) in
    the window's language: each phrase's template through the translator (context
    ``Summary`` of the .ts file), filled with its values; a plain ``str`` as it is."""
    return render(text, lambda template: QtCore.QCoreApplication.translate(CONTEXT, template))


def step_lines(result) -> list[str]:
    """What a finished step did, as the log shows it: the step's own summary (the line
    ``wakeline STEP`` prints: where the points went, rule by rule, why nothing was paired)
    in the window's language (:func:`translated`), for a pipeline one line per stage
    (``clean: …``); the figures of :func:`summarize` where a step has no summary of its
    own. (The log puts command-line advice in the window's words:
    :meth:`MainWindow.log_message`.)"""
    from wakeline.core.pipeline import STEPS

    def one(res) -> str:
        try:
            return translated(STEPS[res.step].summary(res))
        except (KeyError, TypeError, ValueError):  # a report the summary cannot read
            return summarize(res.report)

    if result.stages:
        said = QtCore.QCoreApplication.translate("MainWindow", "{0}: {1}")  # zh "{0}：{1}"
        return [said.format(shown(res.step), one(res)) for res in result.stages]
    return [one(result)]


class ImportReportDialog(QtWidgets.QDialog):
    """A source layer's import report and its quarantined rows (line, reason, raw text)."""

    def __init__(self, layer, parent=None) -> None:
        super().__init__(parent)
        self.setWindowTitle(self.tr("Import report: {0}").format(shown_name(layer.name)))
        rep = layer.meta.get("report", {})
        text = QtWidgets.QPlainTextEdit(readOnly=True)
        text.setPlainText(json.dumps(rep, indent=2, ensure_ascii=False, default=str))
        self.table = QtWidgets.QTableView()
        rows = pd.DataFrame(layer.meta.get("quarantine", []))
        if "reason" in rows.columns:  # in the window's language (app/core_text.py)
            said = {r: shown(r) for r in rows["reason"].unique()}  # once per reason, not row
            rows["reason"] = rows["reason"].map(said)
        heads = {"line": self.tr("line"), "reason": self.tr("reason"), "text": self.tr("text")}
        self.table.setModel(FrameModel(rows.rename(columns=heads), self))
        self.table.resizeColumnsToContents()  # the reason whole, not "short row: 5 …"
        self.table.horizontalHeader().setStretchLastSection(True)
        lay = QtWidgets.QVBoxLayout(self)
        lay.addWidget(text, 1)
        lay.addWidget(
            QtWidgets.QLabel(
                self.tr("Quarantined rows ({0:,}; the first {1:,} are kept):").format(
                    int(rep.get("rows_quarantined", 0)), QUARANTINE_KEPT
                )
            )
        )
        lay.addWidget(self.table, 2)
        close = QtWidgets.QDialogButtonBox(QtWidgets.QDialogButtonBox.StandardButton.Close)
        close.rejected.connect(self.reject)
        lay.addWidget(close)
        self.resize(900, 600)
