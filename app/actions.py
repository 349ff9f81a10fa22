"""The main window's actions, menus and toolbar, and their texts in the current language."""

from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.app import i18n
from wakeline.app.display_zone import install_zone_menu, retranslate_zone_menu

STEPS = ("clean", "maneuvers", "compress", "associate", "fuse")
#: The stages the operator may add to Run ▸ pipeline after Clean, in their order.
PIPELINE_CHOICES = ("compress", "associate")
#: The translation context of the texts here: :func:`retranslate` calls the window's ``tr``.
TR_CONTEXT = "MainWindow"


def build_actions(w) -> None:
    """Create ``w.actions_``, ``w.menus``, ``w.lang_actions`` and the toolbar."""
    style = w.style()
    sp = QtWidgets.QStyle.StandardPixmap
    a = {}

    def act(key, slot, icon=None, shortcut=None, checkable=False):
        a[key] = QtGui.QAction(style.standardIcon(icon), "", w) if icon else QtGui.QAction("", w)
        a[key].setCheckable(checkable)
        if shortcut is not None:
            a[key].setShortcut(shortcut)
        (a[key].toggled if checkable else a[key].triggered).connect(slot)

    keys = QtGui.QKeySequence.StandardKey
    act("open", w.open_dialog, sp.SP_DialogOpenButton, keys.Open)
    act("open_bearings", w.open_bearings_dialog)
    act("open_project", w.open_project_dialog)
    act("load_vessels", w.load_vessels_dialog)
    # Ctrl+S: a project followed is saved as it changes (the status bar says so and
    # where); Save as is its own action (h181 D-ui-1).
    act("save", w.save_or_say_saved, None, keys.Save)
    act("save_project", w.save_project_dialog, sp.SP_DialogSaveButton, keys.SaveAs)
    act("close_project", w.close_project)
    act("export_csv", lambda: w.export_dialog("csv"))
    act("export_geojson", lambda: w.export_dialog("geojson"))
    act("export_maneuvers", lambda: w.export_dialog("maneuvers"))
    act("export_as_came_in", lambda: w.export_dialog("as_came_in"))
    act("export_map", lambda: w.export_map_image())
    act("quit", w.close, None, keys.Quit)
    act("pipeline", lambda: w.run_step("pipeline"), sp.SP_MediaPlay)
    for stage in PIPELINE_CHOICES:  # the stages Run ▸ pipeline runs after Clean
        act(f"pipeline_{stage}", lambda on, s=stage: w.set_pipeline_stage(s, on), checkable=True)
    for step in STEPS:
        act(step, lambda _=False, s=step: w.run_step(s))
    act("save_pipeline", lambda: w._pipeline_dialog(True))
    act("load_pipeline", lambda: w._pipeline_dialog(False))
    act("cancel", w.cancel_jobs, sp.SP_BrowserStop)
    act("fit", lambda: w.canvas.fit(), sp.SP_TitleBarMaxButton, "Home")
    act("zoom_selection", w.zoom_to_selection, None, "Z")
    act("box", lambda on: set_map_mode(w, "box", on), checkable=True, shortcut="B")
    act("measure", lambda on: set_map_mode(w, "measure", on), checkable=True)
    act("find", lambda: focus_filter(w), None, keys.Find)
    act("play", lambda: toggle_play(w), None, "Space")
    act("step_back", lambda: w.time_panel.step(-1), None, "Left")
    act("step_forward", lambda: w.time_panel.step(1), None, "Right")
    a["pipeline"].setShortcut(QtGui.QKeySequence("F5"))
    act("remove_layer", w.remove_active_layer)
    act("layer_color", lambda: w.choose_layer_color())
    act("layer_up", lambda: w.move_layer(None, -1))
    act("layer_down", lambda: w.move_layer(None, 1))
    act("active_on_top", w.set_active_on_top, checkable=True)
    # How the map tells ships and layers apart (h227): kept in the settings.
    act("color_by_track", w.set_color_by_track, checkable=True)
    act("show_removed", w.set_show_removed, checkable=True)
    act("draw_points", w.set_draw_as_points, checkable=True)
    for key, setting, default in (
        ("color_by_track", "map/color_by_track", True),
        ("show_removed", "map/show_removed", False),
        ("active_on_top", "map/active_on_top", True),
    ):
        a[key].blockSignals(True)
        a[key].setChecked(w.map_option(setting, default))
        a[key].blockSignals(False)
    a["draw_points"].setEnabled(False)  # a layer's own choice: set with the active layer
    act("import_report", w.show_import_report)
    act("about", w.show_about)
    act("docs", w.open_documentation)
    w.actions_ = a
    # The keys of the map and the time panel (h225 item 11): Space, Left/Right and Home
    # act while the map or the time panel has the focus, never in a text field or a
    # table (where they edit, or move the current row).
    scoped = QtCore.Qt.ShortcutContext.WidgetWithChildrenShortcut
    for key in ("play", "step_back", "step_forward", "fit"):
        a[key].setShortcutContext(scoped)
        w.canvas.addAction(a[key])
        w.time_panel.addAction(a[key])
    # Esc leaves the map's measuring mode (and Box zoom).
    esc = QtGui.QShortcut(QtGui.QKeySequence("Esc"), w.canvas, context=scoped)
    esc.activated.connect(lambda: (a["measure"].setChecked(False), a["box"].setChecked(False)))
    w.canvas.measured = lambda text: w.statusBar().showMessage(text, 30000)
    w.filter_edit.returnPressed.connect(w.select_filter_match)

    m = {k: QtWidgets.QMenu(w) for k in ("file", "export", "run", "stages", "view", "lang", "help")}
    w.menus = m
    for key in (
        "open",
        "open_bearings",
        "load_vessels",
        "open_project",
        "save",
        "save_project",
        "close_project",
    ):
        m["file"].addAction(a[key])
    m["file"].addMenu(m["export"])
    for key in (
        "export_as_came_in",
        "export_csv",
        "export_geojson",
        "export_maneuvers",
        "export_map",
    ):
        m["export"].addAction(a[key])
    m["file"].addSeparator()
    m["file"].addAction(a["quit"])
    m["run"].addAction(a["pipeline"])
    m["run"].addMenu(m["stages"])
    for stage in PIPELINE_CHOICES:
        m["stages"].addAction(a[f"pipeline_{stage}"])
    m["run"].addSeparator()
    for step in STEPS:
        m["run"].addAction(a[step])
    m["run"].addSeparator()
    m["run"].addAction(a["save_pipeline"])
    m["run"].addAction(a["load_pipeline"])
    m["run"].addSeparator()
    m["run"].addAction(a["cancel"])
    for key in ("fit", "zoom_selection", "box", "measure", "find"):
        m["view"].addAction(a[key])
    m["view"].addSeparator()
    for key in ("play", "step_back", "step_forward"):
        m["view"].addAction(a[key])
    m["view"].addSeparator()
    for key in ("remove_layer", "layer_color", "layer_up", "layer_down", "import_report"):
        m["view"].addAction(a[key])
    m["view"].addSeparator()
    for key in ("color_by_track", "draw_points", "show_removed", "active_on_top"):
        m["view"].addAction(a[key])
    m["view"].addSeparator()
    for dock in w.docks.values():
        m["view"].addAction(dock.toggleViewAction())
    m["view"].addSeparator()
    install_zone_menu(w)  # View ▸ Time zone (h191)
    group = QtGui.QActionGroup(w)
    w.lang_actions = {}
    for code, label in i18n.LANGUAGES.items():
        lang = QtGui.QAction(label, w, checkable=True)
        lang.triggered.connect(lambda _=False, c=code: w.set_language(c))
        group.addAction(lang)
        m["lang"].addAction(lang)
        w.lang_actions[code] = lang
    act("keys", lambda: show_keys(w))
    m["help"].addAction(a["docs"])
    m["help"].addAction(a["keys"])
    m["help"].addAction(a["about"])
    for key in ("file", "run", "view", "lang", "help"):
        w.menuBar().addMenu(m[key])
    w.toolbar = w.addToolBar("main")
    w.toolbar.setObjectName("toolbar")
    toolbar_keys = ("open", "save_project", None, "pipeline", *STEPS, "cancel", None)
    for key in (*toolbar_keys, "fit", "zoom_selection", "box", "measure"):
        if key is None:
            w.toolbar.addSeparator()
        else:
            w.toolbar.addAction(a[key])
    # Zoom to selection and Measure: icons of their own, no text beside them (the toolbar
    # stays as wide as before at 1366 px; the tooltip gives the action's name).
    for key, draw in (("zoom_selection", _draw_zoom_selection), ("measure", _draw_measure)):
        a[key].setIcon(_drawn_icon(draw))
        button = w.toolbar.widgetForAction(a[key])
        if button is not None:
            button.setToolButtonStyle(QtCore.Qt.ToolButtonStyle.ToolButtonIconOnly)


def _drawn_icon(draw) -> QtGui.QIcon:
    """A 32 px icon drawn by ``draw(painter)`` in the palette's text colour."""
    pix = QtGui.QPixmap(32, 32)
    pix.fill(QtCore.Qt.GlobalColor.transparent)
    painter = QtGui.QPainter(pix)
    painter.setRenderHint(QtGui.QPainter.RenderHint.Antialiasing)
    color = QtWidgets.QApplication.palette().color(QtGui.QPalette.ColorRole.WindowText)
    painter.setPen(QtGui.QPen(color, 2.5))
    draw(painter, color)
    painter.end()
    return QtGui.QIcon(pix)


def _draw_zoom_selection(painter, color) -> None:
    """A magnifier over a short track (orange, the selection's halo)."""
    painter.save()
    painter.setPen(QtGui.QPen(QtGui.QColor(255, 150, 0), 3))
    painter.drawPolyline([QtCore.QPointF(5, 17), QtCore.QPointF(10, 11), QtCore.QPointF(16, 15)])
    painter.restore()
    painter.drawEllipse(QtCore.QRectF(3, 3, 18, 18))
    painter.drawLine(QtCore.QPointF(19, 19), QtCore.QPointF(29, 29))


def _draw_measure(painter, color) -> None:
    """A dashed line between two crosses, as the map draws a measure."""
    for x, y in ((6, 26), (26, 6)):
        painter.drawLine(QtCore.QPointF(x - 4, y), QtCore.QPointF(x + 4, y))
        painter.drawLine(QtCore.QPointF(x, y - 4), QtCore.QPointF(x, y + 4))
    pen = QtGui.QPen(QtGui.QColor("#d62728"), 2.5, QtCore.Qt.PenStyle.DashLine)
    painter.setPen(pen)
    painter.drawLine(QtCore.QPointF(6, 26), QtCore.QPointF(26, 6))


def set_map_mode(w, mode: str, on: bool) -> None:
    """Box zoom and Measure are map modes: one at a time (the other unchecks)."""
    other = "measure" if mode == "box" else "box"
    if on and w.actions_[other].isChecked():
        w.actions_[other].setChecked(False)
    if mode == "box":
        w.canvas.set_box_zoom(on)
    else:
        w.canvas.set_measure(on)


def focus_filter(w) -> None:
    """Ctrl+F: the batch table's filter, its text selected (shown first if hidden)."""
    w.docks["batches"].show()
    w.docks["batches"].raise_()
    w.filter_edit.setFocus(QtCore.Qt.FocusReason.ShortcutFocusReason)
    w.filter_edit.selectAll()


def toggle_play(w) -> None:
    """Space: play or pause the time panel."""
    panel = w.time_panel
    if panel.is_playing:
        panel.pause()
    else:
        panel.play()


#: The keys Help ▸ Keyboard shortcuts lists besides the menus' (action key, text key).
KEY_ACTIONS = (
    "pipeline",
    "fit",
    "zoom_selection",
    "box",
    "measure",
    "find",
    "play",
    "step_back",
    "step_forward",
    "open",
    "save",
    "save_project",
)


def keys_text(w) -> str:
    """Help ▸ Keyboard shortcuts: every action with a key, in the window's language."""
    rows = []
    native = QtGui.QKeySequence.SequenceFormat.NativeText
    for key in KEY_ACTIONS:
        action = w.actions_[key]
        seq = action.shortcut().toString(native)
        if seq:
            rows.append((seq, action.text().replace("&", "")))
    rows.append(("Esc", w.tr("Leave Measure or Box zoom")))
    rows.append(("Enter", w.tr("In the filter: select the first match and show it on the map")))
    rows.append(("J / K, A / R / S", w.tr("Review: next / previous, accept / reject / split")))
    lines = [f"<tr><td><b>{html_escape(k)}</b></td><td>{html_escape(t)}</td></tr>" for k, t in rows]
    note = w.tr(
        "Space, ←/→ and Home act when the map or the time panel has the focus. The filter "
        "can aim at one column: batch:4139, sensor:AIS, name:argo."
    )
    return f"<table cellspacing='6'>{''.join(lines)}</table><p>{html_escape(note)}</p>"


def html_escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def show_keys(w):
    """Help ▸ Keyboard shortcuts (non-modal; returned for tests)."""
    box = QtWidgets.QMessageBox(w)
    box.setWindowTitle(w.tr("Keyboard shortcuts"))
    box.setTextFormat(QtCore.Qt.TextFormat.RichText)
    box.setText(keys_text(w))
    box.setModal(False)
    box.show()
    return box


def pipeline_text(w) -> str:
    """Run ▸ pipeline's text: the stages it runs (``w.pipeline_stages``)."""
    tr = w.tr
    texts = {
        ("clean", "compress"): tr("Run &pipeline (clean, maneuvers, compress)"),
        ("clean", "compress", "associate"): tr(
            "Run &pipeline (clean, maneuvers, compress, associate)"
        ),
        ("clean", "associate"): tr("Run &pipeline (clean, associate)"),
        ("clean",): tr("Run &pipeline (clean)"),
    }
    return texts[tuple(w.pipeline_stages)]


def retranslate(w) -> None:
    """Set every action, menu and dock text (called again when the language changes)."""
    tr = w.tr
    texts = {
        "open": tr("&Open tracks…"),
        "open_project": tr("Open &project…"),
        "open_bearings": tr("Open &bearings (bearing-only detection)…"),
        "load_vessels": tr("Load s&hip names (vessel table)…"),
        "save": tr("&Save project"),
        "save_project": tr("Save project &as…"),
        "close_project": tr("&Close project"),
        "export_csv": tr("Active layer as &CSV…"),
        "export_geojson": tr("Active layer as &GeoJSON…"),
        "export_maneuvers": tr("&Maneuver points as CSV…"),
        "export_map": tr("Map &image (PNG)…"),
        "export_as_came_in": tr("Active layer &as it came in (layout, encoding, times)…"),
        "quit": tr("&Quit"),
        "pipeline": pipeline_text(w),
        "pipeline_compress": tr("&Compress (maneuvers and compression)"),
        "pipeline_associate": tr("&Associate (one sensor; proposals to review)"),
        "clean": tr("&Clean"),
        "maneuvers": tr("&Maneuvers"),
        "compress": tr("C&ompress"),
        "associate": tr("&Associate (one sensor)"),
        "fuse": tr("&Fuse (several sensors)"),
        "cancel": tr("Cancel the running job"),
        "save_pipeline": tr("&Save pipeline as…"),
        "load_pipeline": tr("&Load pipeline…"),
        "fit": tr("&Fit to data"),
        "zoom_selection": tr("&Zoom to selection"),
        "box": tr("&Box zoom"),
        "measure": tr("M&easure range and bearing"),
        "find": tr("Fi&nd a track (batch table filter)"),
        "play": tr("&Play / pause"),
        "step_back": tr("Step bac&k"),
        "step_forward": tr("Step forwar&d"),
        "keys": tr("&Keyboard shortcuts"),
        "remove_layer": tr("&Remove active layer"),
        "layer_color": tr("C&hoose the active layer's colour…"),
        "layer_up": tr("Move active layer &up (drawn over the layers below)"),
        "layer_down": tr("Mo&ve active layer down"),
        "active_on_top": tr("Keep the active la&yer on top"),
        "color_by_track": tr("&Colour tracks of the active layer apart (up to 30 tracks)"),
        "draw_points": tr("Dra&w active layer as points (radar plots)"),
        "show_removed": tr("Sh&ow points removed by cleaning"),
        "import_report": tr("&Import report and quarantined rows…"),
        "about": tr("&About Wakeline"),
        "docs": tr("&Documentation"),
    }
    for key, text in texts.items():
        w.actions_[key].setText(text)
    retranslate_zone_menu(w)
    menus = {
        "file": tr("&File"),
        "export": tr("&Export"),
        "run": tr("&Run"),
        "stages": tr("Pipeline s&tages"),
        "view": tr("&View"),
        "lang": tr("&Language"),
        "help": tr("&Help"),
    }
    for key, text in menus.items():
        w.menus[key].setTitle(text)
    titles = {
        "layers": tr("Layers"),
        "params": tr("Parameters"),
        "batches": tr("Batch table"),
        "detail": tr("Detail"),
        "bearing": tr("Bearing-only"),
        "stats": tr("Statistics"),
        "log": tr("Log"),
    }
    for key, title in titles.items():
        w.docks[key].setWindowTitle(title)
    w.toolbar.setWindowTitle(tr("Main toolbar"))  # its name on the toolbars' right-click menu
    export = QtCore.QCoreApplication.translate("GraphicsScene", "Export...")
    for view in w.findChildren(QtWidgets.QGraphicsView):  # the plots' right-click Export...
        for action in getattr(view.scene(), "contextMenu", None) or ():
            action.setText(export)
    w.filter_edit.setPlaceholderText(tr("Filter batches (any column, or batch:4139)…"))
    w.filter_edit.setToolTip(
        tr(
            "Plain text looks in every column; column:text in one column (batch:4139, "
            "sensor:AIS, name:argo). Enter selects the first match and shows it on the map."
        )
    )
    w.cancel_button.setText(tr("Cancel"))
    w.batch_model.set_titles(
        [
            tr("Sensor"),
            tr("Batch"),
            tr("Points"),
            tr("Start (UTC)"),
            tr("End (UTC)"),
            tr("Duration (min)"),
            tr("Length (km)"),
            tr("Speed (kn)"),
            tr("Maneuvers"),
            tr("Target"),
            tr("Status"),
            tr("Name"),
            tr("Type"),
        ],
        relative={"start": tr("Start (T+)"), "end": tr("End (T+)")},
    )
