"""Golden outputs: every command's files on small simulated scenes, pinned by SHA-256.

The scenes are stored in ``tests/data/golden/`` (rows shuffled, so every command sorts),
and the hashes of what each command writes are in ``golden.json``. A speed-up must leave
every byte as it was. When a change of results is intended, regenerate with
``python tests/test_golden.py --update`` and say so in the commit.
"""

import hashlib
import json
import re
import sys
from pathlib import Path

import numpy as np
import pytest

from wakeline.app.cli import main

GOLDEN = Path(__file__).resolve().parent / "data" / "golden"
HASHES = GOLDEN / "golden.json"

#: name → (scene file, command arguments before the input; outputs named by flag).
RUNS: dict[str, tuple[str, list[str], list[str]]] = {
    "import_maneuver": ("maneuver.csv", ["import"], ["-o", "--report"]),
    "import_segments": ("segments.csv", ["import"], ["-o"]),
    "maneuvers_pca": ("maneuver.csv", ["maneuvers"], ["-o"]),
    "maneuvers_window_s": ("maneuver.csv", ["maneuvers", "--window-s", "1500"], ["-o"]),
    "compress_maneuver": ("maneuver.csv", ["compress"], ["-o", "--report"]),
    "compress_raw": ("maneuver.csv", ["compress", "--raw-vertices"], ["-o"]),
    "compress_dp": ("maneuver.csv", ["compress", "--method", "dp"], ["-o", "--report"]),
    "compress_dp_line": (
        "maneuver.csv",
        ["compress", "--method", "dp", "--dp-distance", "line"],
        ["-o", "--report"],
    ),
    "compress_dp_line_tight": (
        "segments.csv",
        ["compress", "--method", "dp", "--tolerance", "50", "--dp-distance", "line"],
        ["-o", "--report"],
    ),
    "compress_dp_tight": (
        "segments.csv",
        ["compress", "--method", "dp", "--tolerance", "50"],
        ["-o", "--report"],
    ),
    "clean": ("segments.csv", ["clean"], ["-o", "--rejected", "--report"]),
    "associate": ("segments.csv", ["associate"], ["-o", "--pairs", "--report"]),
    "associate_greedy": ("segments.csv", ["associate", "--method", "greedy"], ["-o", "--pairs"]),
    "fuse_scene_import": ("multisensor.csv", ["import"], ["-o"]),
    "maneuvers_multisensor": ("multisensor.csv", ["maneuvers"], ["-o"]),
}


def _make_scenes() -> None:
    """Write the scenes (run once; the stored files are what the test reads)."""
    from wakeline.core import simulate

    rng = np.random.default_rng(17)
    scenes = {
        "maneuver.csv": simulate.maneuver_tracks(8, "short", 300.0, seed=17),
        "segments.csv": simulate.segments_scene(seed=17, n_ships=6, area_km=30.0),
        "multisensor.csv": simulate.multisensor_scene(seed=17, n_ships=4, area_km=30.0),
    }
    from wakeline.core.io import write_points

    for name, df in scenes.items():
        write_points(df.iloc[rng.permutation(len(df))], GOLDEN / name)


def _run(name: str, tmp: Path) -> dict[str, str]:
    scene, command, outputs = RUNS[name]
    argv = [*command, str(GOLDEN / scene)]
    files = {}
    for flag in outputs:
        ext = ".json" if flag == "--report" else ".csv"
        path = tmp / f"{name}{flag.strip('-')}{ext}"
        argv += [flag, str(path)]
        files[flag] = path
    assert main(argv) == 0
    return {flag: hashlib.sha256(_content(flag, path)).hexdigest() for flag, path in files.items()}


def _content(flag: str, path: Path) -> bytes:
    """The bytes a run wrote; a JSON report without the values that name files (they
    depend on where the repository is checked out). Numbers written at full float64
    precision (a report's, a maneuver's factor) count to 8 significant digits: numpy's
    sin, cos, arctan2 and log differ in the last bit between CPUs (AVX-512 machines take
    other SIMD paths; ``NPY_DISABLE_CPU_FEATURES="X86_V4 AVX512_ICL"`` shows it)."""
    if flag != "--report":
        return _FULL_FLOAT.sub(lambda m: b"%.8g" % float(m.group()), path.read_bytes())

    def strip(value):
        if isinstance(value, dict):
            return {k: strip(v) for k, v in value.items() if k not in PATH_KEYS}
        if isinstance(value, list):
            return [strip(v) for v in value]
        if isinstance(value, float):
            return float(f"{value:.8g}")
        return value

    return json.dumps(strip(json.loads(path.read_text())), sort_keys=True).encode()


#: A number in a CSV with more than 10 decimals: written at full float64 precision.
_FULL_FLOAT = re.compile(rb"-?\d+\.\d{11,}(?:e[-+]?\d+)?")

#: Report keys whose values are file paths.
PATH_KEYS = {"input", "output", "file", "path", "source_file"}


@pytest.mark.parametrize("name", sorted(RUNS))
def test_outputs_are_unchanged(name, tmp_path):
    expected = json.loads(HASHES.read_text())[name]
    assert _run(name, tmp_path) == expected


if __name__ == "__main__":
    import tempfile

    if "--scenes" in sys.argv:
        _make_scenes()
    if "--update" in sys.argv:
        with tempfile.TemporaryDirectory() as tmp:
            hashes = {name: _run(name, Path(tmp)) for name in sorted(RUNS)}
        HASHES.write_text(json.dumps(hashes, indent=2, sort_keys=True) + "\n")
