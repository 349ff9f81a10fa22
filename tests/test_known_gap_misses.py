"""bench/known_gap_misses.py: every true pair and every wrong join is put in one class."""

import importlib.util
import sys

from conftest import REPO
from wakeline.core import associate as A
from wakeline.core import simulate
from wakeline.core.associate import LinkParams
from wakeline.core.evaluate_association import consecutive_true_pairs, cut_known_gaps


def _bench():
    spec = importlib.util.spec_from_file_location(
        "known_gap_misses", REPO / "bench" / "known_gap_misses.py"
    )
    mod = importlib.util.module_from_spec(spec)
    sys.modules["known_gap_misses"] = mod
    spec.loader.exec_module(mod)
    return mod


def test_the_classes_count_every_true_pair_and_every_wrong_join_once():
    bench = _bench()
    df = simulate.segments_scene(seed=3, n_ships=30, area_km=12.0, sigma_m=30.0)
    # Whole ships as the truth, as MTAD's MMSI: the simulator's batches are its pieces.
    df = df.assign(batch=df["truth"].astype(str))
    params = LinkParams()
    margin, soft = A.margin_test, A.soft_gap_test
    pairs, wrong = bench.classify(df, params, seed=1)
    assert (A.margin_test, A.soft_gap_test) == (margin, soft)  # the wrappers are gone

    a = A.associate_interrupted(cut_known_gaps(df, 300, 900, seed=1), params)
    truth = a.base.column("truth").astype(str).to_numpy()[a.base.index.starts]
    true = set(consecutive_true_pairs(truth, a.base.t0))
    joined = set(zip(a.pairs.i[a.chosen].tolist(), a.pairs.j[a.chosen].tolist(), strict=True))
    assert sum(pairs.values()) == len(true) > 20
    right = sum(c for (_, how), c in pairs.items() if how.startswith("joined"))
    assert right == len(joined & true)
    assert sum(wrong.values()) == len(joined - true)
    # Known gaps of 300-900 s: a third of the true pairs lie beyond T_gap.
    assert sum(c for (where, _), c in pairs.items() if where != "within T_gap") > 0
