"""The core's messages in the window's language (operator test 4, D-i18n-1): the errors,
quarantine reasons, import warnings and layout names a Chinese operator must act on are
shown in Chinese (app/core_text.py over resources/translations/core_zh_CN.json)."""

import bz2
import codecs
import json
import lzma
import re
import zipfile

import pytest

from conftest import SHARED_REAL
from wakeline.app.core_text import catalog, translate
from wakeline.app.window_words import window_words
from wakeline.core.errors import InputError
from wakeline.core.io import read_points
from wakeline.core.io.formats import FORMATS
from wakeline.core.io.reader import nothing_imported
from wakeline.core.io.timetext import AMBIGUOUS_ZONES
from wakeline.resources import translations_dir

GOOD = "S1,1,2024-01-01T00:00:{s:02d}Z,122.5,30.{s:02d}"
BAD_ROWS = [
    "S1,1,2024-01-01T00:01:00Z,122.5",
    "S1,1,2024-01-01T00:01:00Z,122.5,30,9",
    "S1,1,not a time,122.5,30",
    "S1,1,,122.5,30",
    "S1,1,2024-01-01T00:01:00Z,east,30",
    "S1,1,2024-01-01T00:01:00Z,122.5,",
    "S1,1,2024-01-01T00:01:00Z,190.5,30",
    "S1,1,2024-01-01T00:01:00Z,122.5,-91",
    "S1,,2024-01-01T00:01:00Z,122.5,30",
    "S1,1,2024-01-01T00:01:00Z,east,",
    "S1,1,2024-01-01T00:01:00Z,,30",
]

#: Python's own words inside a message (a decompressor's), kept as they are.
_PYTHONS = re.compile(r"（(?:gzip|bz2|xz|zstd|File is not a zip file)[^）]*）")


def _bad_inputs(tmp_path) -> list[tuple]:
    """(file, read_points options) of the operator's common mistakes."""

    def w(name, data):
        p = tmp_path / name
        p.write_bytes(data if isinstance(data, bytes) else data.encode("utf-8"))
        return p

    mixed = "sensor,batch,time,lon,lat\n" + "".join(
        f"{GOOD.format(s=k)}\n{row}\n" for k, row in enumerate(BAD_ROWS)
    )
    several = tmp_path / "two.zip"
    with zipfile.ZipFile(several, "w") as z:
        for name in ("a.csv", "b.csv"):
            z.writestr(name, "mmsi,time,lat,lon\n1,2024-01-01T00:00:00Z,1,2\n")
    xlsx = tmp_path / "ship.xlsx"
    with zipfile.ZipFile(xlsx, "w") as z:
        z.writestr("[Content_Types].xml", "<Types/>")
        z.writestr("xl/workbook.xml", "<workbook/>")
        z.writestr("xl/worksheets/sheet1.xml", "<worksheet/>")
    restart = "mmsi,time,lat,lon\n" + "".join(
        f"265041000,2024-01-01T{h:02d}:{m:02d}:00Z,55.{m:02d},12.{m:02d}\n"
        for h in (3, 1, 2)
        for m in range(0, 40, 5)
    )
    relative = "mmsi,time,lat,lon\n" + "".join(
        f"1,{t},55.{t:03d},12.{t:03d}\n" for t in range(10, 200, 10)
    )
    comma = "mmsi;time;lat;lon\n" + "".join(
        f"1;2024-01-01T00:{m:02d}:00Z;55,{m:02d}1;12,{m:02d}1\n" for m in range(20)
    )
    day_first = "mmsi,time,lat,lon\n" + "".join(
        f"1,0{d}/0{d + 1}/2024 10:00:00,55.{d},12.{d}\n" for d in range(1, 8)
    )
    # operator test 7 D1: GBK text behind a UTF-8 byte order mark (read, and said), the
    # same with utf-8 named (refused), and a GBK header read as cp1252 (refused)
    zh = "批号,时间,经度,纬度\r\n" + "".join(
        f"{b},2024-01-01 00:00:{s:02d},120.{s:02d},30.{s:02d}\r\n" for b in (1, 2) for s in range(9)
    )
    # one sensor's lat and lon swapped, the other's right (review h209, finding 6)
    swapped = "sensor,batch,time,lat,lon\n" + "".join(
        f"{s},1,2024-01-01T00:00:{k:02d}Z,{a}.{k:02d},{b}.{k:02d}\n"
        for s, a, b in (("R1", 120, 30), ("R2", 30, 120))
        for k in range(10)
    )
    return [
        (w("swapped_sensor.csv", swapped), {}),
        (w("bom_gbk.csv", codecs.BOM_UTF8 + zh.encode("gbk")), {}),
        (w("bom_gbk_utf8.csv", codecs.BOM_UTF8 + zh.encode("gbk")), {"encoding": "utf-8"}),
        (w("gbk_cp1252.csv", zh.encode("gbk")), {"encoding": "cp1252"}),
        (w("empty.csv", b""), {}),
        (w("blank.csv", b"\n\n  \n"), {}),
        (w("png.csv", b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR" + bytes(range(256)) * 4), {}),
        (w("zipcut.csv", b"PK\x03\x04" + bytes(200)), {}),
        (w("bz.csv", bz2.compress(b"batch,time,lon,lat\n" * 50)[:-20]), {}),
        (w("xz.csv", lzma.compress(b"batch,time,lon,lat\n" * 50)[:-20]), {}),
        (w("gz.csv", b"\x1f\x8b\x08\x00garbage-not-gzip" * 10), {}),
        (w("7z.csv", b"7z\xbc\xaf\x27\x1c" + bytes(200)), {}),
        (several, {}),
        (xlsx, {}),
        (w("nocol.csv", "name,when,x\na,1,2\n"), {}),
        (w("notime.csv", "MMSI,Date/Time,Lat,Lon\n1,3/1/2023 12:01:46 AM,55,12\n"), {}),
        (
            w("headerless.csv", "5,23.48402,37.35515,1722468684\n5,23.48502,37.35615,1722468694\n"),
            {},
        ),
        (w("header_only.csv", "mmsi,time,lat,lon\n"), {}),
        (
            w(
                "latin.csv",
                b"sensor,batch,time,lon,lat\n" + b"S1,\xe9t\xe9,2024-01-01T00:00:00Z,1,2\n" * 3,
            ),
            {"encoding": "ascii"},
        ),
        (w("mixed.csv", mixed), {}),
        (w("mapped.csv", mixed), {"mapping": {"batch": "MMSI"}}),
        (w("unknown.csv", mixed), {"mapping": {"vessel": "MMSI"}}),
        (tmp_path / "nothere.csv", {}),
        (w("plane.csv", "track_id,time,east,north\n1,2024-01-01T00:00:00Z,10,20\n"), {}),
        (w("restart.csv", restart), {}),
        (w("relative.csv", relative), {}),
        (w("comma.csv", comma), {}),
        (w("day_first.csv", day_first), {}),
        (
            w(
                "truncated.csv",
                "mmsi,time,lat,lon,sog\n"
                + "".join(
                    f"1,2024-01-01T00:{m:02d}:00Z,55.{m:02d},12.{m:02d},3\n" for m in range(20)
                )
                + "1,2024-01-01T00:21:00Z,55",
            ),
            {},
        ),
    ]


def core_messages(tmp_path) -> list[tuple[str, str]]:
    """(kind, message) of every error, quarantine reason, warning and layout name the bad
    inputs give, as the core says them."""
    out: dict[tuple[str, str], None] = {}
    for path, options in _bad_inputs(tmp_path):
        try:
            result = read_points(path, **options)
        except InputError as exc:
            out[("error", str(exc))] = None
            continue
        rep = result.report
        if not rep.get("rows_imported"):
            out[("error", nothing_imported(rep, path.name))] = None
        for text in rep.get("warnings", []):
            out[("warning", text)] = None
        for text in rep.get("quarantine_reasons", {}):
            out[("reason", text)] = None
        out[("layout", rep["format_label"])] = None
    return list(out)


def english_left(text: str) -> list[str]:
    """Runs of three English words or more left in a translated text (a file's path, a
    column's quoted name, a command in backticks, a name such as "Excel en-US" and Python's
    own words not counted)."""
    text = _PYTHONS.sub("", text)
    text = re.sub(r"`[^`]*`|'[^']*'|\S*/\S*|\S+\.(?:csv|zip|xlsx|gz|bz2|xz)\b", " ", text)
    runs = re.findall(r"[A-Za-z]{2,}(?:[ -]+[A-Za-z]{2,}){2,}", text)
    # not a name (Excel en-US) nor a command (tar xf FILE)
    return [r for r in runs if re.search(r"\b[a-z]{3,}\b", r) and "FILE" not in r]


def test_every_core_message_of_the_bad_inputs_is_in_chinese(tmp_path):
    messages = core_messages(tmp_path)
    kinds = {k for k, _ in messages}
    assert kinds == {"error", "warning", "reason", "layout"}
    assert len(messages) >= 35
    left = {}
    for kind, text in messages:
        zh = translate(window_words(text), "zh_CN")
        assert zh != text, (kind, text)
        if english_left(zh):
            left[text] = (zh, english_left(zh))
    assert not left, json.dumps(left, ensure_ascii=False, indent=1)


@pytest.mark.skipif(not SHARED_REAL.exists(), reason="real data not present")
def test_the_real_sets_messages_are_in_chinese():
    """The messages of h168's operator test on the real sets (headerless Saronic, MTAD's
    relative times, Autoferry's plane metres)."""
    files = [
        SHARED_REAL / "greece-ais-annotated/vessels.csv",
        SHARED_REAL / "mtad-dtwcm/two_sensor/scene-7_error_0_AIS.csv",
        SHARED_REAL / "autoferry-fusion/detections.csv.gz",
    ]
    seen = 0
    for path in (p for p in files if p.exists()):
        try:
            rep = read_points(path).report
            texts = [*rep["warnings"], *rep["quarantine_reasons"], rep["format_label"]]
        except InputError as exc:
            texts = [str(exc)]
        for text in texts:
            zh = translate(window_words(text), "zh_CN")
            assert not english_left(zh), (text, zh)
            seen += 1
    assert seen >= 3


def test_a_pattern_keeps_the_numbers_names_and_paths():
    text = (
        "12,345 track(s) start their time again within the file (batch 265041000: 4 runs, "
        "each going forward, the next starting at least 10 min earlier): several passes or "
        "ships may share one id in 'MMSI 号'; they are joined into one track sorted by time. "
        "If a column tells them apart, map it: --map batch=COLUMN, or --map sensor=COLUMN"
    )
    zh = translate(window_words(text), "zh_CN")
    for kept in ("12,345", "265041000", "4 段", "10 分钟", "'MMSI 号'"):
        assert kept in zh, zh
    path = "/data/船舶 2024/ais_10.csv"
    zh = translate(f"{path}: short row: 5 of 12 fields", "zh_CN")
    assert zh == f"{path}: short row: 5 of 12 fields"  # a reason is translated alone ...
    assert translate("short row: 5 of 12 fields", "zh_CN") == "行过短：5 个字段（应为 12 个）"
    zh = translate(f"{path}: the file is empty", "zh_CN")  # ... an error with its file
    assert zh == f"{path}: 文件是空的"
    text = window_words(
        f"{path}: cannot decode the text as utf-8 or gb18030; choose the file's encoding "
        "(--encoding, e.g. gb18030, utf-16, latin-1)"
    )
    zh = translate(text, "zh_CN")
    assert zh.startswith(f"{path}: 无法按 utf-8 or gb18030 解码") and "gb18030、utf-16" in zh
    # a quoted reason inside a sentence is itself translated
    zh = translate(
        "cut.csv: nothing imported: all 1,234 rows were quarantined, 1,200 as 'unparsable time'",
        "zh_CN",
    )
    assert (
        zh == "cut.csv: 未导入任何内容：全部 1,234 行均被隔离，其中 1,200 行原因为“无法解析的时间”"
    )


def test_a_text_without_an_entry_stays_english_and_whole():
    text = "a message no catalog entry knows (42 rows, 'x.csv')"
    assert translate(text, "zh_CN") == text
    assert translate("the file is empty", "en") == "the file is empty"  # no core_en.json


@pytest.mark.parametrize(
    "text",
    [
        # h171's new texts (operator test 4), as its branch wrote them on 2026-12-05
        "line 665, the file's last line, has 5 of 12 fields: the file may be cut short (still "
        "being written or copied when it was read); open it again once it is complete",
        "66,092 of 66,763 rows carry a bearing ('bearing_rad') and no position: a bearing-only "
        "sensor's (a camera's), quarantined here; read them with `wakeline bearing` (in the "
        "window: File > Open bearings); empty scans (nothing detected): 671",
        "a bearing ('bearing_rad') and no position: a bearing-only sensor's row; read these rows "
        "with `wakeline bearing` (in the window: File > Open bearings)",
        "an empty scan (no position, no bearing: nothing detected)",
        "3,320 values were written with a decimal comma and read as decimal numbers "
        "(12,6219 as 12.6219)",
        "the times in 'Date/Time' are whole minutes and 3,000 rows share a minute with their "
        "track's row before: were the seconds lost (Excel saves m/d/yyyy h:mm)? Export the file "
        "again with seconds; clean keeps only the first row of each time",
        "the dates in 'Date/Time' were read month first (m/d/yyyy) because the times use a "
        "12-hour clock with AM/PM (3,300 of them), as US exports (Excel en-US) write, and no "
        "date shows the order (no number above 12 in either place): if the day comes first, "
        "read again with --date-order day-first",
    ],
)
def test_the_new_operator_test_4_texts_are_in_chinese(text):
    zh = translate(window_words(text), "zh_CN")
    assert not english_left(zh), zh
    for number in re.findall(r"\d[\d,.]*\d", text):
        assert number in zh, (number, zh)


def test_every_layout_name_is_in_chinese():
    for fmt in FORMATS:
        assert not english_left(translate(fmt.label, "zh_CN")), fmt.label


def test_the_catalog_entries_fill_with_their_own_groups():
    """Each template names only its pattern's groups; each pattern compiles."""
    entries = json.loads((translations_dir() / "core_zh_CN.json").read_text("utf-8"))["entries"]
    assert len(entries) == len(catalog("zh_CN")) > 80
    for e in entries:
        groups = set(re.compile(e["en"]).groupindex)
        names = set(re.findall(r"\{(\w+)[?}]", e["zh"]))
        assert names <= groups, e["id"]
        assert len({x["id"] for x in entries}) == len(entries)


def test_clean_rule_names_are_phrases_the_window_translates():
    """The clean summary's rule names ("speed 23, turn 33, short_tracks 8") are phrases of
    their own: English on the command line as before, Chinese in the window."""
    from wakeline.app.i18n import TsTranslator
    from wakeline.core.pipeline import _summary_clean
    from wakeline.core.words import CONTEXT, render

    class Res:
        report = {
            "points_in": 245,
            "points_out": 181,
            "tracks_out": 5,
            "rules": {
                "speed": {"removed": 23},
                "turn": {"removed": 33},
                "short_tracks": {"removed": 8},
                "smooth": {"changed": 4},
            },
        }

    text = _summary_clean(Res())
    assert str(text) == (
        "kept 181 of 245 points in 5 tracks; removed 64 (speed 23, turn 33, short_tracks 8); "
        "changed 4 (smooth 4)"
    )
    table = TsTranslator(translations_dir() / "wakeline_zh_CN.ts")
    zh = render(text, lambda t: table.translate(CONTEXT, t))
    assert "速度跳变 23，转向异常 33，短航迹 8" in zh and "平滑 4" in zh, zh


def test_the_status_bars_progress_texts_are_in_chinese():
    for en, zh in [
        ("reading ais_2024.csv", "正在读取 ais_2024.csv"),
        ("reading log.nmea (AIS NMEA)", "正在读取 log.nmea（AIS NMEA）"),
        ("cleaning: 3 of 12 blocks done", "清洗：已完成 12 块中的 3 块"),
        ("short_tracks", "短航迹"),
        ("cleaned", "已清洗"),
        ("clean", "清洗"),  # a step's name in "clean on demo.csv"
        ("associate", "单源关联"),
    ]:
        assert translate(en, "zh_CN") == zh


#: The 15 most frequent import warnings and the 15 most frequent quarantine reasons of the
#: import tests (test_bad_input, test_import, test_headerless, test_date_order,
#: test_excel_days, test_import_title_lines, test_import_units, test_import_swapped_positions,
#: test_import_not_available, test_import_integrity, test_decoding_mixed, test_time_texts,
#: test_compressed, test_local_plane: every read_points report recorded, 2026-12-05, h173),
#: one text of each kind.
TOP_TEXTS = [
    "16 values were written with a decimal comma (like 57,6671) and read as decimal numbers (57.6671)",
    "the times in 'timestamp' write the month first (mm/dd/yyyy: 60 have a second number above 12, none a first): read so (--date-order month-first says it outright)",
    "no batch column: the file is one track named after the file (if a column holds each track's id, map it: --map batch=COLUMN)",
    "2 track(s) start their time again within the file (batch 265041000: 4 runs, each going forward, the next starting at least 10 min earlier): several passes or ships may share one id in 'mmsi'; they are joined into one track sorted by time. If a column tells them apart, map it: --map batch=COLUMN, or --map sensor=COLUMN",
    "the dates in 'time' were read day first (dd/mm/yyyy), but none shows which comes first (45 could be mm/dd/yyyy, no number above 12 in either place): check the dates; if the month comes first, read again with --date-order month-first",
    "text encoding: 15 lines not valid utf-8 were read as Windows-1252 (Latin-1) (lines 17, 18, 19, 20, 21, …); if that is wrong, give the file's encoding (--encoding, e.g. gb18030, utf-16, latin-1)",
    "some bytes are not valid utf-8: their rows are quarantined (give the right --encoding to read them)",
    "quotes do not balance (a quoted cell ran over line ends): the file was read line by line, quoted cells unquoted",
    "6 of 12 rows have a bearing in 'bearing_rad' beyond a full turn (±2π: the header says radians): quarantined",
    "times in 'time' are seconds from a scene start (relative), kept as such: shown from 1970-01-01T00:00:00Z",
    "2 of 10 rows have a bearing in 'Bearing (deg)' beyond a full turn (±360°): quarantined",
    "the times in 'Time' are clock times: each joined with its row's date in 'Date'",
    "60 times in 'time' were read as Excel serial days (1900 date system: 45658.5 is 2025-01-01 12:00) because all lie in 20,000-80,000, 100% have a fraction and the typical step is 10 s as days; if they are seconds, read again with --time-unit seconds",
    "column 'lat' (read as latitude) is beyond ±90° in most rows while 'lon' lies within ±90° (lat_beyond_90_lon_within in the report counts them): the columns look swapped (longitudes under 'lat'); every row is quarantined (none is kept at a mirrored place). If so, import again with --map lat=lon --map lon=lat",
    "time outside 1677-2262 (more than a ns clock holds)",
    "unparsable lon",
    "lat out of range",
    "in a file whose lat and lon columns look swapped",
    "time days from the rest of its track, at its start or end, where the file has no other track (a mistyped date?)",
    "unparsable time",
    "position not available (lon 181 / lat 91)",
    "bearing beyond ±2π ('bearing_rad', radians)",
    "too many fields: 6 of 5",
    "short row: 4 of 5 fields",
    "bytes not valid utf-8",
    "bearing beyond ±360° ('Bearing (deg)', degrees)",
    "not an AIS sentence (!AIVDM, !AIVDO or another AIS talker's VDM/VDO)",
    "bad NMEA checksum",
    "no receive time (no leading time stamp or tag block c:)",
    "incomplete multi-part message",
]


@pytest.mark.parametrize("text", TOP_TEXTS)
def test_the_test_suites_most_frequent_warnings_and_reasons_are_in_chinese(text):
    zh = translate(window_words(text), "zh_CN")
    assert zh != text and not english_left(zh), zh
    for number in re.findall(r"\d[\d,]*\d", text):
        assert number in zh, (number, zh)


@pytest.mark.gui
def test_a_chinese_window_shows_the_cores_messages_in_chinese(window, tmp_path, monkeypatch):
    """Operator test 4 (h168 png/gui_zh_CN.png): the open-failed box, the log's quarantine
    reason, warnings and layout name, the import report's reason column, in zh_CN."""
    pytest.importorskip("pytestqt")
    from PySide6 import QtWidgets

    from conftest import load
    from wakeline.app.dialogs import ImportReportDialog

    boxes = []
    monkeypatch.setattr(QtWidgets.QMessageBox, "warning", lambda *a: boxes.append(a[2]))
    path = tmp_path / "cut.csv"
    rows = "".join(f"1,{t},55.{t:03d},12.{t:03d},3\n" for t in range(10, 200, 10))
    path.write_text("mmsi,time,lat,lon,sog\n" + rows + "1,200,55", encoding="utf-8")
    window.set_language("zh_CN")
    try:
        lid = load(window, path)
        load(window, tmp_path / "nothere.csv")
        log = window.log.toPlainText()
        assert "行过短：3 个字段（应为 5 个）" in log, log
        assert "'time' 列的时间是从场景开始起算的秒数" in log, log
        assert "通用 CSV（按列名识别）" in log, log
        assert boxes and boxes[-1].endswith("nothere.csv: 文件不存在"), boxes
        dialog = ImportReportDialog(window.session.layers[lid], window)
        model = dialog.table.model()
        assert model.index(0, 1).data() == "行过短：3 个字段（应为 5 个）"
        dialog.close()
    finally:
        window.set_language("en")
    load(window, tmp_path / "nothere.csv")
    assert window.log.toPlainText().rstrip().endswith("nothere.csv: no such file")


def test_a_steps_refusal_and_the_bearing_summary_are_in_chinese():
    assert (
        translate(
            "multi-sensor association needs tracks of at least two sensors; found R1", "zh_CN"
        )
        == "多源关联需要至少两个传感器的航迹；只找到：R1"
    )
    zh = translate(
        "1,200 lines: 1,100 bearings in 3 series; 100 quarantined: missing time", "zh_CN"
    )
    assert zh == "1,200 行：3 个序列中共 1,100 个方位；隔离 100 行：缺少时间"


def test_a_refused_files_reason_is_translated_inside_matched_quotes():
    """Operator test 9, D12: the zh window showed "…原因为“time zone CST is ambiguous (…):
    give the zone with the import dialog"s Time zone field'": the reason English, cut at
    the apostrophe of "dialog's", opened with “ and closed with '."""
    for word, zones in AMBIGUOUS_ZONES.items():
        reason = f"time zone {word} is ambiguous ({zones}): give the zone with --tz"
        for n in (1, 13341):
            text = nothing_imported({"rows_read": n, "quarantine_reasons": {reason: n}}, "f.csv")
            zh = translate(window_words(text), "zh_CN")
            assert not english_left(zh), zh
            assert zh.count("“") == zh.count("”") == 1 and "'" not in zh, zh
            assert zh.endswith("”") and f"时区 {word} 有歧义" in zh, zh
            assert all(off in zh for off in re.findall(r"[+-]\d\d:\d\d", zones)), zh
            assert not re.search(r"[A-Za-z]{3,}", zh.replace(word, "").replace("f.csv", "")), zh
