"""Public track captures in layouts the importer had not met (h120): the Brest set's
``sourcemmsi``, a radar's ``TN,UTC,LAT,LON,SPD,CRS``, ogr2ogr's GPX ``track_fid``, a
French ``Date;Heure`` pair with day-first dates, headers in German, French, Spanish,
Portuguese, Italian, Norwegian, Russian, Japanese and Korean, and an id column that only
its values show. Every file: rows read = points + quarantined, the tracks, the times,
the speeds and courses."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wakeline.core.errors import InputError
from wakeline.core.io import read_points
from wakeline.core.io.export_like import write_layout
from wakeline.core.io.formats import guess_columns
from wakeline.core.io.layout import describe_layout
from wakeline.core.io.reader import import_to_csv

T0 = pd.Timestamp("2020-09-13T12:00:00Z")


def _fixes(n: int = 20, ships: int = 2) -> pd.DataFrame:
    """``n`` fixes of ``ships`` ships, interleaved, one a minute."""
    k = np.arange(n)
    return pd.DataFrame(
        {
            "mmsi": 227_000_000 + (k % ships),
            "time": [T0 + pd.Timedelta(minutes=int(i)) for i in k],
            "lat": 48.3 + 0.0005 * k,
            "lon": -4.5 + 0.001 * k,
            "speed": 10.0 + 0.1 * (k % 7),
            "course": (90 + k) % 360,
        }
    )


def _write(path, header: list[str], rows: list[list[str]], delim: str = ","):
    path.write_text(delim.join(header) + "\n" + "".join(delim.join(r) + "\n" for r in rows))
    return path


def _check(res, fx: pd.DataFrame, ships: int) -> None:
    rep = res.report
    assert rep["rows_read"] == len(fx) == rep["rows_imported"] + rep["rows_quarantined"]
    assert rep["rows_quarantined"] == 0, rep["quarantine_reasons"]
    assert res.points["batch"].nunique() == ships
    got = res.points.sort_values("time").reset_index(drop=True)
    assert list(got["time"]) == list(fx["time"])
    assert np.allclose(got["speed"], fx["speed"]) and np.allclose(got["course"], fx["course"])


def test_the_brest_sourcemmsi_is_the_track_id(tmp_path):
    fx = _fixes()
    rows = [
        [str(r.mmsi), "0", "0", f"{r.speed:.1f}", str(r.course), "511", f"{r.lon:.6f}"]
        + [f"{r.lat:.6f}", str(int(r.time.timestamp()))]
        for r in fx.itertuples()
    ]
    head = "sourcemmsi,navigationalstatus,rateofturn,speedoverground,courseoverground"
    path = _write(
        tmp_path / "nari_dynamic.csv", [*head.split(","), "trueheading", "lon", "lat", "t"], rows
    )
    res = read_points(path)
    assert res.report["columns"]["batch"] == "sourcemmsi"
    assert not any("no batch column" in w for w in res.report["warnings"])
    _check(res, fx, 2)


@pytest.mark.parametrize(
    "names",
    [
        ["TN", "UTC", "LAT", "LON", "SPD", "CRS"],  # a radar's track number
        ["track_fid", "time", "latitude", "longitude", "speed", "course"],  # ogr2ogr GPX
        ["vessel_mmsi", "time", "lat", "lon", "sog", "cog"],
        ["Track Nr", "Time", "Lat", "Lon", "Speed over ground", "Course over ground"],
        ["TRK", "time", "lat", "lon", "spd", "crs"],
        ["tno", "time", "lat", "lon", "speed", "course"],
    ],
)
def test_track_numbers_speeds_and_courses_by_their_names(tmp_path, names):
    fx = _fixes(30, 3)
    rows = [
        [str(r.mmsi % 1000), r.time.strftime("%Y-%m-%d %H:%M:%S"), f"{r.lat:.6f}"]
        + [f"{r.lon:.6f}", f"{r.speed:.1f}", str(r.course)]
        for r in fx.itertuples()
    ]
    res = read_points(_write(tmp_path / "radar.csv", names, rows))
    assert res.report["columns"]["batch"] == names[0]
    assert (res.report["columns"]["speed"], res.report["columns"]["course"]) == tuple(names[4:])
    _check(res, fx, 3)


def test_the_receivers_mmsi_and_a_count_of_mmsis_are_no_track_id():
    assert "batch" not in guess_columns(["receiver_mmsi", "time", "lat", "lon"])[0]
    assert "batch" not in guess_columns(["own_mmsi", "time", "lat", "lon"])[0]
    assert "batch" not in guess_columns(["n_shared_mmsi", "time", "lat", "lon"])[0]
    # a name of the synonyms wins over one of the patterns
    assert guess_columns(["sourcemmsi", "MMSI", "time", "lat", "lon"])[0]["batch"] == "MMSI"


def _unnamed_id(tmp_path, name: str, values) -> tuple:
    fx = _fixes(24, 3)
    rows = [
        [values(r), r.time.isoformat(), f"{r.lat:.6f}", f"{r.lon:.6f}", f"{r.speed:.1f}"]
        + [str(r.course)]
        for r in fx.itertuples()
    ]
    path = _write(tmp_path / "x.csv", [name, "time", "lat", "lon", "speed", "course"], rows)
    return path, fx


def test_an_mmsi_column_no_name_says_is_adopted_with_a_warning(tmp_path):
    path, fx = _unnamed_id(tmp_path, "UserID", lambda r: str(r.mmsi))
    res = read_points(path)
    assert res.report["columns"]["batch"] == "UserID"
    (note,) = [w for w in res.report["warnings"] if "'UserID'" in w]
    assert "MMSI-like" in note and "read as the batch" in note
    _check(res, fx, 3)
    # streamed as wakeline import reads it: the same
    out = tmp_path / "o.csv"
    rep = import_to_csv(path, out).report
    assert rep["columns"]["batch"] == "UserID"
    assert pd.read_csv(out)["batch"].nunique() == 3


def test_ids_by_their_values_are_named_when_not_adopted(tmp_path):
    # short codes (a call sign): named with the --map that reads them, not adopted
    path, fx = _unnamed_id(tmp_path, "callsign", lambda r: f"LX{r.mmsi % 10}A")
    res = read_points(path)
    assert res.report["columns"]["batch"] == "(file name)"
    (note,) = [w for w in res.report["warnings"] if "no batch column" in w]
    assert "'callsign'" in note and "--map batch=callsign" in note
    assert read_points(path, mapping=["batch=callsign"]).points["batch"].nunique() == 3
    # a name with a blank: the flag quoted as a shell takes it
    path, _ = _unnamed_id(tmp_path, "Ship code", lambda r: f"S{r.mmsi % 10}")
    note = next(w for w in read_points(path).report["warnings"] if "no batch column" in w)
    assert "--map 'batch=Ship code'" in note
    # two MMSI-like columns: neither is adopted, both are named, the first first
    fx = _fixes(24, 3)
    rows = [
        [str(r.mmsi), str(r.mmsi + 5), r.time.isoformat(), f"{r.lat:.6f}", f"{r.lon:.6f}"]
        for r in fx.itertuples()
    ]
    path = _write(tmp_path / "two.csv", ["a", "b", "time", "lat", "lon"], rows)
    res = read_points(path)
    assert res.report["columns"]["batch"] == "(file name)"
    note = next(w for w in res.report["warnings"] if "no batch column" in w)
    assert note.index("--map batch=a") < note.index("--map batch=b")


def test_nine_digit_numbers_that_run_forward_are_named_not_adopted(tmp_path):
    # seconds of 1990 that a radar scan's tracks share (repeating, running forward)
    fx = _fixes(24, 3)
    rows = [
        [str(631_152_000 + 60 * (k // 3)), r.time.isoformat(), f"{r.lat:.6f}", f"{r.lon:.6f}"]
        for k, r in enumerate(fx.itertuples())
    ]
    res = read_points(_write(tmp_path / "scan.csv", ["scan", "time", "lat", "lon"], rows))
    assert res.report["columns"]["batch"] == "(file name)"
    assert any("--map batch=scan" in w for w in res.report["warnings"])


def test_a_time_position_or_speed_is_never_taken_for_the_id(tmp_path):
    # nine-digit Unix seconds (1990) that run forward, one per row: not an id
    fx = _fixes(24, 3)
    rows = [
        [str(631_152_000 + 60 * k), r.time.isoformat(), f"{r.lat:.6f}", f"{r.lon:.6f}", "7", "90"]
        for k, r in enumerate(fx.itertuples())
    ]
    path = _write(tmp_path / "s.csv", ["stamp", "time", "lat", "lon", "speed", "course"], rows)
    res = read_points(path)
    assert res.report["columns"]["batch"] == "(file name)"
    note = next(w for w in res.report["warnings"] if "no batch column" in w)
    for name in ("stamp", "speed", "course", "lat", "lon", "time"):
        assert f"batch={name}" not in note


def _date_clock_rows(fx, date_fmt: str, decimal: str = ".") -> list[list[str]]:
    return [
        [r.time.strftime(date_fmt), r.time.strftime("%H:%M:%S")]
        + [f"{r.lat:.6f}".replace(".", decimal), f"{r.lon:.6f}".replace(".", decimal)]
        + [f"{r.speed:.1f}".replace(".", decimal), str(r.course), str(r.mmsi)]
        for r in fx.itertuples()
    ]


def test_the_french_date_and_heure_with_day_first_dates(tmp_path):
    # every row was quarantined "unparsable time": Heure unknown, and a day-first date
    # alone did not parse
    fx = _fixes()
    names = ["Date", "Heure", "Latitude", "Longitude", "Vitesse", "Cap", "MMSI"]
    path = _write(tmp_path / "fr.csv", names, _date_clock_rows(fx, "%d/%m/%Y", ","), ";")
    res = read_points(path)
    assert res.report["columns"]["time"] == "Heure" and res.report["time_date_column"] == "Date"
    assert res.report["columns"]["course"] == "Cap"
    _check(res, fx, 2)
    # and written back as it came (the date and the clock apart)
    layout = describe_layout(path, res.report)
    out = tmp_path / "back.csv"
    write_layout(res.points, layout, out)
    assert out.read_text() == path.read_text()


@pytest.mark.parametrize("clock_first", [False, True])
def test_a_clock_column_beside_the_date_is_joined_whatever_its_name(tmp_path, clock_first):
    fx = _fixes()
    rows = _date_clock_rows(fx, "%d.%m.%Y")
    names = ["Date", "Moment", "lat", "lon", "speed", "course", "mmsi"]
    if clock_first:
        rows = [[r[1], r[0], *r[2:]] for r in rows]
        names = ["Moment", "Date", *names[2:]]
    res = read_points(_write(tmp_path / "d.csv", names, rows))
    assert res.report["columns"]["time"] == "Moment"
    assert res.report["time_date_column"] == "Date"
    assert any("joined with its row's date in 'Date'" in w for w in res.report["warnings"])
    _check(res, fx, 2)
    # the operator's choice of the date column stays: every fix at midnight
    got = read_points(_write(tmp_path / "d.csv", names, rows), mapping=["time=Date"])
    assert got.report["columns"]["time"] == "Date" and got.report["rows_quarantined"] == 0


def test_a_day_first_date_alone_reads_as_midnight(tmp_path):
    # 13/09/2020 alone was "unparsable time" where 2020-09-13 read as midnight
    rows = [["13/09/2020", "1", "48.1", "-4.5"], ["14.09.2020", "1", "48.2", "-4.4"]]
    res = read_points(_write(tmp_path / "d.csv", ["Date", "id", "lat", "lon"], rows))
    assert res.report["rows_quarantined"] == 0
    assert list(res.points["time"]) == [
        pd.Timestamp("2020-09-13T00:00:00Z"),
        pd.Timestamp("2020-09-14T00:00:00Z"),
    ]


#: Headers per language: (date or date-time, clock or None, lat, lon, speed, course, id).
LANGUAGES = {
    "german": ("Datum", "Uhrzeit", "Breite", "Länge", "Geschwindigkeit (kn)", "Kurs", "Kennung"),
    "german_grad": ("Zeitstempel", None, "Breitengrad", "Längengrad", "Fahrt", "Kurs", "MMSI"),
    "french": ("Horodatage", None, "Latitude", "Longitude", "Vitesse", "Route", "Navire"),
    "spanish": ("Fecha", "Hora", "Latitud", "Longitud", "Velocidad", "Rumbo", "MMSI"),
    "portuguese": ("Data", "Hora", "Latitude", "Longitude", "Velocidade", "Rumo", "Navio"),
    "italian": ("Data", "Ora", "Latitudine", "Longitudine", "Velocità", "Rotta", "MMSI"),
    "norwegian": ("tidspunkt", None, "breddegrad", "lengdegrad", "fart", "kurs", "mmsi"),
    "norwegian_tid": ("dato", "tid", "breddegrad", "lengdegrad", "fart", "kurs", "mmsi"),
    "russian": ("дата", "время", "широта", "долгота", "скорость", "курс", "судно"),
    "japanese": ("日付", "時刻", "緯度", "経度", "速力", "針路", "船舶"),
    "korean": ("날짜", "시간", "위도", "경도", "속력", "침로", "선박"),
}


def _language_file(path, lang: str, fx: pd.DataFrame, delim: str = ",", date_fmt="%d.%m.%Y"):
    day, clock, lat, lon, speed, course, ident = LANGUAGES[lang]
    names = [day, *([clock] if clock else []), lat, lon, speed, course, ident]
    rows = []
    for r in fx.itertuples():
        when = (
            [r.time.strftime(date_fmt), r.time.strftime("%H:%M:%S")]
            if clock
            else [r.time.strftime("%Y-%m-%dT%H:%M:%SZ")]
        )
        rows.append(
            [*when, f"{r.lat:.6f}", f"{r.lon:.6f}", f"{r.speed:.1f}", str(r.course), str(r.mmsi)]
        )
    path.write_text(
        delim.join(names) + "\n" + "".join(delim.join(r) + "\n" for r in rows), encoding="utf-8"
    )
    return path, names


@pytest.mark.parametrize("lang", sorted(LANGUAGES))
def test_headers_in_other_languages(tmp_path, lang):
    fx = _fixes(30, 3)
    path, names = _language_file(tmp_path / f"{lang}.csv", lang, fx)
    res = read_points(path)
    cols = res.report["columns"]
    assert (cols["lat"], cols["lon"]) == (names[-5], names[-4])
    assert (cols["speed"], cols["course"], cols["batch"]) == tuple(names[-3:])
    if LANGUAGES[lang][1]:
        assert (cols["time"], res.report["time_date_column"]) == (names[1], names[0])
    _check(res, fx, 3)


def test_ambiguous_words_are_taken_only_with_fitting_values(tmp_path):
    fx = _fixes(10, 2)
    # German Länge/Breite are the ship's length and beam here: Lat/Lon are the position
    rows = [
        [r.time.isoformat(), str(r.mmsi), f"{r.lat:.5f}", f"{r.lon:.5f}", "120", "20"]
        for r in fx.itertuples()
    ]
    path = _write(tmp_path / "dim.csv", ["time", "mmsi", "Lat", "Lon", "Länge", "Breite"], rows)
    res = read_points(path)
    assert (res.report["columns"]["lat"], res.report["columns"]["lon"]) == ("Lat", "Lon")
    assert {"Länge", "Breite"} <= set(res.report["extra_columns"])
    # ... and with no other position, the file is refused, not read at (20°N, 120°E)
    rows = [[r[0], r[1], r[4], r[5]] for r in rows]
    path = _write(tmp_path / "dim2.csv", ["Zeit", "MMSI", "Länge", "Breite"], rows)
    with pytest.raises(InputError, match="--map lon=COLUMN"):
        read_points(path)
    # an English "Route" (a route's name) is no course; a number under Route is
    rows = [
        [r.time.isoformat(), str(r.mmsi), f"{r.lat:.5f}", f"{r.lon:.5f}", "Oslo-Kiel"]
        for r in fx.itertuples()
    ]
    path = _write(tmp_path / "route.csv", ["time", "mmsi", "lat", "lon", "Route"], rows)
    res = read_points(path)
    assert "course" not in res.report["columns"] and "Route" in res.report["extra_columns"]
    assert not res.report["values_blanked"]
    # a route's number (42 on every row) is no course either; of Route and Cap, Route
    rows = [[*r[:4], "42"] for r in rows]
    path = _write(tmp_path / "route42.csv", ["time", "mmsi", "lat", "lon", "Route"], rows)
    assert "course" not in read_points(path).report["columns"]
    rows = [
        [r.time.isoformat(), str(r.mmsi), f"{r.lat:.5f}", f"{r.lon:.5f}", "77", str(r.course)]
        for r in fx.itertuples()
    ]
    path = _write(tmp_path / "cap.csv", ["time", "mmsi", "lat", "lon", "Cap", "Route"], rows)
    res = read_points(path)
    assert res.report["columns"]["course"] == "Route" and "Cap" in res.report["extra_columns"]
    # an hour's number under Hora beside full date-times: the date-times are the time
    rows = [
        [r.time.strftime("%d/%m/%Y %H:%M:%S"), str(r.time.hour), str(r.mmsi), f"{r.lat:.5f}"]
        + [f"{r.lon:.5f}"]
        for r in fx.itertuples()
    ]
    path = _write(tmp_path / "hora.csv", ["Fecha", "Hora", "MMSI", "Lat", "Lon"], rows)
    res = read_points(path)
    assert res.report["columns"]["time"] == "Fecha" and res.report["time_date_column"] is None
    assert list(res.points.sort_values("time")["time"]) == list(fx["time"])
    # Italian/Portuguese "Data" of date-times is the time; an English "data" payload is not
    rows = [
        [r.time.strftime("%d/%m/%Y %H:%M:%S"), str(r.mmsi), f"{r.lat:.5f}", f"{r.lon:.5f}"]
        for r in fx.itertuples()
    ]
    path = _write(tmp_path / "it.csv", ["Data", "MMSI", "Latitudine", "Longitudine"], rows)
    assert list(read_points(path).points.sort_values("time")["time"]) == list(fx["time"])
    rows = [["0x1f8b0800", *r[1:]] for r in rows]
    path = _write(tmp_path / "payload.csv", ["data", "MMSI", "lat", "lon"], rows)
    with pytest.raises(InputError, match="named like the time"):
        read_points(path)
    # a "TID" of small whole numbers is a track id, not the Norwegian time
    rows = [[str(k % 2), f"{48 + k / 100:.5f}", "-4.5"] for k in range(10)]
    path = _write(tmp_path / "tid.csv", ["TID", "lat", "lon"], rows)
    with pytest.raises(InputError, match="named like the time"):
        read_points(path)


@settings(max_examples=30, deadline=None)
@given(
    lang=st.sampled_from(sorted(LANGUAGES)),
    delim=st.sampled_from([",", ";", "\t"]),
    ships=st.integers(1, 4),
    n=st.integers(2, 40),
    date_fmt=st.sampled_from(["%d.%m.%Y", "%d/%m/%Y", "%Y-%m-%d"]),
)
def test_any_language_any_delimiter_every_row_read(
    tmp_path_factory, lang, delim, ships, n, date_fmt
):
    fx = _fixes(n, ships)
    path, _ = _language_file(
        tmp_path_factory.mktemp("l") / "f.csv", lang, fx, delim=delim, date_fmt=date_fmt
    )
    res = read_points(path)
    _check(res, fx, min(ships, n))


@settings(max_examples=30, deadline=None)
@given(
    first=st.sampled_from(["date", "clock"]),
    rest=st.permutations(["mmsi", "lat", "lon"]),
    at=st.integers(0, 3),
    delim=st.sampled_from([",", ";", "\t"]),
    date_fmt=st.sampled_from(["%d.%m.%Y", "%d/%m/%Y", "%Y-%m-%d"]),
    ships=st.integers(1, 3),
)
def test_a_headerless_date_and_clock_pair_reads_with_the_suggestion(
    tmp_path_factory, first, rest, at, delim, date_fmt, ships
):
    """A headerless file whose date and clock lie in two columns side by side, anywhere
    among the others: the message's --map flags read every row at its time."""
    fx = _fixes(12, ships)
    pair = ["date", "clock"] if first == "date" else ["clock", "date"]
    order = [*rest[:at], *pair, *rest[at:]]
    cells = {
        "date": lambda r: r.time.strftime(date_fmt),
        "clock": lambda r: r.time.strftime("%H:%M:%S"),
        "mmsi": lambda r: str(r.mmsi),
        "lat": lambda r: f"{r.lat:.6f}",
        "lon": lambda r: f"{r.lon:.6f}",
    }
    path = tmp_path_factory.mktemp("h") / "f.csv"
    path.write_text("".join(delim.join(cells[c](r) for c in order) + "\n" for r in fx.itertuples()))
    with pytest.raises(InputError) as exc:
        read_points(path)
    text = str(exc.value)
    col = {c: f"col{i + 1}" for i, c in enumerate(order)}
    assert f"--map time={col['clock']}" in text and f"dates beside them in {col['date']}" in text
    flags = [w for w in text.split() if w.startswith(("batch=", "time=", "lon=", "lat="))]
    res = read_points(path, mapping=flags)
    assert res.report["rows_read"] == 12 == res.report["rows_imported"]
    assert res.report["time_date_column"] == col["date"]
    assert list(res.points.sort_values("time", kind="stable")["time"]) == list(fx["time"])
