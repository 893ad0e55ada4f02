#!/usr/bin/env python3
"""Writes the bundled fine-mesh work cell data/cell_ur_fine.json and data/cell_ur_fine/
(data/README.md): data/cell_ur.json with meshes of the size of a real cell's.

    python3 scripts/make_cell_ur_fine.py --camplace build/release/camplace
    python3 scripts/make_cell_ur_fine.py --camplace BIN --out DIR   # writes DIR/cell_ur_fine*

Changes against cell_ur (scripts/make_cell_ur.py, whose code makes the robot):
  - every prism of the robot has 140 sides instead of 16: 5,040 triangles per time step;
  - 10 time steps: the 7 rows of the pick-and-place cycle and the midpoints (joint angles
    averaged) of its three longest intervals (2.5-4 s, 4-5.5 s, 6.5-8 s);
  - the 5 people are those cell_ur's person model places at time step 0 (`camplace expand`),
    each of the 13 body parts replaced by the ellipsoid of its vertices' principal axes (semi
    axes = the standard deviations of its 8 or 16 vertices: for a box the inscribed ellipsoid),
    11 slices x 8 stacks, 154 triangles: 2,002 triangles per person; shared events of weight
    0.2 each (the same 5 appearances in every time step), one OFF file per part;
  - 6 cameras: cell_ur's 5 and a depth camera on the west wall.
Deterministic, offline, plain Python; the only input besides make_cell_ur.py is the expanded
cell_ur.json (people at step 0), which `camplace expand` writes identically on every run.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import types

SIDES = 140
SLICES, STACKS = 11, 8


def load_make_cell_ur(here):
    path = os.path.join(here, "make_cell_ur.py")
    with open(path) as f:
        source = f.read()
    assert "PRISM_SIDES = 16" in source
    module = types.ModuleType("make_cell_ur_fine_base")
    module.__file__ = path
    exec(compile(source.replace("PRISM_SIDES = 16", "PRISM_SIDES = %d" % SIDES), path, "exec"),
         module.__dict__)
    return module


def jacobi_eigen(a):
    """Eigenvalues and eigenvectors (columns) of a symmetric 3x3 matrix by Jacobi rotations."""
    a = [row[:] for row in a]
    v = [[1.0 if i == j else 0.0 for j in range(3)] for i in range(3)]
    for _ in range(100):
        off = max(abs(a[0][1]), abs(a[0][2]), abs(a[1][2]))
        if off < 1e-15:
            break
        for p, q in ((0, 1), (0, 2), (1, 2)):
            if abs(a[p][q]) < 1e-300:
                continue
            theta = (a[q][q] - a[p][p]) / (2 * a[p][q])
            t = (1.0 if theta >= 0 else -1.0) / (abs(theta) + math.sqrt(theta * theta + 1))
            c = 1 / math.sqrt(t * t + 1)
            s = t * c
            for k in range(3):
                akp, akq = a[k][p], a[k][q]
                a[k][p], a[k][q] = c * akp - s * akq, s * akp + c * akq
            for k in range(3):
                apk, aqk = a[p][k], a[q][k]
                a[p][k], a[q][k] = c * apk - s * aqk, s * apk + c * aqk
            for k in range(3):
                vkp, vkq = v[k][p], v[k][q]
                v[k][p], v[k][q] = c * vkp - s * vkq, s * vkp + c * vkq
    return [a[i][i] for i in range(3)], v


def ellipsoid_of(vertices):
    """The ellipsoid of the vertices' principal axes, as (vertices, triangles), outward."""
    n = len(vertices)
    c = [sum(p[i] for p in vertices) / n for i in range(3)]
    cov = [[sum((p[i] - c[i]) * (p[j] - c[j]) for p in vertices) / n for j in range(3)]
           for i in range(3)]
    values, vec = jacobi_eigen(cov)
    axes = [[vec[k][i] for k in range(3)] for i in range(3)]  # eigenvectors as rows
    det = (axes[0][0] * (axes[1][1] * axes[2][2] - axes[1][2] * axes[2][1]) -
           axes[0][1] * (axes[1][0] * axes[2][2] - axes[1][2] * axes[2][0]) +
           axes[0][2] * (axes[1][0] * axes[2][1] - axes[1][1] * axes[2][0]))
    if det < 0:
        axes[2] = [-x for x in axes[2]]
    radii = [math.sqrt(max(v, 0.0)) for v in values]

    def point(u, w, z):
        return [round(c[i] + u * radii[0] * axes[0][i] + w * radii[1] * axes[1][i] +
                      z * radii[2] * axes[2][i], 9) for i in range(3)]

    verts = [point(0, 0, -1)]
    for j in range(1, STACKS):
        phi = -math.pi / 2 + math.pi * j / STACKS
        for k in range(SLICES):
            th = 2 * math.pi * k / SLICES
            verts.append(point(math.cos(phi) * math.cos(th), math.cos(phi) * math.sin(th),
                               math.sin(phi)))
    verts.append(point(0, 0, 1))
    top = len(verts) - 1
    ring = lambda j, k: 1 + (j - 1) * SLICES + k % SLICES
    tris = []
    for k in range(SLICES):
        tris.append([0, ring(1, k + 1), ring(1, k)])
        tris.append([top, ring(STACKS - 1, k), ring(STACKS - 1, k + 1)])
    for j in range(1, STACKS - 1):
        for k in range(SLICES):
            a, b = ring(j, k), ring(j, k + 1)
            a2, b2 = ring(j + 1, k), ring(j + 1, k + 1)
            tris.append([a, b, b2])
            tris.append([a, b2, a2])
    return verts, tris


def off_text(verts, tris, title):
    lines = ["OFF", "# " + title, "%d %d 0" % (len(verts), len(tris))]
    lines += ["%r %r %r" % tuple(p) for p in verts]
    lines += ["3 %d %d %d" % tuple(t) for t in tris]
    return "\n".join(lines) + "\n"


def trajectory(base):
    rows = list(base.TRAJECTORY)
    out = []
    for i, row in enumerate(rows):
        out.append(row)
        if i + 1 < len(rows) and row[0] >= 2.5 and rows[i + 1][0] - row[0] >= 1.5:
            t = (row[0] + rows[i + 1][0]) / 2
            q = [round((a + b) / 2, 4) for a, b in zip(row[2], rows[i + 1][2])]
            out.append((t, "between %s and %s" % (row[1], rows[i + 1][1]), q))
    return out


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    data_dir = os.path.join(os.path.dirname(here), "data")
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--camplace", required=True, help="the camplace binary (for expand)")
    ap.add_argument("--out", help="write into this directory instead of data/")
    args = ap.parse_args()
    out_dir = args.out or data_dir
    base = load_make_cell_ur(here)
    base.TRAJECTORY = trajectory(base)
    assert len(base.TRAJECTORY) == 10
    with tempfile.TemporaryDirectory() as tmp:
        base.write_all(tmp)
        expanded = os.path.join(tmp, "expanded.json")
        subprocess.run([args.camplace, "expand", os.path.join(data_dir, "cell_ur.json"), "--out",
                        expanded], check=True, stdout=subprocess.DEVNULL)
        with open(expanded) as f:
            events = json.load(f)["time_steps"][0]["events"]
        files = {}
        cell = os.path.join(tmp, "cell_ur")
        for root, _, names in os.walk(cell):
            for name in names:
                path = os.path.join(root, name)
                rel = os.path.relpath(path, cell)
                with open(path, "rb") as f:
                    data = f.read()
                if rel.endswith(".urdf") or rel.endswith(".csv"):
                    data = data.replace(b"data/cell_ur.json", b"data/cell_ur_fine.json")
                files[os.path.join("cell_ur_fine", rel)] = data
        scene = base.scene()
        shared = []
        for event in events:
            targets = []
            for obj in event["targets"]:
                name = obj["name"]  # zone/k/part
                verts, tris = ellipsoid_of(obj["mesh"]["vertices"])
                rel = "cell_ur_fine/people/%s.off" % name.replace("/", "_")
                files[rel] = off_text(verts, tris, "camplace fine person part %s (world, m)" %
                                      name).encode()
                targets.append({"name": name, "file": rel})
            shared.append({"weight": event["weight"], "targets": targets})
        del scene["people"]
        scene["events"] = shared
        scene["robots"][0]["urdf"] = "cell_ur_fine/ur5e.urdf"
        scene["robots"][0]["package_paths"] = {"cell_ur": "cell_ur_fine"}
        scene["robots"][0]["trajectory"] = "cell_ur_fine/pick_place.csv"
        scene["cameras"]["list"].append({"model": "depth", "mount": "west_wall"})
        scene["description"] = (
            "data/cell_ur.json with meshes of a real cell's size (data/README.md): the UR5e's "
            "prisms with 140 sides (5,040 triangles per time step), 10 time steps of the "
            "pick-and-place cycle, the 5 people of cell_ur's time step 0 with each body part an "
            "ellipsoid (2,002 triangles per person, the same in every time step), 6 cameras. "
            "Written by scripts/make_cell_ur_fine.py.")
        files["cell_ur_fine.json"] = (json.dumps(scene, indent=1) + "\n").encode()
        for rel, data in sorted(files.items()):
            path = os.path.join(out_dir, rel)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path + ".tmp", "wb") as f:
                f.write(data)
            os.replace(path + ".tmp", path)
            print("wrote " + os.path.relpath(path))


if __name__ == "__main__":
    sys.exit(main())
