"""evaluate() against `camplace evaluate --json` on the same inputs: the same keys and values
(wall-clock times aside)."""
import json
import math
from fractions import Fraction

import pytest

import camplace
from conftest import CORNERS, SCENE, TINY_CAMERAS, cli_json, without_timing


@pytest.mark.parametrize("mode", ["center", "conservative"])
def test_voxel_pipeline_equals_the_command_line(paper, mode):
    expected = cli_json("evaluate", SCENE, "--cameras", CORNERS, "--mode", mode, "--json")
    got = camplace.evaluate(paper, CORNERS, mode=mode)
    assert without_timing(got) == without_timing(expected)
    assert set(got["timing_ms"]) == set(expected["timing_ms"])


def test_resolution_and_threads_as_on_the_command_line(paper):
    expected = cli_json("evaluate", SCENE, "--cameras", CORNERS, "--resolution", "8x6x5",
                        "--threads", "2", "--json")
    for resolution in ["8x6x5", (8, 6, 5), [8, 6, 5]]:
        got = camplace.evaluate(paper, CORNERS, resolution=resolution, threads=2)
        assert without_timing(got) == without_timing(expected)
    assert got["resolution"] == [8, 6, 5]


def test_refinement_as_on_the_command_line(paper):
    expected = cli_json("evaluate", SCENE, "--cameras", CORNERS, "--refine", "2", "--json")
    got = camplace.evaluate(paper, CORNERS, refine=2)
    assert got["refine"] == 2
    assert without_timing(got) == without_timing(expected)
    assert got["err_lower_bound"] < camplace.evaluate(paper, CORNERS)["err_lower_bound"]


def test_cameras_as_list_or_dict_give_the_files_result(paper):
    from_file = camplace.evaluate(paper, CORNERS)
    cameras = camplace.load_cameras(CORNERS)
    for given in [cameras, {"cameras": cameras}, [dict(c, position=tuple(c["position"]))
                                                  for c in cameras]]:
        got = camplace.evaluate(paper, given)
        assert got["cameras_file"] is None
        got["cameras_file"] = from_file["cameras_file"]
        assert without_timing(got) == without_timing(from_file)


def test_exact_and_both_pipelines_equal_the_command_line(tiny_files):
    scene_file, cameras_file = tiny_files
    scene = camplace.load_scene(scene_file)
    for pipeline in ["exact", "both"]:
        expected = cli_json("evaluate", scene_file, "--cameras", cameras_file, "--pipeline",
                            pipeline, "--mode", "center", "--json")
        got = camplace.evaluate(scene, cameras_file, pipeline=pipeline, mode="center")
        assert without_timing(got) == without_timing(expected)
    assert got["voxel"]["fov"] == "pyramid"
    assert "differences" in got


def test_exact_fractions_are_fractions(tiny_files):
    scene_file, cameras_file = tiny_files
    scene = camplace.load_scene(scene_file)
    expected = cli_json("evaluate", scene_file, "--cameras", cameras_file, "--pipeline", "exact",
                        "--exact-fractions", "--json")
    got = camplace.evaluate(scene, TINY_CAMERAS, pipeline="exact", fractions=True)
    (state,) = got["states"]
    keys = ["d_true_sq_exact", "d_model_sq_exact", "model_volume_exact"]
    for key in keys:
        assert isinstance(state[key], Fraction)
        assert state[key] == Fraction(expected["states"][0][key])
    # By hand, in exact arithmetic on the file's doubles: robot [3.1, 3.3] x [0.1, 0.3] x
    # [0.1, 0.3], person [1.3, 1.7] x [2.3, 2.7] x [0.3, 0.7]: the boxes overlap in z, so
    # d_true² = (3.1 - 1.7)² + (2.3 - 0.3)² (≈ 1.96 + 4 m²).
    dx = Fraction(3.1) - Fraction(1.7)
    dy = Fraction(2.3) - Fraction(0.3)
    assert state["d_true_sq_exact"] == dx * dx + dy * dy
    assert math.isclose(state["d_true"], math.sqrt(5.96), rel_tol=1e-12)
    plain = {k: v for k, v in state.items() if k not in keys}
    assert plain == {k: v for k, v in expected["states"][0].items() if k not in keys}


def test_voxels_out_writes_the_command_lines_files(paper, tmp_path):
    cli_file, py_file = tmp_path / "cli.npy", tmp_path / "py.npy"
    cli_json("evaluate", SCENE, "--cameras", CORNERS, "--json", "--voxels-out", cli_file)
    camplace.evaluate(paper, CORNERS, voxels_out=py_file)
    assert py_file.read_bytes() == cli_file.read_bytes()
    assert py_file.with_suffix(".vtk").read_bytes() == cli_file.with_suffix(".vtk").read_bytes()
    py_doc = json.loads(py_file.with_suffix(".json").read_text())
    cli_doc = json.loads(cli_file.with_suffix(".json").read_text())
    assert py_doc.pop("data") == "py.npy" and cli_doc.pop("data") == "cli.npy"
    assert py_doc == cli_doc
    assert py_doc["dimensions"] == [16, 12, 12]


def test_export_mesh_writes_the_command_lines_files(tiny_files, tmp_path):
    scene_file, cameras_file = tiny_files
    cli_dir, py_dir = tmp_path / "cli", tmp_path / "py"
    cli_json("evaluate", scene_file, "--cameras", cameras_file, "--pipeline", "exact", "--json",
             "--export-mesh", cli_dir)
    camplace.evaluate(camplace.load_scene(scene_file), cameras_file, pipeline="exact",
                      export_mesh=py_dir)
    names = sorted(p.name for p in cli_dir.iterdir())
    assert names == ["camera-0-pyramid.off", "state-h0-e0-model.off"]
    assert sorted(p.name for p in py_dir.iterdir()) == names
    for name in names:
        assert (py_dir / name).read_text() == (cli_dir / name).read_text()


def test_frustum_models_and_roll_as_on_the_command_line(tmp_path):
    # A scene with two frustum models; cameras with roll_deg and their model's name.
    from conftest import ROOT, write_json
    scene_file = str(ROOT / "tests" / "data" / "frustum_small.json")
    cameras = [
        {"model": "rgb", "position": [0.1, 0.1, 2.4], "yaw_deg": 45, "pitch_deg": -35,
         "roll_deg": 20},
        {"model": "rgb", "position": [2.9, 2.9, 2.4], "yaw_deg": -135, "pitch_deg": -35,
         "roll_deg": -10},
        {"model": "depth", "position": [2.9, 0.1, 2.4], "yaw_deg": 135, "pitch_deg": -40},
    ]
    cameras_file = write_json(tmp_path / "cameras.json", {"cameras": cameras})
    scene = camplace.load_scene(scene_file)
    expected = cli_json("evaluate", scene_file, "--cameras", cameras_file, "--mode", "center",
                        "--json")
    got = camplace.evaluate(scene, cameras, mode="center")
    got["cameras_file"] = expected["cameras_file"]
    assert without_timing(got) == without_timing(expected)
    assert [c["model"] for c in got["diagnostics"]["cameras"]] == ["rgb", "rgb", "depth"]
    assert [c["roll_deg"] for c in got["diagnostics"]["cameras"]] == pytest.approx([20, -10, 0])
    assert camplace.load_cameras(cameras_file, scene)[0]["roll_deg"] == 20
    # Roll turns a frustum: another roll sees another part of S.
    turned = [dict(c, roll_deg=c.get("roll_deg", 0) + 60) for c in cameras]
    fraction = camplace.evaluate(scene, turned, mode="center")["diagnostics"]["cameras"][0]
    assert fraction["fov_fraction"] != got["diagnostics"]["cameras"][0]["fov_fraction"]
