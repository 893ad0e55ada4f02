"""Bad input raises ValueError with the command line's message (file, entry, reason); bad
arguments name the keyword; nothing crashes the interpreter."""
import json

import pytest

import camplace
from conftest import CORNERS, SCENE, TINY_CAMERAS, TINY_SCENE, cli_error, run_cli, write_json


def message(call, *args, **kwargs):
    with pytest.raises(ValueError) as raised:
        call(*args, **kwargs)
    return str(raised.value)


def test_scene_errors_are_the_command_lines(tmp_path):
    missing = str(tmp_path / "missing.json")
    typo = write_json(tmp_path / "typo.json", dict(TINY_SCENE, plausability={}))
    weight = json.loads(json.dumps(TINY_SCENE))
    weight["time_steps"][0]["events"][0]["weight"] = -1
    negative = write_json(tmp_path / "negative.json", weight)
    not_json = tmp_path / "broken.json"
    not_json.write_text('{"area": ')
    for path in [missing, typo, negative, str(not_json)]:
        expected = cli_error("evaluate", path, "--cameras", CORNERS)
        assert message(camplace.load_scene, path) == expected
        assert expected.startswith(path + ": ")
    assert message(camplace.load_scene, typo).startswith(
        f'{typo}: /plausability: unknown field "plausability"')
    assert message(camplace.load_scene, negative) == (
        f"{negative}: /time_steps/0/events/0/weight: weight must not be negative")


def test_camera_file_errors_are_the_command_lines(tmp_path, paper):
    cameras = json.loads(open(CORNERS).read())["cameras"]
    bad_yaw = [dict(c) for c in cameras]
    bad_yaw[2]["yaw_deg"] = 190
    bad_key = [dict(c) for c in cameras]
    bad_key[0]["tilt_deg"] = 0
    for name, value in [("yaw", bad_yaw), ("key", bad_key), ("count", cameras[:2])]:
        path = write_json(tmp_path / f"{name}.json", {"cameras": value})
        expected = cli_error("evaluate", SCENE, "--cameras", path)
        assert message(camplace.evaluate, paper, path) == expected
        assert message(camplace.load_cameras, path, paper) == expected
        # The same list given directly: the same entry and reason, from "cameras argument".
        assert message(camplace.evaluate, paper, value) == expected.replace(
            path, "cameras argument", 1)
    assert message(camplace.evaluate, paper, bad_yaw) == (
        "cameras argument: /cameras/2/yaw_deg: value 190 out of range [-180, 180]")


def test_generate_errors_give_the_command_lines_reason(tmp_path):
    # The library names the argument as the keyword ("family", "param"); the command line names
    # its own FAMILY and --param; the reason is the same.
    out = tmp_path / "x.json"
    assert message(camplace.generate, "nonsense", 1) == cli_error(
        "generate", "nonsense", "--param", 1, "--out", out).replace(
            "command line: FAMILY:", "option: family:")
    assert message(camplace.generate, "resolution", 99) == cli_error(
        "generate", "resolution", "--param", 99, "--out", out).replace(
            "command line: --param:", "option: param:")


def test_bad_arguments_name_the_keyword(paper):
    cases = [
        (camplace.evaluate, (paper, CORNERS), {"mode": "middle"},
         'option: mode: unknown mode "middle" (expected "center" or "conservative")'),
        (camplace.evaluate, (paper, CORNERS), {"pipeline": "fast"},
         'option: pipeline: unknown pipeline "fast" (expected "voxel", "exact" or "both")'),
        (camplace.evaluate, (paper, CORNERS), {"resolution": "16x12"},
         'option: resolution: expected NXxNYxNZ (e.g. 16x12x12), got "16x12"'),
        (camplace.evaluate, (paper, CORNERS), {"resolution": (0, 4, 4)},
         "option: resolution: every voxel count must lie in [1, 4096]"),
        (camplace.evaluate, (paper, CORNERS), {"threads": 999},
         "option: threads: must lie in [0, 256] (0 = one per core)"),
        (camplace.evaluate, (paper, CORNERS), {"fractions": True},
         'option: fractions: needs pipeline "exact" or "both"'),
        (camplace.voxel_model, (paper, CORNERS), {"state": (2, 0)},
         f"option: state: the scene {SCENE} has no state (2, 0) (time step h, event l; see "
         "Scene.states)"),
        (camplace.voxel_model, (paper, CORNERS), {"fov": "sphere"},
         'option: fov: unknown fov "sphere" (expected "cone", "pyramid" or "frustum")'),
        (camplace.labels, (paper, CORNERS), {"camera": 6},
         "option: camera: must lie in [0, 5] (one of the scene's 6 cameras)"),
        (camplace.optimize, (paper,), {"time_limit": -1},
         "option: time_limit: must be a number of seconds in [0, 1e7] (0 = no limit)"),
        (camplace.optimize, (paper,), {"population": -2},
         "option: population: must lie in [0, 100000] (0 = the solver's default)"),
    ]
    for call, args, kwargs, expected in cases:
        assert message(call, *args, **kwargs) == expected, kwargs
    assert message(camplace.evaluate, paper, CORNERS, voxels_out="/proc/none/v.npy") == (
        cli_error("evaluate", SCENE, "--cameras", CORNERS, "--voxels-out", "/proc/none/v.npy")
        .replace("command line: --voxels-out:", "option: voxels_out:"))
    assert message(camplace.evaluate, paper, CORNERS, pipeline="exact",
                   export_mesh="/proc/none") == (
        cli_error("evaluate", SCENE, "--cameras", CORNERS, "--pipeline", "exact",
                  "--export-mesh", "/proc/none")
        .replace("command line: --export-mesh:", "option: export_mesh:"))
    assert "algorithm" in message(camplace.optimize, paper, algorithm="nelder_mead",
                                  max_evaluations=10)
    assert message(camplace.optimize, paper, objective="volume", max_evaluations=10) == (
        "option: objective: unknown objective \"volume\" (expected err, err+volume, "
        "err+touching-volume)")


def test_a_camera_path_no_file_can_have_is_a_value_error(paper):
    # It used to escape as RuntimeError ("Unable to cast Python instance to C++ type").
    assert message(camplace.evaluate, paper, "cams\0.json") == (
        "cameras: not a file path: 'cams\\x00.json'")


def test_wrong_types_raise_type_errors(paper):
    with pytest.raises(TypeError):
        camplace.evaluate(paper, [{"position": object(), "yaw_deg": 0, "pitch_deg": 0}] * 6)
    with pytest.raises(TypeError):
        camplace.evaluate("data/paper_basic.json", CORNERS)  # a path, not a Scene
    with pytest.raises(TypeError):
        camplace.optimize(paper, callback=42)


def nested(depth):
    """A list nested `depth` levels deep: [[[...]]]."""
    value = []
    for _ in range(depth - 1):
        value = [value]
    return value


def test_cameras_that_contain_themselves_or_nest_too_deep_raise_value_errors(paper):
    loop = []
    loop.append(loop)
    assert message(camplace.evaluate, paper, loop) == "cameras/0: a list that contains itself"
    run = {}
    run["cameras"] = run
    assert message(camplace.evaluate, paper, run) == "cameras/cameras: a dict that contains itself"
    cameras = json.loads(open(CORNERS).read())["cameras"]
    position = [1.0, 1.0]
    position.append(position)
    cameras[3] = dict(cameras[3], position=position)
    assert message(camplace.evaluate, paper, cameras) == (
        "cameras/3/position/2: a list that contains itself")
    too_deep = "cameras: lists and dicts nested more than 1000 levels deep"
    for call in [camplace.evaluate, camplace.voxel_model, camplace.labels]:
        assert message(call, paper, nested(200_000)) == too_deep
    assert message(camplace.evaluate, paper, nested(1001)) == too_deep
    # Up to the limit the nesting is only a camera list of the wrong shape.
    assert message(camplace.evaluate, paper, nested(1000)).startswith(
        "cameras argument: /cameras: holds 1 cameras")
    # One camera given many times is no cycle.
    assert camplace.evaluate(paper, [cameras[0]] * 6)["err"] >= 0


def test_scene_json_nested_too_deep_raises_value_error(tmp_path):
    # The description is ignored: the scene loads and evaluates; only its content as dicts and
    # lists is too deep to give.
    deep = tmp_path / "deep.json"
    deep.write_text(json.dumps(dict(TINY_SCENE, description="DEEP")).replace(
        '"DEEP"', "[" * 100_000 + "]" * 100_000))
    cameras = write_json(tmp_path / "cameras.json", {"cameras": TINY_CAMERAS})
    assert run_cli("evaluate", deep, "--cameras", cameras).returncode == 0
    scene = camplace.load_scene(str(deep))
    assert camplace.evaluate(scene, TINY_CAMERAS)["err"] >= 0
    with pytest.raises(ValueError) as raised:
        scene.json
    assert str(raised.value) == f"{deep}: arrays and objects nested more than 1000 levels deep"
    # At the limit (the scene and 999 arrays) the content comes back whole.
    at_limit = tmp_path / "limit.json"
    at_limit.write_text(json.dumps(dict(TINY_SCENE, description="DEEP")).replace(
        '"DEEP"', "[" * 999 + "]" * 999))
    description = camplace.load_scene(str(at_limit)).json["description"]
    for _ in range(998):
        (description,) = description
    assert description == []


def test_control_characters_in_keys_are_escaped_not_cut(tmp_path):
    for name, key, shown in [("nul", "plaus\0ibility", "plaus\\u0000ibility"),
                             ("line", "x\nerror: forged", "x\\nerror: forged")]:
        path = write_json(tmp_path / f"{name}.json", dict(TINY_SCENE, **{key: {}}))
        expected = message(camplace.load_scene, path)
        assert expected.startswith(
            f'{path}: /{shown}: unknown field "{shown}" (expected one of: area, '), expected
        assert expected == cli_error("evaluate", path, "--cameras", CORNERS)
