"""Files without a header: a first row that starts with a date-time is data, not a header
(it was read as the header, and its fix lost); the message suggests --map flags chosen by
the values of the first rows; the import dialog fills its boxes with them."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import real_file
from wakeline.core.errors import InputError
from wakeline.core.io import read_points
from wakeline.core.io.reader import content_guess
from wakeline.core.io.sniff import sniff


def _rows(n: int = 6, lon0: float = 23.48, lat0: float = 37.35, ids=("5", "7")) -> list[list]:
    t = pd.Timestamp("2024-07-31T23:31:24Z")
    return [
        [
            (t + pd.Timedelta(seconds=60 * k)).strftime("%Y-%m-%dT%H:%M:%SZ"),
            ids[k % len(ids)],
            f"{lon0 + 0.001 * k:.5f}",
            f"{lat0 + 0.001 * k:.5f}",
        ]
        for k in range(n)
    ]


def _write(path, rows, delim=","):
    path.write_text("".join(delim.join(r) + "\n" for r in rows))
    return path


def test_a_first_row_starting_with_a_date_time_is_data(tmp_path):
    path = _write(tmp_path / "nohead.csv", _rows())
    sn = sniff(path)
    assert not sn.has_header and sn.columns == ("col1", "col2", "col3", "col4")
    res = read_points(path, mapping=["time=col1", "batch=col2", "lon=col3", "lat=col4"])
    assert res.report["rows_imported"] == 6 and res.report["rows_quarantined"] == 0


def test_the_message_suggests_the_columns_by_their_values(tmp_path):
    path = _write(tmp_path / "nohead.csv", _rows())
    with pytest.raises(InputError) as exc:
        read_points(path)
    text = str(exc.value)
    assert "no header" in text
    for flag in ("--map time=col1", "--map batch=col2", "--map lon=col3", "--map lat=col4"):
        assert flag in text
    assert "check which of the two degree columns is longitude" in text
    # a longitude beyond 90 shows which is which: no doubt left in the message
    path = _write(tmp_path / "west.csv", _rows(lon0=-122.4, lat0=37.8))
    with pytest.raises(InputError) as exc:
        read_points(path)
    assert "--map lon=col3 --map lat=col4" in str(exc.value)
    assert "check which" not in str(exc.value)
    path = _write(tmp_path / "latlon.csv", [[r[0], r[1], r[3], r[2]] for r in _rows(lon0=151.2)])
    with pytest.raises(InputError) as exc:
        read_points(path)
    assert "--map lon=col4 --map lat=col3" in str(exc.value)


@pytest.mark.parametrize(
    "lines, header",
    [
        (["a,b,c,d", "1,2,3,4"], True),  # unknown names over numbers
        (["when,boat,px,py", "2024-07-31T23:31:24Z,A,1.0,2.0"], True),  # words over data
        (["SHIP_A,2024-07-31T23:31:24Z,23.4,37.5", "SHIP_B,2024-07-31T23:32:24Z,23.5,37.6"], False),
        (["31/07/2024 23:31:24,5,23.4,37.5", "31/07/2024 23:32:24,5,23.5,37.6"], False),
        (["time,id,x,y", "2024-07-31T23:31:24Z,5,1.0,2.0"], True),  # known names
        (["1722468684,5,23.4,37.5", "1722468744,5,23.5,37.6"], False),  # numbers only
        # a track named like a field (hypothesis found "T": time's synonym) is still data
        (["2024-07-31T23:31:24Z,T,0.0,0.0", "2024-07-31T23:32:24Z,T,0.1,0.1"], False),
        (["name,comment", "foo,bar"], True),  # words only
        # a blank cell, in the first row or one below (an optional speed missing), is
        # like any: the first row was read as the header and its fix lost
        (["2024-07-31T23:31:24Z,5,23.1,37.1,", "2024-07-31T23:31:25Z,5,23.2,37.2,4.5"], False),
        (["2024-07-31T23:31:24Z,5,23.1,37.1,4.4", "2024-07-31T23:31:25Z,5,23.2,37.2,"], False),
        (["time,id,lon,lat,speed", "2024-07-31T23:31:25Z,5,23.2,37.2,"], True),
    ],
)
def test_header_or_data(tmp_path, lines, header):
    path = tmp_path / "f.csv"
    path.write_text("\n".join(lines) + "\n")
    assert sniff(path).has_header is header


@settings(max_examples=40, deadline=None)
@given(
    n=st.integers(2, 30),
    lon0=st.floats(-179, 179),
    lat0=st.floats(-89, 89),
    ids=st.lists(
        st.from_regex(r"[A-Z]{1,4}_?[0-9]{0,6}", fullmatch=True).filter(
            lambda s: s.upper() not in {"NA", "NAN", "INF", "NULL", "NONE", "N"}
        ),
        min_size=1,
        max_size=4,
    ),
    delim=st.sampled_from([",", ";", "\t"]),
)
def test_no_headerless_row_is_lost(tmp_path_factory, n, lon0, lat0, ids, delim):
    """Rows of ISO times, ids and degrees, without a header: every line is a row read."""
    rows = _rows(n, lon0, lat0, tuple(i or "X" for i in ids))
    path = _write(tmp_path_factory.mktemp("h") / "f.csv", rows, delim)
    assert not sniff(path).has_header
    res = read_points(path, mapping=["time=col1", "batch=col2", "lon=col3", "lat=col4"])
    rep = res.report
    assert rep["rows_read"] == n == rep["rows_imported"] + rep["rows_quarantined"]
    assert rep["rows_imported"] == n


def test_the_real_saronic_file_reads_with_the_suggestion():
    path = real_file("greece-ais-annotated", "vessels.csv")
    with pytest.raises(InputError) as exc:
        read_points(path)
    text = str(exc.value)
    flags = [w for w in text.split() if w.startswith(("batch=", "time=", "lon=", "lat="))]
    assert sorted(flags) == ["batch=col1", "lat=col3", "lon=col2", "time=col4"]
    res = read_points(path, mapping=flags)
    assert res.report["rows_imported"] == 18_834 and res.report["rows_quarantined"] == 0
    assert np.isclose(res.points["lon"].median(), 23.6, atol=0.5)


def test_the_time_column_is_told_by_the_sniffers_date_time_test(tmp_path, recwarn):
    # pandas' guess per cell warned on stderr for every dd/mm/yyyy date ("Parsing dates in
    # %d/%m/%Y format when dayfirst=False") and took a name such as "May 5" for a date
    rows = [
        ["May 5", pd.Timestamp(r[0]).strftime("%d/%m/%Y %H:%M:%S"), r[2], r[3]] for r in _rows()
    ]
    path = _write(tmp_path / "dayfirst.csv", rows)
    with pytest.raises(InputError) as exc:
        read_points(path)
    assert "--map time=col2" in str(exc.value) and "--map batch=col1" in str(exc.value)
    assert not [w for w in recwarn if issubclass(w.category, UserWarning)]
    res = read_points(path, mapping=["time=col2", "batch=col1", "lon=col3", "lat=col4"])
    assert res.report["rows_imported"] == 6


@pytest.mark.parametrize(
    "order, flags",
    [
        ((0, 1, 2, 3), "--map time=col2 --map lon=col3 --map lat=col4 --map batch=col1"),
        ((1, 0, 2, 3), "--map time=col1 --map lon=col3 --map lat=col4 --map batch=col2"),
    ],
)
def test_an_mmsi_beside_unix_seconds_is_the_batch_not_the_time(tmp_path, order, flags):
    # a nine-digit MMSI lies in the range of Unix seconds: as the first such column it was
    # suggested as the time, and the real times as the batch
    t = 1_722_468_684
    rows = [
        [
            ["244660000", "219000123"][k % 2],
            str(t + 60 * k),
            f"{11.2 + 0.001 * k:.5f}",
            f"{57.1 + 0.001 * k:.5f}",
        ]
        for k in range(6)
    ]
    path = _write(tmp_path / "ais.csv", [[r[i] for i in order] for r in rows])
    with pytest.raises(InputError) as exc:
        read_points(path)
    assert flags in str(exc.value)
    # a date-time text is the time whatever number columns come before it
    rows = [[r[0], pd.Timestamp(int(r[1]), unit="s").isoformat(), r[2], r[3]] for r in rows]
    path = _write(tmp_path / "ais_text.csv", rows)
    with pytest.raises(InputError) as exc:
        read_points(path)
    assert "--map time=col2 --map lon=col3 --map lat=col4 --map batch=col1" in str(exc.value)


def test_a_date_alone_is_not_the_time_but_the_clock_beside_it_joined_with_it(tmp_path):
    # a headerless Date,Time pair: the date column was suggested as the time (every fix
    # of a day at midnight) and the clock as the batch; then no guess (the reader joined
    # a clock only with a column named Date); now the clock column, whose dates the
    # reader finds beside it by their values (h120)
    rows = [[r[0][:10], r[0][11:19], r[1], r[2], r[3]] for r in _rows()]
    path = _write(tmp_path / "date_time.csv", rows)
    assert not sniff(path).has_header
    with pytest.raises(InputError) as exc:
        read_points(path)
    text = str(exc.value)
    assert "--map time=col2 --map lon=col4 --map lat=col5 --map batch=col3" in text
    assert "joined with the dates beside them in col1" in text
    flags = [w for w in text.split() if w.startswith(("batch=", "time=", "lon=", "lat="))]
    res = read_points(path, mapping=flags)
    assert res.report["rows_imported"] == 6 and res.report["time_date_column"] == "col1"
    want = [pd.Timestamp(r[0]) for r in _rows()]
    assert list(res.points.sort_values("time")["time"]) == sorted(want)


@settings(max_examples=40, deadline=None)
@given(
    order=st.permutations(["time", "mmsi", "lat", "lon", "speed"]),
    millis=st.booleans(),
    ships=st.integers(2, 4),
    lon0=st.floats(-179, 179).filter(lambda v: abs(v) > 1),
    lat0=st.floats(-80, 80).filter(lambda v: abs(v) > 1),
)
def test_the_suggestion_tells_unix_times_from_mmsi_and_positions_from_speeds(
    tmp_path_factory, order, millis, ships, lon0, lat0
):
    """An operator's headerless AIS dumps (h118): a 9-digit MMSI (2e8-8e8) was taken for
    Unix seconds when its column came first, and a speed column of one decimal beside lon
    and lat left no suggestion at all."""
    cells = {
        "time": lambda k: str((1_772_690_400 + 10 * (k // ships)) * (1000 if millis else 1)),
        "mmsi": lambda k: str(244_000_100 + k % ships),
        "lat": lambda k: f"{lat0 + 1e-4 * k:.6f}",
        "lon": lambda k: f"{lon0 + 1e-4 * k:.6f}",
        "speed": lambda k: f"{7.2 + k % 3 / 10:.1f}",
    }
    rows = [[cells[c](k) for c in order] for k in range(12)]
    path = _write(tmp_path_factory.mktemp("h") / "f.csv", rows)
    guess, sure = content_guess(sniff(path))
    col = {c: f"col{i + 1}" for i, c in enumerate(order)}
    assert guess["time"] == col["time"] and guess["batch"] == col["mmsi"]
    assert {guess["lon"], guess["lat"]} == {col["lon"], col["lat"]}
    lon_max, lat_max = (max(abs(float(cells[c](k))) for k in range(12)) for c in ("lon", "lat"))
    if lon_max > 90 >= lat_max:  # as written (lon0 -90.0 writes no value beyond 90)
        assert sure and (guess["lon"], guess["lat"]) == (col["lon"], col["lat"])
    res = read_points(path, mapping=[f"{k}={v}" for k, v in guess.items()])
    assert res.report["rows_imported"] + res.report["rows_quarantined"] == 12


@settings(max_examples=30, deadline=None)
@given(
    delim=st.sampled_from([";", "\t"]),
    lon0=st.floats(-179, 179).filter(lambda v: abs(v) > 91),
    lat0=st.floats(-80, 80),
    lat_first=st.booleans(),
)
def test_the_suggestion_reads_decimal_commas(tmp_path_factory, delim, lon0, lat0, lat_first):
    """A European headerless export (`2026-03-05 06:00:00;100;30,613482;122,068355`, h118)
    got no suggestion: its degrees did not parse as numbers."""
    rows = []
    for r in _rows(8, lon0, lat0):
        lon, lat = r[2].replace(".", ","), r[3].replace(".", ",")
        rows.append([r[0], r[1], *((lat, lon) if lat_first else (lon, lat))])
    path = _write(tmp_path_factory.mktemp("h") / "f.csv", rows, delim)
    guess, sure = content_guess(sniff(path))
    assert sure and guess["time"] == "col1" and guess["batch"] == "col2"
    assert (guess["lon"], guess["lat"]) == (("col4", "col3") if lat_first else ("col3", "col4"))
    res = read_points(path, mapping=[f"{k}={v}" for k, v in guess.items()])
    assert res.report["rows_imported"] == 8
    assert np.isclose(res.points["lon"].iloc[0], round(lon0, 5))
