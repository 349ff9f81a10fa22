"""What a re-run of Associate costs at the swap when the operator decided while it ran
(docs/review.md, "Decisions made while the step runs"): making the carry again from the
decision log (``Carry.refresh``), on the GUI thread as ``Session.apply_result`` would, and
the window's way — ``Session.reconcile`` in the worker, then the GUI thread's checks
(``Session.stale``, ``Session.late_decisions``) and the swap.

    python bench/bench_rerun_swap.py [--ships 200] [--late 40]

A simulated scene (``simulate.segments_scene(seed=3, n_ships=SHIPS, area_km=80)``), Run ▸
Associate, half the proposals accepted before the re-run and ``--late`` more while it ran.
"""

import argparse
import time

from wakeline.core import review as R
from wakeline.core import simulate
from wakeline.core.review_session import bind, queue_key
from wakeline.core.review_store import decision_row
from wakeline.core.session import Session


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ships", type=int, default=200)
    ap.add_argument("--late", type=int, default=40)
    args = ap.parse_args()
    pts = simulate.segments_scene(seed=3, n_ships=args.ships, area_km=80)
    s = Session()
    src = s.add_layer("x", "source", pts)
    (lay,) = s.apply_result(src.id, s.run_step(src.id, "associate"))
    st, _ = bind(s, lay)

    def do(change: R.Change) -> None:
        st.apply(change)
        s.decisions.append(decision_row(queue_key(lay), change, st.log[-1]))

    pids = list(st.proposals["proposal"])
    half = len(pids) // 2
    for p in pids[:half]:
        do(R.accept(st, p))
    res = s.run_step(src.id, "associate")  # the worker
    for p in pids[half : half + args.late]:  # the operator, while it ran
        do(R.accept(st, p))
    t = time.perf_counter()
    stale = s.stale(res)
    stale_ms = (time.perf_counter() - t) * 1000
    t = time.perf_counter()
    res.carry.refresh(s.layers[lay.id], list(s.decisions), res.layers[0].tables["proposals"])
    refresh_ms = (time.perf_counter() - t) * 1000
    print(
        f"{len(pts):,} points, {len(st.tracks):,} tracks, {len(pids):,} proposals, "
        f"{len(s.decisions):,} decision rows; stale() {stale_ms:.1f} ms ({stale}); carry made "
        f"again {refresh_ms:.0f} ms (late {res.carry.late}, accepted {res.carry.accepted})"
    )
    res = s.run_step(src.id, "associate")
    lay = s.layers[lay.id]
    for p in pids[half + args.late : half + 2 * args.late]:
        do(R.accept(st, p))
    t = time.perf_counter()
    s.reconcile(res)  # the window runs it in the worker
    reconcile_ms = (time.perf_counter() - t) * 1000
    t = time.perf_counter()
    checks = (s.stale(res), s.late_decisions(res))
    checks_ms = (time.perf_counter() - t) * 1000
    t = time.perf_counter()
    s.apply_result(src.id, res)
    apply_ms = (time.perf_counter() - t) * 1000
    print(
        f"window: reconcile in the worker {reconcile_ms:.0f} ms; GUI thread: checks "
        f"{checks_ms:.1f} ms {checks}, apply_result {apply_ms:.1f} ms (late {res.carry.late})"
    )


if __name__ == "__main__":
    main()
