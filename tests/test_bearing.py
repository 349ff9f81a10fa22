import numpy as np
import pandas as pd
import pytest

from wakeline.app.cli import main
from wakeline.core.bearing import (
    SCENARIOS,
    BearingParams,
    Scenario,
    auc_windows,
    detect,
    detect_sequence,
    observer_maneuvering,
    read_bearings,
    simulate_bearings,
    simulate_table,
)
from wakeline.core.errors import InputError


def test_auc_matches_brute_force_with_ties():
    rng = np.random.default_rng(0)
    values = rng.integers(0, 6, size=(40, 17)).astype(float)  # many ties
    m = 7
    got = auc_windows(values, m)
    for row, auc in zip(values, got, strict=True):
        x, y = row[:m], row[m:]
        ref = np.mean([(xi > yj) + 0.5 * (xi == yj) for xi in x for yj in y])
        assert auc == pytest.approx(ref)


def _run(sc: Scenario, turn: float, sigma: float = 0.6, seed: int = 1):
    rng = np.random.default_rng(seed)
    t, b, olon, olat = simulate_bearings(rng, sc, turn, 450.0, sigma)
    excl = observer_maneuvering(t, olon, olat, BearingParams().observer_dv_ms)
    return detect_sequence(t, b, BearingParams(), excl)


def test_no_maneuver_no_detection():
    for sc in SCENARIOS:
        for seed in (1, 2):
            assert _run(sc, 0.0, sigma=0.3, seed=seed) == [], sc.name


def test_large_maneuver_detected_after_it_with_its_time():
    found = 0
    for seed in range(1, 11):
        hits = _run(SCENARIOS[0], 60.0, seed=seed)  # seed 002's example: +60 deg at 20 km
        assert all(h.detect_time_s >= 450.0 for h in hits)  # nothing before the turn
        if hits and abs(hits[0].maneuver_time_s - 450.0) <= 90.0:
            found += 1
    assert found >= 6
    hits = _run(SCENARIOS[2], 90.0)  # 30 km, 25 kn: a large, well observed turn
    assert hits and abs(hits[0].maneuver_time_s - 450.0) <= 60.0


def test_bearings_across_north_do_not_raise_a_detection():
    # bearing starts at 359.5 deg and crosses 0 while the target runs east
    sc = Scenario("north", 20_000, 359.5, 18, 90)
    rng = np.random.default_rng(2)
    t, b, _, _ = simulate_bearings(rng, sc, 0.0, 450.0, 0.3)
    assert (b > 350).any() and (b < 10).any()
    assert detect_sequence(t, b, BearingParams()) == []


def test_observer_maneuver_is_excluded():
    sc = SCENARIOS[4]  # the observer turns 60 deg at 120 s
    rng = np.random.default_rng(3)
    t, b, olon, olat = simulate_bearings(rng, sc, 0.0, 450.0, 0.3)
    excl = observer_maneuvering(t, olon, olat, 1.0)
    assert excl[122:170].all() and not excl[:100].any() and not excl[300:].any()
    assert detect_sequence(t, b, BearingParams(), excl) == []


def test_detect_table_and_cli(tmp_path, capsys):
    src = tmp_path / "b.csv"
    assert main(["simulate", "bearing", "--seed", "4", "-o", str(src)]) == 0
    out = tmp_path / "d.csv"
    assert main(["bearing", str(src), "-o", str(out)]) == 0
    d = pd.read_csv(out)
    assert list(d.columns) == ["batch", "detect_time", "maneuver_time", "z"]
    assert d.batch.str.endswith("-m").all()  # nothing on the straight runs
    assert d.batch.nunique() >= 3
    # shuffled rows give the same answer (sorted per batch)
    shuffled = tmp_path / "s.csv"
    pd.read_csv(src).sample(frac=1.0, random_state=0).to_csv(shuffled, index=False)
    out2 = tmp_path / "d2.csv"
    assert main(["bearing", str(shuffled), "-o", str(out2)]) == 0
    pd.testing.assert_frame_equal(pd.read_csv(out2), d)


def test_bad_bearing_input(tmp_path, capsys):
    p = tmp_path / "x.csv"
    p.write_text("batch,time,azimuth\n1,2024-01-01T00:00:00Z,10\n")
    with pytest.raises(InputError, match="missing required column bearing"):
        read_bearings(p)
    p.write_text("batch,time,bearing\n1,2024-01-01T00:00:00Z,10\n1,2024-01-01T00:00:01Z,north\n")
    with pytest.raises(InputError, match="not a number on line"):
        read_bearings(p)
    assert main(["bearing", str(p), "-o", str(tmp_path / "o.csv")]) == 2
    assert "line(s) 3" in capsys.readouterr().err
    p.write_text("batch,time,bearing\n1,2024-01-01T00:00:00Z,10\n1,2024-01-01T00:00:00Z,11\n")
    with pytest.raises(InputError, match="repeated time"):
        detect(read_bearings(p))


def test_simulated_table_has_truth():
    df = simulate_table(seed=0)
    assert df.batch.nunique() == 10
    assert df[df.batch.str.endswith("-m")].true_maneuver_time.notna().all()
