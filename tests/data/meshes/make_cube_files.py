#!/usr/bin/env python3
"""Writes the cube test files of tests/core/mesh_file_test.cpp (run once; the outputs are
committed). Every file holds the same box; read with camplace's defaults (units "m" except the
3MF, up_axis "file") it is x in [1, 1.5], y in [1, 2], z in [0, 0.8] m (world, z up):

- cube_yup_mm.dae: COLLADA, <up_axis>Y_UP</up_axis>, <unit meter="0.001">: the box in file
  coordinates (y up, millimetres) x in [1000, 1500], y in [0, 800], z in [-2000, -1000].
- cube_zup_cm.dae: COLLADA, Z_UP, <unit meter="0.01">: x in [100, 150], y in [100, 200],
  z in [0, 80] (centimetres, as the world).
- cube.gltf / cube.glb: glTF 2.0 (y up, metres by its specification), 24 vertices (4 per face,
  as exporters write them for flat normals), a node translation [1, 0, 0]: mesh x in [0, 0.5],
  y in [0, 0.8], z in [-2, -1].
- cube_mm.3mf: 3MF (z up), coordinates in millimetres, x in [1000, 1500], y in [1000, 2000],
  z in [0, 800] (read with "units": "mm").
"""
import base64
import json
import struct
import zipfile

# Corners of a unit cube and its 12 outward triangles (counter-clockwise seen from outside).
CORNERS = [(i & 1, (i >> 1) & 1, (i >> 2) & 1) for i in range(8)]
QUADS = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]


def box(lo, hi):
    return [tuple(lo[k] + c[k] * (hi[k] - lo[k]) for k in range(3)) for c in CORNERS]


def triangles():
    out = []
    for a, b, c, d in QUADS:
        out += [(a, b, c), (a, c, d)]
    return out


def dae(path, up, meter, lo, hi):
    v = box(lo, hi)
    floats = " ".join("%g %g %g" % p for p in v)
    idx = " ".join("%d %d %d" % t for t in triangles())
    text = f"""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="u" meter="{meter}"/><up_axis>{up}</up_axis></asset>
  <library_geometries>
    <geometry id="cube" name="cube"><mesh>
      <source id="cube-pos">
        <float_array id="cube-pos-array" count="24">{floats}</float_array>
        <technique_common><accessor source="#cube-pos-array" count="8" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common>
      </source>
      <vertices id="cube-vtx"><input semantic="POSITION" source="#cube-pos"/></vertices>
      <triangles count="12"><input semantic="VERTEX" source="#cube-vtx" offset="0"/>
        <p>{idx}</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene"><node id="n" name="n"><instance_geometry url="#cube"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
"""
    open(path, "w").write(text)


def gltf_parts(lo, hi):
    v = box(lo, hi)
    positions, indices = [], []
    for quad in QUADS:  # 4 vertices of their own per face
        base = len(positions)
        positions += [v[i] for i in quad]
        indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    pos = b"".join(struct.pack("<3f", *p) for p in positions)
    ind = b"".join(struct.pack("<H", i) for i in indices)
    data = pos + ind
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "translation": [1, 0, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"byteLength": len(data)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
            {"buffer": 0, "byteOffset": len(pos), "byteLength": len(ind)},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 24, "type": "VEC3",
             "min": list(lo), "max": list(hi)},
            {"bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR"},
        ],
    }
    return doc, data


def gltf(path, lo, hi):
    doc, data = gltf_parts(lo, hi)
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(
        data).decode()
    open(path, "w").write(json.dumps(doc, indent=1))


def glb(path, lo, hi):
    doc, data = gltf_parts(lo, hi)
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    data += b"\0" * (-len(data) % 4)
    body = struct.pack("<I4s", len(js), b"JSON") + js + struct.pack("<I4s", len(data), b"BIN\0") + data
    open(path, "wb").write(struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body)


def three_mf(path, lo, hi):
    v = box(lo, hi)
    verts = "".join('<vertex x="%g" y="%g" z="%g"/>' % p for p in v)
    tris = "".join('<triangle v1="%d" v2="%d" v3="%d"/>' % t for t in triangles())
    model = f"""<?xml version="1.0" encoding="UTF-8"?>
<model unit="millimeter" xml:lang="en-US" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">
 <resources><object id="1" type="model"><mesh><vertices>{verts}</vertices><triangles>{tris}</triangles></mesh></object></resources>
 <build><item objectid="1"/></build>
</model>
"""
    types = """<?xml version="1.0" encoding="UTF-8"?>
<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/><Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/></Types>
"""
    rels = """<?xml version="1.0" encoding="UTF-8"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>
"""
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        for name, text in [("[Content_Types].xml", types), ("_rels/.rels", rels),
                           ("3D/3dmodel.model", model)]:
            info = zipfile.ZipInfo(name, date_time=(2026, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(info, text)


if __name__ == "__main__":
    dae("cube_yup_mm.dae", "Y_UP", "0.001", (1000, 0, -2000), (1500, 800, -1000))
    dae("cube_zup_cm.dae", "Z_UP", "0.01", (100, 100, 0), (150, 200, 80))
    gltf("cube.gltf", (0, 0, -2), (0.5, 0.8, -1))
    glb("cube.glb", (0, 0, -2), (0.5, 0.8, -1))
    three_mf("cube_mm.3mf", (1000, 1000, 0), (1500, 2000, 800))
