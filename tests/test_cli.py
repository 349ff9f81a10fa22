import json
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

from wakeline.app.cli import build_parser, main

SUBCOMMANDS = (
    "import",
    "simulate",
    "clean",
    "maneuvers",
    "compress",
    "bearing",
    "associate",
    "evaluate",
    "gui",
)


@pytest.mark.parametrize("sub", SUBCOMMANDS)
def test_help_for_every_subcommand(sub, capsys):
    with pytest.raises(SystemExit) as exc:
        main([sub, "--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    assert f"usage: wakeline {sub}" in out


def test_top_level_help_lists_subcommands(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    out = capsys.readouterr().out
    for sub in SUBCOMMANDS:
        assert sub in out


def test_import_help_documents_formats_and_options(capsys):
    with pytest.raises(SystemExit):
        main(["import", "--help"])
    out = capsys.readouterr().out
    for word in (
        "--format",
        "--map",
        "--quarantine",
        "--report",
        "MarineCadastre",
        "SendShipNO",
        "MTAD",
    ):
        assert word in out


def test_usage_error_exits_2(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["import"])
    assert exc.value.code == 2
    assert "required" in capsys.readouterr().err


@pytest.mark.parametrize("kind", ["maneuver", "segments", "multisensor", "demo"])
def test_simulate_writes_truth(kind, tmp_path):
    out = tmp_path / f"{kind}.csv"
    assert (
        main(["simulate", kind, "--seed", "3", "-o", str(out), "--tracks", "5", "--ships", "4"])
        == 0
    )
    df = pd.read_csv(out, dtype={"batch": str})
    assert {"sensor", "batch", "time", "lon", "lat", "truth", "true_lon", "true_lat"} <= set(
        df.columns
    )
    again = tmp_path / "again.csv"
    main(["simulate", kind, "--seed", "3", "-o", str(again), "--tracks", "5", "--ships", "4"])
    assert out.read_bytes() == again.read_bytes()  # seeded: same seed, same file


def test_simulate_rejects_bad_numbers(capsys, tmp_path):
    with pytest.raises(SystemExit) as exc:
        main(["simulate", "maneuver", "--tracks", "0", "-o", str(tmp_path / "x.csv")])
    assert exc.value.code == 2
    assert "must be at least 1" in capsys.readouterr().err


def _numeric_flags():
    """(subcommand, flag, type) of every flag of every subcommand whose argparse type
    is a number parser: the hand-written ones (the generated parameter flags take
    text and are range-checked by their dataclass, below)."""
    import argparse

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    out = []
    for name, p in sub.choices.items():
        for a in p._actions:
            if a.type is None or not a.option_strings or a.type in (str, Path):
                continue
            if (
                a.type in (int, float)
                or a.type.__name__ in NUMBER_TYPES
                or "int_in" in (a.type.__name__)
            ):
                out.append((name, a.option_strings[-1], a.type))
    return out


NUMBER_TYPES = ("positive_int", "positive_float", "seed_int", "whole_int")
#: whole numbers whose range the reader checks, naming the flag (tests/test_skip_rows_everywhere.py)
RANGE_CHECKED_LATER = ("whole_int",)


def test_no_numeric_flag_takes_a_bare_int_or_float():
    flags = _numeric_flags()
    assert len(flags) > 30  # simulate, evaluate, batch, clean, the bearing flags ...
    bare = [(s, f) for s, f, kind in flags if kind in (int, float)]
    assert not bare, f"unchecked numbers (a negative or NaN one is an internal error): {bare}"
    assert {("simulate", "--seed"), ("evaluate", "--seed")} <= {(s, f) for s, f, _ in flags}


@pytest.mark.parametrize("bad", ["-1", "-0.5", "nan", "inf", "-inf", "1e400", "x", "", "1.5.2"])
def test_every_numeric_flag_refuses_a_bad_number(bad):
    import argparse

    for sub, flag, kind in _numeric_flags():
        if kind.__name__ in RANGE_CHECKED_LATER and bad.lstrip("-").isdigit():
            continue
        with pytest.raises(argparse.ArgumentTypeError):
            kind(bad)
            raise AssertionError(f"{sub} {flag} took {bad!r}")


@pytest.mark.parametrize(
    "argv",
    [
        ["simulate", "maneuver", "--seed", "-1"],
        ["simulate", "bearing", "--seed", "-1"],
        ["simulate", "segments", "--seed", "-7"],
        ["simulate", "multisensor", "--seed", str(2**32)],
        ["simulate", "maneuver", "--sigma", "nan"],
        ["simulate", "segments", "--area-km", "inf"],
        ["evaluate", "bearing", "--seed", "-1"],
        ["evaluate", "maneuver", "--seed", "1.5"],
        ["evaluate", "maneuver", "--real", "x", "--gnss-gate-m", "-3"],
        ["import", "x.csv", "--skip-rows", "1.5"],
        ["clean", "x.csv", "--smooth", "0"],
        ["export", "x.csv", "--like", "y.csv", "--like-skip-rows", "two"],
    ],
)
def test_a_bad_number_is_exit_2_with_one_message_and_no_output(argv, tmp_path, capsys):
    out = tmp_path / "out.csv"
    if argv[0] != "evaluate":
        argv = [*argv, "-o", str(out)]
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    flag = [a for a in argv if a.startswith("--")][-1]
    assert f"error: argument {flag}" in err
    assert "internal error" not in err and "Traceback" not in err
    assert len([line for line in err.splitlines() if "error:" in line]) == 1
    assert not out.exists()


@pytest.mark.parametrize("seed", ["0", "4294967295"])
def test_seeds_at_both_ends_of_the_range_run(seed, tmp_path):
    out = tmp_path / "b.csv"
    assert main(["simulate", "bearing", "--seed", seed, "-o", str(out)]) == 0
    assert out.stat().st_size > 0


def test_generated_parameter_flags_are_range_checked_by_their_dataclass(tmp_path, capsys):
    """Flags made from a Params dataclass (one per field) take text; the field's range
    refuses a bad value with exit 2 (one message), never an internal error."""
    from wakeline.core.bearing import BearingParams

    bearings = tmp_path / "b.csv"
    main(["simulate", "bearing", "-o", str(bearings)])
    capsys.readouterr()
    fields = [d for d in BearingParams.describe() if d.get("hi") is not None]
    assert fields
    for d in fields:
        flag = "--" + d["name"].removesuffix("_s").replace("_", "-")
        code = 0
        try:
            code = main(["bearing", str(bearings), "-o", str(tmp_path / "o.csv"), flag, "1e30"])
        except SystemExit as exc:
            code = exc.code
        assert code == 2, flag
        assert "internal error" not in capsys.readouterr().err


def test_console_script_runs_as_a_process(tmp_path):
    out = tmp_path / "m.csv"
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "wakeline.app.cli",
            "simulate",
            "maneuver",
            "--tracks",
            "2",
            "-o",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    assert out.exists()


def test_parser_is_built_without_qt():
    assert build_parser().prog == "wakeline"


def test_evaluate_maneuver_on_a_real_folder(tmp_path, capsys):
    from conftest import real_file

    folder = real_file("oresund-encounters")
    out = tmp_path / "real.csv"
    assert main(["evaluate", "maneuver", "--real", str(folder), "--csv", str(out)]) == 0
    text = capsys.readouterr().out
    assert "oresund" in text and "GW_with_turn" in text
    assert set(pd.read_csv(out)["method"]) == {"ours", "paper"}
    (tmp_path / "empty").mkdir()
    assert main(["evaluate", "maneuver", "--real", str(tmp_path / "empty")]) == 2
    assert "no track files in this folder (.csv, .tsv, .txt, .nmea" in capsys.readouterr().err


def test_every_step_reads_a_headerless_file_with_map(tmp_path, capsys):
    """A reading error tells the operator to use --map; every step takes it (before, only
    clean and import did: `associate FILE --map ...` was refused as an unknown flag)."""
    rows = ["5 23.48402 37.35515 1722468684", "5 23.48410 37.35520 1722468744"]
    rows += ["7 23.50000 37.40000 1722468684", "7 23.50010 37.40010 1722468744"]
    src = tmp_path / "headerless.csv"
    src.write_text("\n".join(rows) + "\n")
    mapping = ["--map", "batch=col1", "--map", "lon=col2", "--map", "lat=col3"]
    mapping += ["--map", "time=col4"]
    for step in ("maneuvers", "compress", "associate"):
        out = tmp_path / f"{step}.csv"
        assert main([step, str(src), "-o", str(out), *mapping]) == 0, step
        assert out.exists()
    radar = tmp_path / "headerless_radar.csv"
    radar.write_text(src.read_text())
    fused = tmp_path / "f.csv"
    assert main(["fuse", str(src), str(radar), "-o", str(fused), *mapping]) == 0
    assert fused.exists()
    capsys.readouterr()


@pytest.mark.parametrize("step", ["clean", "maneuvers", "associate"])
def test_a_step_on_a_file_with_no_usable_row_says_why(step, tmp_path, capsys):
    """Operator test: `wakeline clean` on a file whose every time is unreadable said only
    "no usable points" (the reading's quarantine counts were lost); every step now says
    how many rows went to the quarantine, for what, and what to try."""
    src = tmp_path / "us.csv"
    # (was "05/01/2024 08:0m:00 AM", readable since h111's 12-hour clocks)
    rows = [f"7,08h0{m} on the 1st of May,12.{m},56.0" for m in range(5)]
    src.write_text("mmsi,timestamp,lon,lat\n" + "\n".join(rows) + "\n")
    assert main([step, str(src), "-o", str(tmp_path / "o.csv")]) == 2
    err = capsys.readouterr().err
    assert "all 5 rows were quarantined" in err and "'unparsable time'" in err, err
    assert "--map time=" in err and str(src) in err
    assert not (tmp_path / "o.csv").exists()


@pytest.mark.parametrize("step", ["clean", "maneuvers", "compress"])
def test_step_reports_say_where_every_input_row_went(step, tmp_path, capsys):
    """A step's --report carries the reading's counts (rows read, points, quarantined by
    reason); stderr names the reasons; export of a file with no usable row fails."""
    import json

    good = [f"S,1,2024-05-01T00:{m:02d}:00Z,{10 + m * 1e-3:.4f},55" for m in range(30)]
    bad = [
        "S,1,not a time,10,55",
        "S,1,2024-05-01T01:00:00Z,999,55",
        "S,1,2300-01-01T00:00:00Z,10,55",
    ]
    src = tmp_path / "in.csv"
    src.write_text("sensor,batch,time,lon,lat\n" + "\n".join(good + bad) + "\n")
    assert (
        main([step, str(src), "-o", str(tmp_path / "o.csv"), "--report", str(tmp_path / "r.json")])
        == 0
    )
    read = json.loads((tmp_path / "r.json").read_text())["read"]
    assert read["rows_read"] == 33 and read["rows_imported"] == 30
    assert read["rows_quarantined"] == 3 and sum(read["quarantine_reasons"].values()) == 3
    err = capsys.readouterr().err
    assert "3 rows quarantined on reading" in err and "lon out of range" in err
    allbad = tmp_path / "bad.csv"
    allbad.write_text("sensor,batch,time,lon,lat\n" + "\n".join(bad) + "\n")
    assert main(["export", str(allbad), "-o", str(tmp_path / "e.csv")]) == 2
    err = capsys.readouterr().err  # as the steps say it (operator test 10)
    assert "nothing imported: all 3 rows were quarantined" in err, err


@pytest.mark.parametrize("kinds", [1, 3, 4, 5, 7])
def test_import_names_every_quarantine_reason_with_its_count(kinds, tmp_path, capsys):
    """Operator test 10: `wakeline import` said only "23 quarantined" (23 local times a
    clock change skipped: why, only in --quarantine's file), and the steps said "1 more
    reasons". Now import names the reasons, and a step one more reason rather than "1
    more reasons"; the counts add up to the rows quarantined."""
    bad = [
        "S,1,not a time,10,55",
        "S,1,2024-05-01T01:00:00Z,999,55",
        "S,1,2024-05-01T01:00:00Z,10,95",
        "S,1,2024-05-01T01:00:00Z",
        "S,1,2024-05-01T01:00:00Z,10,55,9,9,9,9",
        "S,,2024-05-01T01:00:00Z,10,55",
        "S,1,2024-05-01T01:00:00Z,east,55",
    ][:kinds]
    good = [f"S,1,2024-05-01T00:{m:02d}:00Z,{10 + m * 1e-3:.4f},55" for m in range(30)]
    src = tmp_path / "in.csv"
    src.write_text("sensor,batch,time,lon,lat\n" + "\n".join(good + bad + bad) + "\n")
    assert main(["import", str(src), "-o", str(tmp_path / "o.csv")]) == 0
    err = capsys.readouterr().err
    line = next(x for x in err.splitlines() if x.startswith("quarantined: "))
    parts = line.removeprefix("quarantined: ").split("; ")
    assert len(parts) == kinds  # every reason named (up to 8)
    assert sum(int(p.split(" ")[0]) for p in parts) == 2 * kinds
    assert main(["clean", str(src), "-o", str(tmp_path / "c.csv")]) == 0
    err = capsys.readouterr().err
    assert "1 more reason" not in err  # one more is named, not counted
    if kinds > 4:
        assert f"{kinds - 3} more reasons" in err


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["evaluate", "bearing", "--hard"], "--hard applies"),
        (["evaluate", "associate", "--real", "x.csv", "--hard"], "not --real"),
        (["evaluate", "maneuver", "--real", "x.csv", "--hard"], "not --real"),
        (["evaluate", "fuse", "--real", "x.csv"], "--real applies"),
        (["evaluate", "bearing", "--real", "x.csv"], "--real applies"),
        (["evaluate", "associate", "--real", "x.csv", "--sensor", "lidar"], "--sensor applies"),
        (["evaluate", "maneuver", "--sensor", "lidar"], "--sensor applies"),
        (["simulate", "demo", "--hard", "-o", "x.csv"], "--hard applies"),
        (["simulate", "bearing", "--hard", "-o", "x.csv"], "--hard applies"),
        (["simulate", "maneuver", "--hard", "--sigma", "3", "-o", "x.csv"], "--length and"),
        (["simulate", "maneuver", "--hard", "--length", "long", "-o", "x.csv"], "--length and"),
    ],
)
def test_flags_that_do_not_apply_are_refused_not_ignored(argv, message, tmp_path, capsys):
    """`--hard` where there is no hard scene (bearing, demo, real data), and seed 000's
    classes with the hard maneuver scene, are refused (exit 2), not ignored."""
    argv = [str(tmp_path / a) if a == "x.csv" else a for a in argv]
    assert main(argv) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "x.csv").exists()


def test_simulate_maneuver_hard_writes_a_scene_import_reads_whole(tmp_path, capsys):
    """`simulate maneuver --hard` (before: refused) writes the hard scene with its truth
    columns; `import` reads every row of it."""
    out = tmp_path / "hard.csv"
    assert (
        main(["simulate", "maneuver", "--hard", "--tracks", "12", "--seed", "3", "-o", str(out)])
        == 0
    )
    df = pd.read_csv(out, dtype={"batch": str})
    assert {"kind", "rate", "true_turn", "turn_deg", "true_lon", "true_lat"} <= set(df.columns)
    assert set(df["rate"]) == {"radar", "ais10", "ais30"} and df["true_turn"].sum() > 0
    easy = tmp_path / "easy.csv"
    assert main(["simulate", "maneuver", "--tracks", "12", "--seed", "3", "-o", str(easy)]) == 0
    assert "kind" not in pd.read_csv(easy).columns  # without --hard: seed 000's protocol
    capsys.readouterr()
    report = tmp_path / "r.json"
    assert main(["import", str(out), "-o", str(tmp_path / "i.csv"), "--report", str(report)]) == 0
    rep = json.loads(report.read_text())
    assert rep["rows_quarantined"] == 0 and rep["rows_imported"] == len(df)


def test_evaluate_maneuver_hard_prints_the_hard_table(tmp_path, capsys):
    """`evaluate maneuver --hard` (before: refused) scores ours and the paper's detector
    and compressor on hard scenes, per sampling class."""
    out = tmp_path / "hard.csv"
    argv = ["evaluate", "maneuver", "--hard", "--tracks", "10", "--scenes", "1", "--csv", str(out)]
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "Hard maneuver scenes: 1 scene(s) of 10 ships" in text
    for row in ("radar  ours", "ais10  paper", "ais30  ours", "all    paper"):
        assert row in text
    assert "Douglas-Peucker" in text and "still" in text
    assert "nan" not in text  # a class without gradual turns to find shows "-"
    table = pd.read_csv(out)
    assert set(table["method"]) == {"ours", "paper"} and len(table) == 8
    assert {"precision", "recall", "slow_share", "kept", "dp_kept", "dis_e_true_m"} <= set(
        table.columns
    )


def test_evaluate_maneuver_takes_the_step_limit():
    from wakeline.app.cli_evaluate import _maneuver_params

    def params(*extra):
        return _maneuver_params(build_parser().parse_args(["evaluate", "maneuver", *extra]))

    assert params().max_step_windows == 4.0
    assert params("--max-step-windows", "0").max_step_windows == 0.0
    assert params("--paper").max_step_windows == 0.0


def test_summaries_count_one_track_in_the_singular(tmp_path, capsys):
    """The command line's summaries share the window's counted nouns: "1 track", not
    "1 tracks" (:func:`wakeline.core.words.count`)."""
    from wakeline.core import simulate
    from wakeline.core.io import write_points

    pts = simulate.demo_scene(seed=3)
    one = pts[
        (pts["sensor"] == "AIS") & (pts["batch"] == pts["batch"][pts["sensor"] == "AIS"].iloc[0])
    ]
    src = tmp_path / "one.csv"
    write_points(one, src)
    assert main(["import", str(src), "-o", str(tmp_path / "out.csv")]) == 0
    err = capsys.readouterr().err
    assert f"imported {len(one)} rows in 1 track (" in err, err
    assert main(["associate", str(src), "-o", str(tmp_path / "a.csv")]) == 0
    err = capsys.readouterr().err
    assert "1 track -> 1 target (0 joins of 0 candidate pairs" in err, err


def test_no_written_points_file_carries_clean_s_row_id(tmp_path):
    """Operator test 7, D18: clean's internal row id `wl_id` showed in the clean,
    associate and review CSVs and the window's File > Export CSV. Points files leave it
    out; the reject trail keeps it (it keys the rejected rows); the rows are the same."""
    from wakeline.core.clean import clean
    from wakeline.core.export import export_csv
    from wakeline.core.io import read_points

    src = tmp_path / "scene.csv"
    assert main(["simulate", "segments", "--seed", "4", "--ships", "4", "-o", str(src)]) == 0
    cleaned, rej = tmp_path / "clean.csv", tmp_path / "rej.csv"
    assert main(["clean", str(src), "-o", str(cleaned), "--rejected", str(rej)]) == 0
    assoc, gui = tmp_path / "assoc.csv", tmp_path / "gui.csv"
    assert main(["associate", str(cleaned), "-o", str(assoc)]) == 0
    reviewed = tmp_path / "reviewed.csv"
    assert main(["review", str(assoc), "-o", str(reviewed)]) == 0
    step = clean(read_points(src).points)
    assert "wl_id" in step.points.columns  # in memory it is there
    export_csv(step.points, gui)
    for path in (cleaned, assoc, reviewed, gui):
        header = path.read_text(encoding="utf-8-sig").splitlines()[0].split(",")
        assert "wl_id" not in header, path.name
    assert "wl_id" in rej.read_text().splitlines()[0].split(",")
    got = pd.read_csv(cleaned)
    assert len(got) == len(step.points)
    assert set(got.columns) == set(step.points.columns) - {"wl_id"}


def test_step_outputs_list_tracks_in_natural_order(tmp_path):
    """Operator test 7, D19: the maneuvers CSV listed batches as text (161, 162, 21, …),
    and so did clean's, compress's and associate's. Every step's file now lists tracks
    in natural order (numbers by value, before other ids), each track's rows as the step
    gave them; the rows are the same."""
    from wakeline.core import simulate
    from wakeline.core.io import write_points
    from wakeline.core.tracks import natural_ranks

    df = simulate.maneuver_tracks(6, "short", 50.0, seed=5)
    ids = {
        b: new
        for b, new in zip(
            sorted(df["batch"].unique()), ["161", "21", "9", "1000", "x", "22"], strict=True
        )
    }
    df["batch"] = df["batch"].map(ids)
    src = tmp_path / "in.csv"
    write_points(df.sample(frac=1.0, random_state=3), src)  # rows shuffled
    outs = {}
    for step, extra in (("clean", []), ("maneuvers", []), ("compress", []), ("associate", [])):
        out = tmp_path / f"{step}.csv"
        assert main([step, str(src), "-o", str(out), *extra]) == 0
        outs[step] = pd.read_csv(out, dtype=str)
    for step, got in outs.items():
        runs = got["batch"][got["batch"] != got["batch"].shift()].tolist()
        assert len(runs) == len(set(runs)), step  # each track's rows together
        rank = natural_ranks(pd.Series(runs))[0]
        assert (rank[1:] > rank[:-1]).all(), (step, runs)
    assert outs["clean"]["batch"].unique().tolist()[:4] == ["9", "21", "22", "161"]
    for step, got in outs.items():  # within a track: time order, as the step writes it
        assert (
            got.groupby("batch", sort=False)["time"]
            .apply(lambda t: t.is_monotonic_increasing)
            .all()
        ), step


def test_evaluate_maneuver_flags_are_the_maneuvers_commands():
    """Session 29's leftover: `evaluate maneuver`'s detector flags were hand-written (and
    recorded as given through argparse internals). Now generated as on `maneuvers`: every
    ManeuverParams field has the same flags on both, the older spellings parse, and a flag
    given applies over --paper as on the step command."""
    import dataclasses

    from wakeline.app.cli_evaluate import _maneuver_params
    from wakeline.app.cli_steps import step_params
    from wakeline.core.maneuver import ManeuverParams
    from wakeline.core.pipeline import STEPS

    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")

    def flags(command):
        return {o for a in sub.choices[command]._actions for o in a.option_strings}

    ours = flags("evaluate")
    for f in dataclasses.fields(ManeuverParams):
        flag = "--" + f.name.replace("_", "-")
        assert flag in ours and flag in flags("maneuvers"), flag
    assert {"--window", "--radius", "--threshold", "--min-speed", "--paper"} <= ours

    d = ManeuverParams()
    cases = [
        ["--window", "7", "--threshold", "20", "--min-speed", "2.5"],
        ["--paper", "--min-speed", "2.5", "--confirm-z", "3"],
        ["--rest-radius-m", str(d.rest_radius_m * 2), "--no-confirm-grow-deg"],
    ]
    for extra in cases:
        evaluated = _maneuver_params(parser.parse_args(["evaluate", "maneuver", *extra]))
        stepped = step_params(
            STEPS["maneuvers"], parser.parse_args(["maneuvers", "x.csv", "-o", "y.csv", *extra])
        )["maneuver"]
        assert evaluated == stepped, extra
        assert evaluated != d
    paper = _maneuver_params(
        parser.parse_args(["evaluate", "maneuver", "--paper", "--window", "9"])
    )
    assert paper == ManeuverParams.paper().replace(window_p=9)


@pytest.mark.parametrize(
    ("argv", "word", "meant"),
    [
        (["clen", "x.csv"], "clen", "clean"),
        (["improt", "x.csv", "-o", "y.csv"], "improt", "import"),
        (["--debug", "reveiw", "x.csv"], "reveiw", "review"),
    ],
)
def test_a_mistyped_command_is_named_not_opened(argv, word, meant, capsys, monkeypatch, tmp_path):
    """Operator test 9, D5: `wakeline clen FILE` opened the desktop application on a file
    named "clen"; `improt … -o x` blamed "-o x". Now: the word and the command it is close
    to, exit 2, and no window."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr("wakeline.app.cli._cmd_gui", lambda args: pytest.fail("a window"))
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert f"unknown command '{word}' — did you mean '{meant}'?" in err


def test_an_unknown_word_lists_the_commands_and_a_file_still_opens(capsys, monkeypatch, tmp_path):
    """D5: a word close to no command lists them (exit 2); an existing file of that name,
    or a name with a suffix or a folder, is still a file for the window."""
    monkeypatch.chdir(tmp_path)
    opened = []
    monkeypatch.setattr("wakeline.app.cli._cmd_gui", lambda args: opened.append(args.files) or 0)
    assert main(["nosuchcommand"]) == 2
    err = capsys.readouterr().err
    assert "unknown command 'nosuchcommand'" in err and "clean" in err and "review" in err
    assert opened == []
    (tmp_path / "clen").write_text("sensor,batch,time,lon,lat\n")
    assert main(["clen"]) == 0  # an existing file: opened as before
    assert main(["tracks.csv"]) == 0  # a suffix: a file (missing: the window says so)
    assert main(["data/clen"]) == 0
    assert [str(f[0]) for f in opened] == ["clen", "tracks.csv", "data/clen"]


def test_review_refuses_an_output_suffix_it_does_not_write(tmp_path, capsys):
    """Operator test 9, D14: `review -o x.txt` wrote CSV into a .txt with no word. Now it
    refuses, before any work, naming the suffixes it writes (as render refuses a
    non-PNG); --log must be .csv."""
    pts = tmp_path / "p.csv"
    pts.write_text(
        "sensor,batch,time,lon,lat\n"
        + "".join(f"S,1,2024-01-01T00:00:{k:02d}Z,10.{k:02d},55\n" for k in range(10))
    )
    for name in ("x.txt", "x", "x.xlsx"):
        assert main(["review", str(pts), "-o", str(tmp_path / name)]) == 2
        err = capsys.readouterr().err
        assert "review writes by the suffix of -o: .csv" in err and ".geojson or .gpx" in err
        assert not (tmp_path / name).exists()
    log = tmp_path / "log.txt"
    assert main(["review", str(pts), "-o", str(tmp_path / "ok.csv"), "--log", str(log)]) == 2
    assert "--log" in capsys.readouterr().err and not log.exists()
    assert main(["review", str(pts), "-o", str(tmp_path / "ok.csv")]) == 0
    assert "wrote csv" in capsys.readouterr().err


def test_an_mtad_file_with_a_sensor_column_keeps_course_and_truth(tmp_path):
    """Operator test 9, D9: an MTAD scene with a `sensor` column added (two sensors in
    one file) was read as canonical: cou and mmsi became extra columns, the points had
    no course and no truth. Now the MTAD columns are mapped whatever columns are added."""
    from wakeline.core.io import read_points

    rows = [
        f"{s},{m}-0,{k:.1f},{20 + k * 1e-3:.6f},{131 + k * 1e-3:.6f},11.9,{260 + k},{b}"
        for k in range(12)
        for s, m, b in (("AIS", 413804828, 0), ("radar", 209351000, 1))
    ]
    plain = tmp_path / "plain.csv"
    plain.write_text(
        "mmsi,time,lat,lon,vel,cou,batch\n" + "\n".join(r.split(",", 1)[1] for r in rows)
    )
    both = tmp_path / "both.csv"
    both.write_text("sensor,mmsi,time,lat,lon,vel,cou,batch\n" + "\n".join(rows) + "\n")
    one, two = read_points(plain), read_points(both)
    assert one.report["columns"]["course"] == "cou" and one.report["columns"]["truth"] == "mmsi"
    cols = two.report["columns"]
    assert cols["course"] == "cou" and cols["truth"] == "mmsi" and cols["sensor"] == "sensor"
    assert two.report["format"].startswith("mtad")
    pts = two.points
    assert set(pts["sensor"]) == {"AIS", "radar"}
    assert pts["course"].notna().all() and set(pts["truth"]) == {"413804828-0", "209351000-0"}
    assert "cou" not in pts.columns and "mmsi" not in pts.columns
    # a canonical file with no MTAD column is read as before
    canon = tmp_path / "canon.csv"
    canon.write_text("sensor,batch,time,lon,lat,mmsi\nS,1,2024-01-01T00:00:00Z,10,55,7\n")
    got = read_points(canon)
    assert got.report["format"] == "canonical" and "truth" not in got.report["columns"]


def test_evaluate_real_on_a_simulated_hard_file_scores_its_turn_truth(tmp_path, capsys):
    """Operator test 9, D10: `evaluate maneuver --real` on a `simulate maneuver --hard`
    file printed the no-truth table only. Now the file's true_turn/turn_deg (and the turn
    spans simulate writes) give precision and recall as `--hard` scores the same scene,
    and true_lon/true_lat the Dis_e against the true path."""
    from wakeline.core.evaluate import evaluate_maneuver_hard

    sim = tmp_path / "sim.csv"
    assert (
        main(["simulate", "maneuver", "--hard", "--seed", "5", "--tracks", "30", "-o", str(sim)])
        == 0
    )
    head = pd.read_csv(sim, nrows=5)
    assert {"turn_before_s", "turn_after_s", "turn_kind"} <= set(head.columns)
    csv = tmp_path / "scores.csv"
    capsys.readouterr()
    assert main(["evaluate", "maneuver", "--real", str(sim), "--csv", str(csv)]) == 0
    out = capsys.readouterr().out
    assert "turn truth: the file's true_turn/turn_deg columns" in out
    got = pd.read_csv(csv).set_index("method")
    hard = evaluate_maneuver_hard(30, seed=5, scenes=1).table
    want = hard[hard["rows"] == "all"].set_index("method")
    for method in ("ours", "paper"):
        assert got.loc[method, "detections"] == want.loc[method, "detections"]
        assert got.loc[method, "precision"] == pytest.approx(
            want.loc[method, "precision"], abs=0.02
        )
        assert got.loc[method, "recall"] == pytest.approx(want.loc[method, "recall"], abs=0.03)
        assert abs(got.loc[method, "turns"] - want.loc[method, "turns"]) <= 2
        assert got.loc[method, "ours_dis_e_true_m"] == pytest.approx(
            want.loc[method, "dis_e_true_m"], rel=1e-6
        )
    # without the span columns: still scored, and said so
    bare = tmp_path / "bare.csv"
    pd.read_csv(sim).drop(columns=["turn_before_s", "turn_after_s"]).to_csv(bare, index=False)
    assert main(["evaluate", "maneuver", "--real", str(bare)]) == 0
    out = capsys.readouterr().out
    assert "no turn_before_s/turn_after_s columns" in out and "precision" in out
    # half the truth: said, not used
    half = tmp_path / "half.csv"
    pd.read_csv(sim).drop(columns=["turn_deg"]).to_csv(half, index=False)
    assert main(["evaluate", "maneuver", "--real", str(half)]) == 0
    out = capsys.readouterr().out
    assert "truth columns found but not used" in out and "precision" not in out
