#!/usr/bin/env python3
"""Writes the bundled work cell data/cell_ur.json and its robot data/cell_ur/ (data/README.md).

    python3 scripts/make_cell_ur.py            # (re)writes the files under data/
    python3 scripts/make_cell_ur.py --check    # checks the committed files (see check())
    python3 scripts/make_cell_ur.py --out DIR  # writes DIR/cell_ur.json and DIR/cell_ur/

Deterministic and offline: plain Python (math, struct, json, xml.etree), no third-party
module, so every rerun writes identical bytes.

The robot is a UR5e built from its published kinematic (DH) parameters (Universal Robots,
"DH parameters for calculations of kinematics and dynamics"). Frames (data/README.md):
  - DH frame 0 is the URDF root link base_link; the base transform of the scene places it.
  - link i (shoulder_link .. wrist_3_link) has the frame of DH frame i-1 turned by theta_i
    about its z axis: joint i rotates about the z axis of its origin frame, as URDF requires.
  - joint i+1's origin in link i is Tz(d_i) Tx(a_i) Rx(alpha_i): xyz = (a_i, 0, d_i),
    rpy = (alpha_i, 0, 0). tool0 is DH frame 6: a fixed joint with origin (0, 0, d_6) in
    wrist_3_link. The gripper link is fixed to tool0 with an identity origin.
  - every collision element has an identity origin: its STL file is in the link frame.
So the pose of link i is Base * prod_{k<i} [Rz(q_k) Tz(d_k) Tx(a_k) Rx(alpha_k)] * Rz(q_i).
"""

import argparse
import filecmp
import json
import math
import os
import struct
import sys
import tempfile
import xml.etree.ElementTree as ET

# --- UR5e DH parameters (m, rad): Universal Robots, "DH parameters for calculations of
# kinematics and dynamics". Index k = 0..5 is joint k+1.
DH_D = [0.1625, 0.0, 0.0, 0.1333, 0.0997, 0.0996]
DH_A = [0.0, -0.425, -0.3922, 0.0, 0.0, 0.0]
DH_ALPHA = [math.pi / 2, 0.0, 0.0, math.pi / 2, -math.pi / 2, 0.0]

JOINTS = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint",
          "wrist_2_joint", "wrist_3_joint"]
LINKS = ["base_link", "shoulder_link", "upper_arm_link", "forearm_link", "wrist_1_link",
         "wrist_2_link", "wrist_3_link"]
# Joint limits as in ur_description's UR5e: +-2 pi, the elbow +-pi; effort (N m) and
# velocity (rad/s) from the same files (informational; camplace uses only the limits).
LIMITS = [2 * math.pi, 2 * math.pi, math.pi, 2 * math.pi, 2 * math.pi, 2 * math.pi]
EFFORT = [150.0, 150.0, 150.0, 28.0, 28.0, 28.0]
VELOCITY = [3.14159265, 3.14159265, 3.14159265, 3.14159265, 3.14159265, 3.14159265]

# --- The cell (metres, world frame, z up): data/README.md explains every number.
AREA = {"min": [0, 0, 0], "max": [6, 5, 3]}
VOXELS = [24, 20, 12]
ROBOT_BASE = {"rotate_deg": [0, 0, 90], "translate": [3.0, 2.0, 0.75]}

# The pick-and-place cycle (rad). Each row was found once by damped least squares on the DH
# model (flange at a chosen point, tool z straight down, tool x at a chosen yaw), rounded to
# 4 decimals; wrist_3 is kept continuous across +-pi. check() prints where the tool goes.
TRAJECTORY = [
    (0.0, "wait above the conveyor", [-0.2699, -1.5708, 1.7969, -1.7968, -1.5708, 2.8717]),
    (1.5, "pick from the conveyor", [-0.2699, -1.3069, 2.1136, -2.3776, -1.5708, 2.8717]),
    (2.5, "lift", [-0.2699, -1.59, 1.6866, -1.6674, -1.5708, 2.8717]),
    (4.0, "turn toward the bench", [0.8045, -1.7235, 1.68, -1.5273, -1.5708, 3.1607]),
    (5.5, "place on the bench", [1.7998, -0.7902, 1.2524, -2.0329, -1.5708, 3.3705]),
    (6.5, "retreat up", [1.7454, -1.0973, 1.2024, -1.6759, -1.5708, 3.3162]),
    (8.0, "return toward the conveyor", [-0.2127, -1.8339, 1.7657, -1.5026, -1.5708, 2.9289]),
]

PRISM_SIDES = 16  # sides of every prism that stands for a cylinder


# ---------------------------------------------------------------------------------------------
# Small linear algebra on nested lists (4x4 homogeneous transforms).
def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def rot_x(t):
    c, s = math.cos(t), math.sin(t)
    return [[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]]


def rot_y(t):
    c, s = math.cos(t), math.sin(t)
    return [[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]]


def rot_z(t):
    c, s = math.cos(t), math.sin(t)
    return [[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]


def translation(x, y, z):
    return [[1, 0, 0, x], [0, 1, 0, y], [0, 0, 1, z], [0, 0, 0, 1]]


def apply(m, p):
    return [m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3] for i in range(3)]


def base_transform():
    """World pose of base_link: Rz(c) Ry(b) Rx(a), then the translation (an object transform)."""
    a, b, c = (math.radians(v) for v in ROBOT_BASE["rotate_deg"])
    r = mat_mul(rot_z(c), mat_mul(rot_y(b), rot_x(a)))
    return mat_mul(translation(*ROBOT_BASE["translate"]), r)


def f32(x):
    """x rounded to the nearest float32: every mesh coordinate is one, so a float or a double
    reader of the STL and DAE files gets exactly the same vertices."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


# ---------------------------------------------------------------------------------------------
# Meshes: closed, outward convex solids (prisms standing for cylinders, boxes).
def frame_for_axis(axis):
    """Columns (e1, e2, e3) of a right-handed frame whose e3 is the coordinate axis `axis`
    ("x", "y", "z", "-y")."""
    return {
        "z": ([1, 0, 0], [0, 1, 0], [0, 0, 1]),
        "x": ([0, 1, 0], [0, 0, 1], [1, 0, 0]),
        "y": ([0, 0, 1], [1, 0, 0], [0, 1, 0]),
        "-y": ([1, 0, 0], [0, 0, 1], [0, -1, 0]),
    }[axis]


def prism(centre, axis, radius, lo, hi, sides=PRISM_SIDES):
    """The regular `sides`-gon prism whose polygon circumscribes the circle of `radius` (its
    apothem is the radius, so it contains the cylinder), around the line centre + s * axis,
    s in [lo, hi]. Returns (vertices, triangles), outward, vertices rounded to float32."""
    e1, e2, e3 = frame_for_axis(axis)
    r = radius / math.cos(math.pi / sides)  # circumradius
    verts = []
    for s in (lo, hi):
        for k in range(sides):
            # Vertices at half-step angles, so that a flat side faces each of +-e1, +-e2.
            phi = 2 * math.pi * (k + 0.5) / sides
            c, sn = r * math.cos(phi), r * math.sin(phi)
            verts.append([f32(centre[i] + c * e1[i] + sn * e2[i] + s * e3[i]) for i in range(3)])
    tris = []
    n = sides
    for k in range(n):
        k1 = (k + 1) % n
        tris.append([k, k1, n + k1])
        tris.append([k, n + k1, n + k])
    for k in range(1, n - 1):
        tris.append([0, k + 1, k])          # bottom cap, facing -e3
        tris.append([n, n + k, n + k + 1])  # top cap, facing +e3
    return verts, tris


def box(lo, hi):
    """Axis-aligned box [lo, hi] (link frame), 12 outward triangles."""
    v = [[f32([lo, hi][(k >> i) & 1][i]) for i in range(3)] for k in range(8)]
    tris = [[0, 2, 3], [0, 3, 1], [4, 5, 7], [4, 7, 6], [0, 1, 5], [0, 5, 4],
            [2, 6, 7], [2, 7, 3], [0, 4, 6], [0, 6, 2], [1, 3, 7], [1, 7, 5]]
    return v, tris


D1, D4, D5, D6 = DH_D[0], DH_D[3], DH_D[4], DH_D[5]
A2, A3 = DH_A[1], DH_A[2]
GRIPPER_LENGTH = 0.14  # tool0 to the finger tips (m)

# Collision elements of each link, in the link frame (data/README.md, "The robot"). Radii are
# the real UR5e's housing and tube radii, rounded up (the prisms contain those cylinders).
LINK_ELEMENTS = {
    "base_link": [("base", prism([0, 0, 0], "z", 0.076, 0.0, 0.06))],
    "shoulder_link": [
        ("column", prism([0, 0, 0], "z", 0.066, 0.06, D1)),
        ("housing", prism([0, 0, D1], "-y", 0.068, -0.075, 0.075)),
    ],
    "upper_arm_link": [
        ("tube", prism([0, 0, 0], "x", 0.054, A2, 0.0)),
        ("elbow", prism([A2, 0, 0], "z", 0.062, -0.065, 0.065)),
    ],
    "forearm_link": [("tube", prism([0, 0, 0], "x", 0.042, A3, 0.0))],
    "wrist_1_link": [("housing", prism([0, 0, 0], "z", 0.046, -0.05, D4))],
    "wrist_2_link": [("housing", prism([0, 0, 0], "z", 0.046, -0.05, D5))],
    "wrist_3_link": [("flange", prism([0, 0, 0], "z", 0.040, -0.045, D6))],
    "gripper": [
        ("body", box([-0.045, -0.035, 0.0], [0.045, 0.035, 0.07])),
        ("finger_a", box([-0.035, -0.012, 0.07], [-0.015, 0.012, GRIPPER_LENGTH])),
        ("finger_b", box([0.015, -0.012, 0.07], [0.035, 0.012, GRIPPER_LENGTH])),
    ],
}
# Links whose visual is also written as COLLADA (exercises the DAE reader); the others use
# their STL files for the visual too.
DAE_VISUALS = ["upper_arm_link", "forearm_link"]


def element_file(link, k):
    return "%s%s.stl" % (link, "" if k == 0 else "_%d" % k)


def stl_bytes(verts, tris, title):
    """Binary STL: an 80-byte header, the count, per triangle its unit normal and 3 vertices."""
    out = bytearray(title.encode("ascii")[:80].ljust(80, b" "))
    out += struct.pack("<I", len(tris))
    for t in tris:
        a, b, c = (verts[i] for i in t)
        u = [b[i] - a[i] for i in range(3)]
        w = [c[i] - a[i] for i in range(3)]
        n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
        ln = math.sqrt(sum(x * x for x in n))
        out += struct.pack("<3f", *(x / ln for x in n))
        for p in (a, b, c):
            out += struct.pack("<3f", *p)
        out += struct.pack("<H", 0)
    return bytes(out)


def read_stl(path):
    """The triangles of a binary STL file as lists of three (x, y, z) tuples."""
    with open(path, "rb") as f:
        data = f.read()
    (count,) = struct.unpack_from("<I", data, 80)
    if len(data) != 84 + 50 * count:
        raise ValueError("%s: %d bytes, expected %d" % (path, len(data), 84 + 50 * count))
    tris = []
    for k in range(count):
        vals = struct.unpack_from("<12f", data, 84 + 50 * k)
        tris.append([tuple(vals[3:6]), tuple(vals[6:9]), tuple(vals[9:12])])
    return tris


def fmt(x):
    """The shortest decimal that reads back as the same double (Python's repr)."""
    return repr(float(x))


def dae_text(parts):
    """COLLADA 1.4.1 with one geometry per part, in metres, z up (the link frame)."""
    lines = [
        '<?xml version="1.0" encoding="utf-8"?>',
        '<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">',
        "  <asset>",
        "    <contributor><authoring_tool>camplace scripts/make_cell_ur.py</authoring_tool>"
        "</contributor>",
        "    <created>2026-01-01T00:00:00Z</created>",
        "    <modified>2026-01-01T00:00:00Z</modified>",
        '    <unit name="meter" meter="1"/>',
        "    <up_axis>Z_UP</up_axis>",
        "  </asset>",
        "  <library_geometries>",
    ]
    for name, (verts, tris) in parts:
        gid = name + "-mesh"
        coords = " ".join(fmt(c) for v in verts for c in v)
        idx = " ".join(str(i) for t in tris for i in t)
        lines += [
            '    <geometry id="%s" name="%s">' % (gid, name),
            "      <mesh>",
            '        <source id="%s-positions">' % gid,
            '          <float_array id="%s-positions-array" count="%d">%s</float_array>'
            % (gid, 3 * len(verts), coords),
            "          <technique_common>",
            '            <accessor source="#%s-positions-array" count="%d" stride="3">'
            % (gid, len(verts)),
            '              <param name="X" type="float"/>',
            '              <param name="Y" type="float"/>',
            '              <param name="Z" type="float"/>',
            "            </accessor>",
            "          </technique_common>",
            "        </source>",
            '        <vertices id="%s-vertices">' % gid,
            '          <input semantic="POSITION" source="#%s-positions"/>' % gid,
            "        </vertices>",
            '        <triangles count="%d">' % len(tris),
            '          <input semantic="VERTEX" source="#%s-vertices" offset="0"/>' % gid,
            "          <p>%s</p>" % idx,
            "        </triangles>",
            "      </mesh>",
            "    </geometry>",
        ]
    lines += ["  </library_geometries>", "  <library_visual_scenes>",
              '    <visual_scene id="scene" name="scene">']
    for name, _ in parts:
        lines += ['      <node id="%s" name="%s">' % (name, name),
                  '        <instance_geometry url="#%s-mesh"/>' % name, "      </node>"]
    lines += ["    </visual_scene>", "  </library_visual_scenes>",
              '  <scene><instance_visual_scene url="#scene"/></scene>', "</COLLADA>"]
    return "\n".join(lines) + "\n"


def read_dae(path):
    """The triangles of every geometry of a DAE file written by dae_text()."""
    ns = {"c": "http://www.collada.org/2005/11/COLLADASchema"}
    root = ET.parse(path).getroot()
    tris = []
    for mesh in root.iterfind(".//c:geometry/c:mesh", ns):
        vals = [float(x) for x in mesh.find("c:source/c:float_array", ns).text.split()]
        verts = [tuple(vals[i:i + 3]) for i in range(0, len(vals), 3)]
        idx = [int(x) for x in mesh.find("c:triangles/c:p", ns).text.split()]
        tris += [[verts[idx[i]], verts[idx[i + 1]], verts[idx[i + 2]]]
                 for i in range(0, len(idx), 3)]
    return tris


# ---------------------------------------------------------------------------------------------
# URDF
def origin_xml(xyz, rpy):
    return '<origin xyz="%s" rpy="%s"/>' % (" ".join(fmt(v) for v in xyz),
                                             " ".join(fmt(v) for v in rpy))


def urdf_text():
    out = ['<?xml version="1.0"?>',
           "<!-- A UR5e built from its published DH parameters by scripts/make_cell_ur.py;",
           "     frames and sources: data/README.md. Do not edit: rerun the script. -->",
           '<robot name="ur5e">']

    def link(name):
        out.append('  <link name="%s">' % name)
        for k, (_, _) in enumerate(LINK_ELEMENTS.get(name, [])):
            uri = "package://cell_ur/meshes/" + element_file(name, k)
            if k == 0 and name in DAE_VISUALS:
                vis = "package://cell_ur/meshes/visual/%s.dae" % name
            else:
                vis = uri
            if k == 0 or name not in DAE_VISUALS:
                out.append('    <visual>%s<geometry><mesh filename="%s"/></geometry></visual>'
                           % (origin_xml([0, 0, 0], [0, 0, 0]), vis))
            out.append('    <collision>%s<geometry><mesh filename="%s"/></geometry></collision>'
                       % (origin_xml([0, 0, 0], [0, 0, 0]), uri))
        out.append("  </link>")

    for name in LINKS:
        link(name)
    link("tool0")
    link("gripper")
    parents = LINKS[:-1]
    for k, joint in enumerate(JOINTS):
        if k == 0:
            xyz, rpy = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
        else:
            xyz, rpy = [DH_A[k - 1], 0.0, DH_D[k - 1]], [DH_ALPHA[k - 1], 0.0, 0.0]
        out += ['  <joint name="%s" type="revolute">' % joint,
                '    <parent link="%s"/>' % parents[k],
                '    <child link="%s"/>' % LINKS[k + 1],
                "    " + origin_xml(xyz, rpy),
                '    <axis xyz="0 0 1"/>',
                '    <limit lower="%s" upper="%s" effort="%s" velocity="%s"/>'
                % (fmt(-LIMITS[k]), fmt(LIMITS[k]), fmt(EFFORT[k]), fmt(VELOCITY[k])),
                "  </joint>"]
    out += ['  <joint name="wrist_3-flange" type="fixed">',
            '    <parent link="wrist_3_link"/>', '    <child link="tool0"/>',
            "    " + origin_xml([DH_A[5], 0.0, DH_D[5]], [DH_ALPHA[5], 0.0, 0.0]),
            "  </joint>",
            '  <joint name="tool0-gripper" type="fixed">',
            '    <parent link="tool0"/>', '    <child link="gripper"/>',
            "    " + origin_xml([0, 0, 0], [0, 0, 0]),
            "  </joint>",
            "</robot>"]
    return "\n".join(out) + "\n"


def csv_text():
    lines = ["# UR5e pick-and-place cycle for data/cell_ur.json (scripts/make_cell_ur.py):",
             "# joint angles in rad, t in s. Rows: " +
             "; ".join("%s %s" % (fmt(t), what) for t, what, _ in TRAJECTORY) + ".",
             "t," + ",".join(JOINTS)]
    for t, _, q in TRAJECTORY:
        lines.append(",".join([fmt(t)] + [fmt(v) for v in q]))
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------------------------
# The scene
def scene():
    def boxobj(name, lo, hi):
        return {"name": name, "box": {"min": lo, "max": hi}}

    # Every static obstacle except the conveyor's legs lies on the 0.25 m voxel grid
    # (data/README.md, "Why the obstacles lie on the voxel grid").
    statics = [
        boxobj("robot pedestal", [2.75, 1.75, 0.0], [3.25, 2.25, 0.75]),
        boxobj("conveyor belt", [-1.0, 1.25, 0.5], [7.0, 1.75, 0.75]),
    ]
    for x in (-0.5, 1.5, 3.5, 5.5):
        statics.append(boxobj("conveyor leg x=%s" % fmt(x), [x - 0.04, 1.3, 0.0],
                              [x + 0.04, 1.7, 0.5]))
    statics.append(boxobj("work bench", [3.25, 1.75, 0.0], [4.5, 2.75, 0.75]))
    statics.append(boxobj("parts shelf", [5.25, 4.0, 0.0], [6.0, 5.0, 1.75]))

    cameras = {
        "models": [
            {"name": "depth", "fov": "frustum", "horizontal_deg": 87, "vertical_deg": 58,
             "range": [0.3, 6]},
            {"name": "rgb", "fov": "frustum", "horizontal_deg": 69, "vertical_deg": 42,
             "range": [0.1, 8]},
        ],
        "mounts": [
            {"name": "ceiling", "corner": [0, 0, 3], "edges": [[0, 5, 0], [6, 0, 0]],
             "yaw_deg": [-45, 45], "pitch_deg": [-45, 45], "roll_deg": [-45, 45]},
            {"name": "west_wall", "corner": [0, 0, 1.8], "edges": [[0, 5, 0], [0, 0, 1.2]],
             "yaw_deg": [-60, 60], "pitch_deg": [-70, 10]},
            {"name": "north_wall", "corner": [0, 5, 1.8], "edges": [[6, 0, 0], [0, 0, 1.2]],
             "yaw_deg": [-60, 60], "pitch_deg": [-70, 10]},
        ],
        "keep_out": [{"name": "robot reach", "min": [1.9, 0.9, -0.1], "max": [4.1, 3.1, 3.1]}],
        "list": [
            {"model": "depth", "mount": "west_wall"},
            {"model": "depth", "mount": "north_wall"},
            {"model": "rgb", "mount": "ceiling"},
            {"model": "rgb", "mount": "ceiling"},
            {"model": "rgb", "mount": "west_wall"},
        ],
    }
    return {
        "description": (
            "A real-looking human-robot work cell (data/README.md): 6 x 5 x 3 m, a UR5e "
            "(built from its published DH parameters, data/cell_ur/ur5e.urdf) on a 0.75 m "
            "pedestal picks parts from a conveyor that crosses the cell and places them on a "
            "work bench (7 samples of data/cell_ur/pick_place.csv); people at a loading zone "
            "by the conveyor and an assembly zone by the bench; 2 depth and 3 RGB cameras on "
            "two walls and the ceiling, not within the robot's reach. Written by "
            "scripts/make_cell_ur.py."),
        "area": AREA,
        "voxels": VOXELS,
        "cameras": cameras,
        "static_obstacles": statics,
        "robots": [{
            "name": "ur5e",
            "urdf": "cell_ur/ur5e.urdf",
            "package_paths": {"cell_ur": "cell_ur"},
            "links": "collision",
            "base": ROBOT_BASE,
            "trajectory": "cell_ur/pick_place.csv",
        }],
        "people": [
            {"name": "loading", "zone": {"min": [1.0, 0.25], "max": [5.0, 1.0]},
             "postures": ["standing", "reaching"], "count": 3, "seed": 1,
             "weight": 0.6},
            {"name": "assembly",
             "zone": {"polygon": [[3.0, 3.25], [5.0, 3.25], [5.0, 3.75], [4.8, 4.5], [3.0, 4.5]]},
             "postures": ["standing", "reaching"], "count": 2, "seed": 2,
             "weight": 0.4},
        ],
        "dynamic_mode": "masked",
        "plausibility": {"min_volume": 0.03, "min_height": 1.52},
    }


# ---------------------------------------------------------------------------------------------
def write_all(out_dir):
    """Writes out_dir/cell_ur.json and out_dir/cell_ur/...; returns the paths written."""
    cell = os.path.join(out_dir, "cell_ur")
    meshes = os.path.join(cell, "meshes")
    os.makedirs(os.path.join(meshes, "visual"), exist_ok=True)
    files = {}
    for link, elements in LINK_ELEMENTS.items():
        for k, (what, (verts, tris)) in enumerate(elements):
            title = "camplace UR5e %s %s (link frame, m)" % (link, what)
            files[os.path.join(meshes, element_file(link, k))] = stl_bytes(verts, tris, title)
        if link in DAE_VISUALS:
            parts = [("%s_%s" % (link, what), mesh) for what, mesh in elements]
            files[os.path.join(meshes, "visual", link + ".dae")] = dae_text(parts).encode()
    files[os.path.join(cell, "ur5e.urdf")] = urdf_text().encode()
    files[os.path.join(cell, "pick_place.csv")] = csv_text().encode()
    files[os.path.join(out_dir, "cell_ur.json")] = (json.dumps(scene(), indent=1) + "\n").encode()
    for path, data in sorted(files.items()):
        tmp = path + ".tmp"
        with open(tmp, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    return sorted(files)


# ---------------------------------------------------------------------------------------------
# --check: the committed files against an independent reading of them.
def urdf_fk(urdf_path, q_by_joint):
    """World pose of every link by the URDF rules: a joint's origin (xyz, then rpy as
    Rz(yaw) Ry(pitch) Rx(roll)), then its motion (rotation about the axis, here z)."""
    root = ET.parse(urdf_path).getroot()
    joints = {}
    for j in root.iter("joint"):
        o = j.find("origin")
        xyz = [float(v) for v in o.get("xyz").split()]
        rpy = [float(v) for v in o.get("rpy").split()]
        axis = j.find("axis")
        joints[j.find("child").get("link")] = (j.get("name"), j.get("type"),
                                               j.find("parent").get("link"), xyz, rpy,
                                               axis.get("xyz") if axis is not None else None)
    poses = {}

    def pose(link):
        if link in poses:
            return poses[link]
        if link not in joints:
            poses[link] = base_transform()
            return poses[link]
        name, kind, parent, xyz, rpy, axis = joints[link]
        o = mat_mul(translation(*xyz),
                    mat_mul(rot_z(rpy[2]), mat_mul(rot_y(rpy[1]), rot_x(rpy[0]))))
        m = mat_mul(pose(parent), o)
        if kind == "revolute":
            assert axis == "0 0 1", (name, axis)
            m = mat_mul(m, rot_z(q_by_joint[name]))
        else:
            assert kind == "fixed", (name, kind)
        poses[link] = m
        return m

    for j in root.iter("link"):
        pose(j.get("name"))
    return poses


def dh_fk(q):
    """World pose of every link by the DH formulas (data/README.md)."""
    poses = {"base_link": base_transform()}
    f = poses["base_link"]
    for k in range(6):
        poses[LINKS[k + 1]] = mat_mul(f, rot_z(q[k]))
        f = mat_mul(poses[LINKS[k + 1]],
                    mat_mul(translation(0, 0, DH_D[k]),
                            mat_mul(translation(DH_A[k], 0, 0), rot_x(DH_ALPHA[k]))))
    poses["tool0"] = f
    poses["gripper"] = f
    return poses


def read_csv(path):
    rows = []
    with open(path) as f:
        lines = [ln.strip() for ln in f if ln.strip() and not ln.startswith("#")]
    header = lines[0].split(",")
    assert header == ["t"] + JOINTS, header
    for ln in lines[1:]:
        vals = [float(v) for v in ln.split(",")]
        rows.append((vals[0], dict(zip(JOINTS, vals[1:]))))
    return rows


def mesh_problems(tris):
    """Why a triangle soup is not a closed, consistently and outward oriented manifold with
    non-zero-area triangles ([] when it is one)."""
    index = {}
    faces = [[index.setdefault(p, len(index)) for p in t] for t in tris]
    pts = [None] * len(index)
    for p, i in index.items():
        pts[i] = p
    problems = []
    edges = {}
    vol = 0.0
    for k, (a, b, c) in enumerate(faces):
        if len({a, b, c}) < 3:
            problems.append("triangle %d repeats a vertex" % k)
        for e in ((a, b), (b, c), (c, a)):
            edges[e] = edges.get(e, 0) + 1
        pa, pb, pc = pts[a], pts[b], pts[c]
        u = [pb[i] - pa[i] for i in range(3)]
        w = [pc[i] - pa[i] for i in range(3)]
        n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
        if math.sqrt(sum(x * x for x in n)) < 1e-12:
            problems.append("triangle %d has zero area" % k)
        vol += (pa[0] * (pb[1] * pc[2] - pb[2] * pc[1]) - pa[1] * (pb[0] * pc[2] - pb[2] * pc[0])
                + pa[2] * (pb[0] * pc[1] - pb[1] * pc[0])) / 6.0
    for (a, b), n in edges.items():
        if n != 1 or edges.get((b, a), 0) != 1:
            problems.append("edge %d-%d is not shared by exactly two opposite triangles" % (a, b))
            break
    if vol <= 0:
        problems.append("signed volume %g is not positive" % vol)
    return problems


def check(data_dir):
    ok = True

    def fail(msg):
        nonlocal ok
        ok = False
        print("FAIL: " + msg)

    # 1. A rerun writes identical bytes.
    with tempfile.TemporaryDirectory() as tmp:
        for path in write_all(tmp):
            rel = os.path.relpath(path, tmp)
            mine = os.path.join(data_dir, rel)
            if not os.path.exists(mine) or not filecmp.cmp(path, mine, shallow=False):
                fail("%s differs from a fresh run of the script" % mine)
    print("rerun: the committed files equal a fresh run")

    # 2. FK by the URDF rules (parsed from the file) equals FK by the DH formulas.
    urdf = os.path.join(data_dir, "cell_ur", "ur5e.urdf")
    rows = read_csv(os.path.join(data_dir, "cell_ur", "pick_place.csv"))
    if len(rows) != 7:
        fail("the trajectory has %d rows, expected 7" % len(rows))
    worst = 0.0
    for t, q_by_joint in rows:
        a = urdf_fk(urdf, q_by_joint)
        b = dh_fk([q_by_joint[j] for j in JOINTS])
        if set(a) != set(b):
            fail("links differ: %s vs %s" % (sorted(a), sorted(b)))
        for link in b:
            for i in range(3):
                for j in range(4):
                    worst = max(worst, abs(a[link][i][j] - b[link][i][j]))
        tip = apply(b["tool0"], [0, 0, GRIPPER_LENGTH])
        flange = apply(b["tool0"], [0, 0, 0])
        print("t = %4.1f s  flange (%.4f, %.4f, %.4f)  finger tips (%.4f, %.4f, %.4f)  "
              "tool z (%.3f, %.3f, %.3f)" % ((t,) + tuple(flange) + tuple(tip) +
                                             tuple(b["tool0"][i][2] for i in range(3))))
    if worst > 1e-12:
        fail("URDF and DH poses differ by %g" % worst)
    print("FK: URDF rules and DH formulas agree within %.1e at all %d rows (every link pose)"
          % (worst, len(rows)))

    # 3. Every mesh is a closed, outward, consistently oriented solid; DAE = STL.
    meshes = os.path.join(data_dir, "cell_ur", "meshes")
    total = {}
    for link, elements in LINK_ELEMENTS.items():
        for k in range(len(elements)):
            tris = read_stl(os.path.join(meshes, element_file(link, k)))
            total[link] = total.get(link, 0) + len(tris)
            for p in mesh_problems(tris):
                fail("%s: %s" % (element_file(link, k), p))
        if link in DAE_VISUALS:
            stl = [t for k in range(len(elements))
                   for t in read_stl(os.path.join(meshes, element_file(link, k)))]
            dae = read_dae(os.path.join(meshes, "visual", link + ".dae"))
            if stl != dae:
                fail("visual/%s.dae does not hold the triangles of its STL files" % link)
    print("meshes: closed and outward; triangles per link: " +
          ", ".join("%s %d" % kv for kv in total.items()))

    # 4. The robot's vertices stay out of the static obstacles at every row (a vertex test,
    # enough for these convex, coarse parts; the base sits on the pedestal's top face).
    cell = scene()
    for t, q_by_joint in rows:
        poses = dh_fk([q_by_joint[j] for j in JOINTS])
        for link, elements in LINK_ELEMENTS.items():
            for _, (verts, _) in elements:
                for v in verts:
                    w = apply(poses[link], v)
                    for obj in cell["static_obstacles"]:
                        lo, hi = obj["box"]["min"], obj["box"]["max"]
                        if all(lo[i] + 1e-9 < w[i] < hi[i] - 1e-9 for i in range(3)):
                            fail("t = %g: %s enters %s" % (t, link, obj["name"]))
    print("clearance: no robot vertex inside a static obstacle at any row")
    return ok


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    data_dir = os.path.join(os.path.dirname(here), "data")
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true", help="check the committed files")
    ap.add_argument("--out", help="write into this directory instead of data/")
    args = ap.parse_args()
    if args.check:
        sys.exit(0 if check(args.out or data_dir) else 1)
    for path in write_all(args.out or data_dir):
        print("wrote " + os.path.relpath(path))


if __name__ == "__main__":
    main()
