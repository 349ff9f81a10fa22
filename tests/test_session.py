"""The session model (layers by id with lineage), the step registry shared by the CLI and
the session, and the incremental project file."""

import json
import os
import shutil
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest

from wakeline.app.cli import main
from wakeline.core import simulate
from wakeline.core.errors import InputError
from wakeline.core.io import read_points, write_points
from wakeline.core.maneuver import ManeuverParams, _scales
from wakeline.core.pipeline import STEPS, Pipeline, params_from_json, params_to_json
from wakeline.core.project import ProjectWriter, load_project, save_project
from wakeline.core.session import Session


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    """A small two-sensor scene written as canonical CSV, and its points as read back."""
    path = tmp_path_factory.mktemp("scene") / "scene.csv"
    write_points(simulate.multisensor_scene(seed=3, n_ships=6, area_km=30.0), path)
    return path, read_points(path).points


def test_layers_by_id_with_lineage_and_rerun_replaces_only_its_own(scene):
    _, points = scene
    s = Session()
    events = []
    s.subscribe(lambda e, lid: events.append((e, lid)))
    a = s.add_layer("scene.csv", "source", points)
    b = s.add_layer("scene.csv", "source", points.head(500))  # same display name
    assert a.id != b.id and [e for e, _ in events] == ["added", "added"]

    cleaned = s.apply_result(a.id, s.run_step(a.id, "clean"), STEPS["clean"].defaults())[0]
    assert (cleaned.parent, cleaned.step, cleaned.role) == (a.id, "clean", "cleaned")
    assert cleaned.params["clean"]["speed"]["v_max_kn"] > 0
    comp_src = s.apply_result(a.id, s.run_step(a.id, "compress"))
    comp_cln = s.apply_result(cleaned.id, s.run_step(cleaned.id, "compress"))
    # Compress of the cleaned layer did not replace the one compressed from the source.
    assert {lay.id for lay in comp_src}.isdisjoint({lay.id for lay in comp_cln})
    assert s.root(comp_cln[-1].id).id == a.id
    n = len(s.layers)
    again = s.apply_result(a.id, s.run_step(a.id, "compress"))
    assert [lay.id for lay in again] == [lay.id for lay in comp_src] and len(s.layers) == n
    assert ("changed", comp_src[0].id) in events
    # The maneuver layer that goes with a compressed layer is its sibling.
    assert s.related(comp_cln[-1].id, "maneuvers").id == comp_cln[0].id
    # A step asked for on a maneuvers layer reads its parent (operator test: Compress
    # with the maneuvers layer active made "… · maneuvers · maneuvers"); lineage too.
    assert s.step_input(comp_cln[0].id) == cleaned.id
    assert s.step_input(cleaned.id) == cleaned.id and s.step_input(a.id) == a.id
    assert s.ancestors(comp_cln[-1].id) == [cleaned.id, a.id] and s.ancestors(a.id) == []
    assert s.sources_of(comp_cln[-1].id) == {a.id} and s.sources_of(a.id) == {a.id}
    # Results of a second input coexist.
    s.apply_result(b.id, s.run_step(b.id, "clean"))
    assert (
        s.find(b.id, "clean", "cleaned") is not None and s.find(a.id, "clean", "cleaned") is cleaned
    )


def test_pipeline_applies_stage_by_stage(scene):
    _, points = scene
    s = Session()
    src = s.add_layer("scene", "source", points)
    pipe = Pipeline.default()
    made = s.apply_result(src.id, pipe.run(points))
    roles = [(lay.role, s.get(lay.parent).role or "source") for lay in made]
    assert roles == [("cleaned", "source"), ("maneuvers", "cleaned"), ("compressed", "cleaned")]
    back = Pipeline.from_json(pipe.to_json())
    assert params_to_json(back.stages[0][1]) == params_to_json(pipe.stages[0][1])
    with pytest.raises(InputError, match="not a Wakeline pipeline"):
        Pipeline.from_json("{}")


def test_a_version_1_pipeline_runs_the_windows_it_ran():
    # version 1 (before h79): max_window_s was "double while within"; 600 s from 10 s
    # windows ran 10 ... 320 s, which max_window_s = 320 s means now
    def read(version, **maneuver):
        steps = [{"step": "compress", "params": {"maneuver": maneuver}}]
        text = json.dumps({"wakeline_pipeline": version, "steps": steps})
        return Pipeline.from_json(text).stages[0][1]["maneuver"]

    assert read(1, max_window_s=600.0).max_window_s == 320.0
    assert _scales(read(1, max_window_s=600.0)) == _scales(ManeuverParams())
    assert read(1, window_s=8.0, max_window_s=600.0).max_window_s == 512.0
    assert read(1, window_s=8.0, max_window_s=320.0).max_window_s == 256.0
    assert read(1, max_window_s=0.0).max_window_s == 0.0
    assert read(1, window_s=0.0, max_window_s=600.0).max_window_s == 600.0  # one scale anyway
    assert read(2, max_window_s=600.0).max_window_s == 600.0
    assert json.loads(Pipeline.default().to_json())["wakeline_pipeline"] == 2


def test_a_project_saved_before_params_had_a_version_runs_the_windows_it_ran(tmp_path):
    # projects keep the panel's parameter table; one saved before the params_version row
    # (version 1) meant max_window_s 600 s as the ladder 10 ... 320 s
    s = Session()
    s.params = {"maneuver": {"window_s": 10.0, "max_window_s": 600.0}, "compress": {}}
    path = tmp_path / "p.wakeline"
    save_project(s, path)
    assert load_project(path).params["maneuver"]["max_window_s"] == 600.0  # saved today
    with sqlite3.connect(path) as con:
        con.execute("DELETE FROM state WHERE key = 'params_version'")
    con.close()
    back = load_project(path)
    assert back.params["maneuver"]["max_window_s"] == 320.0
    assert back.params["compress"] == {} and "params_version" not in back.state
    with sqlite3.connect(path) as con:
        con.execute("INSERT INTO state VALUES ('params_version', '\"two\"')")
    con.close()
    with pytest.raises(InputError, match="damaged"):
        load_project(path)
    with sqlite3.connect(path) as con:  # not even JSON: damaged, not read as version 1
        con.execute("UPDATE state SET json = 'two' WHERE key = 'params_version'")
    con.close()
    with pytest.raises(InputError, match="damaged"):
        load_project(path)


def test_a_version_1_table_with_a_bad_window_is_refused_by_the_parameters_not_crashed():
    # review: "x", null, [1] raised TypeError/ValueError from the translation itself (out
    # of Load preset's InputError handler, into Qt's loop), Infinity looped for ever
    from wakeline.core.pipeline import params_from_version

    for bad in ("x", None, [1], float("inf"), float("nan"), -5.0):
        table = {"maneuver": {"window_s": 10.0, "max_window_s": bad}}
        assert params_from_version(table, 1) == table  # left for the parameters' check
        steps = [{"step": "maneuvers", "params": {"maneuver": {"max_window_s": bad}}}]
        text = json.dumps({"wakeline_pipeline": 1, "steps": steps})
        with pytest.raises(InputError):
            Pipeline.from_json(text)
    table = {"maneuver": {"window_s": "ten", "max_window_s": 600.0}}
    assert params_from_version(table, 1) == table


def test_params_json_round_trip_and_refusal():
    for name, step in STEPS.items():
        data = params_to_json(step.defaults())
        assert params_to_json(params_from_json(name, data)) == data
    with pytest.raises(InputError, match="threshold_deg"):
        params_from_json("maneuvers", {"maneuver": {"threshold_deg": 500.0}})


STEP_ARGS = {
    "clean": (["--rejected", "{extra}"], "rejected"),
    "maneuvers": ([], None),
    "compress": ([], None),
    "associate": (["--pairs", "{extra}"], "pairs"),
    "fuse": (["--pairs", "{extra}"], "pairs"),
}


@pytest.mark.parametrize("name", sorted(STEP_ARGS))
def test_every_step_cli_equals_session_byte_for_byte(scene, tmp_path, name):
    """One implementation per step: the CLI's files equal the session's tables written by
    the same writers (the GUI's export)."""
    from wakeline.app.cli_steps import write_table

    path, points = scene
    extra_args, extra_table = STEP_ARGS[name]
    out, extra = tmp_path / "cli.csv", tmp_path / "cli_extra.csv"
    args = [a.replace("{extra}", str(extra)) for a in extra_args]
    assert main([name, str(path), "-o", str(out), *args]) == 0

    s = Session()
    src = s.add_layer(path.name, "source", points)
    step = STEPS[name]
    made = s.apply_result(src.id, s.run_step(src.id, name))
    layer = next(lay for lay in made if lay.role == step.primary)
    mine = tmp_path / "session.csv"
    table = layer.points if step.output == "points" else layer.tables[step.output]
    write_table(step.output, table, mine)
    assert mine.read_bytes() == out.read_bytes()
    if extra_table:
        write_table(extra_table, layer.tables[extra_table], tmp_path / "s_extra.csv")
        assert (tmp_path / "s_extra.csv").read_bytes() == extra.read_bytes()


def test_generated_flags_reach_the_parameters(scene, tmp_path):
    path, _ = scene
    out = tmp_path / "m.csv"
    rep = tmp_path / "r.json"
    assert (
        main(["maneuvers", str(path), "-o", str(out), "--threshold", "30", "--report", str(rep)])
        == 0
    )
    assert '"threshold_deg": 30.0' in rep.read_text()
    assert main(["maneuvers", str(path), "-o", str(out), "--threshold-deg", "999"]) == 2
    assert main(["associate", str(path), "-o", str(out), "--set", "nope=1"]) == 2


def test_incremental_project_writes_small_rows_and_reopens(scene, tmp_path):
    _, points = scene
    s = Session()
    src = s.add_layer("scene", "source", points)
    s.apply_result(src.id, s.run_step(src.id, "clean"))
    path = tmp_path / "p.wakeline"
    save_project(s, path, {"note": [1, 2, 3, 4]})
    errors = []
    writer = ProjectWriter(path, errors.append)
    cleaned = s.find(src.id, "clean", "cleaned")
    cleaned.visible = False
    writer.submit(lambda st: st.put_layer(cleaned, 1, with_data=False))
    writer.submit(lambda st: st.put_state("selection", [(cleaned.id, "R1", "3")]))
    writer.submit(lambda st: st.add_decision({"action": "accept", "proposal": 1}))
    assert writer.flush(10)
    writer.close()
    assert errors == []
    back = load_project(path)
    assert [lay.id for lay in back.layers] == [src.id, cleaned.id]
    assert back.layers[1].visible is False and back.layers[1].parent == src.id
    assert back.selection == [(cleaned.id, "R1", "3")] and back.state["note"] == [1, 2, 3, 4]
    assert back.decisions == [{"action": "accept", "proposal": 1}]
    assert "rejected" in back.layers[1].tables
    s2 = back.to_session()
    assert s2.root(cleaned.id).id == src.id and s2.new_id() not in s2.layers


def test_every_write_is_in_the_project_file_itself(scene, tmp_path):
    """Operator test: with WAL the committed work sat in a ``-wal`` side file, so a copy
    of the ``.wakeline`` made while it was open held one layer of four, and a project
    renamed while open lost what was written before and after. Now a copy taken after a
    flush is complete, and a write after a rename fails with a message (nothing is
    written to a file nobody opens)."""
    _, points = scene
    s = Session()
    src = s.add_layer("scene", "source", points)
    path = tmp_path / "p.wakeline"
    save_project(s, path)
    errors = []
    writer = ProjectWriter(path, errors.append)
    cleaned = s.apply_result(src.id, s.run_step(src.id, "clean"))[0]
    writer.submit(lambda st: st.put_layer(cleaned, 1))
    writer.submit(lambda st: st.add_decision({"action": "accept", "proposal": 1}))
    assert writer.flush(10) and errors == []
    copy = tmp_path / "copy.wakeline"
    shutil.copyfile(path, copy)  # the file alone, as a user copies it to a stick
    assert [lay.id for lay in load_project(copy).layers] == [src.id, cleaned.id]
    assert load_project(copy).decisions == [{"action": "accept", "proposal": 1}]
    assert not Path(f"{path}-wal").exists()
    moved = tmp_path / "moved.wakeline"
    path.rename(moved)
    writer.submit(lambda st: st.add_decision({"action": "reject", "proposal": 2}))
    assert writer.flush(10)
    writer.close()
    assert len(errors) == 1 and "moved, renamed or removed" in str(errors[0])
    assert not path.exists()  # no new, empty project at the old name
    back = load_project(moved)
    assert [lay.id for lay in back.layers] == [src.id, cleaned.id]
    assert back.decisions == [{"action": "accept", "proposal": 1}]


def test_a_project_left_in_wal_mode_opens_from_a_read_only_folder(scene, tmp_path, monkeypatch):
    """A project an older Wakeline (or a crash) left in WAL mode, in a folder that cannot
    be written: SQLite cannot open it there ("unable to open database file", reported as
    "not a Wakeline project"); it is read from a copy and opens read-only."""
    _, points = scene
    s = Session()
    s.add_layer("scene", "source", points)
    folder = tmp_path / "ro"
    folder.mkdir()
    path = folder / "p.wakeline"
    save_project(s, path)
    con = sqlite3.connect(path)
    con.execute("PRAGMA journal_mode=WAL")
    con.execute("PRAGMA wal_autocheckpoint=0")
    con.execute('INSERT INTO decisions (json) VALUES (\'{"action": "accept"}\')')
    con.commit()
    # The files as a crash leaves them: the decision only in the -wal file.
    shutil.copyfile(path, tmp_path / "main.bin")
    shutil.copyfile(f"{path}-wal", tmp_path / "wal.bin")
    con.close()
    shutil.copyfile(tmp_path / "main.bin", path)
    shutil.copyfile(tmp_path / "wal.bin", f"{path}-wal")
    for f in folder.glob("p.wakeline-shm"):
        f.unlink()
    folder.chmod(0o555)
    try:
        if os.access(folder, os.W_OK):  # root: SQLite's refusal there is simulated
            import wakeline.core.project as project_mod

            real = project_mod._open_read_only

            def refuse(p):
                if Path(p).parent == folder:
                    raise sqlite3.OperationalError("unable to open database file")
                return real(p)

            monkeypatch.setattr(project_mod, "_open_read_only", refuse)
            monkeypatch.setattr(project_mod.os, "access", lambda p, mode: False)
        back = load_project(path)
        assert back.read_only and back.decisions == [{"action": "accept"}]
    finally:
        folder.chmod(0o755)


def test_writer_reports_failures(tmp_path):
    errors = []
    writer = ProjectWriter(tmp_path / "gone" / "p.wakeline", errors.append)
    writer.submit(lambda st: st.put_state("x", 1))
    assert writer.flush(10)
    writer.close()
    assert len(errors) == 1


def test_damaged_and_newer_projects_give_one_message(scene, tmp_path):
    _, points = scene
    s = Session()
    s.add_layer("scene", "source", points)
    good = tmp_path / "good.wakeline"
    save_project(s, good)
    truncated = tmp_path / "truncated.wakeline"
    truncated.write_bytes(good.read_bytes()[: good.stat().st_size // 3])
    with pytest.raises(InputError):
        load_project(truncated)
    for name, sql in {
        "badlayer": "UPDATE layers SET data = x'00112233'",
        "nolayerdata": "UPDATE layers SET data = NULL",
        "badparams": "INSERT INTO params VALUES ('maneuver', '{not json')",
        "newer": "UPDATE meta SET value = '99' WHERE key = 'schema'",
    }.items():
        p = tmp_path / f"{name}.wakeline"
        p.write_bytes(good.read_bytes())
        con = sqlite3.connect(p)
        con.execute(sql)
        con.commit()
        con.close()
        with pytest.raises(InputError, match="newer" if name == "newer" else "damaged"):
            load_project(p)


@pytest.mark.skipif(os.geteuid() == 0, reason="root can write read-only files")
def test_read_only_project_is_flagged(scene, tmp_path):
    _, points = scene
    s = Session()
    s.add_layer("scene", "source", points)
    p = tmp_path / "ro.wakeline"
    save_project(s, p)
    p.chmod(0o444)
    assert load_project(p).read_only


def test_killed_writer_loses_at_most_the_task_in_flight(tmp_path):
    """Each write is its own transaction: a process killed after a write keeps it."""
    path = tmp_path / "k.wakeline"
    code = (
        "import os, sys\n"
        "from wakeline.core.project import ProjectWriter\n"
        f"w = ProjectWriter({str(path)!r}, print, create=True)\n"
        "w.submit(lambda st: st.add_decision({'action': 'reject', 'proposal': 7}))\n"
        "w.flush(10)\n"
        "os.kill(os.getpid(), 9)\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, timeout=60)
    assert proc.returncode != 0
    time.sleep(0.1)
    assert load_project(path).decisions == [{"action": "reject", "proposal": 7}]


def test_cancel_stops_cleaning_between_blocks(monkeypatch, scene):
    """The cleaning thread pool does not run every queued block after a cancel."""
    from wakeline.core import clean as clean_mod
    from wakeline.core.errors import Cancelled

    _, points = scene
    big = pd.concat([points.assign(batch=points["batch"] + f"_{k}") for k in range(20)])
    monkeypatch.setattr(clean_mod, "BLOCK_ROWS", len(points) // 4)
    calls = []

    def progress(fraction, text=""):
        calls.append(text)
        if len(calls) > 2:
            raise Cancelled()

    t0 = time.perf_counter()
    with pytest.raises(Cancelled):
        clean_mod.clean(big, progress=progress)
    assert time.perf_counter() - t0 < 5
    _, index = clean_mod.sorted_with_index(big)
    assert len(clean_mod._blocks(index, len(points) // 4)) > 10


def test_step_outputs_may_not_overwrite_the_input(scene, tmp_path):
    path, _ = scene
    assert main(["clean", str(path), "-o", str(tmp_path / "o.csv"), "--rejected", str(path)]) == 2
    out = tmp_path / "same.csv"
    assert main(["associate", str(path), "-o", str(out), "--pairs", str(out)]) == 2


def test_target_ids_are_unique_across_sensors():
    """Batch 7 of R1 and batch 7 of R2, 50 km apart, are two targets."""
    t = pd.date_range("2024-05-01", periods=20, freq="10s", tz="UTC")
    rows = []
    for sensor, lon0 in (("R1", 122.0), ("R2", 122.5)):
        for k, tt in enumerate(t):
            rows.append((sensor, "7", tt, lon0 + 0.0005 * k, 30.0))
    pts = pd.DataFrame(rows, columns=["sensor", "batch", "time", "lon", "lat"])
    out = STEPS["associate"](pts).tables["points"]
    assert out.groupby("sensor")["target"].first().to_dict() == {"R1": "R1:7", "R2": "R2:7"}


def test_save_as_never_waits_for_the_previous_writer_on_the_calling_thread(
    scene, tmp_path, monkeypatch
):
    """Operator test: a second Save as 0.2 s after the first blocked the window 1 s (the
    old file's writer was joined on the GUI thread). Now the new writer waits for it in
    its own thread; both files are whole, the same file saved twice too."""
    pytest.importorskip("PySide6")
    import wakeline.app.project_controller as pc
    from wakeline.app.project_controller import ProjectController

    slow = pc.save_project

    def save_slowly(*args, **kwargs):
        time.sleep(0.5)
        slow(*args, **kwargs)

    monkeypatch.setattr(pc, "save_project", save_slowly)
    s = Session()
    s.add_layer("scene.csv", "source", scene[1])
    ctl = ProjectController(s)
    a, b = tmp_path / "a.wakeline", tmp_path / "b.wakeline"
    ctl.save_as(a)
    started = time.perf_counter()
    ctl.save_as(b)
    ctl.save_as(b)  # the same file again, right away
    assert time.perf_counter() - started < 0.25
    s.add_layer("more.csv", "source", scene[1].head(50))  # followed by the last writer
    ctl.detach()
    assert len(load_project(a).layers) == 1
    assert [lay.name for lay in load_project(b).layers] == ["scene.csv", "more.csv"]
    # A read-only project opened between two slow saves of one file (review: the second
    # save did not wait for the first, and the first's older session won).
    calls = []

    def first_slowly(*args, **kwargs):
        calls.append(1)
        time.sleep(0.5 if len(calls) == 1 else 0.0)
        slow(*args, **kwargs)

    monkeypatch.setattr(pc, "save_project", first_slowly)
    ctl = ProjectController(s)
    ctl.save_as(a)
    ctl.release()
    ctl.follow(tmp_path / "elsewhere.wakeline", read_only=True)
    s.remove_layer(next(iter(s.layers)))
    ctl.save_as(a)
    ctl.detach()
    assert [lay.name for lay in load_project(a).layers] == ["more.csv"]


def test_layer_data_never_goes_through_a_bound_parameter(scene, tmp_path):
    """A layer's Parquet bound as an INSERT parameter was copied by SQLite into fresh
    memory with the GIL held (0.2–0.9 s for a 1-M-point layer: the GUI thread stopped
    during a Save as). It is now written with ``Blob.write`` (GIL released): no
    statement carries the data, and the layer and its side tables read back the same."""
    from wakeline.core.project import ProjectStore

    _, points = scene
    s = Session()
    src = s.add_layer("scene", "source", points)
    s.apply_result(src.id, s.run_step(src.id, "clean"))
    cleaned = s.find(src.id, "clean", "cleaned")
    assert "rejected" in cleaned.tables
    path = tmp_path / "p.wakeline"
    store = ProjectStore(path)
    statements = []
    store.con.set_trace_callback(statements.append)  # the SQL with its parameters
    store.put_layer(src, 0)
    store.put_layer(cleaned, 1)
    store.put_layer(cleaned, 1)  # replaced in place
    store.close()
    inserts = [sql for sql in statements if "INSERT" in sql.upper()]
    assert inserts and max(len(sql) for sql in inserts) < 10_000  # the Parquet is ~100 kB
    assert all("x'" not in sql.lower() for sql in inserts)
    back = load_project(path)
    assert [lay.id for lay in back.layers] == [src.id, cleaned.id]
    pd.testing.assert_frame_equal(back.layers[0].points, src.points.reset_index(drop=True))
    pd.testing.assert_frame_equal(back.layers[1].points, cleaned.points.reset_index(drop=True))
    for name, table in cleaned.tables.items():
        pd.testing.assert_frame_equal(back.layers[1].tables[name], table.reset_index(drop=True))


def test_layer_data_is_never_selected_as_a_column(scene, tmp_path, monkeypatch):
    """Fetched as a ``SELECT`` column, a layer's blob was gathered by SQLite and copied
    by Python with the GIL held (0.1–0.4 s for a 1-M-point layer: the GUI thread stopped
    during an Open project). It is read with ``Blob.read`` (GIL released): no statement
    of the open selects ``data`` (its ``typeof`` only), and everything reads back."""
    import re

    import wakeline.core.project as wp

    _, points = scene
    s = Session()
    src = s.add_layer("scene", "source", points)
    s.apply_result(src.id, s.run_step(src.id, "clean"))
    cleaned = s.find(src.id, "clean", "cleaned")
    path = tmp_path / "p.wakeline"
    save_project(s, path)
    statements = []
    opened = wp._open_read_only

    def traced(p):
        con = opened(p)
        con.set_trace_callback(statements.append)
        return con

    monkeypatch.setattr(wp, "_open_read_only", traced)
    back = load_project(path)
    selects = [sql for sql in statements if sql.lstrip().upper().startswith("SELECT")]
    assert any("layers" in sql for sql in selects)
    assert not [sql for sql in selects if re.search(r"\bdata\b", sql.replace("typeof(data)", ""))]
    pd.testing.assert_frame_equal(back.layers[0].points, src.points.reset_index(drop=True))
    pd.testing.assert_frame_equal(back.layers[1].points, cleaned.points.reset_index(drop=True))
    for name, table in cleaned.tables.items():
        pd.testing.assert_frame_equal(back.layers[1].tables[name], table.reset_index(drop=True))


def test_a_file_read_again_replaces_its_sources_hash():
    """``note_source``: a path read again keeps one Source, with the last read's hash."""
    s = Session()
    s.note_source("/data/b.csv", "aaa")
    s.note_source("/data/c.csv", "ccc")
    s.note_source("/data/b.csv", "bbb")
    assert [(x.path, x.sha256) for x in s.sources] == [
        ("/data/b.csv", "bbb"),
        ("/data/c.csv", "ccc"),
    ]


def test_time_window_is_kept_in_the_session_and_the_project(scene, tmp_path):
    """The map's time window was not saved: a project reopened showed every point. Now the
    session holds it (s, with its unit in the file), Save as and the incremental writer
    store it, opening gives it back; a project without it (saved before) opens with no
    window; a window that is not one (reversed, not finite, another unit) is refused as
    damaged, as any bad row."""
    from wakeline.core.timeline import TimeWindow

    _, points = scene
    s = Session()
    events = []
    s.subscribe(lambda e, lid: events.append((e, lid)))
    s.add_layer("scene", "source", points)
    t0 = float(points["time"].astype("int64").min()) / 1e9
    s.set_time_window((t0 + 60.0, t0 + 600.5))
    s.set_time_window(TimeWindow(t0 + 60.0, t0 + 600.5))  # the same: no event
    assert events[1:] == [("time_window", "")]
    assert s.time_window == TimeWindow(t0 + 60.0, t0 + 600.5)
    with pytest.raises(ValueError):
        s.set_time_window((t0 + 10.0, t0))
    path = tmp_path / "p.wakeline"
    save_project(s, path)
    back = load_project(path)
    assert back.time_window == s.time_window and "time_window" not in back.state
    assert back.to_session().time_window == s.time_window
    # The writer's small row (as the window writes it when the operator moves the window).
    errors = []
    writer = ProjectWriter(path, errors.append)
    writer.submit(lambda st: st.put_time_window(TimeWindow(t0, t0 + 1.25)))
    assert writer.flush(10)
    writer.close()
    assert errors == [] and load_project(path).time_window == TimeWindow(t0, t0 + 1.25)
    con = sqlite3.connect(path)
    (raw,) = con.execute("SELECT json FROM state WHERE key = 'time_window'").fetchone()
    con.close()
    assert json.loads(raw) == {"start": t0, "end": t0 + 1.25, "unit": "s"}
    # Cleared: null in the file, no window back.
    s.set_time_window(None)
    save_project(s, path)
    assert load_project(path).time_window is None
    # A project saved before the window was kept: no row, opens as before.
    s.set_time_window((t0, t0 + 5.0))
    save_project(s, path)
    con = sqlite3.connect(path)
    con.execute("DELETE FROM state WHERE key = 'time_window'")
    con.commit()
    con.close()
    old = load_project(path)
    assert old.time_window is None and [lay.name for lay in old.layers] == ["scene"]
    assert old.to_session().time_window is None
    for bad in (
        {"start": t0 + 5.0, "end": t0, "unit": "s"},
        {"start": t0, "end": t0 + 5.0, "unit": "ms"},
        {"start": "noon", "end": t0, "unit": "s"},
        {"start": t0, "end": float("inf"), "unit": "s"},
        [t0, t0 + 5.0],
    ):
        # A bad window only says what the map showed: left out with one warning (it
        # refused the whole project as damaged before), the layers open.
        _put_state_row(path, "time_window", json.dumps(bad))
        back = load_project(path)
        assert back.time_window is None and [lay.name for lay in back.layers] == ["scene"]
        assert len(back.warnings) == 1 and "time window" in back.warnings[0]


def test_slider_time_is_kept_in_the_session_and_the_project(scene, tmp_path):
    """Review: the time slider's time was not saved (a reopened project started at the
    layers' first time). Now the session holds it (s on the layers' clock), Save as and
    the writer's small row store it as {t, unit}, opening gives it back; a project without
    the row opens as before; a bad row is left out with one warning and the project
    opens."""
    _, points = scene
    s = Session()
    events = []
    s.subscribe(lambda e, lid: events.append((e, lid)))
    s.add_layer("scene", "source", points)
    t0 = float(points["time"].astype("int64").min()) / 1e9
    s.set_current_time(t0 + 125.5)
    s.set_current_time(t0 + 125.5)  # the same: no event
    assert events[1:] == [("current_time", "")]
    for bad in (float("nan"), float("inf"), "noon", True):
        with pytest.raises(ValueError):
            s.set_current_time(bad)
    assert s.current_time == t0 + 125.5
    path = tmp_path / "p.wakeline"
    save_project(s, path)
    back = load_project(path)
    assert back.current_time == t0 + 125.5 and "current_time" not in back.state
    assert back.warnings == [] and back.to_session().current_time == t0 + 125.5
    errors = []
    writer = ProjectWriter(path, errors.append)
    writer.submit(lambda st: st.put_current_time(t0 + 7.25))
    assert writer.flush(10)
    writer.close()
    assert errors == [] and load_project(path).current_time == t0 + 7.25
    con = sqlite3.connect(path)
    (raw,) = con.execute("SELECT json FROM state WHERE key = 'current_time'").fetchone()
    con.close()
    assert json.loads(raw) == {"t": t0 + 7.25, "unit": "s"}
    s.clear()
    assert s.current_time is None and events[-1] == ("current_time", "")
    _drop_state_rows(path, "current_time")  # saved before it was kept: opens as before
    old = load_project(path)
    assert old.current_time is None and old.warnings == [] and old.layers


def _put_state_row(path, key: str, raw: str) -> None:
    """Write the state row ``key`` of the project ``path`` as the text ``raw``."""
    con = sqlite3.connect(path)
    con.execute("INSERT OR REPLACE INTO state VALUES (?, ?)", (key, raw))
    con.commit()
    con.close()


def _drop_state_rows(path, *keys: str) -> None:
    con = sqlite3.connect(path)
    con.executemany("DELETE FROM state WHERE key = ?", [(k,) for k in keys])
    con.commit()
    con.close()


def test_view_active_layer_and_selection_round_trip(scene, tmp_path):
    """A reopened project framed all the data again, and made the selection's (or the
    last) layer active: the view Save as stored was never read, the active layer never
    written by Save as. Now the session holds the map's view (degrees, with the unit in
    the file) and the active layer; Save as and the writer's small rows store them, and
    opening gives back the view, the active layer, the visible layers and the selection."""
    from wakeline.core.session import MapView

    _, points = scene
    s = Session()
    events = []
    s.subscribe(lambda e, lid: events.append((e, lid)))
    a = s.add_layer("a", "source", points)
    b = s.add_layer("b", "source", points.head(300))
    c = s.add_layer("c", "source", points.head(100))
    s.set_visible(c.id, False)
    s.set_active(b.id)
    s.set_active(b.id)  # the same: no event
    s.selection = [(b.id, "R1", "3"), (b.id, "AIS", "7")]
    view = MapView(11.25, 11.5, 57.6, 57.75)
    s.set_map_view((11.25, 11.5, 57.6, 57.75))
    s.set_map_view(view)  # the same: no event
    assert [e for e, _ in events[3:]] == ["visibility", "active", "map_view"]
    with pytest.raises(ValueError):
        s.set_map_view((11.5, 11.25, 57.6, 57.75))  # west > east
    with pytest.raises(InputError):
        s.set_active("L99")
    assert s.map_view == view and s.active == b.id

    path = tmp_path / "p.wakeline"
    save_project(s, path)
    back = load_project(path)
    assert back.warnings == []
    assert (back.map_view, back.active) == (view, b.id)
    assert back.selection == s.selection
    assert [lay.visible for lay in back.layers] == [True, True, False]
    s2 = back.to_session()
    assert (s2.map_view, s2.active, s2.selection) == (view, b.id, s.selection)
    con = sqlite3.connect(path)
    (raw,) = con.execute("SELECT json FROM state WHERE key = 'view'").fetchone()
    con.close()
    assert json.loads(raw) == {"x": [11.25, 11.5], "y": [57.6, 57.75], "unit": "deg"}

    # The writer's small rows, as the window writes them when they change.
    errors = []
    writer = ProjectWriter(path, errors.append)
    zoomed = MapView(11.3, 11.31, 57.7, 57.705)
    writer.submit(lambda st: st.put_map_view(zoomed))
    writer.submit(lambda st: st.put_state("active", a.id))
    writer.submit(lambda st: st.put_state("selection", [(a.id, "R1", "2")]))
    assert writer.flush(10)
    writer.close()
    back = load_project(path)
    assert errors == [] and back.warnings == []
    assert (back.map_view, back.active, back.selection) == (zoomed, a.id, [(a.id, "R1", "2")])

    # Another layer made active drops the selection of the last one (the table shows
    # the active layer's tracks); a selection of a layer not active is not restored.
    s.set_active(a.id)
    assert s.selection == []
    _put_state_row(path, "selection", json.dumps([[b.id, "R1", "3"]]))
    assert load_project(path).to_session().selection == []
    # Removing the active layer leaves none active.
    s.remove_layer(a.id)
    assert s.active is None and events[-1] == ("active", "")

    # The view Save as wrote before it had a unit: the map's [[x0, x1], [y0, y1]].
    _put_state_row(path, "view", json.dumps([[11.3, 11.31], [57.7, 57.705]]))
    assert load_project(path).map_view == zoomed


def test_a_project_without_view_rows_opens_as_before(scene, tmp_path):
    """A project saved before the view and active layer were kept (no rows) opens as
    before: no view (the map frames the data), the selection's layer active, else none."""
    _, points = scene
    s = Session()
    a = s.add_layer("a", "source", points)
    b = s.add_layer("b", "source", points.head(300))
    s.set_active(b.id)
    s.selection = [(b.id, "R1", "3")]
    s.set_map_view((11.25, 11.5, 57.6, 57.75))
    path = tmp_path / "p.wakeline"
    save_project(s, path)
    _drop_state_rows(path, "view", "active")
    back = load_project(path)
    assert back.warnings == [] and (back.map_view, back.active) == (None, None)
    s2 = back.to_session()
    assert (s2.map_view, s2.active, s2.selection) == (None, b.id, [(b.id, "R1", "3")])
    _drop_state_rows(path, "selection", "time_window")
    s3 = load_project(path).to_session()
    assert (s3.active, s3.selection, s3.time_window) == (None, [], None)
    assert list(s3.layers) == [a.id, b.id]


@pytest.mark.parametrize(
    ("key", "raw", "what"),
    [
        ("view", '{"x": [11.5, 11.25], "y": [57.6, 57.75], "unit": "deg"}', "map view"),
        ("view", '{"x": [11.25, 11.5], "y": [57.6, 57.75], "unit": "m"}', "map view"),
        ("view", '{"x": [11.25, NaN], "y": [57.6, 57.75], "unit": "deg"}', "map view"),
        ("view", "[1, 2, 3, 4]", "map view"),
        ("view", "{not json", "map view"),
        ("active", '"L99"', "active layer"),
        ("active", "[1]", "active layer"),
        ("selection", '[["L2", "R1"]]', "selected tracks"),
        ("selection", '"L2"', "selected tracks"),
        ("time_window", '{"start": 5, "end": 1, "unit": "s"}', "time window"),
        ("time_window", "{", "time window"),
        ("current_time", '{"t": "noon", "unit": "s"}', "slider's time"),
        ("current_time", '{"t": 5, "unit": "ms"}', "slider's time"),
        ("current_time", '{"t": Infinity, "unit": "s"}', "slider's time"),
        ("current_time", "12.5", "slider's time"),
    ],
)
def test_a_bad_view_state_row_is_left_out_with_one_warning(scene, tmp_path, key, raw, what):
    """One bad row of where the operator was (view, active layer, selection, time
    window) refused the whole project as damaged. Now it is left out with one warning and
    the project opens with everything else; a bad data row still refuses it."""
    _, points = scene
    s = Session()
    s.add_layer("a", "source", points)
    b = s.add_layer("b", "source", points.head(300))
    s.set_active(b.id)
    s.selection = [(b.id, "R1", "3")]
    s.set_map_view((11.25, 11.5, 57.6, 57.75))
    s.set_time_window((0.0, 60.0))
    s.set_current_time(30.0)
    path = tmp_path / "p.wakeline"
    save_project(s, path)
    good = load_project(path)
    _put_state_row(path, key, raw)
    back = load_project(path)
    assert len(back.warnings) == 1, back.warnings
    assert what in back.warnings[0] and "left out" in back.warnings[0]
    assert [lay.id for lay in back.layers] == [lay.id for lay in good.layers]
    for field in ("map_view", "active", "selection", "time_window", "current_time"):
        expected = getattr(good, field)
        wanted = {"view": "map_view"}.get(key, key)
        if field == wanted:
            expected = [] if field == "selection" else None
        assert getattr(back, field) == expected, field
    back.to_session()  # opens


def test_a_bad_data_row_still_refuses_the_project(scene, tmp_path):
    _, points = scene
    s = Session()
    s.add_layer("a", "source", points)
    path = tmp_path / "p.wakeline"
    save_project(s, path)
    con = sqlite3.connect(path)
    con.execute("INSERT INTO params VALUES ('clean', '{not json')")
    con.commit()
    con.close()
    with pytest.raises(InputError, match="damaged"):
        load_project(path)


def test_a_removed_step_layer_made_again_since_is_not_restored_beside_it(scene):
    """Clean's layer removed, Clean run again on the same layer (a new layer of the same
    step, role and input), then the removal undone: two layers of one name, a re-run
    replacing the restored (older) one and leaving the newer stale. The restore is
    refused, nothing changed; once the newer one is removed it is restored (h245)."""
    _, points = scene
    s = Session()
    a = s.add_layer("scene.csv", "source", points.head(2000))
    (old,) = s.apply_result(a.id, s.run_step(a.id, "clean"))
    removal = s.remove_layer(old.id)
    (new,) = s.apply_result(a.id, s.run_step(a.id, "clean"))
    assert new.id != old.id
    with pytest.raises(InputError, match="made again"):
        s.restore_layer(removal)
    assert list(s.layers) == [a.id, new.id]
    s.remove_layer(new.id)
    assert s.restore_layer(removal) is old and list(s.layers) == [a.id, old.id]
    (again,) = s.apply_result(a.id, s.run_step(a.id, "clean"))
    assert again is old  # a re-run replaces it in place, as before the removal
