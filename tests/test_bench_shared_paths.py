"""The benches that read ../shared find it through $WAKELINE_SHARED as the tests do: in a
git worktree (../shared is not beside it) `python bench/oresund_association.py` stopped
with "encounters.csv not found" although the data was there."""

import importlib.util

import pytest

from conftest import REPO


def _load(name: str):
    spec = importlib.util.spec_from_file_location(f"_bench_{name}", REPO / "bench" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize(
    ("name", "attr", "tail"),
    [
        ("oresund_association", "SHARED", "data/real/oresund-encounters"),
        ("moored_harbour", "SARONIC", "data/real/greece-ais-annotated/vessels.csv"),
        ("sampling_sweep", "REAL", "data/real"),
        ("atd_known_gaps", "ATD", "data/real/atd2025-noaa/example_truth.csv.gz"),
        ("overlay_days", "REAL", "data/real"),
        ("compare_libraries", "REAL", "data/real"),
        ("radar_slow_extra", "REAL", "data/real"),
    ],
)
def test_bench_reads_shared_from_the_environment(monkeypatch, tmp_path, name, attr, tail):
    monkeypatch.setenv("WAKELINE_SHARED", str(tmp_path))
    assert getattr(_load(name), attr) == tmp_path / tail


def test_gui_block_probe_makes_its_own_million_file(monkeypatch, tmp_path):
    """bench/gui_block_probe.py without --file (S29: its scratch default was gone) writes
    the ATD example repeated over days once: copy k k days later, point ids after the
    others', ship ids kept (or ``* 10 + k`` by day); a second call reuses the file."""
    import gzip

    monkeypatch.setenv("WAKELINE_SHARED", str(tmp_path))
    mod = _load("gui_block_probe")
    assert mod.ATD_EXAMPLE == tmp_path / "data/real/atd2025-noaa/example_truth.csv.gz"
    src = tmp_path / "ex.csv.gz"
    rows = [
        "point_id,point_id_original,track_id,time,lat,lon,speed,course",
        "0,7,215726000,2024-01-01T00:00:00,23.6,-83.6,10.7,280.9",
        "1,3,563093400,2024-01-01T23:59:59,24.0,-82.1,13.6,279.0",
    ]
    with gzip.open(src, "wt") as f:
        f.write("\n".join(rows) + "\n")
    out = mod.atd_million(days=3, source=src, folder=tmp_path / "cache")
    lines = out.read_text().splitlines()
    assert lines[0] == rows[0] and len(lines) == 1 + 3 * 2
    assert [ln.split(",")[0] for ln in lines[1:]] == ["0", "1", "2", "3", "4", "5"]
    assert lines[5] == "4,7,215726000,2024-01-03T00:00:00,23.6,-83.6,10.7,280.9"
    assert lines[6].split(",")[3] == "2024-01-03T23:59:59"
    by_day = mod.atd_million(days=3, by_day=True, source=src, folder=tmp_path / "cache")
    assert by_day != out
    assert [ln.split(",")[2] for ln in by_day.read_text().splitlines()[1::2]] == [
        "2157260000", "2157260001", "2157260002",
    ]  # fmt: skip
    stamp = out.stat().st_mtime_ns
    assert mod.atd_million(days=3, source=src, folder=tmp_path / "cache") == out
    assert out.stat().st_mtime_ns == stamp  # made once


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_radar_slow_extra_statistic_is_the_confirmation_test(seed):
    """bench/radar_slow_extra.py prints the confirmation test's statistic per detection
    (session 30): it exceeds z exactly where the detector's ``_confirmed`` says so, legs
    clipped at the tracks' ends included."""
    import numpy as np
    import pandas as pd

    from wakeline.core import maneuver as m
    from wakeline.core.tracks import TrackIndex

    bench = _load("radar_slow_extra")
    rng = np.random.default_rng(seed)
    sizes = rng.integers(15, 40, 3)
    ends = np.cumsum(sizes)
    starts = ends - sizes
    tr = np.repeat(np.arange(3), sizes)
    n = int(sizes.sum())
    t = np.concatenate([np.cumsum(rng.uniform(3.0, 5.5, s)) for s in sizes])
    heading = np.cumsum(rng.normal(0, 0.2, n))
    x = np.cumsum(10 * np.sin(heading)) + rng.normal(0, 1.5, n)
    y = np.cumsum(10 * np.cos(heading)) + rng.normal(0, 1.5, n)
    keys = pd.DataFrame({"sensor": ["R"] * 3, "batch": [str(k) for k in range(3)]})
    index = TrackIndex(starts, ends, tr, keys)
    sigma = rng.uniform(0.5, 2.0, 3)
    rows = np.arange(n)[(np.arange(n) > starts[tr]) & (np.arange(n) < ends[tr] - 1)]
    for legs in (6, 10):
        stat = np.array([bench.confirm_stat(x, y, t, index, r, legs, sigma, 0.5) for r in rows])
        for z in (2.0, 4.0):
            ours = m._confirmed(
                x, y, t, index, rows, np.full(len(rows), legs), sigma, np.zeros(0, "int64"), z, 0.5
            )
            assert np.array_equal(stat > z, ours)
            assert 0 < ours.sum() < len(rows)  # both outcomes occur
