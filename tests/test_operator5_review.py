"""Operator test 5 (h181), `wakeline review`: the summary says how many proposals were
counted as accepted without a decision (D-export-1), and a decisions table saved with
``;`` (a European-locale spreadsheet) is read (D-review-6)."""

import pandas as pd

from wakeline.app.cli import main
from wakeline.core.io import write_points
from wakeline.core.simulate import segments_scene


def _proposals(tmp_path):
    radar = tmp_path / "seg.csv"
    write_points(segments_scene(seed=2, n_ships=8, area_km=15), radar)
    props = tmp_path / "p.csv"
    assert (
        main(["associate", str(radar), "-o", str(tmp_path / "a.csv"), "--proposals", str(props)])
        == 0
    )
    return radar, props, pd.read_csv(props, dtype=str)["proposal"].tolist()


def test_review_summary_counts_the_proposals_taken_as_accepted(tmp_path, capsys):
    radar, props, ids = _proposals(tmp_path)
    assert len(ids) >= 2
    dec = tmp_path / "d.csv"
    dec.write_text(f"proposal,decision\n{ids[0]},reject\n", encoding="utf-8")
    capsys.readouterr()
    out = tmp_path / "out.csv"
    argv = [
        "review",
        str(radar),
        "--proposals",
        str(props),
        "--decisions",
        str(dec),
        "-o",
        str(out),
    ]
    assert main(argv) == 0
    err = capsys.readouterr().err
    n = len(ids)
    assert f"{n - 1} of {n} proposals not reviewed: counted as accepted" in err
    every = "proposal,decision\n" + "".join(f"{p},accept\n" for p in ids)
    dec.write_text(every, encoding="utf-8")
    assert main(argv) == 0
    assert "not reviewed" not in capsys.readouterr().err


def test_a_semicolon_decisions_table_is_read(tmp_path, capsys):
    radar, props, ids = _proposals(tmp_path)
    comma, semi = tmp_path / "c.csv", tmp_path / "s.csv"
    comma.write_text(f"proposal,decision\n{ids[0]},reject\n", encoding="utf-8")
    semi.write_bytes(f"\ufeffproposal;decision\r\n{ids[0]};Reject\r\n".encode())
    outs = []
    for dec in (comma, semi):
        out = tmp_path / f"out_{dec.stem}.csv"
        argv = ["review", str(radar), "--proposals", str(props), "--decisions", str(dec)]
        assert main([*argv, "-o", str(out)]) == 0, capsys.readouterr().err
        outs.append(out.read_bytes())
    assert outs[0] == outs[1]
