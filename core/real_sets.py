"""Readers for the real data sets the maneuver evaluation scores against (SOURCE.md in each
folder of ``shared/data/real``): each returns canonical points (sensor, batch, time, lon,
lat[, speed]) plus, where the set has it, a truth table.

A folder is recognised by the files it holds, so ``evaluate maneuver --real DIR`` works on a
copy of any of these sets wherever it lives.
"""

from pathlib import Path

import numpy as np
import pandas as pd

from wakeline.core import geo
from wakeline.core.errors import InputError

#: Autoferry's local "Piren" NED frame origin (SOURCE.md).
PIREN_LON, PIREN_LAT = 10.39908278, 63.4389029083


def _times(seconds: np.ndarray) -> pd.Series:
    return pd.Series(pd.to_datetime(np.asarray(seconds, dtype="float64"), unit="s", utc=True))


def read_greece(folder: Path) -> pd.DataFrame:
    """Saronic Gulf AIS, raw input (``vessels.csv``: id lon lat t, no header); positions only."""
    raw = pd.read_csv(
        folder / "vessels.csv", sep=r"\s+", header=None, names=["id", "lon", "lat", "t"]
    )
    return pd.DataFrame(
        {
            "sensor": "AIS",
            "batch": raw["id"].astype(str),
            "time": _times(raw["t"].to_numpy()),
            "lon": raw["lon"].astype("float64"),
            "lat": raw["lat"].astype("float64"),
        }
    )


def read_dma(folder: Path) -> pd.DataFrame:
    """One DMA ship, one day (``sample_ship.csv``; day-first timestamps)."""
    raw = pd.read_csv(folder / "sample_ship.csv")
    return pd.DataFrame(
        {
            "sensor": "AIS",
            "batch": raw["mmsi"].astype(str),
            "time": pd.to_datetime(raw["position_timestamp"], dayfirst=True, utc=True),
            "lon": raw["longitude"].astype("float64"),
            "lat": raw["latitude"].astype("float64"),
        }
    )


def read_oresund(folder: Path) -> pd.DataFrame:
    """Øresund encounters: one batch per (encounter, ship); ``role`` GW manoeuvres, SO not."""
    raw = pd.read_csv(folder / "encounters.csv")
    return pd.DataFrame(
        {
            "sensor": "AIS",
            "batch": raw["encounter_id"].astype(str) + "/" + raw["mmsi"].astype(str),
            "time": _times(raw["timestamp"].to_numpy()),
            "lon": raw["lon"].astype("float64"),
            "lat": raw["lat"].astype("float64"),
            "speed": raw["sog"].astype("float64"),
            "role": raw["ship_role"].astype(str),
        }
    )


def oresund_cut(pts: pd.DataFrame, seed: int, lo: float, hi: float) -> pd.DataFrame:
    """Øresund tracks (:func:`read_oresund`) with one window of fixes removed from each —
    random length in [``lo``, ``hi``] s, at a random place at least 2 min from either end
    (a track too short keeps whole; :func:`~wakeline.core.evaluate_association.cut_known_gaps`)
    — the pieces renumbered at random and the old batch as ``truth``; the encounters put a
    day apart on their shared relative clock, so they never meet."""
    from wakeline.core.evaluate_association import cut_known_gaps

    enc = pts["batch"].str.split("/").str[0].astype(int)
    pts = pts.assign(time=pts["time"] + pd.to_timedelta(enc * 86400, unit="s"))
    return cut_known_gaps(pts, lo, hi, seed=seed, margin_s=120.0)


#: The Autoferry sensors that give positions (relative to the ferry): radar scans every
#: 1.68 s, lidar every 0.50 s.
AUTOFERRY_POSITION_SENSORS = ("radar", "lidar")


def read_autoferry(
    folder: Path, gate_m: float = 15.0, exclusive: bool = False, sensor: str = "radar"
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Autoferry radar (or lidar) plots turned into one track per (scenario, target), and
    the targets' GNSS truth.

    A plot belongs to a target when it lies within ``gate_m`` (m) of the target's GNSS
    position at the plot's time (the radar also sees quays and buildings; the lidar gives
    several returns per hull); per scan the nearest such plot is kept. ``sensor``: radar
    (1.68 s scans) or lidar (0.50 s scans), same gate and rules. Returns (sensor points,
    truth points), both canonical with batch ``scenario/target``, the points' sensor
    ``sensor``.

    ``exclusive``: a plot serves one target at most — the one whose GNSS position is nearer
    (a tracker never puts one plot in two tracks; when two targets pass within a gate, the
    plain rule hands one merged plot to both, and each track then shows the other's motion).
    """
    det = pd.read_csv(folder / "detections.csv.gz")
    truth = pd.read_csv(folder / "ground_truth.csv.gz")
    truth = truth.drop_duplicates(["scenario", "target_id", "time"]).sort_values(
        ["scenario", "target_id", "time"]
    )
    if sensor not in AUTOFERRY_POSITION_SENSORS:
        raise InputError(
            f"sensor {sensor!r}: the Autoferry position sensors are "
            + ", ".join(AUTOFERRY_POSITION_SENSORS)
        )
    radar = det[(det["sensor"] == sensor) & det["meas_north"].notna()].copy()
    radar["north"] = radar["own_north"] + radar["meas_north"]
    radar["east"] = radar["own_east"] + radar["meas_east"]
    parts = []
    for (scen, target), tr in truth.groupby(["scenario", "target_id"]):  # 18 small groups
        r = radar[radar["scenario"] == scen]
        if r.empty:
            continue
        tn = np.interp(r["time"], tr["time"], tr["north"])
        te = np.interp(r["time"], tr["time"], tr["east"])
        d = np.hypot(r["north"].to_numpy() - tn, r["east"].to_numpy() - te)
        inside = (
            (d <= gate_m)
            & (r["time"].to_numpy() >= tr["time"].min())
            & (r["time"].to_numpy() <= tr["time"].max())
        )
        hit = r[inside].assign(d=d[inside], plot=r.index[inside], batch=f"{scen}/{target}")
        if not exclusive:
            hit = hit.sort_values("d").drop_duplicates("scan").sort_values("time")
            hit = hit.drop_duplicates("time")
        parts.append(hit)
    if not parts:
        raise InputError(f"{folder}: no {sensor} plot lies near a GNSS target")
    radar_pts = pd.concat(parts, ignore_index=True)
    if exclusive:  # each plot to its nearest target, then each target's nearest plot per scan
        radar_pts = radar_pts.sort_values("d", kind="stable").drop_duplicates("plot")
        radar_pts = radar_pts.drop_duplicates(["batch", "scan"]).sort_values(["batch", "time"])
        radar_pts = radar_pts.drop_duplicates(["batch", "time"]).reset_index(drop=True)
    truth["batch"] = truth["scenario"].astype(str) + "/" + truth["target_id"].astype(str)
    return _ned_points(radar_pts, sensor), _ned_points(truth, "gnss")


def autoferry_bearings(
    folder: Path, gate_deg: float = 3.0, sensor: str = "eo"
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Autoferry camera bearings (``sensor`` eo or ir) gated to each target by its GNSS
    truth bearing from the ferry (within ``gate_deg``; per time the nearest one), as a
    bearing table (``batch`` scenario-target, ``time``, ``bearing`` deg from north,
    ``obs_lon``/``obs_lat`` the ferry, ``truth_bearing``) and the de-duplicated truth
    (scenario, target_id, time s, north, east in m). The gate uses the truth, so the
    sequences are what an ideal association gives, clutter within the gate included."""
    from wakeline.core import geo

    det = pd.read_csv(folder / "detections.csv.gz")
    truth = pd.read_csv(folder / "ground_truth.csv.gz")
    det = det[(det["sensor"] == sensor) & det["bearing_rad"].notna()]
    truth = truth.drop_duplicates(["scenario", "target_id", "time"]).sort_values("time")
    frames = []
    for (scenario, target), tr in truth.groupby(["scenario", "target_id"]):
        d = det[det["scenario"] == scenario]
        north = np.interp(d["time"], tr["time"], tr["north"])
        east = np.interp(d["time"], tr["time"], tr["east"])
        true_b = np.degrees(np.arctan2(east - d["own_east"], north - d["own_north"]))
        b = np.degrees(d["bearing_rad"].to_numpy())
        err = geo.angle_diff(b, true_b)
        seq = d.assign(bearing=b % 360.0, truth_bearing=true_b % 360.0, err=err)[err < gate_deg]
        seq = seq.sort_values("err").drop_duplicates("time").sort_values("time")
        lon, lat = geo.from_local(
            seq["own_east"].to_numpy(), seq["own_north"].to_numpy(), PIREN_LON, PIREN_LAT
        )
        frames.append(
            pd.DataFrame(
                {
                    "batch": f"{scenario}-{target}",
                    "time": _times(seq["time"].to_numpy()),
                    "bearing": seq["bearing"].to_numpy(),
                    "obs_lon": lon,
                    "obs_lat": lat,
                    "truth_bearing": seq["truth_bearing"].to_numpy(),
                }
            )
        )
    return pd.concat(frames, ignore_index=True), truth


def _ned_points(df: pd.DataFrame, sensor: str) -> pd.DataFrame:
    lon, lat = geo.from_local(
        df["east"].to_numpy(dtype="float64"),
        df["north"].to_numpy(dtype="float64"),
        PIREN_LON,
        PIREN_LAT,
    )
    return pd.DataFrame(
        {
            "sensor": sensor,
            "batch": df["batch"].to_numpy(),
            "time": _times(df["time"].to_numpy()).to_numpy(),
            "lon": lon,
            "lat": lat,
        }
    )


def association_tracks(folder: Path) -> pd.DataFrame:
    """The tracks of a recognised real set (:func:`recognise`) for ``evaluate associate
    --real DIR``, each batch one ship's track (its id the truth): Saronic ``vessels.csv``,
    the DMA ship's ``sample_ship.csv`` (not the third-party ``processed_*.csv``
    simplifications beside it), the Øresund encounters a day apart (:func:`oresund_cut`'s
    clock; a ship of two encounters is two tracks), and Autoferry's exclusive radar tracks
    (:func:`read_autoferry`: the plots within 15 m of a target's GNSS position; batch
    ``scenario/target``) with each scenario two days from the next, so no join can cross
    scenarios — the radar's own gaps, not its clutter, are the test."""
    name = recognise(folder)
    if name == "autoferry":
        pts, _ = read_autoferry(Path(folder), exclusive=True)
        scenario = pts["batch"].str.split("/").str[0].astype(int)
        return pts.assign(time=pts["time"] + pd.to_timedelta(scenario * 2 * 86400, unit="s"))
    if name == "oresund":
        pts = read_oresund(Path(folder)).drop(columns="role")
        enc = pts["batch"].str.split("/").str[0].astype(int)
        return pts.assign(time=pts["time"] + pd.to_timedelta(enc * 86400, unit="s"))
    return {"greece": read_greece, "dma": read_dma}[name](Path(folder))


def recognise(folder: Path) -> str:
    """Which real set a folder holds: greece, dma, oresund or autoferry."""
    folder = Path(folder)
    if not folder.is_dir():
        raise InputError(f"{folder}: not a folder")
    checks = {
        "greece": "vessels.csv",
        "dma": "sample_ship.csv",
        "oresund": "encounters.csv",
        "autoferry": "ground_truth.csv.gz",
    }
    for name, file in checks.items():
        if (folder / file).exists():
            return name
    raise InputError(
        f"{folder}: no known real set (expected one of {', '.join(checks.values())}); "
        "see shared/data/real/*/SOURCE.md"
    )
