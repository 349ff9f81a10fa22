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
    ],
)
def test_bench_reads_shared_from_the_environment(monkeypatch, tmp_path, name, attr, tail):
    monkeypatch.setenv("WAKELINE_SHARED", str(tmp_path))
    assert getattr(_load(name), attr) == tmp_path / tail
