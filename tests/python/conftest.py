"""Shared fixtures of the Python module's tests (run by ctest as `python_tests`).

The module comes from PYTHONPATH (build/release/python); the `camplace` command-line tool, the
reference every function is compared with, from CAMPLACE_BINARY (default
build/release/app/camplace).
"""
import json
import os
import subprocess
from pathlib import Path

import pytest

import camplace

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "data"
SCENE = str(DATA / "paper_basic.json")
CORNERS = str(DATA / "paper_basic_corners.json")
BINARY = os.environ.get("CAMPLACE_BINARY", str(ROOT / "build" / "release" / "app" / "camplace"))

# A hand-built scene whose voxels are 1 m cubes: S = [0, 4] x [0, 3] x [0, 2], 4 x 3 x 2 voxels.
# One camera far above S's centre looks straight down and sees all of S. A static block fills
# the middle of voxel (i, j, k) = (3, 2, 0); the target (person) fills the middle of voxel
# (1, 2, 0); the critical object (robot) sits in voxel (3, 0, 0) and occludes nothing.
TINY_SCENE = {
    "area": {"min": [0, 0, 0], "max": [4, 3, 2]},
    "voxels": [4, 3, 2],
    "cameras": {"count": 1, "half_angle_deg": 10, "sides": 8},
    "static_obstacles": [
        {"name": "block", "box": {"min": [3.05, 2.05, 0.05], "max": [3.95, 2.95, 0.95]}}
    ],
    "time_steps": [
        {
            "critical": [{"name": "robot", "box": {"min": [3.1, 0.1, 0.1], "max": [3.3, 0.3, 0.3]}}],
            "events": [
                {
                    "weight": 1,
                    "targets": [
                        {"name": "person", "box": {"min": [1.3, 2.3, 0.3], "max": [1.7, 2.7, 0.7]}}
                    ],
                }
            ],
        }
    ],
}
TINY_CAMERAS = [{"position": [2.0, 1.5, 50.0], "yaw_deg": 0.0, "pitch_deg": -90.0}]


def run_cli(*args):
    """Runs the command-line tool; returns the CompletedProcess (stdout, stderr as text)."""
    return subprocess.run([BINARY, *map(str, args)], capture_output=True, text=True, check=False)


def cli_json(*args):
    """The JSON the command-line tool prints with these arguments (which must succeed)."""
    result = run_cli(*args)
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)


def cli_error(*args):
    """The message the command-line tool prints after "error: " (it must fail with exit 1)."""
    result = run_cli(*args)
    assert result.returncode == 1, result.stdout
    line = result.stderr.strip()
    assert line.startswith("error: "), line
    return line[len("error: "):]


def without_timing(result):
    """`result` without its wall-clock times ("timing_ms", at any depth)."""
    if isinstance(result, dict):
        return {k: without_timing(v) for k, v in result.items() if k != "timing_ms"}
    if isinstance(result, list):
        return [without_timing(v) for v in result]
    return result


def write_json(path, value):
    path.write_text(json.dumps(value))
    return str(path)


@pytest.fixture(scope="session")
def paper():
    return camplace.load_scene(SCENE)


@pytest.fixture
def tiny_files(tmp_path):
    """(scene path, camera file path) of the hand-built scene."""
    return (
        write_json(tmp_path / "tiny.json", TINY_SCENE),
        write_json(tmp_path / "tiny_cameras.json", {"cameras": TINY_CAMERAS}),
    )
