"""Built-in parameter presets (session 29, h215): core.presets' registry, the command
line's ``--preset`` and ``wakeline presets``, and the guidance's suggestion rules."""

import dataclasses
import json
import re

import numpy as np
import pandas as pd
import pytest

from conftest import SHARED_REAL
from wakeline.app.cli import build_parser, main
from wakeline.core import geo
from wakeline.core.compress import CompressParams
from wakeline.core.errors import InputError
from wakeline.core.maneuver import ManeuverParams
from wakeline.core.pipeline import STEPS, Pipeline
from wakeline.core.presets import (
    SuggestInputs,
    apply_preset,
    menu_table,
    noise_floor_ratio,
    preset,
    preset_pipeline,
    presets,
    retired_note,
    suggest_from,
    suggest_inputs,
    suggested_presets,
)

#: Every parameter class a preset may change, by the pipeline's key.
CLASSES = {key: cls for step in STEPS.values() for key, cls in step.params}


def test_the_registry_holds_the_two_measured_presets():
    assert list(presets()) == ["noisy-tracks", "paper"]
    for p in presets().values():
        assert p.title and p.purpose and p.evidence
        assert "docs/evaluation.md" in p.evidence or p.name == "paper"
    assert preset("noisy-tracks").changes == {"maneuver": {"confirm_z": 4.0, "confirm_grow": 4}}


#: slow-radar's note (session 31, h247: its values are the defaults, the preset removed).
SLOW_NOTE = "slow-radar: this preset was retired, its values (radius_s 15, edge_s 12) are now the defaults; nothing changed"


def test_slow_radar_is_retired_its_name_taken_with_a_note_and_no_change():
    """Session 31 (h241) made slow-radar's radius_s 15 + edge_s 12 the defaults (gated by
    step_noise_max 0.15); the preset is removed (h247) and its name still taken: a note,
    nothing changed (not even another preset's values the menu would set back)."""
    assert "slow-radar" not in presets()
    assert retired_note("slow-radar") == retired_note("Slow radar scans (3-7 s)") == SLOW_NOTE
    assert retired_note("noisy-tracks") is None and retired_note("quiet") is None
    p = preset("slow-radar")
    assert p.changes == {} and p.name == "slow-radar"
    noisy = ManeuverParams().replace(confirm_z=4.0, confirm_grow=4, radius_s=9.0)
    for step in STEPS.values():
        before = {
            **step.defaults(),
            **({"maneuver": noisy} if "maneuver" in step.defaults() else {}),
        }
        assert apply_preset("slow-radar", before) == before
    assert preset_pipeline(Pipeline.default(), "slow-radar") == Pipeline.default()
    table = {"maneuver": {"confirm_z": 4.0, "confirm_grow": 4}}
    assert menu_table("slow-radar", table) == {} == menu_table("slow-radar")


@pytest.mark.parametrize("name", ["noisy-tracks", "paper"])
def test_every_change_names_a_field_and_applies_over_the_defaults(name):
    p = preset(name)
    assert p.changes, "a preset changes something"
    for key, values in p.changes.items():
        assert key in CLASSES, key
        fields = {f.name for f in dataclasses.fields(CLASSES[key])}
        assert set(values) <= fields
        default = CLASSES[key]()
        # each change is a change (no value equal to the default's)
        assert all(getattr(default, n) != v for n, v in values.items())
    for step in STEPS.values():
        before = step.defaults()
        after = apply_preset(name, before)
        for key, value in after.items():
            changes = p.changes.get(key, {})
            for f in dataclasses.fields(value):
                want = changes.get(f.name, getattr(before[key], f.name))
                assert getattr(value, f.name) == want, (key, f.name)
            assert value.problems() == []
        # the defaults themselves are unchanged
        assert step.defaults() == before


def test_the_defaults_are_unchanged_by_the_registry():
    presets()
    assert ManeuverParams().confirm_z == 0.0 and ManeuverParams().confirm_grow == 0
    assert ManeuverParams().radius_s == 15.0 and ManeuverParams().edge_s == 12.0  # session 31
    assert ManeuverParams().step_noise_max == 0.15
    assert CompressParams().refine is True


def test_the_paper_preset_is_each_steps_paper_parameters():
    out = apply_preset("paper", {"maneuver": ManeuverParams(), "compress": CompressParams()})
    assert out["maneuver"] == ManeuverParams.paper()
    assert out["compress"] == CompressParams.paper()
    assert set(preset("paper").changes) == {k for k, c in CLASSES.items() if hasattr(c, "paper")}


def test_an_unknown_preset_is_refused_with_the_names():
    with pytest.raises(InputError, match="noisy-tracks, paper"):
        preset("quiet")
    assert preset("Noisy tracks").name == "noisy-tracks"  # its title, any case


def test_the_menus_table_sets_the_other_presets_fields_back_to_their_defaults():
    table = menu_table("noisy-tracks")
    assert table["maneuver"]["confirm_z"] == 4.0
    assert table["maneuver"]["radius_s"] == ManeuverParams().radius_s == 15.0
    assert table["maneuver"]["edge_s"] == ManeuverParams().edge_s == 12.0
    assert table["maneuver"]["window_s"] == ManeuverParams().window_s  # the paper's, undone
    assert table["compress"]["refine"] is True
    paper = menu_table("paper")
    assert paper["maneuver"]["window_s"] == 0.0 and paper["maneuver"]["confirm_z"] == 0.0


def test_a_preset_pipeline_changes_every_stage_it_names():
    pipe = preset_pipeline(Pipeline.default(), "noisy-tracks")
    (clean_name, clean), (name, params) = pipe.stages
    assert clean == Pipeline.default().stages[0][1]
    assert params["maneuver"].confirm_z == 4.0 and params["maneuver"].confirm_grow == 4
    assert params["maneuver"].replace(confirm_z=0.0, confirm_grow=0) == ManeuverParams()
    assert params["compress"] == CompressParams()


# -- the command line ---------------------------------------------------------------------


def _track_file(tmp_path, dt=10.0, n=120, sigma=0.0, batch="1", sensor="S1", seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(n) * dt
    heading = np.where(t < t[n // 2], 0.0, np.pi / 2)
    v = 10 * geo.KN_MS
    x = np.cumsum(v * np.sin(heading) * dt) + rng.normal(0, sigma, n) if sigma else None
    y = np.cumsum(v * np.cos(heading) * dt) + rng.normal(0, sigma, n) if sigma else None
    if x is None:
        x = np.cumsum(v * np.sin(heading) * dt)
        y = np.cumsum(v * np.cos(heading) * dt)
    lon, lat = geo.from_local(x, y, 11.0, 57.0)
    pts = pd.DataFrame(
        {
            "sensor": sensor,
            "batch": batch,
            "time": pd.to_datetime(1.6e9 + t, unit="s", utc=True),
            "lon": lon,
            "lat": lat,
        }
    )
    path = tmp_path / "track.csv"
    from wakeline.core.io import write_points

    write_points(pts, path)
    return path, pts


def _report_params(tmp_path, argv):
    rep = tmp_path / "r.json"
    assert main([*argv, "--report", str(rep)]) == 0
    return json.loads(rep.read_text(encoding="utf-8"))["params"]


@pytest.mark.parametrize("step", ["maneuvers", "compress"])
def test_preset_on_a_step_command_and_a_flag_over_it(tmp_path, step):
    src, _ = _track_file(tmp_path)
    out = str(tmp_path / "out.csv")
    base = [step, str(src), "-o", out]
    plain = _report_params(tmp_path, base)["maneuver"]
    assert plain["confirm_z"] == 0.0
    got = _report_params(tmp_path, [*base, "--preset", "noisy-tracks"])["maneuver"]
    assert got["confirm_z"] == 4.0 and got["confirm_grow"] == 4
    assert {k: v for k, v in got.items() if k not in ("confirm_z", "confirm_grow")} == {
        k: v for k, v in plain.items() if k not in ("confirm_z", "confirm_grow")
    }
    over = _report_params(tmp_path, [*base, "--preset", "noisy-tracks", "--confirm-z", "3"])
    assert over["maneuver"]["confirm_z"] == 3.0 and over["maneuver"]["confirm_grow"] == 4
    over = _report_params(tmp_path, [*base, "--preset", "noisy-tracks", "--set", "confirm_grow=0"])
    assert over["maneuver"]["confirm_z"] == 4.0 and over["maneuver"]["confirm_grow"] == 0


@pytest.mark.parametrize("step", ["maneuvers", "compress"])
def test_the_retired_slow_radar_on_a_step_command_is_a_note_and_no_change(tmp_path, capsys, step):
    src, _ = _track_file(tmp_path)
    base = [step, str(src), "-o", str(tmp_path / "out.csv")]
    plain = _report_params(tmp_path, base)
    capsys.readouterr()
    assert _report_params(tmp_path, [*base, "--preset", "slow-radar"]) == plain
    err = capsys.readouterr().err
    assert err.count(SLOW_NOTE) == 1 and "unknown" not in err and "invalid" not in err
    # flags still apply over it
    over = _report_params(tmp_path, [*base, "--preset", "slow-radar", "--set", "edge_s=0"])
    assert over["maneuver"]["edge_s"] == 0.0 and over["maneuver"]["radius_s"] == 15.0


def test_paper_preset_on_compress_is_the_paper_flag(tmp_path):
    src, _ = _track_file(tmp_path)
    base = ["compress", str(src), "-o", str(tmp_path / "o.csv")]
    assert _report_params(tmp_path, [*base, "--preset", "paper"]) == _report_params(
        tmp_path, [*base, "--paper"]
    )


def test_preset_flag_only_where_a_preset_changes_the_step():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command").choices
    for name, step in STEPS.items():
        has = any(a.dest == "preset" for a in sub[name]._actions)
        keys = {key for key, _ in step.params}
        assert has == any(set(p.changes) & keys for p in presets().values()), name
    for name in ("batch", "evaluate"):
        assert any(a.dest == "preset" for a in sub[name]._actions)


def test_presets_command_and_preset_list(capsys):
    assert main(["presets"]) == 0
    out = capsys.readouterr().out
    with pytest.raises(SystemExit) as exc:
        main(["maneuvers", "--preset", "list"])  # no input needed
    assert exc.value.code == 0
    assert capsys.readouterr().out == out
    for p in presets().values():
        assert p.name in out and p.purpose in out and p.evidence in out


def test_unknown_preset_on_the_command_line(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["maneuvers", "x.csv", "-o", "y.csv", "--preset", "quiet"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "noisy-tracks" in err and "slow-radar" not in err  # the retired one not offered


def test_presets_help_and_list_do_not_offer_slow_radar(capsys):
    assert main(["presets"]) == 0
    assert "slow-radar" not in capsys.readouterr().out
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command").choices
    for name in ("maneuvers", "batch", "evaluate"):
        flag = next(a for a in sub[name]._actions if a.dest == "preset")
        assert "slow-radar" not in flag.help and "slow-radar" not in list(flag.choices)
        assert "slow-radar" in flag.choices  # still taken


def test_batch_print_pipeline_with_the_retired_slow_radar_is_the_default(capsys):
    assert main(["batch", "--print-pipeline"]) == 0
    plain = capsys.readouterr().out
    assert main(["batch", "--print-pipeline", "--preset", "slow-radar"]) == 0
    got = capsys.readouterr()
    assert got.out == plain and got.err.count(SLOW_NOTE) == 1


def test_batch_print_pipeline_with_a_preset(capsys):
    assert main(["batch", "--print-pipeline", "--preset", "noisy-tracks"]) == 0
    data = json.loads(capsys.readouterr().out)
    compress = next(s for s in data["steps"] if s["step"] == "compress")
    assert compress["params"]["maneuver"]["confirm_z"] == 4.0
    assert main(["batch", "--print-pipeline"]) == 0
    data = json.loads(capsys.readouterr().out)
    compress = next(s for s in data["steps"] if s["step"] == "compress")
    assert compress["params"]["maneuver"]["confirm_z"] == 0.0


def test_evaluate_maneuver_takes_the_preset_under_its_flags(capsys):
    from wakeline.app.cli_evaluate import _maneuver_params

    parser = build_parser()
    args = parser.parse_args(["evaluate", "maneuver", "--preset", "noisy-tracks"])
    mp = _maneuver_params(args)
    assert mp.confirm_z == 4.0 and mp.confirm_grow == 4
    args = parser.parse_args(
        ["evaluate", "maneuver", "--preset", "noisy-tracks", "--confirm-z", "3"]
    )
    assert _maneuver_params(args).confirm_z == 3.0
    args = parser.parse_args(["evaluate", "maneuver", "--preset", "slow-radar"])  # retired
    assert _maneuver_params(args) == ManeuverParams()
    assert capsys.readouterr().err.count(SLOW_NOTE) == 1
    assert _maneuver_params(parser.parse_args(["evaluate", "maneuver"])) == ManeuverParams()
    assert main(["evaluate", "fuse", "--preset", "noisy-tracks"]) == 2
    assert "--preset applies to evaluate maneuver" in capsys.readouterr().err


# -- the suggestions -----------------------------------------------------------------------


def _names(pts):
    return [s.name for s in suggested_presets(pts)]


def test_noisy_tracks_suggested_where_the_noise_floor_exceeds_the_threshold(tmp_path):
    # 1 s plots at 15 m noise, 10 kn: the first scale's floor is several times t
    noisy = pd.concat(
        [_track_file(tmp_path, dt=1.0, n=900, sigma=15.0, batch=str(s), seed=s)[1] for s in (1, 2)]
    )
    assert noise_floor_ratio(noisy) > 1
    assert "noisy-tracks" in _names(noisy)
    # the same ships with 2 m noise: no suggestion
    clean = pd.concat(
        [_track_file(tmp_path, dt=1.0, n=900, sigma=2.0, batch=str(s), seed=s)[1] for s in (1, 2)]
    )
    assert noise_floor_ratio(clean) < 1
    assert "noisy-tracks" not in _names(clean)


def test_nothing_suggested_for_clean_radar_at_3_to_7_s_since_slow_radar_retired(tmp_path):
    """Until session 31 slow-radar was suggested for 3-7 s data not AIS; its values are the
    defaults now and it is removed: clean plots at any rate suggest nothing, noisy ones at
    3-7 s still suggest noisy-tracks."""
    for dt in (2.0, 4.0, 5.0, 6.5, 10.0):
        _, pts = _track_file(tmp_path, dt=dt, sensor="radar", batch="7")
        assert _names(pts) == [], dt
    for dt in (4.0, 5.0):
        noisy = pd.concat(
            [
                _track_file(
                    tmp_path, dt=dt, n=400, sigma=40.0, sensor="radar", batch=str(s), seed=s
                )[1]
                for s in (1, 2)
            ]
        )
        assert noise_floor_ratio(noisy) > 1, dt
        assert _names(noisy) == ["noisy-tracks"], dt
    for interval in (3.0, 4.0, 5.0, 7.0):
        inputs = SuggestInputs(noise_deg=1.0, interval_s=interval, ais=False)
        assert suggest_from(inputs, 15.0) == []


@pytest.mark.skipif(not SHARED_REAL.exists(), reason="shared real sets not present")
def test_on_the_real_sets_noisy_fires_on_mtad_not_on_the_ais_sets():
    from wakeline.core import real_sets
    from wakeline.core.evaluate_real import read_track_files

    for pts in (
        real_sets.read_greece(SHARED_REAL / "greece-ais-annotated"),
        real_sets.read_dma(SHARED_REAL / "dma-single-ship"),
        real_sets.read_oresund(SHARED_REAL / "oresund-encounters"),
    ):
        assert _names(pts) == []
    mtad = read_track_files(SHARED_REAL / "mtad-dtwcm" / "original", None)[0]
    assert _names(mtad) == ["noisy-tracks"]
    radar, _ = real_sets.read_autoferry(SHARED_REAL / "autoferry-fusion", exclusive=True)
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
    from sampling_sweep import decimate

    # the radar at 1.68 s and at 5 s (where slow-radar was suggested until session 31)
    assert "slow-radar" not in _names(radar) + _names(decimate(radar, 5))


# -- the parameter panel ---------------------------------------------------------------------


def _panel(qtbot):
    pytest.importorskip("pytestqt")
    from wakeline.app.params_panel import ParamsPanel

    panel = ParamsPanel()
    qtbot.addWidget(panel)
    panel.retranslate()
    return panel


def test_the_panels_built_in_presets_menu_applies_and_logs(qtbot):
    panel = _panel(qtbot)
    assert panel.builtin.text() == "Built-in presets"
    assert panel.builtin.menu() is panel.builtin_menu
    actions = panel.builtin_menu.actions()
    assert [a.text() for a in actions] == [p.title for p in presets().values()]
    for a, p in zip(actions, presets().values(), strict=True):
        assert a.toolTip().startswith(p.purpose) and p.evidence in a.toolTip()
    said, changed = [], []
    panel.message.connect(said.append)
    panel.changed.connect(changed.append)
    panel.builtin_actions["noisy-tracks"].trigger()
    mp = panel.params("maneuver")
    assert (mp.confirm_z, mp.confirm_grow) == (4.0, 4)
    assert said[-1].startswith("Built-in preset “Noisy tracks” applied: ")
    assert "confirm_z 0 → 4" in said[-1] and "confirm_grow 0 → 4" in said[-1]
    assert "maneuver" in changed  # the project is told, as for an edit
    panel.from_dict({"maneuver": {"threshold_deg": 20.0}})  # the operator's own value
    panel.apply_builtin("noisy-tracks")
    assert said[-1] == "Built-in preset “Noisy tracks”: every value was already set"
    # the retired slow-radar (a caller naming it): its note, nothing changed
    before = panel.to_dict()
    n_changed = len(changed)
    assert panel.apply_builtin("slow-radar") == []
    assert said[-1] == SLOW_NOTE and panel.to_dict() == before and len(changed) == n_changed
    panel.apply_builtin("paper")
    assert panel.params("maneuver") == ManeuverParams.paper().replace(threshold_deg=20.0)
    assert panel.params("compress") == CompressParams.paper()
    panel.reset()
    assert panel.params("maneuver") == ManeuverParams()


def test_the_built_in_presets_in_chinese(qtbot):
    from PySide6 import QtWidgets

    from wakeline.app import core_text, i18n

    panel = _panel(qtbot)
    app = QtWidgets.QApplication.instance()
    translator = i18n.install(app, "zh_CN", None)
    said = []
    panel.message.connect(said.append)
    han = re.compile(r"[\u4e00-\u9fff]")
    english = re.compile(r"[A-Za-z_]{3,}")
    try:
        core_text.set_language("zh_CN")
        panel.retranslate()
        assert panel.builtin.text() == "内置预设"
        for name, action in panel.builtin_actions.items():
            p = preset(name)
            for text, en in ((action.text(), p.title), (action.toolTip(), p.purpose)):
                assert han.search(text) and en not in text, text
            # what stays English in a tooltip: identifiers, the sets' names, the doc's
            # section titles (after docs/evaluation.md)
            head = action.toolTip().split("docs/evaluation.md")[0]
            words = {w for w in english.findall(head) if "_" not in w}
            words -= {"Autoferry", "MTAD", "DMA", "AIS", "paper"}
            assert not words, (name, words)
        panel.apply_builtin("noisy-tracks")
        assert (
            said[-1].startswith("已应用内置预设“噪声大的航迹”：") and "confirm_z 0 → 4" in said[-1]
        )
        panel.apply_builtin("slow-radar")  # retired: its note in Chinese
        assert said[-1].startswith("slow-radar：") and han.search(said[-1])
        # English only in the preset's and the parameters' own names
        allowed = ("slow", "radar", "radius_s", "edge_s")
        assert not {w for w in english.findall(said[-1]) if w not in allowed}
    finally:
        core_text.set_language("en")
        i18n.install(app, "en", translator)


def test_the_guidance_suggests_the_preset_that_suits_the_layer(qtbot, tmp_path):
    from wakeline.core.tracks import track_summary

    panel = _panel(qtbot)
    noisy = pd.concat(
        [_track_file(tmp_path, dt=1.0, n=900, sigma=15.0, batch=str(s), seed=s)[1] for s in (1, 2)]
    )
    panel.show_guidance(track_summary(noisy), noisy)
    text = panel.guidance.text()
    assert text.startswith("Smallest turn found for this data")
    assert "the built-in preset “Noisy tracks” finds far fewer false turns" in text
    assert "Slow radar" not in text
    # a parameter change shows the guidance again, the suggestion with it
    panel.from_dict({"maneuver": {"threshold_deg": 20.0}})
    assert "“Noisy tracks”" in panel.guidance.text()
    panel.reset()
    # clean plots every 5 s (slow-radar was suggested there until session 31): no preset
    _, slow = _track_file(tmp_path, dt=5.0, sensor="radar", batch="3")
    panel.show_guidance(track_summary(slow), slow)
    text = panel.guidance.text()
    assert text.startswith("Smallest turn found for this data")
    assert "built-in preset" not in text and "Slow radar" not in text
    _, ais = _track_file(tmp_path, dt=5.0, sensor="AIS", batch="3")
    panel.show_guidance(track_summary(ais), ais)
    assert "built-in preset" not in panel.guidance.text()
    # without points (a caller that gives none): the limit only, as before
    panel2 = _panel(qtbot)
    panel2.show_guidance(track_summary(noisy))
    assert "built-in preset" not in panel2.guidance.text()


@pytest.mark.parametrize(
    "flags, field",
    [
        (["--preset", "noisy-tracks", "--confirm-z", "0"], "confirm_z"),
        (["--preset", "noisy-tracks", "--confirm-grow", "0"], "confirm_grow"),
    ],
)
def test_evaluate_maneuver_flag_given_at_its_default_beats_the_preset(flags, field):
    """Review h216: a flag given at the default's value still applies over the preset, as
    on the step commands (`maneuvers --preset noisy-tracks --confirm-z 0` keeps 0)."""
    from wakeline.app.cli_evaluate import _maneuver_params

    args = build_parser().parse_args(["evaluate", "maneuver", *flags])
    given = type(getattr(ManeuverParams(), field))(flags[-1])
    assert getattr(_maneuver_params(args), field) == given


def test_choosing_a_preset_keeps_the_operators_values_and_undoes_the_preset_in_effect(qtbot):
    """Review h216: choosing a preset set 14 other fields back to their defaults (every
    field any preset touches); now only another preset's values still in effect go back."""
    panel = _panel(qtbot)
    own = ManeuverParams().window_s + 7.0
    panel.from_dict({"maneuver": {"window_s": own}, "compress": {"refine": False}})
    panel.apply_builtin("noisy-tracks")
    mp = panel.params("maneuver")
    assert mp.window_s == own and (mp.confirm_z, mp.confirm_grow) == (4.0, 4)
    # refine False is the paper's value too: "Paper" is taken to be in effect there
    assert panel.params("compress").refine is True
    panel.reset()
    panel.apply_builtin("paper")
    assert panel.params("maneuver").window_s == 0.0
    panel.apply_builtin("noisy-tracks")
    expected = ManeuverParams().replace(confirm_z=4.0, confirm_grow=4)
    assert panel.params("maneuver") == expected  # the paper's fields went back
    assert panel.params("compress") == CompressParams()
    # a field that differs from both the default and the preset's value is the operator's
    panel.apply_builtin("paper")
    panel.from_dict({"maneuver": {"min_speed_kn": 0.5}})
    panel.apply_builtin("noisy-tracks")
    mp = panel.params("maneuver")
    assert mp.min_speed_kn == 0.5 and mp.window_s == ManeuverParams().window_s
    table = menu_table("paper", panel.to_dict())
    assert table["maneuver"]["confirm_z"] == 0.0  # noisy-tracks' value in effect, undone
    assert menu_table("noisy-tracks", panel.to_dict())["maneuver"] == {
        "confirm_z": 4.0,
        "confirm_grow": 4,
    }


def test_the_suggestion_is_computed_once_per_layer_off_the_gui_thread(qtbot, tmp_path, monkeypatch):
    """Review h216: the suggestion ran on the GUI thread (120 ms at 1.1 M points) on every
    layer activation and every maneuver value change. Its points part runs in the
    executor, once per layer and set of the fields it reads; a threshold change compares."""
    import threading

    from wakeline.app import params_panel
    from wakeline.app.lod_worker import LodWorker
    from wakeline.core.tracks import track_summary

    threads = []

    def counted(points, params=None):
        threads.append(threading.get_ident())
        return suggest_inputs(points, params)

    monkeypatch.setattr(params_panel, "suggest_inputs", counted)
    panel = _panel(qtbot)
    worker = LodWorker(panel)
    panel.executor = worker
    noisy = pd.concat(
        [_track_file(tmp_path, dt=1.0, n=900, sigma=15.0, batch=str(s), seed=s)[1] for s in (1, 2)]
    )
    summary = track_summary(noisy)
    panel.show_guidance(summary, noisy, "layer-1")
    assert "built-in preset" not in panel.guidance.text()  # not yet: it is computed
    qtbot.waitUntil(lambda: "“Noisy tracks”" in panel.guidance.text(), timeout=10_000)
    assert len(threads) == 1 and threads[0] != threading.get_ident()
    said = panel.guidance.text()
    for value in (31.0, 32.0, 33.0):  # the threshold: compared here, nothing recomputed
        panel.from_dict({"maneuver": {"threshold_deg": value}})
    ratio = suggest_from(suggest_inputs(noisy, panel.params("maneuver")), 33.0)[0].value
    assert f"{ratio:.1f} × the threshold" in panel.guidance.text() != said
    panel.show_guidance(summary, noisy, "layer-1")  # the layer activated again
    assert len(threads) == 1
    # a field the noise estimate reads: computed again, off the GUI thread too
    panel.from_dict({"maneuver": {"window_s": 20.0}})
    qtbot.waitUntil(lambda: len(threads) == 2, timeout=10_000)
    assert threads[1] != threading.get_ident()
    worker.wait()


def test_noisy_tracks_is_not_suggested_for_fixes_minutes_apart():
    """Between fixes over NOISY_MAX_INTERVAL_S apart the measured 'noise' is the ship's own
    motion (ATD's 30-min posits: ratio 2.4–2.7): no noisy-tracks suggestion there; the same
    ratio at a minute's interval (MTAD) suggests it."""
    from wakeline.core.presets import NOISY_MAX_INTERVAL_S, SuggestInputs, suggest_from

    def names(interval_s: float) -> list[str]:
        inputs = SuggestInputs(noise_deg=40.0, interval_s=interval_s, ais=True)
        return [s.name for s in suggest_from(inputs, 15.0)]

    assert names(65.0) == ["noisy-tracks"]
    assert names(NOISY_MAX_INTERVAL_S) == ["noisy-tracks"]
    assert names(1762.0) == []


def test_a_collapsed_groups_rows_made_on_expanding_show_values_set_before(qtbot):
    """The tree makes a collapsed group's rows when it is first expanded (h253): a preset,
    a value and the language set before then are in the rows it makes."""
    from wakeline.app import core_text

    panel = _panel(qtbot)
    compress = panel.root.child("compress")
    resample = panel.root.child("clean", "resample")
    rows = {p.name(): next(iter(p.items)) for p in (compress, resample)}
    assert all(item.childCount() == 0 for item in rows.values())  # not made yet
    panel.apply_builtin("paper")
    panel.from_dict({"clean": {"resample": {"max_gap_s": 77.0}}})
    assert panel.params("compress") == CompressParams.paper()
    try:
        core_text.set_language("zh_CN")
        panel.retranslate()
        for group in (compress, resample):
            group.setOpts(expanded=True)
            item = rows[group.name()]
            assert item.isExpanded()
            assert item.childCount() == len(group.children()) > 0
            for k, param in enumerate(group.children()):
                row = item.child(k)
                assert row.param is param
                assert row.widget.toolTip() == param.opts["tip"]
                assert row.text(0) == param.title()
                assert fn_eq(row.widget.value(), param.value())
            assert item.childCount() == len(group.children())  # made once
            group.setOpts(expanded=False)
            group.setOpts(expanded=True)
            assert item.childCount() == len(group.children())
        assert resample.child("max_gap_s").value() == 77.0
        values = panel.params("compress")
        for param in compress.children():
            assert param.value() == getattr(values, param.name())
        # an edit in a row made late reaches the panel's values
        param = next(p for p in compress.children() if p.type() == "float")
        row = rows["compress"].child(compress.children().index(param))
        row.widget.setValue(getattr(values, param.name()) + 1.0)
        assert getattr(panel.params("compress"), param.name()) == getattr(values, param.name()) + 1
    finally:
        core_text.set_language("en")
        panel.retranslate()


def fn_eq(a, b) -> bool:
    return a == b or (isinstance(a, float) and isinstance(b, float) and abs(a - b) < 1e-9)
