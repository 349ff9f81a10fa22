"""Unix seconds with decimals read to the decimal written (h118: Autoferry-like NED files
write `1620114891.8000`; the float64 1620114891.7999999523 was kept to the ns, so the
time was written .799999952 and a resampling grid started from it kept the error)."""

from decimal import Decimal

import pandas as pd
from hypothesis import given, settings
from hypothesis import strategies as st

from wakeline.core.io import read_points


@settings(max_examples=60, deadline=None)
@given(
    base=st.integers(1_000_000_000, 2_000_000_000),
    steps=st.lists(st.integers(0, 600), min_size=1, max_size=8),
    micros=st.lists(st.integers(0, 999_999), min_size=8, max_size=8),
    places=st.integers(1, 6),
    millis=st.booleans(),
)
def test_unix_times_with_decimals_read_to_the_decimal_written(
    tmp_path_factory, base, steps, micros, places, millis
):
    whole = [base + sum(steps[: k + 1]) for k in range(len(steps))]
    texts = []
    for w, u in zip(whole, micros, strict=False):
        frac = f"{u:06d}"[: min(places, 3) if millis else places]  # µs at most
        texts.append(f"{w * 1000 if millis else w}.{frac}")
    rows = [f"{t},A,57.{k:04d},11.5" for k, t in enumerate(texts)]
    path = tmp_path_factory.mktemp("u") / "f.csv"
    path.write_text("time,id,lat,lon\n" + "\n".join(rows) + "\n")
    res = read_points(path)
    got = pd.DatetimeIndex(res.points.sort_values("lat")["time"]).as_unit("ns").asi8
    scale = 1_000_000 if millis else 1_000_000_000
    want = [int(Decimal(t) * scale) for t in texts]
    # to the µs: what a float64 holds at these magnitudes (a ms time's µs: 1e-3 ms)
    assert [g // 1000 for g in got] == [w // 1000 for w in want]
    assert all(g % 1000 == 0 for g in got)


def test_the_autoferry_time_is_written_as_it_was(tmp_path):
    path = tmp_path / "ned.csv"
    path.write_text("time,id,lat,lon\n1620114891.8000,A,63.4,10.4\n1620114892.3000,A,63.4,10.4\n")
    res = read_points(path)
    assert [str(t) for t in res.points["time"]] == [
        "2021-05-04 07:54:51.800000+00:00",
        "2021-05-04 07:54:52.300000+00:00",
    ]
