"""Generate the small layout samples in this folder (synthetic data, no third-party rows).

Run from the repository root: ``python tests/data/layouts/make_layouts.py``. The files
are committed; this script documents how they were made (seeded, reproducible).
"""

from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
rng = np.random.default_rng(19)


def tracks(n_tracks: int, n_points: int, lon0: float, lat0: float, dt_s: int):
    """Straight-ish tracks with one turn: (track, seconds, lon, lat, speed_kn, course)."""
    rows = []
    for k in range(n_tracks):
        t = 1664590563 + k * 37 + np.arange(n_points) * dt_s
        course = np.where(np.arange(n_points) < n_points // 2, 40.0 + 20 * k, 95.0 + 15 * k)
        speed = 10 + 2 * k + rng.normal(0, 0.3, n_points)
        step = speed * 0.5144 * dt_s
        dx = np.cumsum(step * np.sin(np.radians(course)))
        dy = np.cumsum(step * np.cos(np.radians(course)))
        lat = lat0 + 0.05 * k + dy / 111_320
        lon = lon0 + 0.03 * k + dx / (111_320 * np.cos(np.radians(lat0)))
        for i in range(n_points):
            rows.append((k, int(t[i]), lon[i], lat[i], speed[i], course[i]))
    return rows


def radar() -> None:
    kinds = ["货船", "渔船", "油轮"]
    lines = ["SendShipNO,SendTime,nNO,lon,lat,speed,course,目标类型,备注"]
    for k, t, lon, lat, v, c in tracks(3, 14, 122.41, 30.12, 20):
        note = "疑似拖网" if (t % 7 == 0) else ""
        lines.append(f"1043,{t},{k + 101},{lon:.6f},{lat:.6f},{v:.1f},{c:.1f},{kinds[k]},{note}")
    (HERE / "radar_gb18030.csv").write_bytes(("\r\n".join(lines) + "\r\n").encode("gb18030"))


def marinecadastre() -> None:
    head = (
        "MMSI,BaseDateTime,LAT,LON,SOG,COG,Heading,VesselName,IMO,CallSign,VesselType,"
        "Status,Length,Width,Draft,Cargo,TransceiverClass"
    )
    names = ['"SEA STAR, II"', "NORDIC MIST", ""]
    lines = [head]
    for k, t, lon, lat, v, c in tracks(3, 12, -94.41, 28.9, 60):
        iso = np.datetime64(t, "s").astype(str)
        heading = "511" if k == 2 else f"{int(c)}"
        imo = f"IMO{9300000 + k}" if k < 2 else ""
        lines.append(
            f"{367000100 + k},{iso},{lat:.5f},{lon:.5f},{v:.1f},{c:.1f},{heading},{names[k]},"
            f"{imo},WDC{k}7,{70 + k},0,{120 + 10 * k},{20 + k},{6.5 + k:.1f},{70 + k},A"
        )
    (HERE / "marinecadastre.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")


def dma() -> None:
    head = (
        "# Timestamp,Type of mobile,MMSI,Latitude,Longitude,Navigational status,ROT,SOG,COG,"
        "Heading,IMO,Callsign,Name,Ship type,Cargo type,Width,Length,"
        "Type of position fixing device,Draught,Destination,ETA,Data source type,A,B,C,D"
    )
    lines = [head]
    for k, t, lon, lat, v, c in tracks(2, 15, 11.80, 57.66, 10):
        stamp = np.datetime64(t, "s").astype(object).strftime("%d/%m/%Y %H:%M:%S")
        sog = "" if (t % 11 == 0) else f"{v:.1f}"
        lines.append(
            f"{stamp},Class A,{219000300 + k},{lat:.6f},{lon:.6f},Under way using engine,"
            f"0.0,{sog},{c:.1f},{int(c)},Unknown,OXA{k}2,STENA {k},Cargo,,{20 + k},{150 + k},"
            f"GPS,{7.2 + k:.1f},GOTEBORG,01/03/2023 06:00:00,AIS,{100 + k},{50 + k},10,10"
        )
    (HERE / "dma.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")


def mtad() -> None:
    # Scene layout: BOM, seconds from scene start written like "12.0", trimmed decimals.
    lines = ["MMSI,time,lat,lon,vel,cou"]
    for k, t, lon, lat, v, c in tracks(3, 10, 131.2, 20.1, 6):
        rel = float(t - 1664590563)
        vals = (lat, 6 - (k % 2)), (lon, 6), (v * 0.5144, 6), (c + rng.normal(0, 2), 6)
        lat_s, lon_s, vel_s, cou_s = (repr(round(float(x), d)) for x, d in vals)
        lines.append(f"41380482{k}-0,{rel!r},{lat_s},{lon_s},{vel_s},{cou_s}")
    (HERE / "mtad_scene.csv").write_bytes(b"\xef\xbb\xbf" + ("\n".join(lines) + "\n").encode())
    # Measurement layout: batch and source columns, float seconds.
    lines = ["batch,source,time,lat,lon,vel,cou"]
    for k, t, lon, lat, v, c in tracks(4, 9, 130.9, 19.9, 10):
        lines.append(
            f"{k % 2},{9001 + k // 2},{t - 1664590563 + 0.5 * k:.1f},{lat:.6f},{lon:.6f},"
            f"{v:.3f},{c:.2f}"
        )
    (HERE / "mtad_measurement.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")


def canonical() -> None:
    import pandas as pd

    from wakeline.core.io import write_points

    rows = tracks(3, 12, 4.2, 52.1, 30)
    df = pd.DataFrame(rows, columns=["k", "t", "lon", "lat", "speed", "course"])
    out = pd.DataFrame(
        {
            "sensor": np.where(df["k"] < 2, "R1", "AIS"),
            "batch": df["k"].map(lambda k: f"{k:03d}"),
            "time": pd.to_datetime(df["t"] * 1000 + df["k"] * 125, unit="ms", utc=True),
            "lon": df["lon"].round(7),
            "lat": df["lat"].round(7),
            "speed": df["speed"].round(2),
            "course": df["course"],
        }
    )
    write_points(out, HERE / "canonical.csv")


if __name__ == "__main__":
    radar()
    marinecadastre()
    dma()
    mtad()
    canonical()
