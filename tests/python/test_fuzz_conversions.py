"""The conversions of Python arguments, fuzzed: seeded random values (nested lists, dicts and
tuples of every Python scalar, cycles, deep nesting, mutated valid camera lists) go to every
function that converts a Python object. Each either works or raises ValueError or TypeError;
anything else (a crash of the interpreter, another exception) fails the test. The seed and the
count come from CAMPLACE_FUZZ_SEED and CAMPLACE_FUZZ_INPUTS (default 1 and 400 per function)."""
import copy
import json
import math
import os
import random

import pytest

import camplace
from conftest import CORNERS

SEED = int(os.environ.get("CAMPLACE_FUZZ_SEED", "1"))
INPUTS = int(os.environ.get("CAMPLACE_FUZZ_INPUTS", "400"))

SCALARS = [None, True, False, 0, -1, 1, 2**63, -(2**64), 1e308, -0.0, math.nan, math.inf,
           -math.inf, 0.5, "", "yaw_deg", "x" * 1000, "\u0000\n\"", b"bytes", bytearray(b"b"),
           1j, object(), Ellipsis, range(3), {1, 2}]
KEYS = ["position", "yaw_deg", "pitch_deg", "roll_deg", "model", "cameras", "provenance", "",
        "\u0000", 7, None, (1, 2), 2.5]


def random_value(rng, depth=0):
    """A random Python value: scalars, containers of them, and now and then a cycle."""
    roll = rng.random()
    if depth > 6 or roll < 0.35:
        return rng.choice(SCALARS)
    if roll < 0.6:
        value = [random_value(rng, depth + 1) for _ in range(rng.randint(0, 7))]
        if rng.random() < 0.05:
            value.append(value)
        return value if rng.random() < 0.8 else tuple(value)
    value = {}
    for _ in range(rng.randint(0, 6)):
        value[rng.choice(KEYS)] = random_value(rng, depth + 1)
    if rng.random() < 0.05:
        value[rng.choice(KEYS)] = value
    return value


def mutated_cameras(rng, cameras):
    """The valid camera list with a few entries replaced by random values."""
    value = copy.deepcopy(cameras)
    for _ in range(rng.randint(1, 3)):
        camera = value[rng.randrange(len(value))]
        key = rng.choice(list(camera.keys()) + ["extra"])
        if key in camera and isinstance(camera[key], list) and camera[key] and rng.random() < 0.5:
            camera[key][rng.randrange(len(camera[key]))] = random_value(rng, 4)
        else:
            camera[key] = random_value(rng, 4)
    return value


def deep(rng):
    value = rng.choice(SCALARS)
    for _ in range(rng.choice([999, 1000, 1001, 5000])):
        value = [value] if rng.random() < 0.5 else {"cameras": value}
    return value


def call(function, *args, **kwargs):
    try:
        function(*args, **kwargs)
    except (ValueError, TypeError):
        pass


@pytest.mark.parametrize("name", ["evaluate", "voxel_model", "labels"])
def test_random_camera_arguments_raise_only_value_or_type_errors(paper, name):
    function = getattr(camplace, name)
    rng = random.Random(f"{SEED}-{name}")
    cameras = json.loads(open(CORNERS).read())["cameras"]
    for i in range(INPUTS):
        kind = i % 4
        if kind == 0:
            value = random_value(rng)
        elif kind == 1:
            value = mutated_cameras(rng, cameras)
        elif kind == 2:
            value = {"cameras": mutated_cameras(rng, cameras), "provenance": random_value(rng)}
        else:
            value = deep(rng) if rng.random() < 0.1 else [random_value(rng) for _ in range(6)]
        # A coarse grid keeps each evaluation of a valid input at about a millisecond.
        kwargs = {"resolution": [4, 3, 3]} if rng.random() < 0.5 else {}
        call(function, paper, value, **kwargs)


def test_random_keyword_values_raise_only_value_or_type_errors(paper):
    rng = random.Random(f"{SEED}-keywords")
    cameras = json.loads(open(CORNERS).read())["cameras"]
    keywords = ["pipeline", "mode", "resolution", "refine", "threads", "fractions"]
    for _ in range(INPUTS):
        kwargs = {rng.choice(keywords): random_value(rng, 5) for _ in range(rng.randint(1, 3))}
        kwargs.setdefault("resolution", [4, 3, 3])
        if kwargs.get("pipeline") in ("exact", "both"):
            kwargs["pipeline"] = "voxel"  # seconds each: not fuzzed here
        call(camplace.evaluate, paper, cameras, **kwargs)
