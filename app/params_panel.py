"""The parameter panel, generated from the core's parameter dataclasses.

Every field of a :class:`~wakeline.core.params.Params` becomes an editable row with its
unit, range and tooltip (meaning and source). A value the core refuses is put back and the
reason shown. Presets are the values as JSON; the built-in presets
(:mod:`wakeline.core.presets`: measured settings for some kinds of data) are a menu beside
them, and the guidance under the tree suggests the one that suits the active layer. A resample ``max_gap_s`` set here without
``max_gap_steps`` is the gap limit, as on the command line (core.transform.stated_max_gap):
``max_gap_steps`` shows 0 and a note says why.
"""

import dataclasses
import json
import logging
import re
import weakref
from functools import lru_cache
from pathlib import Path

import pandas as pd
import shiboken6
from pyqtgraph.parametertree import Parameter, ParameterTree
from PySide6 import QtCore, QtGui, QtWidgets

from wakeline.app import core_text
from wakeline.core.associate import LinkParams
from wakeline.core.bearing import BearingParams
from wakeline.core.clean import STEPS, CleanParams
from wakeline.core.compress import CompressParams
from wakeline.core.errors import InputError
from wakeline.core.fuse import FuseParams
from wakeline.core.maneuver import (
    ManeuverParams,
    detection_limit,
)
from wakeline.core.params import Params, shown_source
from wakeline.core.pipeline import (
    PARAMS_VERSION,
    AssociateOptions,
    CompressOptions,
    FuseOptions,
    ManeuverOptions,
    params_from_version,
)
from wakeline.core.presets import (
    NOISE_FIELDS,
    SuggestInputs,
    menu_table,
    preset,
    presets,
    retired_note,
    suggest_from,
    suggest_inputs,
)
from wakeline.core.transform import stated_max_gap
from wakeline.resources import translations_dir

log = logging.getLogger(__name__)

#: A preset file's version key (its table is the panel's form, :data:`PARAMS_VERSION`).
PRESET_VERSION_KEY = "wakeline_params"

#: Lines of the texts under the tree (guidance, notes) shown at most; more scroll.
GUIDANCE_LINES = 7
#: ... and at least (the first lines of a guidance always in sight).
GUIDANCE_MIN_LINES = 3

#: Pipeline steps in order: key, title, parameter class.
GROUPS = (
    ("maneuver", "Maneuvers", ManeuverParams),
    ("compress", "Compression", CompressParams),
    ("associate", "Association, one sensor", LinkParams),
    ("fuse", "Association and fusion, several sensors", FuseParams),
    ("bearing", "Bearing-only", BearingParams),
    ("maneuver_options", "Maneuver detector", ManeuverOptions),
    ("compress_options", "Compression method", CompressOptions),
    ("associate_options", "Association mode", AssociateOptions),
    ("fuse_options", "Fusion distance and assignment", FuseOptions),
)


class TextLabel(QtWidgets.QLabel):
    """A word-wrapped label that says when its text changed (the box under the tree
    shows while one of its labels has text)."""

    changed = QtCore.Signal()

    def setText(self, text: str) -> None:  # noqa: N802 - Qt's name
        super().setText(text)
        self.changed.emit()


def panel_classes() -> list[type]:
    """Every parameter class the panel shows: the clean rules', then :data:`GROUPS`'."""
    clean = CleanParams()
    return [type(getattr(clean, step)) for step in STEPS] + [cls for _, _, cls in GROUPS]


@lru_cache(maxsize=4)
def doc_table(code: str) -> dict:
    """The parameters' help in language ``code`` (``params_<code>.json``: ``docs`` by
    "ClassName.field", ``labels`` for the tooltip's source/default/range); empty for a
    language without one. The core's ``doc`` stays English (operator test 6, D-i18n-2 c)."""
    path = translations_dir() / f"params_{code}.json"
    if not path.exists():
        return {}
    return json.loads(path.read_text(encoding="utf-8"))


#: Every field the panel shows, by "ClassName.field" (the tooltips' retranslation).
_FIELDS: dict[str, tuple[type, dataclasses.Field]] = {}

_noted: set[str] = set()  # keys already logged as missing (one note each)


def field_doc(owner: type, f: dataclasses.Field, code: str | None = None) -> str:
    """The help of ``owner``'s field ``f`` in ``code`` (the window's language by default):
    the table's entry, or the core's English with a logged note when it has none."""
    code = core_text.language() if code is None else code
    english = f.metadata.get("doc", "")
    if code == "en":
        return english
    table = doc_table(code)
    key = f"{owner.__name__}.{f.name}"
    text = table.get("docs", {}).get(key)
    if text is None:
        if table and key not in _noted:
            _noted.add(key)
            log.warning("params_%s.json has no help for %s: shown in English", code, key)
        return english
    return text


def field_title(owner: type, f: dataclasses.Field, code: str | None = None) -> str | None:
    """The row title of a field whose name is an identifier (``window_p``) in ``code``
    (the window's language by default): the table's ``titles`` entry by
    "ClassName.field", else by field name; None in English or without an entry (the
    row shows the identifier). Its identifier, shared with the command line and the
    presets, is in its tooltip's last line (operator test 7, D11)."""
    code = core_text.language() if code is None else code
    if code == "en":
        return None
    titles = doc_table(code).get("titles", {})
    return titles.get(f"{owner.__name__}.{f.name}") or titles.get(f.name)


_OURS = re.compile(r"\bours\b")
_SEED = re.compile(r"\bseed (\d{3})\b")


def field_tip(owner: type, f: dataclasses.Field, code: str | None = None) -> str:
    """A field's tooltip: its help, unit, source, default and range, in ``code``."""
    code = core_text.language() if code is None else code
    labels = doc_table(code).get("labels", {}) if code != "en" else {}
    meta = f.metadata
    unit = meta.get("unit", "")
    tip = field_doc(owner, f, code)
    if unit:
        tip += f" [{unit}]"
    if meta.get("source"):
        src = shown_source(meta["source"])
        if code != "en":  # the source's labels (the rest is a measurement, kept as written)
            src = _SEED.sub(r"种子文献 \1", _OURS.sub("本项目", src))
        tip += f"\n{labels.get('source', 'source: ')}{src}"
    tip += f"\n{labels.get('default', 'default: ')}{f.default}"
    kind = "bool" if isinstance(f.default, bool) else type(f.default).__name__
    lo, hi = meta.get("lo"), meta.get("hi")
    if kind in ("int", "float") and (lo is not None or hi is not None):
        tip += f"\n{labels.get('range', 'range: ')}{'' if lo is None else lo} … "
        tip += f"{'' if hi is None else hi}"
    if field_title(owner, f, code):  # the row says it in Chinese: its identifier here
        tip += f"\n{labels.get('name', 'name: ')}{f.name}"
    return tip


def _field_param(owner: type, f: dataclasses.Field, value) -> dict:
    meta = f.metadata
    kind = "bool" if isinstance(f.default, bool) else type(f.default).__name__
    unit = meta.get("unit", "")
    tip = field_tip(owner, f)
    opts = {"name": f.name, "type": kind, "value": value, "tip": tip, "default": f.default}
    title = field_title(owner, f)
    if title:
        opts["title"] = title
    # its tooltip in the window's language: retranslate (a plain string in the opts)
    opts["doc_key"] = f"{owner.__name__}.{f.name}"
    _FIELDS[opts["doc_key"]] = (owner, f)
    if meta.get("choices"):
        opts["type"] = "list"
        opts["limits"] = list(meta["choices"])
    if kind in ("int", "float"):
        # No spin-box limits: an out-of-range value reaches the core's validation, which
        # refuses it with the reason (a clamped value would hide the mistake).
        if unit:
            opts["suffix"] = f" {unit}"
            opts["unit"] = unit  # the suffix in the window's language: retranslate
        if kind == "float":
            opts["decimals"] = 6
    return opts


def _group(name: str, title: str, params: Params) -> dict:
    return {
        "name": name,
        "title": title,
        "type": "group",
        "children": [
            _field_param(type(params), f, getattr(params, f.name))
            for f in dataclasses.fields(params)
        ],
    }


def _seconds(value: float) -> str:
    """A time in the guidance: whole seconds, or two digits below one (GNSS at 10 Hz
    read "interval 0 s")."""
    return f"{value:.0f}" if value >= 1 else f"{value:.2g}"


def _value_text(value) -> str:
    """A parameter value in the log: numbers without a needless ".0"."""
    if isinstance(value, float) and value.is_integer():
        return str(int(value))
    return str(value)


class ReleasedParameterTree(ParameterTree):
    """pyqtgraph's :class:`ParameterTree` that lets go of its root item with its life.

    pyqtgraph's ``TreeWidget`` keeps, for the tree's whole life, a Python wrapper of its
    invisible root item. Qt made that item (it is no QObject), so PySide never learns
    that it died with the tree: the wrapper stayed registered at the freed address, and
    a C++ object later made there came back to Python as that ``QTreeWidgetItem`` (a
    pyqtgraph SpinBox's ``lineEdit()``, a plot's ``children()``: the GUI tests'
    intermittent AttributeErrors and crashes, one window's tree each). Here the wrapper
    is invalidated (forgotten by PySide, the item untouched) when the tree is destroyed.
    """

    def __init__(self, parent: QtWidgets.QWidget | None = None, showHeader: bool = True) -> None:
        super().__init__(parent, showHeader=showHeader)
        root = self._invRootItem._real_item
        # Capture the item only: the tree's own wrapper is invalid by then.
        self.destroyed.connect(lambda _obj=None, root=root: shiboken6.invalidate(root))
        self.itemExpanded.connect(self._build_rows)

    def addParameters(self, param, root=None, depth=0, showTop=True) -> None:  # noqa: N802
        """pyqtgraph's ``addParameters`` (0.14), except that a collapsed group's rows are
        made when it is first expanded (:meth:`_build_rows`): ~190 value widgets made for
        every window were ~60 % of its construction (h253). The parameters themselves
        all exist: a value, preset or title set on a group not yet expanded is in its
        parameters, and its rows show it when they are made."""
        if root is None or not param.hasChildren() or param.opts.get("expanded", True):
            super().addParameters(param, root=root, depth=depth, showTop=showTop)
            return
        item = param.makeTreeItem(depth=depth)
        root.addChild(item)
        item.treeWidgetChanged()
        item.setChildIndicatorPolicy(QtWidgets.QTreeWidgetItem.ChildIndicatorPolicy.ShowIndicator)
        item._rows_depth = depth  # its children's rows: not made yet

    def _build_rows(self, item: QtWidgets.QTreeWidgetItem) -> None:
        """A collapsed group's rows, made the first time it is expanded."""
        depth = getattr(item, "_rows_depth", None)
        if depth is None:
            return
        del item._rows_depth
        made = {id(item.child(i).param) for i in range(item.childCount())}
        for child in item.param:
            if id(child) not in made:  # (a child added since has its row already)
                self.addParameters(child, root=item, depth=depth + 1)
        item.setChildIndicatorPolicy(
            QtWidgets.QTreeWidgetItem.ChildIndicatorPolicy.DontShowIndicatorWhenChildless
        )


class ParamsPanel(QtWidgets.QWidget):
    """Tree of every pipeline parameter; emits ``changed`` with the step name."""

    changed = QtCore.Signal(str)
    refused = QtCore.Signal(str)
    #: a line for the log (a built-in preset applied: what it changed)
    message = QtCore.Signal(str)

    def __init__(self, parent: QtWidgets.QWidget | None = None) -> None:
        super().__init__(parent)
        self._values: dict[str, Params] = {}
        self._clean = CleanParams()
        self._guard = False
        self._loading = False  # a table (preset, project, pipeline) is being applied
        # Resample values set here (edited or loaded) since the start or Defaults: what the
        # operator stated, for the core's max_gap rule (core.transform.stated_max_gap).
        self._stated: set[str] = set()
        self._note_key = ""  # the note under the tree (_show_note)
        self._just_refused = ""  # a refusal said this turn (_tree_changed)
        self._summary: pd.DataFrame | None = None  # the data the guidance is about
        self._points = None  # weak reference to its points (the presets' suggestion)
        # The suggestion's points part (core.presets.suggest_inputs) by (layer, the maneuver
        # fields it reads): computed once per layer, off the GUI thread with an executor;
        # the threshold is compared here (review h216: 120 ms at 1.1 M points on every
        # layer activation and every maneuver value change).
        self._layer: object = None  # the guided layer's key (show_guidance)
        self._version = 0  # a key for points given without one
        self._inputs: dict[tuple, SuggestInputs | None] = {}
        self._pending: set[tuple] = set()
        #: ``executor(job, done)``: runs ``job()`` off the GUI thread and calls
        #: ``done(result)`` on it (the window's LodWorker); None: run here (tests).
        self.executor = None
        children = [
            {
                "name": "clean",
                "title": "Cleaning",
                "type": "group",
                "children": [
                    _group(step, step.replace("_", " "), getattr(self._clean, step))
                    for step in STEPS
                ],
            }
        ]
        for key, title, cls in GROUPS:
            self._values[key] = cls()
            children.append(_group(key, title, self._values[key]))
        self.root = Parameter.create(name="params", type="group", children=children)
        for grp in self.root.children():
            for sub in grp.children():
                if sub.hasChildren():
                    sub.setOpts(expanded=False)
            grp.setOpts(expanded=grp.name() in ("clean", "maneuver"))
        self.tree = ReleasedParameterTree(showHeader=False)
        self.tree.setParameters(self.root, showTop=False)
        self.root.sigTreeStateChanged.connect(self._tree_changed)

        self.guidance = TextLabel(wordWrap=True)
        self.guidance.setTextFormat(QtCore.Qt.TextFormat.PlainText)
        self.problem = TextLabel(wordWrap=True)
        self.problem.setStyleSheet("color: #b00020")
        self.note = TextLabel(wordWrap=True)
        self.note.setTextFormat(QtCore.Qt.TextFormat.PlainText)
        self.buttons = [QtWidgets.QPushButton() for _ in range(3)]
        save, load, reset = self.buttons
        save.clicked.connect(self._save_dialog)
        load.clicked.connect(self._load_dialog)
        reset.clicked.connect(self.reset)
        # the built-in presets: a menu of the measured settings, each one's purpose and
        # evidence in its tooltip (core.presets)
        self.builtin = QtWidgets.QPushButton()
        self.builtin_menu = QtWidgets.QMenu(self.builtin)
        self.builtin_menu.setToolTipsVisible(True)
        self.builtin_actions: dict[str, QtGui.QAction] = {}
        for name in presets():
            action = self.builtin_menu.addAction(name)
            action.triggered.connect(lambda _checked=False, n=name: self.apply_builtin(n))
            self.builtin_actions[name] = action
        self.builtin.setMenu(self.builtin_menu)
        # two by two: four in a row widened the dock (the window fits 1280 px)
        buttons = QtWidgets.QGridLayout()
        for k, b in enumerate((save, load, reset, self.builtin)):
            buttons.addWidget(b, k // 2, k % 2)
        lay = QtWidgets.QVBoxLayout(self)
        lay.setContentsMargins(2, 2, 2, 2)
        lay.addWidget(self.tree, 1)
        # The texts under the tree scroll in a box of GUIDANCE_LINES lines at most: a
        # label of their own height was cut mid-line at 1366x768 and at HiDPI, and the
        # tree shrank to 2-3 rows (operator look h225 item 13).
        texts = QtWidgets.QWidget()
        tl = QtWidgets.QVBoxLayout(texts)
        tl.setContentsMargins(0, 0, 0, 0)
        for label in (self.problem, self.note, self.guidance):
            label.setAlignment(QtCore.Qt.AlignmentFlag.AlignTop | QtCore.Qt.AlignmentFlag.AlignLeft)
            tl.addWidget(label)
        tl.addStretch(1)
        self.texts = QtWidgets.QScrollArea()
        self.texts.setWidgetResizable(True)
        self.texts.setFrameShape(QtWidgets.QFrame.Shape.NoFrame)
        self.texts.setHorizontalScrollBarPolicy(QtCore.Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.texts.setWidget(texts)
        line = self.fontMetrics().lineSpacing()
        self.texts.setMaximumHeight(GUIDANCE_LINES * line + 4)
        self.texts.setMinimumHeight(GUIDANCE_MIN_LINES * line + 4)
        lay.addWidget(self.texts)
        lay.addLayout(buttons)
        for label in (self.problem, self.note, self.guidance):
            label.changed.connect(self._texts_shown)
        self._texts_shown()

    def _texts_shown(self) -> None:
        """The box of texts under the tree only while one of them says something: the
        tree keeps the room otherwise."""
        labels = (self.problem, self.note, self.guidance)
        for label in labels:  # an empty label takes no line of the box
            label.setVisible(bool(label.text()))
        self.texts.setVisible(any(x.text() for x in labels))

    @staticmethod
    def field_titles() -> dict[str, str]:
        """The parameters whose name is one English word, titled in the current language
        beside that name ("启用 enabled"; English: the name), as the error messages name a
        column ("经度 lon"); a name with an underscore is the parameter's identifier, as
        on the command line and in a preset (operator test 6, D-i18n-2)."""
        return {
            "enabled": QtCore.QCoreApplication.translate("ParamName", "enabled"),
            "steps": QtCore.QCoreApplication.translate("ParamName", "steps"),
            "bridge": QtCore.QCoreApplication.translate("ParamName", "bridge"),
            "window": QtCore.QCoreApplication.translate("ParamName", "window"),
            "refine": QtCore.QCoreApplication.translate("ParamName", "refine"),
            "alpha": QtCore.QCoreApplication.translate("ParamName", "alpha"),
            "beta": QtCore.QCoreApplication.translate("ParamName", "beta"),
            "gamma": QtCore.QCoreApplication.translate("ParamName", "gamma"),
            "predict": QtCore.QCoreApplication.translate("ParamName", "predict"),
            "gate": QtCore.QCoreApplication.translate("ParamName", "gate"),
            "sigmas": QtCore.QCoreApplication.translate("ParamName", "sigmas"),
            "margin": QtCore.QCoreApplication.translate("ParamName", "margin"),
            "limit": QtCore.QCoreApplication.translate("ParamName", "limit"),
            "pieces": QtCore.QCoreApplication.translate("ParamName", "pieces"),
            "windows": QtCore.QCoreApplication.translate("ParamName", "windows"),
            "method": QtCore.QCoreApplication.translate("ParamName", "method"),
            "sigma": QtCore.QCoreApplication.translate("ParamName", "sigma"),
            "mode": QtCore.QCoreApplication.translate("ParamName", "mode"),
            "normalize": QtCore.QCoreApplication.translate("ParamName", "normalize"),
            "stitch": QtCore.QCoreApplication.translate("ParamName", "stitch"),
            "fill": QtCore.QCoreApplication.translate("ParamName", "fill"),
            "distance": QtCore.QCoreApplication.translate("ParamName", "distance"),
            "glr": QtCore.QCoreApplication.translate("ParamName", "glr"),
        }

    def group_titles(self) -> dict[str, str]:
        """The tree's group titles in the current language, by group name (the pipeline
        steps of :data:`GROUPS`, ``clean`` and its rules)."""
        return {
            "clean": self.tr("Cleaning"),
            "duplicates": self.tr("duplicates"),
            "stationary": self.tr("stationary"),
            "speed": self.tr("speed"),
            "turn": self.tr("turn"),
            "speed_outliers": self.tr("speed outliers"),
            "isolated": self.tr("isolated"),
            "short_tracks": self.tr("short tracks"),
            "bspline": self.tr("bspline"),
            "resample": self.tr("resample"),
            "smooth": self.tr("smooth"),
            "maneuver": self.tr("Maneuvers"),
            "compress": self.tr("Compression"),
            "associate": self.tr("Association, one sensor"),
            "fuse": self.tr("Association and fusion, several sensors"),
            "bearing": self.tr("Bearing-only"),
            "maneuver_options": self.tr("Maneuver detector"),
            "compress_options": self.tr("Compression method"),
            "associate_options": self.tr("Association mode"),
            "fuse_options": self.tr("Fusion distance and assignment"),
        }

    def group_tips(self) -> dict[str, str]:
        """The step groups' tooltips: the seed papers their methods come from (the
        titles said "(seed 000)", words for the developers, not the operator: h225 item
        13)."""
        return {
            "clean": self.tr("Cleaning (seeds 001, 003)"),
            "maneuver": self.tr("Maneuvers (seed 000)"),
            "compress": self.tr("Compression (seed 000)"),
            "associate": self.tr("Association, one sensor (seeds 001, 003)"),
            "fuse": self.tr("Association and fusion, several sensors (seed 003)"),
            "bearing": self.tr("Bearing-only (seed 002)"),
        }

    def retranslate(self) -> None:
        # the tree's (hidden) column titles: pyqtgraph's English ones were left
        self.tree.setHeaderLabels([self.tr("Parameter"), self.tr("Value")])
        titles = self.group_titles()
        tips = self.group_tips()
        fields = self.field_titles()
        for grp in self.root.children():
            grp.setOpts(title=titles.get(grp.name(), grp.opts.get("title")))
            if grp.name() in tips:
                for item in list(grp.items):  # the tree's row of the group
                    item.setToolTip(0, tips[grp.name()])
            for sub in grp.children():
                if sub.hasChildren() and sub.name() in titles:
                    sub.setOpts(title=titles[sub.name()])
        stack = [c for grp in self.root.children() for c in grp.children()]
        while stack:  # a field named by one word: titled in the language now
            item = stack.pop()
            stack += item.children()
            if item.name() in fields and item.name() not in titles:
                if item.opts.get("title") != fields[item.name()]:
                    item.setOpts(title=fields[item.name()])
        for button, text in zip(
            self.buttons,
            (self.tr("Save preset…"), self.tr("Load preset…"), self.tr("Defaults")),
            strict=True,
        ):
            button.setText(text)
        self.builtin.setText(self.tr("Built-in presets"))
        self.builtin.setToolTip(
            self.tr(
                "Measured settings for some kinds of data (options, not defaults): choosing "
                "one sets its values and puts the other built-in presets' values still in "
                "effect back to their defaults (values you set are kept); the log says what "
                "changed"
            )
        )
        for name, action in self.builtin_actions.items():
            p = preset(name)
            action.setText(core_text.shown(p.title))
            action.setToolTip(core_text.shown(p.purpose) + "\n" + core_text.shown(p.evidence))
        self._show_note(self._note_key)
        units = self.unit_texts()
        stack = list(self.root.children())
        while stack:  # every parameter with a unit: its suffix in the language now
            item = stack.pop()
            stack += item.children()
            unit = item.opts.get("unit")
            if unit and item.opts.get("suffix") != f" {units.get(unit, unit)}":
                item.setOpts(suffix=f" {units.get(unit, unit)}")
        stack = list(self.root.children())
        while stack:  # every parameter's tooltip in the language now (D-i18n-2 c)
            item = stack.pop()
            stack += item.children()
            if item.opts.get("doc_key") in _FIELDS:
                tip = field_tip(*_FIELDS[item.opts["doc_key"]])
                if item.opts.get("tip") != tip:
                    item.setOpts(tip=tip)
                if item.name() not in fields:  # an identifier: its title, or itself
                    title = field_title(*_FIELDS[item.opts["doc_key"]]) or item.name()
                    if item.opts.get("title") != title:
                        item.setOpts(title=title)
        if getattr(self, "_summary", None) is not None:  # the detection limit's paragraph
            self.show_guidance(self._summary, self._guided_points())

    def unit_texts(self) -> dict[str, str]:
        """The parameters' units as the tree shows them, in the current language (in
        Chinese the unit words 秒/米/公里/节 the rest of the window uses, operator test 8 D6)."""
        return {
            "s": self.tr("s"),
            "m": self.tr("m"),
            "km": self.tr("km"),
            "kn": self.tr("kn"),
            "m/s": self.tr("m/s"),
            "m/s²": self.tr("m/s²"),
            "points": self.tr("points"),
            "samples": self.tr("samples"),
            "fixes": self.tr("fixes"),
            "intervals": self.tr("intervals"),
            "steps": self.tr("steps"),
            "at-rest windows": self.tr("at-rest windows"),
            "deg": self.tr("deg"),
            "sigma": self.tr("sigma"),
            "windows": self.tr("windows"),
            "doublings": self.tr("doublings"),
        }

    # -- values --------------------------------------------------------------------

    def clean_params(self) -> CleanParams:
        return self._clean

    def params(self, key: str) -> Params:
        return self._values[key]

    def keys(self) -> list[str]:
        """The parameter sets the panel holds (besides ``clean``)."""
        return list(self._values)

    def to_dict(self) -> dict[str, dict]:
        out = {"clean": {s: dataclasses.asdict(getattr(self._clean, s)) for s in STEPS}}
        for key, value in self._values.items():
            out[key] = dataclasses.asdict(value)
        return out

    def from_dict(self, data: dict) -> list[str]:
        """Apply values (e.g. a preset); returns the problems with values not applied."""
        problems = []
        self._loading = True
        self._show_note("")
        resample = data.get("clean", {}).get("resample")
        if isinstance(resample, dict):
            # The command line's rule, by what the table holds (an older table without
            # max_gap_steps gets 0, as with_settings gives it), whatever the order of its
            # values and whatever was edited before: what it holds is what was stated.
            data = {**data, "clean": {**data["clean"], "resample": stated_max_gap(resample)}}
            self._stated = set(data["clean"]["resample"])
        try:
            for key, values in data.items():
                if key == "clean":
                    for step, vals in values.items():
                        for name, v in vals.items():
                            problems += self._set_value(("clean", step, name), v)
                elif key in self._values:
                    for name, v in values.items():
                        problems += self._set_value((key, name), v)
                else:
                    problems.append(f"unknown parameter group {key!r}")
        finally:
            self._loading = False
        return problems

    def reset(self) -> None:
        self.from_dict(
            {
                "clean": {s: dataclasses.asdict(getattr(CleanParams(), s)) for s in STEPS},
                **{k: dataclasses.asdict(c()) for k, _, c in GROUPS},
            }
        )
        self._stated.clear()  # nothing stated: the defaults' adaptive limit again
        self.problem.setText("")  # every value is a default: the last refusal is gone

    def _set_value(self, path: tuple[str, ...], value) -> list[str]:
        try:
            p = self.root.child(*path)
        except KeyError:
            return [f"unknown parameter {'.'.join(path)}"]
        if p.value() == value:
            return []  # unchanged: no widget update (a project opens with ~100 values)
        p.setValue(value)  # goes through _tree_changed, which validates
        return [] if p.value() == value else [f"{'.'.join(path)}: {value!r} refused"]

    def _tree_changed(self, _param, changes) -> None:
        if self._guard:
            return
        for param, change, value in changes:
            if change != "value":
                continue
            path = self.root.childPath(param)
            try:
                note = self._apply(path, value)
            except InputError as exc:
                self._guard = True
                param.setValue(self._current(path))
                self._guard = False
                self.problem.setText(str(exc))
                # The spin box echoes the refused value back once more in the same turn
                # (pyqtgraph: widget -> param): one refusal, one log line (h181 D-params-2).
                if self._just_refused != str(exc):
                    self._just_refused = str(exc)
                    QtCore.QTimer.singleShot(0, self._forget_refusal)
                    self.refused.emit(str(exc))
            else:
                self.problem.setText("")
                self._show_note("" if self._loading else note)
                if path[0] == "maneuver" and self._summary is not None:
                    # its window and threshold changed
                    self.show_guidance(self._summary, self._guided_points())
                self.changed.emit(path[0])

    def _forget_refusal(self) -> None:
        self._just_refused = ""

    def _current(self, path: list[str]):
        if path[0] == "clean":
            return getattr(getattr(self._clean, path[1]), path[2])
        return getattr(self._values[path[0]], path[1])

    def _show_note(self, key: str) -> None:
        """The note under the tree: ``key`` names it ("" for none), so that a language
        switch can write it again."""
        self._note_key = key
        self.note.setText(
            self.tr(
                "resample: max_gap_steps is now 0, so the max_gap_s you set is the gap limit "
                "on every track (as with --max-gap). Set max_gap_steps to use the adaptive "
                "limit again."
            )
            if key == "max_gap_steps"
            else ""
        )

    def _apply(self, path: list[str], value) -> str:
        """Take a value (:class:`InputError` when the core refuses it); returns the key of
        a note on what else it changed ("" for nothing; :meth:`_show_note`)."""
        if path[0] != "clean":
            new = self._values[path[0]].replace(**{path[1]: value})
            new.checked()
            self._values[path[0]] = new
            return ""
        changes = {path[2]: value}
        if path[1] == "resample":  # the command line's rule for a stated max_gap_s
            stated = {name: self._current(["clean", "resample", name]) for name in self._stated}
            changes = stated_max_gap({**stated, **changes})
        step = getattr(self._clean, path[1]).replace(**changes)
        new = dataclasses.replace(self._clean, **{path[1]: step})
        new.checked()
        old, self._clean = getattr(self._clean, path[1]), new
        if path[1] != "resample":
            return ""
        self._stated.add(path[2])
        ruled = [n for n in changes if n != path[2] and getattr(step, n) != getattr(old, n)]
        self._guard = True  # the values the rule changed, shown
        try:
            for name in ruled:
                self.root.child("clean", "resample", name).setValue(getattr(step, name))
        finally:
            self._guard = False
        return "max_gap_steps" if "max_gap_steps" in ruled else ""

    # -- presets -------------------------------------------------------------------

    def save_preset(self, path: str | Path) -> None:
        data = {PRESET_VERSION_KEY: PARAMS_VERSION, **self.to_dict()}
        Path(path).write_text(json.dumps(data, indent=2) + "\n", encoding="utf-8")

    def load_preset(self, path: str | Path) -> list[str]:
        try:
            data = json.loads(Path(path).read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise InputError(f"{path}: not a parameter preset ({exc})") from None
        if not isinstance(data, dict):
            raise InputError(f"{path}: not a parameter preset")
        version = data.pop(PRESET_VERSION_KEY, 1)  # none before max_window_s's meaning changed
        if not isinstance(version, int):
            raise InputError(f"{path}: not a parameter preset (version {version!r})")
        return self.from_dict(params_from_version(data, version))

    def _save_dialog(self) -> None:
        path, _ = QtWidgets.QFileDialog.getSaveFileName(
            self, self.tr("Save preset"), "", "JSON (*.json)"
        )
        if path:
            self.save_preset(path)

    def _load_dialog(self) -> None:
        path, _ = QtWidgets.QFileDialog.getOpenFileName(
            self, self.tr("Load preset"), "", "JSON (*.json)"
        )
        if not path:
            return
        try:
            problems = self.load_preset(path)
        except InputError as exc:
            QtWidgets.QMessageBox.warning(self, self.tr("Cannot load preset"), str(exc))
            return
        if problems:
            QtWidgets.QMessageBox.warning(
                self, self.tr("Preset loaded with problems"), "\n".join(problems)
            )

    def apply_builtin(self, name: str) -> list[str]:
        """Apply the built-in preset ``name`` (:func:`wakeline.core.presets.menu_table`: its
        values; another built-in preset's values back at their defaults where they are still
        that preset's; the rest, and the operator's own values, kept);
        the log is told what changed. Returns the problems (values not applied). A retired
        preset's name (core.presets.RETIRED): its note, nothing changed."""
        note = retired_note(name)
        if note:
            self.message.emit(core_text.shown(note))
            return []
        p = preset(name)
        before = self.to_dict()
        problems = self.from_dict(menu_table(p, before))
        after = self.to_dict()
        titles = self.group_titles()
        parts = []
        for key, values in after.items():
            if key == "clean":
                continue
            diff = [
                f"{field} {_value_text(before[key][field])} → {_value_text(value)}"
                for field, value in values.items()
                if before[key][field] != value
            ]
            if diff:
                parts.append(f"{titles.get(key, key)}: {', '.join(diff)}")
        title = core_text.shown(p.title)
        if parts:
            text = self.tr("Built-in preset “{0}” applied: {1}").format(title, "; ".join(parts))
        else:
            text = self.tr("Built-in preset “{0}”: every value was already set").format(title)
        if problems:
            text += " " + self.tr("Not applied: {0}").format("; ".join(problems))
        self.message.emit(text)
        return problems

    # -- guidance ------------------------------------------------------------------

    def _guided_points(self):
        return self._points() if self._points is not None else None

    def _suggest_key(self) -> tuple:
        mp = self._values["maneuver"]
        return (self._layer, tuple(getattr(mp, f) for f in NOISE_FIELDS))

    def _suggestions(self, points) -> list:
        """The built-in presets suggested for ``points`` (core.presets.suggest_from): the
        points' part (core.presets.suggest_inputs) kept by layer and the maneuver fields it
        reads, made by :attr:`executor` (off the GUI thread; none yet: no suggestion until it
        arrives, then the guidance is shown again); the threshold compared here."""
        if points is None or len(points) == 0:
            return []
        key = self._suggest_key()
        if key in self._inputs:
            found = self._inputs[key]
            return (
                [] if found is None else suggest_from(found, self._values["maneuver"].threshold_deg)
            )
        mp = self._values["maneuver"]

        def job(points=points, mp=mp):
            try:
                return suggest_inputs(points, mp)
            except (InputError, KeyError, ValueError) as exc:  # no tracks to judge
                log.info("no preset suggestion: %s", exc)
                return None

        if self.executor is None:
            self._store_inputs(key, job())
            return self._suggestions(points)
        if key not in self._pending:
            self._pending.add(key)
            self.executor(job, lambda found, key=key: self._inputs_arrived(key, found))
        return []

    def _store_inputs(self, key: tuple, found: SuggestInputs | None) -> None:
        if len(self._inputs) >= 16:  # a few layers' worth
            self._inputs.pop(next(iter(self._inputs)))
        self._inputs[key] = found

    def _inputs_arrived(self, key: tuple, found: SuggestInputs | None) -> None:
        self._pending.discard(key)
        if not shiboken6.isValid(self):
            return
        self._store_inputs(key, found)
        if key == self._suggest_key() and self._summary is not None:
            self.show_guidance(self._summary)  # the suggestion with it now

    def _suggestion_text(self, points) -> str:
        texts = []
        for s in self._suggestions(points):
            title = core_text.shown(preset(s.name).title)
            if s.name == "noisy-tracks":
                texts.append(
                    self.tr(
                        "The position noise is large for this sampling (the noise floor of "
                        "the first windows is {1:.1f} × the threshold on a typical track): "
                        "the built-in preset “{0}” finds far fewer false turns."
                    ).format(title, s.value)
                )
        return " ".join(texts)

    def show_guidance(
        self, summary: pd.DataFrame, points: pd.DataFrame | None = None, layer: object = None
    ) -> None:
        """Seed 000's detection limit for the loaded data: typical speed and interval
        (core.maneuver.detection_limit), or why none can be given; with the layer's
        ``points``, the built-in presets that suit them (core.presets.suggested_presets),
        kept by ``layer`` (a key that changes with the layer's points: the window gives its
        id and run; None: these points, while they live)."""
        self._summary = summary
        if points is not None:
            if layer is None and self._guided_points() is points:
                layer = self._layer  # the same points: the same layer
            elif layer is None:  # other points, no key: a new version
                self._version += 1
                layer = ("points", self._version)
            self._layer = layer
            self._points = weakref.ref(points)
        suggestion = self._suggestion_text(self._guided_points())
        self._show_limit(summary)
        if suggestion:
            text = self.guidance.text()
            self.guidance.setText(f"{text} {suggestion}" if text else suggestion)

    def _show_limit(self, summary: pd.DataFrame) -> None:
        mp = self._values["maneuver"]
        limit = detection_limit(
            summary,
            mp.window_p,
            mp.threshold_deg,
            window_s=mp.window_s,
            window_max_s=mp.window_max_s,
        )
        if limit is None:
            self.guidance.setText("")
            self.guidance.setToolTip("")
            return
        repeats = ""
        if limit.repeats:
            repeats = " " + (
                self.tr(
                    "1 row repeats an earlier row of its track (same time and position): "
                    "not counted here; Clean's duplicates rule removes it."
                )
                if limit.repeats == 1
                else self.tr(
                    "{0} rows repeat an earlier row of their track (same time and "
                    "position): not counted here; Clean's duplicates rule removes them."
                ).format(f"{limit.repeats:,}")
            )
        if limit.gap_tracks:
            # operator test 8, D5: a track spanning days of runs gave a speed over its gaps
            repeats += " " + self.tr(
                "{0} of {1} tracks span {2} h, {3:.0%} of it in long gaps: the speed is "
                "taken between the gaps; reading the file with one track per run (a column "
                "such as scenario as batch) gives tracks without them."
            ).format(
                f"{limit.gap_tracks:,}",
                f"{limit.tracks:,}",
                f"{limit.gap_span_s / 3600:,.1f}",
                limit.gap_share,
            )
        # The operator's words in the text; the seed paper's (its window of p points,
        # "detection limit") in the tooltip (operator look h225 item 13).
        if limit.reason is not None:
            reason = core_text.shown(limit.reason)
            self.guidance.setText(
                self.tr("Smallest turn found for this data: none can be given: {0}.").format(reason)
                + repeats
            )
            self.guidance.setToolTip(
                self.tr("Detection limit (seed 000): none for this data: {0}.").format(reason)
            )
            return
        if not limit.eps_m >= 1.0:
            # "position errors up to 0 m" promised nothing (operator test 8, D5)
            errors = self.tr(
                "A {0:.0f}° turn stands out only from position errors under 1 m ({1:.2f} m) at "
                "this speed and leg"
            ).format(mp.threshold_deg, limit.eps_m)
        else:
            errors = self.tr(
                "A {0:.0f}° turn stands out from position errors up to {1:.0f} m"
            ).format(mp.threshold_deg, limit.eps_m)
        self.guidance.setText(
            self.tr(
                "Smallest turn found for this data: {0:.1f}° with 100 m position errors "
                "(median speed {1:.1f} kn, interval {2} s). {3}."
            ).format(limit.turn_deg, limit.speed_kn, _seconds(limit.interval_s), errors)
            + repeats
        )
        self.guidance.setToolTip(
            self.tr(
                "Detection limit (seed 000) for this data: median speed {0:.1f} kn, "
                "interval {1} s, legs of p = {2} points ({3} s). {4}; with 100 m errors the "
                "smallest turn found is {5:.1f}°."
            ).format(
                limit.speed_kn,
                _seconds(limit.interval_s),
                limit.window_p,
                _seconds(limit.leg_s),
                errors,
                limit.turn_deg,
            )
        )
