"""Positions rounded to a coarse grid (D-import-7, operator test 5): a file whose
latitudes and longitudes carry 2 decimals or fewer puts every fix on a grid of about a
kilometre (0.01° is 1,113 m north–south). A ship moving 50 m per fix then stands still
for a while and jumps a grid step: clean's stationary rule takes the standing for rest,
and turns found by maneuvers follow the grid's staircase. The import says so, once."""

import numpy as np

from wakeline.core.geo import EARTH_RADIUS_M

#: Fewer positions than this: no judgement (a handful of rows may sit on round values).
GRID_MIN_ROWS = 50
#: The start of the warning (a read in pieces keeps it only when every piece has it).
GRID_MARK = "the positions carry "


#: Positions a grid is judged on: the first ones and as many spread over the rest (the
#: warning is advice; a full pass over every value cost 4 s on 10 M rows, two busy cores).
_SAMPLE = 200_000


def _sample(values: np.ndarray) -> np.ndarray:
    if len(values) <= 2 * _SAMPLE:
        return values
    spread = np.linspace(_SAMPLE, len(values) - 1, _SAMPLE).astype("int64")
    return np.concatenate([values[:_SAMPLE], values[spread]])


def _on_grid(values: np.ndarray) -> int | None:
    """The fewest decimals (0, 1 or 2) every value (of a sample: :data:`_SAMPLE`) is
    written with; None: finer."""
    values = _sample(values)
    for k in (0, 1, 2):
        head = values[:20_000] * 10.0**k  # most files are decided here
        if len(head) and np.abs(head - np.rint(head)).max() > 1e-6:
            continue
        scaled = values * 10.0**k
        if len(scaled) and np.abs(scaled - np.rint(scaled)).max() > 1e-6:
            continue
        return k
    return None


def _three(values: np.ndarray) -> list[float]:
    """Up to three distinct values of ``values`` (no sort, no index arrays)."""
    if not len(values):
        return []
    out = [float(values[0])]
    differ = values != values[0]
    for _ in range(2):
        at = int(differ.argmax())
        if not differ[at]:
            break
        out.append(float(values[at]))
        differ &= values != values[at]
    return out


class GridSeen:
    """What the positions of a file's pieces show of a grid, piece by piece (a streamed
    read sees one piece at a time)."""

    def __init__(self) -> None:
        self.k = 0
        self.off = False
        self.n = 0
        self.lats: set[float] = set()
        self.lons: set[float] = set()
        self.lat: np.ndarray | None = None

    def add(self, lon: np.ndarray, lat: np.ndarray) -> "GridSeen":
        lon = np.asarray(lon, dtype="float64")
        lat = np.asarray(lat, dtype="float64")
        if self.off:
            return self
        head = np.concatenate([lon[:10_000], lat[:10_000]])
        if _on_grid(head[np.isfinite(head)]) is None:  # most files: decided on their start
            self.off = True
            return self
        ok = np.isfinite(lon) & np.isfinite(lat)
        if not ok.any():
            return self
        if not ok.all():  # (a copy only where some are missing)
            lon, lat = lon[ok], lat[ok]
        k_lon, k_lat = _on_grid(lon), _on_grid(lat)
        if k_lon is None or k_lat is None:
            self.off = True
            return self
        self.k = max(self.k, k_lon, k_lat)
        self.n += len(lat)
        if len(self.lats) < 3:
            self.lats.update(_three(lat))
        if len(self.lons) < 3:
            self.lons.update(_three(lon))
        if self.lat is None:
            self.lat = lat[ok][:10_000]
        return self

    def decimals(self) -> int | None:
        """The grid's decimals, or None: positions finer, too few, or at rest on round
        values (fewer than three values in either)."""
        if self.off or self.n < GRID_MIN_ROWS:
            return None
        if len(self.lats) < 3 and len(self.lons) < 3:
            return None
        return self.k


def grid_decimals(lon: np.ndarray, lat: np.ndarray) -> int | None:
    """The decimals (0, 1 or 2) every finite lon and lat is written with, when all lie on
    that grid, there are at least :data:`GRID_MIN_ROWS` and they take at least three
    values; None otherwise (the common case, decided on the first values mostly)."""
    return GridSeen().add(lon, lat).decimals()


def grid_warning(decimals: int, lat: np.ndarray) -> str:
    """The import's warning for positions on a grid of ``decimals`` decimals: the step in
    metres (north–south; east–west at the median latitude) and what it does to the steps."""
    step = 10.0**-decimals
    ns = np.radians(step) * EARTH_RADIUS_M
    lat = np.asarray(lat, dtype="float64")
    mid = float(np.nanmedian(lat)) if np.isfinite(lat).any() else 0.0
    ew = ns * np.cos(np.radians(mid))
    word = "decimal" if decimals == 1 else "decimals"
    return (
        f"{GRID_MARK}at most {decimals} {word} (a grid of {step:g}°: {ns:,.0f} m north–south, "
        f"{ew:,.0f} m east–west at {abs(mid):.0f}°{'N' if mid >= 0 else 'S'}): a ship moving "
        "less than a step between fixes seems to stand still, then to jump; clean's "
        "stationary rule and the turns maneuvers finds follow the grid, not the ship "
        f"(turns and stops under ~{ns:,.0f} m are not real): export the positions with "
        "more decimals if you can"
    )
