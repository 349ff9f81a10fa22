"""Time texts with words (h134): month names in German, French, Spanish, Portuguese,
Italian, Dutch, Norwegian, Swedish and Danish (``01-Mär-2024``, ``1 janv. 2024``,
``15 de enero de 2024``); zone words after a time (``CET``, ``EST``, ``UTC+8``,
``GMT+01:00``; ``CST`` ambiguous); core/io/timetext.py, docs/import.md."""

import numpy as np
import pandas as pd
import pyarrow as pa
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.test_import_spaced_pipe_nmea import _lines_accounted, _three_ways
from wakeline.core.io import read_points
from wakeline.core.io.reader import parse_times

_SETTINGS = settings(
    max_examples=80, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)

#: Each language's months as its locale writes them: (full names, abbreviations).
LANGUAGES = {
    "de": (
        "Januar Februar März April Mai Juni Juli August September Oktober November Dezember",
        "Jan Feb Mär Apr Mai Jun Jul Aug Sep Okt Nov Dez",
    ),
    "fr": (
        "janvier février mars avril mai juin juillet août septembre octobre novembre décembre",
        "janv. févr. mars avr. mai juin juil. août sept. oct. nov. déc.",
    ),
    "es": (
        "enero febrero marzo abril mayo junio julio agosto septiembre octubre noviembre diciembre",
        "ene feb mar abr may jun jul ago sep oct nov dic",
    ),
    "pt": (
        "janeiro fevereiro março abril maio junho julho agosto setembro outubro novembro dezembro",
        "jan fev mar abr mai jun jul ago set out nov dez",
    ),
    "it": (
        "gennaio febbraio marzo aprile maggio giugno luglio agosto settembre ottobre novembre "
        "dicembre",
        "gen feb mar apr mag giu lug ago set ott nov dic",
    ),
    "nl": (
        "januari februari maart april mei juni juli augustus september oktober november december",
        "jan feb mrt apr mei jun jul aug sep okt nov dec",
    ),
    "no": (
        "januar februar mars april mai juni juli august september oktober november desember",
        "jan feb mar apr mai jun jul aug sep okt nov des",
    ),
    "sv": (
        "januari februari mars april maj juni juli augusti september oktober november december",
        "jan feb mar apr maj jun jul aug sep okt nov dec",
    ),
    "da": (
        "januar februar marts april maj juni juli august september oktober november december",
        "jan feb mar apr maj jun jul aug sep okt nov dec",
    ),
}
#: Layouts of a date with a month word ({d} day, {mon} the word, {y} year, {t} clock).
FORMS = ["{d}-{mon}-{y} {t}", "{d} {mon} {y} {t}", "{d}. {mon} {y} {t}", "{y}-{mon}-{d} {t}"]


def _cell(t: pd.Timestamp, lang: str, full: bool, form: str, upper: bool) -> str:
    words = LANGUAGES[lang][0 if full else 1].split()
    if lang in ("es", "pt") and form == "{d} {mon} {y} {t}":
        form = "{d} de {mon} de {y} {t}"
    cell = form.format(d=t.day, mon=words[t.month - 1], y=t.year, t=f"{t:%H:%M:%S}")
    return cell.upper() if upper else cell


def test_the_forms_the_brief_names(tmp_path, monkeypatch):
    cells = [
        "01-Mär-2024 00:00:05",
        "1 janv. 2024 00:00:05",
        "15 de enero de 2024 00:00:05",
        "1er février 2024 10:00",
        "3. März 2024 10:00:00",
        "15 de fevereiro de 2024 10:00:00",
        "15-MÄR-24 10.00.05",
        "2024-déc-15 10:00:00",
        "15 mrt 2024 10:00",
        "15. desember 2024 10:00",
        "15 dicembre 2024 10:00:00",
        "15 Mai 2024 10:00:00 +0200",
    ] * 3
    want = [
        "2024-03-01 00:00:05",
        "2024-01-01 00:00:05",
        "2024-01-15 00:00:05",
        "2024-02-01 10:00:00",
        "2024-03-03 10:00:00",
        "2024-02-15 10:00:00",
        "2024-03-15 10:00:05",
        "2024-12-15 10:00:00",
        "2024-03-15 10:00:00",
        "2024-12-15 10:00:00",
        "2024-12-15 10:00:00",
        "2024-05-15 08:00:00",
    ] * 3
    src = tmp_path / "m.csv"
    src.write_text(
        # a track per row: the months apart are no mistyped dates
        "time,id,lat,lon\n" + "".join(f"{c},{k},37.{k:04d},23.6\n" for k, c in enumerate(cells))
    )
    r = _three_ways(src, tmp_path, monkeypatch, size=200)
    assert r.report["rows_quarantined"] == 0
    assert r.report["time_format"] == "month-name text"
    got = r.points.sort_values("lat")["time"].tolist()
    assert got == [pd.Timestamp(w, tz="UTC") for w in want]


def test_an_unknown_month_word_is_quarantined_alone(tmp_path):
    src = tmp_path / "m.csv"
    src.write_text(
        "time,id,lat,lon\n15 janv. 2024 10:00,1,37.9,23.6\n15 foo. 2024 10:00,1,37.9,23.6\n"
    )
    r = read_points(src)
    _lines_accounted(r, src)
    assert r.quarantine["reason"].tolist() == ["unparsable time"]


@_SETTINGS
@given(
    seconds=st.lists(st.integers(0, 40 * 365 * 86_400), min_size=1, max_size=12, unique=True),
    lang=st.sampled_from(sorted(LANGUAGES)),
    full=st.booleans(),
    form=st.sampled_from(FORMS),
    upper=st.booleans(),
)
def test_month_names_read_back_any_time_in_any_language(seconds, lang, full, form, upper):
    times = [pd.Timestamp("2000-01-01", tz="UTC") + pd.Timedelta(seconds=s) for s in seconds]
    cells = [_cell(t, lang, full, form, upper) for t in times]
    ns, ok = parse_times(pa.chunked_array([pa.array(cells)]), "auto")
    assert ok.all(), cells
    assert (np.asarray(ns) == np.array([t.value for t in times])).all(), cells


@pytest.mark.parametrize("lang", sorted(LANGUAGES))
def test_every_month_of_every_language(lang):
    for full in (True, False):
        words = LANGUAGES[lang][0 if full else 1].split()
        cells = [f"15 {w} 2024 10:00" for w in words]
        ns, ok = parse_times(pa.chunked_array([pa.array(cells)]), "auto")
        assert ok.all(), cells
        got = pd.to_datetime(np.asarray(ns), utc=True).month.tolist()
        assert got == list(range(1, 13)), (lang, full)


# --- zone words after a time ---------------------------------------------------------


def test_zone_words_and_offsets_after_a_time(tmp_path, monkeypatch):
    cells = {
        "2024-01-01 00:00:05 CET": "2023-12-31 23:00:05",
        "2024-07-01 00:00:05 CEST": "2024-06-30 22:00:05",
        "2024-01-01 00:00:05 EST": "2024-01-01 05:00:05",
        "2024-07-01 00:00:05 EDT": "2024-07-01 04:00:05",
        "2024-01-01 00:00:05 PST": "2024-01-01 08:00:05",
        "2024-01-01 00:00:05 JST": "2023-12-31 15:00:05",
        "2024-01-01 00:00:05 UTC+8": "2023-12-31 16:00:05",
        "2024-01-01 00:00:05 GMT+01:00": "2023-12-31 23:00:05",
        "2024-01-01 00:00:05 utc-0330": "2024-01-01 03:30:05",
        "2024-01-01 00:00:05 Z": "2024-01-01 00:00:05",
        "2024-01-01T00:00:05 (CET)": "2023-12-31 23:00:05",
        "01-Jan-2024 00:00:05 CET": "2023-12-31 23:00:05",
        "1 janv. 2024 12:00 PM EST": "2024-01-01 17:00:00",
        "Mon Jan  1 00:00:05 CET 2024": "2023-12-31 23:00:05",
    }
    src = tmp_path / "z.csv"
    src.write_text(
        "time,id,lat,lon\n"
        + "".join(f"{c},{k},37.{k:04d},23.6\n" for k, c in enumerate(list(cells) * 2))
    )
    r = _three_ways(src, tmp_path, monkeypatch, size=200)
    assert r.report["rows_quarantined"] == 0, r.quarantine
    got = r.points.sort_values("lat")["time"].tolist()
    assert got == [pd.Timestamp(w, tz="UTC") for w in list(cells.values()) * 2]
    assert any("end in a zone word" in w for w in r.report["warnings"])
    # --tz for the times without a word; those with one keep theirs
    r = read_points(src, tz="Asia/Tokyo")
    got = r.points.sort_values("lat")["time"].tolist()
    assert got == [pd.Timestamp(w, tz="UTC") for w in list(cells.values()) * 2]
    assert any("--tz applies only to the times without one" in w for w in r.report["warnings"])


def test_an_ambiguous_zone_word_is_refused_without_tz_and_read_in_it(tmp_path, monkeypatch):
    src = tmp_path / "cst.csv"
    lines = [f"2024-01-01 00:{k:02d}:00 CST,1,37.{k:04d},23.6" for k in range(20)]
    lines[3] = "2024-01-01 00:03:00 CET,1,37.0003,23.6"
    lines[5] = "2024-01-01 00:05:00 XYZ,1,37.0005,23.6"  # no zone: unparsable as before
    src.write_text("time,id,lat,lon\n" + "\n".join(lines) + "\n")
    r = _three_ways(src, tmp_path, monkeypatch, size=200)
    _lines_accounted(r, src)
    assert len(r.points) == 1  # the CET row
    reasons = r.quarantine.set_index("line")["reason"]
    assert reasons[7] == "unparsable time"
    assert reasons[2] == (
        "time zone CST is ambiguous (US Central -06:00, China +08:00, Cuba -05:00): "
        "give the zone with --tz"
    )
    assert (reasons.drop([4, 7], errors="ignore").str.startswith("time zone CST")).all()
    r = read_points(src, tz="Asia/Shanghai")
    assert len(r.points) == 19 and r.quarantine["line"].tolist() == [7]
    assert r.points["time"].iloc[0] == pd.Timestamp("2023-12-31 16:00:00", tz="UTC")
    assert any("CST" in w and "read in --tz Asia/Shanghai" in w for w in r.report["warnings"])


@_SETTINGS
@given(
    seconds=st.lists(st.integers(0, 40 * 365 * 86_400), min_size=1, max_size=12, unique=True),
    word=st.sampled_from(["CET", "CEST", "EST", "EDT", "PST", "PDT", "JST", "AEST", "NZDT"]),
    form=st.sampled_from(
        ["%Y-%m-%d %H:%M:%S {w}", "%d-%b-%Y %H:%M:%S {w}", "%Y-%m-%dT%H:%M:%S{w}"]
    ),
)
def test_zone_words_read_back_any_time(seconds, word, form):
    from wakeline.core.io.timetext import ZONE_WORDS

    times = [pd.Timestamp("2000-01-01", tz="UTC") + pd.Timedelta(seconds=s) for s in seconds]
    offset = pd.Timedelta(hours=int(ZONE_WORDS[word][:3]), minutes=int(ZONE_WORDS[word][4:]))
    cells = [(t + offset).strftime(form.format(w=" " + word)) for t in times]
    ns, ok = parse_times(pa.chunked_array([pa.array(cells)]), "auto")
    assert ok.all(), cells
    assert (np.asarray(ns) == np.array([t.value for t in times])).all(), cells


@_SETTINGS
@given(
    seconds=st.integers(0, 40 * 365 * 86_400),
    hours=st.integers(-12, 14),
    minutes=st.sampled_from([0, 30, 45]),
    word=st.sampled_from(["UTC", "GMT", "utc"]),
    colon=st.booleans(),
)
def test_utc_offsets_read_back_any_time(seconds, hours, minutes, word, colon):
    t = pd.Timestamp("2000-01-01", tz="UTC") + pd.Timedelta(seconds=seconds)
    sign = "-" if hours < 0 else "+"
    offset = pd.Timedelta(hours=abs(hours), minutes=minutes) * (-1 if hours < 0 else 1)
    tail = f"{sign}{abs(hours)}" + (f"{':' if colon else ''}{minutes:02d}" if minutes else "")
    cell = f"{(t + offset):%Y-%m-%d %H:%M:%S} {word}{tail}"
    ns, ok = parse_times(pa.chunked_array([pa.array([cell])]), "auto")
    assert ok.all(), cell
    assert ns[0] == t.value, cell


def test_austrian_january_and_a_dotted_month_between_year_and_day():
    cells = ["01-Jän-2024 00:00:05", "1. Jänner 2024 00:00:05", "2024-janv.-01 00:00:05"]
    ns, ok = parse_times(pa.chunked_array([pa.array(cells)]), "auto")
    assert ok.all()
    assert set(np.asarray(ns)) == {pd.Timestamp("2024-01-01 00:00:05", tz="UTC").value}
