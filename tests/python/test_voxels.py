"""voxel_model, labels and voxel_grid: orientation on a hand-built scene, models against
`camplace evaluate --voxels-out`."""
import json

import numpy as np
import pytest

import camplace
from conftest import CORNERS, SCENE, TINY_CAMERAS, run_cli


def cli_models(tmp_path, scene_file, cameras_file, *options):
    """The --voxels-out files' models as bool arrays (states, nz, ny, nx): the .npy array and
    its JSON sidecar (which lists the states), as docs/files.md describes them."""
    path = tmp_path / "voxels.npy"
    result = run_cli("evaluate", scene_file, "--cameras", cameras_file, "--voxels-out", path,
                     *options)
    assert result.returncode == 0, result.stderr
    doc = json.loads(path.with_suffix(".json").read_text())
    models = np.load(path).astype(bool)
    nx, ny, nz = doc["dimensions"]
    assert models.shape == (len(doc["states"]), nz, ny, nx)
    return doc, models


@pytest.mark.parametrize("mode", ["center", "conservative"])
def test_models_equal_voxels_out(paper, tmp_path, mode):
    doc, expected = cli_models(tmp_path, SCENE, CORNERS, "--mode", mode, "--resolution", "9x7x5")
    got = camplace.voxel_model(paper, CORNERS, state=None, mode=mode, resolution="9x7x5")
    assert got.dtype == np.bool_
    assert got.shape == (6, 5, 7, 9)
    np.testing.assert_array_equal(got, expected)
    for index, state in enumerate(doc["states"]):
        one = camplace.voxel_model(paper, CORNERS, state=(state["time_step"], state["event"]),
                                   mode=mode, resolution=(9, 7, 5))
        np.testing.assert_array_equal(one, expected[index])


def test_pyramid_models_equal_voxels_out_of_pipeline_both(tiny_files, tmp_path):
    scene_file, cameras_file = tiny_files
    _, expected = cli_models(tmp_path, scene_file, cameras_file, "--pipeline", "both",
                             "--resolution", "8x6x4")
    scene = camplace.load_scene(scene_file)
    got = camplace.voxel_model(scene, TINY_CAMERAS, state=None, fov="pyramid",
                               resolution="8x6x4")
    np.testing.assert_array_equal(got, expected)


def test_model_orientation_on_the_hand_built_scene(tiny_files):
    scene = camplace.load_scene(tiny_files[0])
    model = camplace.voxel_model(scene, TINY_CAMERAS, state=(0, 0), mode="center")
    # The camera sees every voxel centre free except along the rays through the person (voxel
    # (1, 2, 0) and the one above it, (1, 2, 1): occupied) and behind the block's top (voxel
    # (3, 2, 0): undetectable, but its centre lies inside the block, so not in M).
    expected = np.zeros((2, 3, 4), dtype=bool)  # (nz, ny, nx)
    expected[0, 2, 1] = True  # [k, j, i] of voxel (i, j, k) = (1, 2, 0)
    expected[1, 2, 1] = True  # (1, 2, 1)
    np.testing.assert_array_equal(model, expected)
    grid = camplace.voxel_grid(scene)
    assert grid["origin"] == (0.0, 0.0, 0.0)
    assert grid["spacing"] == (1.0, 1.0, 1.0)
    assert grid["resolution"] == (4, 3, 2)
    assert grid["shape"] == model.shape
    # The voxels of M, by the grid: x in [1, 2], y in [2, 3], z in [0, 2] holds the person box.
    k, j, i = np.nonzero(model)
    lo = np.array(grid["origin"]) + np.stack([i, j, k], axis=1) * np.array(grid["spacing"])
    assert lo.tolist() == [[1.0, 2.0, 0.0], [1.0, 2.0, 1.0]]


def test_labels_on_the_hand_built_scene(tiny_files):
    scene = camplace.load_scene(tiny_files[0])
    labels = camplace.labels(scene, TINY_CAMERAS, state=(0, 0), mode="center")
    assert labels.dtype == np.uint8
    assert labels.shape == (1, 2, 3, 4)  # (cameras, nz, ny, nx)
    expected = np.full((2, 3, 4), camplace.FREE, dtype=np.uint8)
    expected[0, 2, 1] = expected[1, 2, 1] = camplace.OCCUPIED  # the rays through the person
    expected[0, 2, 3] = camplace.UNDETECTABLE  # behind the block's top face (z = 0.95)
    np.testing.assert_array_equal(labels[0], expected)
    np.testing.assert_array_equal(
        camplace.labels(scene, TINY_CAMERAS, state=(0, 0), camera=0, mode="center"), expected)
    assert (camplace.FREE, camplace.OCCUPIED, camplace.UNDETECTABLE) == (0, 1, 2)


def test_labels_per_camera_make_the_unfiltered_model(paper):
    # M before the filter is the voxels no camera labels free, minus obstacle interiors; the
    # filter only removes voxels, so M after it lies inside the voxels no camera sees free.
    labels = camplace.labels(paper, CORNERS, state=(1, 2), mode="conservative")
    model = camplace.voxel_model(paper, CORNERS, state=(1, 2), mode="conservative")
    assert labels.shape == (6, 12, 12, 16)
    seen_free = (labels == camplace.FREE).any(axis=0)
    assert model.any()
    assert not (model & seen_free).any()
