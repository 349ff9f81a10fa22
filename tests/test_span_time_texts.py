"""core.clean.time_texts: the at-rest span table's times as pandas' astype(str) writes them,
made by numpy in chunks (pandas held the GIL over the whole column: the window's event
loop blocked 1.0-1.8 s in Clean on 1.1 M points, operator test 4 D-gui-1)."""

import numpy as np
import pandas as pd
from hypothesis import given, settings
from hypothesis import strategies as st

from wakeline.core.clean import time_texts


@settings(max_examples=200, deadline=None)
@given(
    st.lists(st.integers(0, 4_000_000_000_000_000_000), max_size=30),
    st.sampled_from([None, "UTC"]),
    st.sampled_from([1, 1000, 1_000_000_000, 86_400_000_000_000]),
    st.booleans(),
)
def test_time_texts_are_pandas_texts(values, tz, step, with_nat):
    ns = np.array([v // step * step for v in values], dtype="int64").view("datetime64[ns]")
    times = pd.Series(ns)
    if with_nat and len(times):
        times.iloc[0] = pd.NaT
    if tz:
        times = times.dt.tz_localize(tz)
    want = [str(x) for x in times.astype(str).to_numpy()]
    assert [str(x) for x in time_texts(times)] == want


def test_time_texts_over_chunks():
    t = pd.Series(pd.to_datetime(np.arange(0, 45_000) * 7 + 1.7e9, unit="s", utc=True))
    assert (time_texts(t) == t.astype(str).to_numpy()).all()
