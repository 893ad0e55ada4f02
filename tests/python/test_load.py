"""load_scene, Scene's properties and load_cameras, against the files they read."""
import json

import pytest

import camplace
from conftest import CORNERS, SCENE, TINY_SCENE, cli_error, write_json


def test_scene_properties_are_the_files_values(paper):
    with open(SCENE) as f:
        doc = json.load(f)
    assert paper.file == SCENE
    assert paper.area == {"min": (0.0, 0.0, 0.0), "max": (4.0, 3.0, 3.0)}
    assert paper.voxels == (16, 12, 12)
    assert paper.camera_count == 6
    assert paper.json == doc
    # Err's states: h over the time steps, l over each step's events, with the file's weights.
    expected = [
        {"time_step": h, "event": l, "t": float(step["t"]), "weight": float(event["weight"])}
        for h, step in enumerate(doc["time_steps"])
        for l, event in enumerate(step["events"])
    ]
    assert paper.states == expected
    assert len(paper.states) == 6
    assert "6 cameras" in repr(paper)


def test_scene_json_is_a_copy(paper):
    paper.json["voxels"] = [1, 1, 1]
    assert paper.json["voxels"] == [16, 12, 12]


def test_load_scene_takes_path_objects(tmp_path):
    write_json(tmp_path / "t.json", TINY_SCENE)
    scene = camplace.load_scene(tmp_path / "t.json")  # a pathlib.Path
    assert scene.file == str(tmp_path / "t.json")
    assert scene.voxels == (4, 3, 2)
    assert scene.states == [{"time_step": 0, "event": 0, "t": 0.0, "weight": 1.0}]


def test_load_cameras_returns_the_files_entries(paper):
    with open(CORNERS) as f:
        doc = json.load(f)
    assert camplace.load_cameras(CORNERS) == doc["cameras"]
    assert camplace.load_cameras(CORNERS, paper) == doc["cameras"]


def test_load_cameras_checks_the_count_against_the_scene(tmp_path, paper):
    path = write_json(tmp_path / "one.json", {"cameras": [
        {"position": [1, 1, 1], "yaw_deg": 0, "pitch_deg": 0}]})
    assert len(camplace.load_cameras(path)) == 1  # no scene: any count
    with pytest.raises(ValueError) as raised:
        camplace.load_cameras(path, paper)
    assert str(raised.value) == cli_error("evaluate", SCENE, "--cameras", path)
    assert str(raised.value) == (
        f"{path}: /cameras: holds 1 cameras but the scene {SCENE} has 6")
