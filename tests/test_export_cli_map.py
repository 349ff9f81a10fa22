"""Operator test 5's D-cli-1: `wakeline export`'s --map and --format describe ORIGINAL
(the --like file) while in every other command they describe the input. Without --like
they were ignored without a word; now they are IN's (as --in-map/--in-format, with a
note). With --like, a --map column that only IN has is named as IN's, with the
--in-map to give."""

import pytest

from wakeline.app.cli import main

#: A file whose time column nothing finds by name ('when' beside a text 'stamp').
IN = "stamp,id,lat,lon,when\nx,1,50,8,2024-01-01 00:00:00\nx,1,50.001,8,2024-01-01 00:00:10\n"
ORIGINAL = "MMSI,time,lat,lon\n1,2024-01-01 00:00:00,50.0,8.0\n1,2024-01-01 00:00:10,50.001,8.0\n"


def _files(tmp_path):
    src, original = tmp_path / "in.csv", tmp_path / "original.csv"
    src.write_text(IN)
    original.write_text(ORIGINAL)
    return src, original


def test_without_like_map_is_the_inputs(tmp_path, capsys):
    src, _ = _files(tmp_path)
    out = tmp_path / "out.csv"
    assert main(["export", str(src), "--map", "time=when", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    assert "no --like ORIGINAL: --map as --in-map" in err and "exported 2 rows" in err
    assert out.read_text().splitlines()[1].startswith("S1,1,2024-01-01T00:00:00.000Z")
    # the same as --in-map
    same = tmp_path / "same.csv"
    assert main(["export", str(src), "--in-map", "time=when", "-o", str(same)]) == 0
    assert same.read_bytes() == out.read_bytes()


def test_without_like_map_and_in_map_together_are_refused(tmp_path, capsys):
    src, _ = _files(tmp_path)
    argv = ["export", str(src), "--map", "time=when", "--in-map", "time=when"]
    assert main([*argv, "-o", str(tmp_path / "o.csv")]) == 2
    assert "without --like give IN's once, with --in-map" in capsys.readouterr().err


def test_with_like_a_map_of_ins_column_names_in_map(tmp_path, capsys):
    src, original = _files(tmp_path)
    argv = ["export", str(src), "--like", str(original), "--map", "time=when"]
    assert main([*argv, "-o", str(tmp_path / "o.csv")]) == 2
    err = capsys.readouterr().err
    assert "mapped column(s) not found: time=when" in err
    assert "--map names ORIGINAL's columns" in err and "--in-map time=when" in err
    # as told: IN's column with --in-map, ORIGINAL's found by itself
    argv = ["export", str(src), "--like", str(original), "--in-map", "time=when"]
    assert main([*argv, "-o", str(tmp_path / "o.csv")]) == 0
    assert (tmp_path / "o.csv").read_text() == ORIGINAL


def test_the_help_says_whose_columns(capsys):
    with pytest.raises(SystemExit):
        main(["export", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "without --like, --map is IN's (as --in-map)" in text
    assert "IN's: --in-encoding" in text and "IN's zone: --in-tz" in text
