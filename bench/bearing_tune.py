"""Bearing-only detection on the tune set (seed 1001's six geometries x 1 s, 2 s and
jittered sampling; the report set is seed 1's, see ``wakeline evaluate bearing``): the
default (the observer's positions in the fit) next to the first version's exclusion of
the observer's turns, and any variants given as FIELD=VALUE.

    nice -n 5 .venv/bin/python bench/bearing_tune.py [--runs 8] [alpha=1e-4 ...]

Prints one line per cell and a summary per variant: detection mean / worst, false
alarms mean / worst, mean reaction (min), the same on the cells whose expected peak z
reaches the threshold ("visible"), CPU seconds and the load average.
"""

import argparse
import time
from dataclasses import fields, replace

import numpy as np

from wakeline.core.bearing import BearingParams
from wakeline.core.bearing_eval import peak_z, random_scenarios, run_metrics


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=8)
    ap.add_argument("--seed", type=int, default=1001)
    ap.add_argument("--geometries", type=int, default=6)
    ap.add_argument("variants", nargs="*", help="FIELD=VALUE on top of the defaults")
    args = ap.parse_args()
    variants = {
        "model (default)": BearingParams(),
        "exclude": BearingParams(exclude_observer_turns=True),
    }
    kinds = {f.name: type(f.default) for f in fields(BearingParams)}
    for v in args.variants:
        key, value = v.split("=")
        kind = kinds[key]
        variants[v] = replace(
            BearingParams(), **{key: value == "true" if kind is bool else kind(value)}
        )
    cells = random_scenarios(args.seed, args.geometries)
    for name, p in variants.items():
        t0 = time.process_time()
        det, fa, react, vis = [], [], [], []
        for sc in cells:
            m = run_metrics(np.random.default_rng(7), sc, p, args.runs)
            z = peak_z(sc, 50.0, p)
            det.append(m["detection"])
            fa.append(m["false_alarm"])
            react.append(m["reaction_min"])
            vis.append(z >= p.z_crit)
            print(
                f"  {name:<16} {sc.name:<52} peak z {z:5.1f} detect {m['detection']:.2f} "
                f"fa {m['false_alarm']:.2f} react {m['reaction_min']:.2f}",
                flush=True,
            )
        det, fa, vis = np.array(det), np.array(fa), np.array(vis)
        load = " ".join(open("/proc/loadavg").read().split()[:3])
        seen = (
            f"visible {vis.sum()}: {det[vis].mean():.1%} / {det[vis].min():.1%}"
            if vis.any()
            else "visible 0"
        )
        print(
            f"{name:<16} detect {det.mean():.1%} / {det.min():.1%}  false alarms "
            f"{fa.mean():.1%} / {fa.max():.1%}  reaction {np.nanmean(react):.2f} min | {seen} | "
            f"CPU {time.process_time() - t0:.0f} s, load {load}",
            flush=True,
        )


if __name__ == "__main__":
    main()
