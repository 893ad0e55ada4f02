"""generate() against `camplace generate`."""
import json

import camplace
from conftest import run_cli


def test_generate_equals_the_command_lines_scene(tmp_path):
    for family, param, seed in [("resolution", 2, 1), ("dynamic_objects", 1, 7),
                                ("domain_ceiling", None, 1)]:
        out = tmp_path / f"{family}.json"
        args = ["generate", family, "--seed", seed, "--out", out]
        if param is not None:
            args += ["--param", param]
        result = run_cli(*args)
        assert result.returncode == 0, result.stderr
        expected = json.loads(out.read_text())
        assert camplace.generate(family, param, seed) == expected


def test_generate_writes_a_scene_that_loads(tmp_path):
    out = tmp_path / "cameras5.json"
    scene = camplace.generate("cameras", 5, out=out)
    assert json.loads(out.read_text()) == scene
    assert scene["cameras"]["count"] == 5
    assert camplace.load_scene(out).camera_count == 5


def test_scene_families_match_the_command_line():
    families = camplace.scene_families()
    help_text = run_cli("generate", "--help").stdout
    assert [f["name"] for f in families][:2] == ["resolution", "static_facets"]
    for f in families:
        assert f"  {f['name']}" in help_text
        if f["has_param"]:
            lo, hi = f["param_range"]
            assert f"{f['name']} (i = {lo}..{hi})" in help_text
        else:
            assert f["param_range"] is None
