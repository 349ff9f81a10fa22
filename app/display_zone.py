"""View ▸ Time zone (h191, D-time-1): the window's dates in UTC, in the zone the data came in
(the import's time zone, in the layer's report and so in the project) or in this
computer's zone. The choice is kept in QSettings (``view/time_zone``) and the project (the
``time_zone`` state row); times in files and exports are unchanged (the core stores UTC).

The batch table's Start/End and their titles, the time slider, the Statistics dock and the
review Gantt follow it and name the zone (``开始 (UTC+8)``). Formatting is
:mod:`wakeline.app.time_text`'s.
"""

from PySide6 import QtGui

from wakeline.app import time_text

#: The translation context of the texts here (the main window's ``tr``).
TR_CONTEXT = "MainWindow"
SETTING = "view/time_zone"
#: The project's state row.
STATE = "time_zone"


def install_zone_menu(w) -> None:
    """View ▸ Time zone (three exclusive choices) in ``w.menus["view"]``; ``w.zone_actions``."""
    menu = w.menus["view"].addMenu("")
    w.menus["zone"] = menu
    group = QtGui.QActionGroup(w)
    w.zone_actions = {}
    for choice in time_text.ZONE_CHOICES:
        action = QtGui.QAction("", w, checkable=True)
        action.triggered.connect(lambda _=False, c=choice: set_zone_choice(w, c))
        group.addAction(action)
        menu.addAction(action)
        w.zone_actions[choice] = action
    w.zone_choice = stored_choice(w)
    w.zone_actions[w.zone_choice].setChecked(True)
    time_text.set_display_zone(None, "UTC")  # no layer yet (a window before may have set it)


def retranslate_zone_menu(w) -> None:
    """The menu's texts in the current language."""
    tr = w.tr
    w.menus["zone"].setTitle(tr("&Time zone"))
    w.zone_actions["utc"].setText(tr("&UTC"))
    w.zone_actions["data"].setText(tr("The zone the &data came in (the import's time zone)"))
    w.zone_actions["local"].setText(tr("This &computer's zone"))


def stored_choice(w) -> str:
    """The settings' choice (:data:`~wakeline.app.time_text.DEFAULT_ZONE_CHOICE` when none
    or unknown)."""
    value = w.settings.value(SETTING)
    return value if value in time_text.ZONE_CHOICES else time_text.DEFAULT_ZONE_CHOICE


def data_zone(w) -> str | None:
    """The time zone the active layer's data came in: its import's (or, for a step's
    layer, its source layer's); else the one UTC offset its times were written with
    (``time_zone_written``: a file of ``…-05:00`` times showed UTC, operator test 10);
    None when there is none or its times carry several ("mixed": UTC)."""
    if getattr(w, "active", None) is None:
        return None
    try:
        layer = w.session.root(w.active)
    except (KeyError, AttributeError):
        return None
    report = (layer.meta or {}).get("report") or {} if layer is not None else {}
    if not isinstance(report, dict):
        return None
    zone = report.get("time_zone")
    if not zone or str(zone).upper() == "UTC":
        zone = report.get("time_zone_written")
    return None if not zone or str(zone).upper() in ("UTC", "MIXED") else str(zone)


def set_zone_choice(w, choice: str, store: bool = True, force: bool = True) -> None:
    """View ▸ Time zone ▸ ``choice``: kept (settings and project when ``store``), shown:
    every date drawn again, or (``force`` false) only when the zone shown changes."""
    if choice not in time_text.ZONE_CHOICES:
        choice = time_text.DEFAULT_ZONE_CHOICE
    w.zone_choice = choice
    action = w.zone_actions[choice]
    was = action.blockSignals(True)
    action.setChecked(True)
    action.blockSignals(was)
    if store:
        w.settings.setValue(SETTING, choice)
        project = getattr(w, "project", None)
        if project is not None:
            project.put_state(STATE, choice)
    apply_zone(w, force=force)


def apply_zone(w, force: bool = False) -> bool:
    """Show dates in the zone of ``w.zone_choice`` for the active layer (its data's zone
    may differ from the last layer's); True when the zone changed and what shows dates was
    redrawn."""
    start = None
    view = w.views.get(w.active) if getattr(w, "active", None) else None
    if view is not None and len(view.summary):
        import pandas as pd

        first = pd.to_datetime(view.summary["start"], utc=True).min()
        start = None if pd.isna(first) else first.value / 1e9
    zone, label = time_text.zone_for(getattr(w, "zone_choice", "utc"), data_zone(w), start)
    if not force and (zone, label) == (time_text.display_zone(), time_text.zone_label()):
        return False
    time_text.set_display_zone(zone, label)
    redraw(w)
    return True


def redraw(w) -> None:
    """Every date the window shows, again in the display zone."""
    from wakeline.app.models import display_text

    for view in list(getattr(w, "views", {}).values()):
        if view is not None and view.text and len(view.summary):
            fresh = display_text(view.summary)
            view.text["start"], view.text["end"] = fresh["start"], fresh["end"]
    model = getattr(w, "batch_model", None)
    if model is not None:
        view = w.views.get(w.active) if getattr(w, "active", None) else None
        if view is not None:
            model.set_summary(view.summary, view.text, view.extra.get("table_index"))
        n = model.columnCount()
        if n:
            from PySide6 import QtCore

            model.headerDataChanged.emit(QtCore.Qt.Orientation.Horizontal, 0, n - 1)
    panel = getattr(w, "time_panel", None)
    if panel is not None:
        panel._update_labels()
    if hasattr(w, "_update_stats"):
        w._update_stats()
    review = getattr(w, "review", None)
    for bound in getattr(review, "queues", {}).values():
        bound.gantt.retranslate()
