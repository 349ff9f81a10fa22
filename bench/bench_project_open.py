"""Wall time of opening a project with review decisions (``load_project``) and of its
migration on open alone (``repair_decisions``, the check for rows a join of an older
Wakeline left split or rejected inside a target), on the ATD 2025 example
($WAKELINE_SHARED/data/real/atd2025-noaa/example_truth.csv.gz, ~72 k AIS posits, as
bench_gui_associate.py; the committed sample in tests/data makes no proposals): a source
layer, Run ▸ Associate, and 40 decisions of today's code (accept, reject, split of a track, in turn, over the queue).

    python bench/bench_project_open.py [--runs 7] [--decisions 40]

The project is written to a temporary folder without the mark of checked decisions (as a
Wakeline before it wrote it); the first open is that project's (the migration checks
every queue; the window then stores the mark, here
:meth:`ProjectStore.mark_decisions_checked` when it exists); the later opens are timed
(wall and CPU time), and the migration's check alone on the same decisions.
"""

import argparse
import os
import sqlite3
import statistics
import tempfile
import time
from pathlib import Path

from wakeline.core import review as R
from wakeline.core.associate import LinkParams
from wakeline.core.io import read_points
from wakeline.core.project import ProjectStore, load_project, save_project
from wakeline.core.review_session import bind, queue_key, repair_decisions
from wakeline.core.review_store import decision_row
from wakeline.core.session import Session

SHARED = Path(os.environ.get("WAKELINE_SHARED", Path(__file__).resolve().parents[2] / "shared"))
ATD = SHARED / "data" / "real" / "atd2025-noaa" / "example_truth.csv.gz"


def make_project(path: Path, n_decisions: int) -> int:
    s = Session()
    src = s.add_layer(ATD.name, "source", read_points(ATD).points)
    # ATD's proposals tie different MMSIs (mmsi_apart keeps them apart: none); the
    # review's load is what this measures, so the rule is off here.
    off = {"associate": LinkParams(mmsi_apart=False)}
    (lay,) = s.apply_result(src.id, s.run_step(src.id, "associate", off))
    st, _ = bind(s, lay)
    key = queue_key(lay)
    pids = st.proposals["proposal"].tolist()
    made = 0
    k = 0
    while made < n_decisions and k < 10 * len(pids):
        pid = pids[k % len(pids)]
        kind = k % 3
        k += 1
        try:
            if kind == 0:
                change = R.accept(st, pid)
            elif kind == 1:
                change = R.reject(st, pid)
            else:
                change = R.split_track(st, st.track_a[pids.index(pid)])
        except Exception:  # noqa: BLE001 - a decision that does not apply now: the next
            continue
        if change.empty:
            continue
        st.apply(change)
        s.decisions.append(decision_row(key, change, st.log[-1]))
        made += 1
    save_project(s, path)
    return len(pids)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--decisions", type=int, default=40)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "atd.wakeline"
        n_props = make_project(path, args.decisions)
        con = sqlite3.connect(path)  # as a Wakeline before the mark wrote it
        with con:
            con.execute("DELETE FROM meta WHERE key = 'decisions_checked'")
        con.close()
        first = time.perf_counter()
        proj = load_project(path)
        first = time.perf_counter() - first
        print(f"ATD example: {n_props} proposals, {len(proj.decisions)} decisions")
        print(f"first open: load_project {1000 * first:.0f} ms")
        store = ProjectStore(path, create=False)
        if hasattr(store, "mark_decisions_checked"):
            store.mark_decisions_checked()
        store.close()
        loads, cpus, repairs = [], [], []
        for _ in range(args.runs):
            t, c = time.perf_counter(), time.process_time()
            proj = load_project(path)
            loads.append(time.perf_counter() - t)
            cpus.append(time.process_time() - c)
            t = time.process_time()
            repair_decisions(proj.layers, proj.decisions)
            repairs.append(time.process_time() - t)
        ms = lambda xs: f"{1000 * statistics.median(xs):.0f}"  # noqa: E731
        print(
            f"later opens ({args.runs}): load_project median {ms(loads)} ms wall "
            f"(min {1000 * min(loads):.0f}), {ms(cpus)} ms CPU; the migration's check "
            f"(repair_decisions) alone median {ms(repairs)} ms CPU"
        )
    print("load average", " ".join(open("/proc/loadavg").read().split()[:3]))


if __name__ == "__main__":
    main()
