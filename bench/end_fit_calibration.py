"""How well an end's stated velocity error covers its real one (issue 15, the review of
session 10): ships at 6 m/s, sampled every DT s in SIGMA m of noise, straight or turning
over their last fixes; each end fitted by ``segment_stats`` with the fits of session 9
(``end_points_max`` 10) and the default (40). Prints, per case, the share of ends whose
velocity error exceeds 3 × its stated standard deviation (a calibrated error: 1.1 %, the
Rayleigh tail) and the rms velocity error.

    python bench/end_fit_calibration.py [--dt 10] [--sigma 60]
"""

import argparse

import numpy as np
import pandas as pd

from wakeline.core import geo
from wakeline.core.segments import segment_stats


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dt", type=float, default=10.0, help="sampling interval, s")
    ap.add_argument("--sigma", type=float, default=60.0, help="position noise per axis, m")
    args = ap.parse_args()
    dt, sigma = args.dt, args.sigma
    rng = np.random.default_rng(7)
    ends, fixes, speed = 1500, 60, 6.0
    t = np.arange(fixes) * dt
    print(f"{ends} ends per case, {speed:g} m/s, {sigma:g} m noise, every {dt:g} s")
    for rate, last in ((0.0, 0), (0.05, 20), (0.1, 20), (0.2, 10), (0.1, 40), (0.3, 10)):
        turn = np.radians(rate) * (t >= t[-1] - last * dt)
        heading = np.cumsum(turn * dt)
        vx, vy = speed * np.sin(heading), speed * np.cos(heading)
        x = np.concatenate([[0.0], np.cumsum(vx[:-1] * dt)])
        y = np.concatenate([[0.0], np.cumsum(vy[:-1] * dt)])
        xs = x[None, :] + rng.normal(0, sigma, (ends, fixes)) + 5000.0 * np.arange(ends)[:, None]
        ys = y[None, :] + rng.normal(0, sigma, (ends, fixes))
        lon, lat = geo.from_local(xs.ravel(), ys.ravel(), 10.0, 55.0)
        df = pd.DataFrame(
            {
                "sensor": "R",
                "batch": np.repeat(np.arange(ends), fixes).astype(str),
                "time": pd.to_datetime(np.tile(t, ends), unit="s", utc=True),
                "lon": lon,
                "lat": lat,
            }
        )
        cells = []
        for k_max in (10, 40):
            seg = segment_stats(df, 10, end_points_max=k_max)
            err = np.hypot(seg.vx1 - vx[-1], seg.vy1 - vy[-1])
            cells.append(
                f"end_points_max {k_max}: {(err / seg.vel_sd1 > 3).mean():.3f} beyond 3 sd, "
                f"rms {np.sqrt(np.mean(err**2)):.2f} m/s"
            )
        print(f"turn {rate:4.2f} deg/s over the last {last:2d} fixes: " + "; ".join(cells))


if __name__ == "__main__":
    main()
