"""Operator test 5's new import messages (a second table, zones mixed, zone-less times
from a Chinese system, positions on a coarse grid) as the window shows them in zh_CN:
each from a real read, translated whole, its numbers and names kept."""

import re

import pytest
from test_core_text import english_left
from test_import_second_table import FIRST, _file
from test_import_zones_grid import _ship

from wakeline.app.core_text import translate
from wakeline.app.window_words import window_words
from wakeline.core.io import read_points


def _messages(write) -> list[str]:
    texts = {
        "order.csv": _file(
            ["index", "mmsi", "position_timestamp", "longitude", "latitude"], 30, 20
        ),
        "changed.csv": _file(["index", "position_timestamp", "mmsi", "lat", "lon", "sog"], 30, 20),
        "split.csv": _file(["index", "mmsi", "latitude", "longitude", "sog"], 30, 20),
        "fewer.csv": _file(["position_timestamp", "mmsi", "latitude", "longitude"], 30, 20)
        + ",".join(["1", "2023-03-01T01:00:00Z", "220614000", "57.1", "11.1"])
        + "\n",
        "zones.csv": _ship(100, naive_every=2),
        "cn.csv": _ship(100, naive_every=1).replace("mmsi,time,lat,lon", "批号,时间,纬度,经度"),
        "grid.csv": _ship(100, decimals=2),
    }
    out: dict[str, None] = {}
    for name, text in texts.items():
        r = read_points(write(name, text))
        for w in r.report["warnings"]:
            out[w] = None
        for reason in r.report["quarantine_reasons"]:
            out[reason] = None
    return list(out)


def test_operator_5_import_messages_are_in_chinese(write):
    messages = _messages(write)
    new = [
        m
        for m in messages
        if "second table" in m or "carry no zone" in m or m.startswith("the positions carry")
    ]
    assert len(new) >= 10, messages
    for text in messages:
        zh = translate(window_words(text), "zh_CN")
        assert zh != text, text
        assert not english_left(zh), (text, zh)
        for number in re.findall(r"\d[\d,]*\d", text):
            assert number in zh, (number, zh)
    assert FIRST  # the first header of the tables read


@pytest.mark.parametrize(
    "text",
    [
        "line 1,502 starts a second table with its columns in another order: read by its own "
        "header (1,800 rows)",
        "line 1,502 starts a second table with its columns changed (+sog): read by its own "
        "header (1,800 rows; columns it adds not read)",
        "line 32 starts a second table separated by ';': its 30 rows quarantined; split the "
        "file and import each table on its own",
        "the header of a second table separated by ';': split the file",
        "the tables of this file write the times in 'position_timestamp' in 2 forms (ISO 8601 "
        "text, day-first text): each table's read in its own",
        "the times in '时间' carry no zone: read as UTC (this file looks written on a Chinese "
        "system: if they are local times, --tz Asia/Shanghai)",
        # h192: window_words made its --map a field, and the zh entry's tail no longer matched
        "this file carries targets: 6 tracks in 5 targets (column 'target'), read with their "
        "target; --map batch=target reads one track per target",
    ],
)
def test_the_tester_s_cases_read_in_chinese(text):
    zh = translate(window_words(text), "zh_CN")
    assert not english_left(zh) and zh != text, zh
    assert "Asia/Shanghai" in zh or "1,800" in zh or "日在前" in zh or "';'" in zh or "6 条" in zh


def test_operator_5_project_messages_are_in_chinese():
    """h192: h184's two project sentences (a source found beside a moved project, a write
    to a project moved while open) reached the zh_CN window in English."""
    from wakeline.core.file_identity import moved_message

    for text in (
        "source file found beside the project: /a/b/x.csv (same content as /c/x.csv, which "
        "is no longer there)",
        moved_message("/p/x.wakeline"),
    ):
        zh = translate(window_words(text), "zh_CN")
        assert zh != text and not english_left(zh), zh
        assert "/a/b/x.csv" in zh or "/p/x.wakeline" in zh
