// Mesh files and mesh validity (SPEC §2): structural defects in OFF/OBJ/PLY files are rejected
// quickly with a reason naming the element, and meshes that do not bound a volume (nested
// shells with one orientation, flat shells) are rejected as such.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "camplace/core/error.hpp"
#include "camplace/core/scene.hpp"
#include "scene_builder.hpp"
#include "scene_fixtures.hpp"

namespace camplace::testing {
namespace {

using nlohmann::json;

// A scene whose first static obstacle is `object`, written into `dir`.
std::string scene_with(const std::string& dir, const json& object) {
  json s = base_scene();
  s["static_obstacles"][0] = object;
  return write_file(dir + "/scene.json", s.dump());
}

// Writes `text` as mesh file `name` next to a scene using it; expects the file entry rejected.
void expect_file_rejected(const std::string& name, const std::string& text,
                          const std::string& reason) {
  const std::string dir = temp_dir("meshfile-" + name);
  write_file(dir + "/" + name, text);
  expect_rejected(scene_with(dir, {{"file", name}}), "/static_obstacles/0/file", reason);
}

// An outward tetrahedron in the free part of the base scene, and its faces.
const std::vector<std::array<double, 3>> kTetV = {{1, 1, 1}, {2, 1, 1}, {1, 2, 1}, {1, 1, 2}};
const std::vector<std::array<int, 3>> kTetT = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

// kTetV followed by a second tetrahedron: kTetV shrunk by half about its centroid (nested) or
// shifted by 1.2 along x (disjoint); its faces optionally reversed.
json two_shells(bool nested, bool reverse_second) {
  std::vector<std::array<double, 3>> v = kTetV;
  for (const auto& p : kTetV) {
    if (nested) {
      v.push_back(
          {1.25 + 0.5 * (p[0] - 1.25), 1.25 + 0.5 * (p[1] - 1.25), 1.25 + 0.5 * (p[2] - 1.25)});
    } else {
      v.push_back({p[0] + 1.2, p[1], p[2]});
    }
  }
  auto t = kTetT;
  for (const auto& tri : kTetT) {
    t.push_back(reverse_second ? std::array<int, 3>{tri[0] + 4, tri[2] + 4, tri[1] + 4}
                               : std::array<int, 3>{tri[0] + 4, tri[1] + 4, tri[2] + 4});
  }
  return inline_mesh(v, t);
}

const char* kTetOffHeader = "OFF\n4 4 0\n1 1 1\n2 1 1\n1 2 1\n1 1 2\n3 0 2 1\n3 0 1 3\n3 0 3 2\n";
const char* kPlyAsciiHeader =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float "
    "z\n"
    "element face 4\nproperty list uchar int vertex_indices\nend_header\n";

// The kTetV/kTetT tetrahedron as a binary PLY (float coordinates, `Count` list counts, int
// indices), with `last_count` as the list count of the last face.
template <class Count>
std::string binary_tet_ply(bool big_endian, std::uint32_t last_count) {
  const char* count_type = sizeof(Count) == 1 ? "uchar" : "uint";
  std::string out = std::string("ply\nformat ") +
                    (big_endian ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 4\nproperty list " +
                    count_type + " int vertex_indices\nend_header\n";
  auto put = [&](auto value) {
    char bytes[sizeof(value)];
    std::memcpy(bytes, &value, sizeof(value));  // the test machine is little endian
    if (big_endian) std::reverse(bytes, bytes + sizeof(value));
    out.append(bytes, sizeof(value));
  };
  for (const auto& p : kTetV) {
    for (double c : p) put(static_cast<float>(c));
  }
  for (std::size_t f = 0; f < kTetT.size(); ++f) {
    put(static_cast<Count>(f + 1 == kTetT.size() ? last_count : 3));
    for (int i : kTetT[f]) put(static_cast<std::int32_t>(i));
  }
  return out;
}

TEST(MeshFile, PlyListCountBeyondTheDataIsRejectedQuickly) {
  const auto start = std::chrono::steady_clock::now();
  expect_file_rejected(
      "listbig.ply",
      std::string(kPlyAsciiHeader) +
          "1 1 1\n2 1 1\n1 2 1\n1 1 2\n4000000000 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
      "PLY face 0: list count 4000000000 exceeds the data in the file");
  expect_file_rejected("listbig_le.ply", binary_tet_ply<std::uint32_t>(false, 4000000000u),
                       "PLY face 3: list count 4000000000 exceeds the data in the file");
  expect_file_rejected("listbig_be.ply", binary_tet_ply<std::uint32_t>(true, 1000000u),
                       "PLY face 3: list count 1000000 exceeds the data in the file");
  std::string many_faces = kPlyAsciiHeader;
  many_faces.replace(many_faces.find("face 4"), 6, "face 4000000000");
  expect_file_rejected("facesbig.ply", many_faces + "1 1 1\n2 1 1\n1 2 1\n1 1 2\n3 0 2 1\n",
                       "PLY element face: count 4000000000 exceeds the data in the file");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
}

TEST(MeshFile, ValidBinaryPlyInBothByteOrdersLoads) {
  for (const bool big_endian : {false, true}) {
    const std::string dir = temp_dir(big_endian ? "ply-be" : "ply-le");
    write_file(dir + "/tet.ply", binary_tet_ply<std::uint8_t>(big_endian, 3));
    const core::Scene s = core::load_scene(scene_with(dir, {{"file", "tet.ply"}}));
    EXPECT_NEAR(core::signed_volume(s.static_obstacles[0].mesh), 1.0 / 6, 1e-12);
  }
}

TEST(MeshFile, OffFaceVertexCountBeyondItsLineIsRejectedQuickly) {
  const auto start = std::chrono::steady_clock::now();
  expect_file_rejected("countbig.off", std::string(kTetOffHeader) + "4000000000 1 2 3\n",
                       "OFF face 3: vertex count 4000000000 exceeds the 3 numbers on its line");
  expect_file_rejected("headerbig.off",
                       "OFF\n4000000000 4 0\n1 1 1\n2 1 1\n1 2 1\n1 1 2\n3 0 2 1\n",
                       "OFF header announces 4000000000 vertices and 4 faces");
  // Binary OFF: CGAL trusts its 32-bit face counts (and misreads standard files), so it is
  // refused before CGAL sees it. Face 0 announces 2^31 - 1 vertices.
  std::string binary = "OFF BINARY\n";
  for (const std::uint32_t word :
       {4u, 1u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0x7fffffffu}) {
    for (int shift = 24; shift >= 0; shift -= 8)
      binary += static_cast<char>((word >> shift) & 0xff);
  }
  expect_file_rejected("countbig_binary.off", binary, "binary OFF is not supported");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
}

TEST(MeshFile, FractionalAndHugeVertexIndicesAreNamed) {
  expect_file_rejected("floatidx.off", std::string(kTetOffHeader) + "3 1 2 2.5\n",
                       "OFF face 3: vertex index \"2.5\" is not a non-negative integer");
  expect_file_rejected("bigidx.off", std::string(kTetOffHeader) + "3 1 2 99999999999999999999\n",
                       "OFF face 3: vertex index 99999999999999999999 is out of range");
  expect_file_rejected("idx4.off", std::string(kTetOffHeader) + "3 1 2 4\n",
                       "OFF face 3: vertex index 4 is out of range (the file has 4 vertices)");
  expect_file_rejected("floatidx.ply",
                       std::string(kPlyAsciiHeader) +
                           "1 1 1\n2 1 1\n1 2 1\n1 1 2\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 2.5\n",
                       "PLY face 3: vertex index \"2.5\" is not a non-negative integer");
  expect_file_rejected("floatidx.obj",
                       "v 1 1 1\nv 2 1 1\nv 1 2 1\nv 1 1 2\nf 1 3 2\nf 1 2 4\nf 1 4 3.5\n",
                       "OBJ face 2: vertex index \"3.5\" is not an integer");
  expect_file_rejected("bigidx.obj",
                       "v 1 1 1\nv 2 1 1\nv 1 2 1\nv 1 1 2\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 9\n",
                       "OBJ face 3: vertex index 9 is out of range (the file has 4 vertices)");
}

TEST(MeshFile, NonFiniteCoordinatesAreNamed) {
  expect_file_rejected(
      "nan.off", "OFF\n4 4 0\n1 1 1\n2 1 1\n1 nan 1\n1 1 2\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
      "vertex 2 has a non-finite coordinate");
  expect_file_rejected("inf.obj",
                       "v 1 1 1\nv 2 1 inf\nv 1 2 1\nv 1 1 2\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
                       "vertex 1 has a non-finite coordinate");
  expect_file_rejected("overflow.ply",
                       std::string(kPlyAsciiHeader) +
                           "1 1 1\n2 1 1\n1 2 1\n1 1e400 2\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
                       "vertex 3 has a non-finite coordinate");
}

TEST(MeshValidation, NestedShellsWithTheSameOrientationDoNotBoundAVolume) {
  const std::string dir = temp_dir("nested");
  expect_rejected(scene_with(dir, two_shells(true, false)), "/static_obstacles/0",
                  "does not bound a volume");
  // The same shells from a mesh file go through the same check.
  const json m = two_shells(true, false)["mesh"];
  std::string off = "OFF\n8 8 0\n";
  for (const auto& p : m["vertices"])
    off += p[0].dump() + " " + p[1].dump() + " " + p[2].dump() + "\n";
  for (const auto& t : m["triangles"])
    off += "3 " + t[0].dump() + " " + t[1].dump() + " " + t[2].dump() + "\n";
  write_file(dir + "/nested.off", off);
  expect_rejected(scene_with(dir, {{"file", "nested.off"}}), "/static_obstacles/0",
                  "does not bound a volume");
  // Disjoint shells must agree instead: one facing inward bounds no volume either.
  expect_rejected(scene_with(dir, two_shells(false, true)), "/static_obstacles/0",
                  "does not bound a volume");
}

TEST(MeshValidation, HollowSolidWithAnInwardInnerShellLoads) {
  const core::Scene s = core::load_scene(scene_with(temp_dir("hollow"), two_shells(true, true)));
  // Outer tetrahedron 1/6 minus the inner one scaled by 1/2: 1/6 · (1 − 1/8).
  EXPECT_NEAR(core::signed_volume(s.static_obstacles[0].mesh), 7.0 / 48, 1e-12);
}

TEST(MeshValidation, UnusedVerticesAreDroppedNotPartOfTheSolid) {
  // A fifth vertex far outside S that no triangle uses (CGAL's volume test crashed on it).
  const core::Scene s = core::load_scene(scene_with(
      temp_dir("unused"), inline_mesh({{1, 1, 1}, {100, 100, 100}, {2, 1, 1}, {1, 2, 1}, {1, 1, 2}},
                                      {{0, 3, 2}, {0, 2, 4}, {0, 4, 3}, {2, 3, 4}})));
  const core::TriangleMesh& m = s.static_obstacles[0].mesh;
  ASSERT_EQ(m.vertices.size(), 4u);
  for (const auto& v : m.vertices) EXPECT_LE(v.maxCoeff(), 2.0);
  EXPECT_NEAR(core::signed_volume(m), 1.0 / 6, 1e-12);  // the unit corner tetrahedron
}

TEST(MeshValidation, FlatTetrahedronIsDegenerateNotSelfIntersecting) {
  const std::string dir = temp_dir("flat");
  expect_rejected(
      scene_with(dir, inline_mesh({{1, 1, 1}, {2, 1, 1}, {1, 2, 1}, {1.3, 1.3, 1}}, kTetT)),
      "/static_obstacles/0", "degenerate");
  // A flat shell beside a sound one is named too, not reported as a self-intersection.
  json both = two_shells(false, false);
  both["mesh"]["vertices"][7] = {2.3, 1.3, 1};
  expect_rejected(scene_with(dir, both), "/static_obstacles/0", "encloses no volume");
}

// ---- Formats read through assimp, units and up axis ----------------------------------------

std::string read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

std::string data_mesh(const std::string& name) {
  return std::string(CAMPLACE_SOURCE_DIR) + "/tests/data/meshes/" + name;
}

// The first static obstacle of a scene whose first static obstacle is `object`.
core::SceneObject load_first_obstacle(const std::string& name, const json& object) {
  return core::load_scene(scene_with(temp_dir("meshformat-" + name), object)).static_obstacles[0];
}

// Expects the 8 corners of the box lo–hi, each once, and 12 triangles (hand-computed corners;
// tolerance for glTF's single-precision floats).
void expect_box(const core::TriangleMesh& mesh, const core::Vec3& lo, const core::Vec3& hi) {
  ASSERT_EQ(mesh.vertices.size(), 8u);
  EXPECT_EQ(mesh.triangles.size(), 12u);
  std::vector<int> hits(8, 0);
  for (const core::Vec3& v : mesh.vertices) {
    for (int i = 0; i < 8; ++i) {
      const core::Vec3 corner((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(),
                              (i & 4) ? hi.z() : lo.z());
      if ((v - corner).norm() < 1e-6) ++hits[i];
    }
  }
  for (int i = 0; i < 8; ++i) EXPECT_EQ(hits[i], 1) << "corner " << i;
}

// Every cube file of tests/data/meshes (make_cube_files.py) holds this box once read with the
// defaults (world, metres, z up).
const core::Vec3 kCubeLo(1, 1, 0), kCubeHi(1.5, 2, 0.8);

TEST(MeshFormat, ColladaYUpMillimetresReadsAsZUpMetres) {
  // File: y up, x in [1000, 1500] mm, y (up) in [0, 800], z in [-2000, -1000]; y up -> z up is
  // (x, y, z) -> (x, -z, y).
  expect_box(load_first_obstacle("dae-y", {{"file", data_mesh("cube_yup_mm.dae")}}).mesh, kCubeLo,
             kCubeHi);
}

TEST(MeshFormat, ColladaZUpCentimetresKeepsItsAxes) {
  expect_box(load_first_obstacle("dae-z", {{"file", data_mesh("cube_zup_cm.dae")}}).mesh, kCubeLo,
             kCubeHi);
}

TEST(MeshFormat, ColladaUpAxisZTakesTheCoordinatesAsWritten) {
  // up_axis "z" ignores the file's <up_axis>; its <unit> still applies.
  expect_box(
      load_first_obstacle("dae-asis", {{"file", data_mesh("cube_yup_mm.dae")}, {"up_axis", "z"}})
          .mesh,
      core::Vec3(1, 0, -2), core::Vec3(1.5, 0.8, -1));
}

TEST(MeshFormat, GltfIsYUpWithItsNodeTransformAndSharedCornersMerged) {
  // 24 vertices in the file (4 per face) at x in [0, 0.5], y in [0, 0.8], z in [-2, -1], node
  // translation [1, 0, 0].
  expect_box(load_first_obstacle("gltf", {{"file", data_mesh("cube.gltf")}}).mesh, kCubeLo,
             kCubeHi);
}

TEST(MeshFormat, GlbReadsAsItsGltf) {
  expect_box(load_first_obstacle("glb", {{"file", data_mesh("cube.glb")}}).mesh, kCubeLo, kCubeHi);
}

TEST(MeshFormat, ThreeMfInMillimetresWithUnitsMm) {
  expect_box(load_first_obstacle("3mf", {{"file", data_mesh("cube_mm.3mf")}, {"units", "mm"}}).mesh,
             kCubeLo, kCubeHi);
}

TEST(MeshFormat, ThreeMfWithoutUnitsIsTakenAsMetres) {
  expect_box(load_first_obstacle("3mf-m", {{"file", data_mesh("cube_mm.3mf")}}).mesh,
             core::Vec3(1000, 1000, 0), core::Vec3(1500, 2000, 800));
}

TEST(MeshFormat, CorruptFilesOfEachFormatAreNamed) {
  for (const char* name : {"cube_yup_mm.dae", "cube.gltf", "cube.glb", "cube_mm.3mf"}) {
    SCOPED_TRACE(name);
    const std::string text = read_text_file(data_mesh(name));
    const std::string dir = temp_dir(std::string("meshcorrupt-") + name);
    write_file(dir + "/" + name, text.substr(0, text.size() / 2));
    expect_rejected(scene_with(dir, {{"file", name}}), "/static_obstacles/0/file",
                    "cannot be read");
    write_file(dir + "/" + name, "");
    expect_rejected(scene_with(dir, {{"file", name}}), "/static_obstacles/0/file",
                    "cannot be read");
  }
}

TEST(MeshFormat, UnknownExtensionIsUnsupported) {
  expect_file_rejected("cube.fbx", "not read", "unsupported format");
}

TEST(MeshUnits, UnitsThenUpAxisThenTransform) {
  // kTetV in millimetres, y up, then translated: v -> 0.001 (x, -z, y) + (1, 1, 1).
  const std::string dir = temp_dir("meshunits-order");
  write_file(dir + "/tet.off", std::string(kTetOffHeader) + "3 1 2 3\n");
  const core::SceneObject o =
      core::load_scene(scene_with(dir, {{"file", "tet.off"},
                                        {"units", "mm"},
                                        {"up_axis", "y"},
                                        {"transform", {{"translate", {1, 1, 1}}}}}))
          .static_obstacles[0];
  ASSERT_EQ(o.mesh.vertices.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    const auto& p = kTetV[i];
    const core::Vec3 expected(1 + 0.001 * p[0], 1 - 0.001 * p[2], 1 + 0.001 * p[1]);
    EXPECT_LT((o.mesh.vertices[i] - expected).norm(), 1e-15) << i;
  }
}

TEST(MeshUnits, InchesAndCentimetresScale) {
  const std::string dir = temp_dir("meshunits-in");
  write_file(dir + "/tet.off", std::string(kTetOffHeader) + "3 1 2 3\n");
  for (const auto& [units, scale] : {std::pair<const char*, double>{"in", 0.0254}, {"cm", 0.01}}) {
    const core::SceneObject o =
        core::load_scene(scene_with(dir, {{"file", "tet.off"}, {"units", units}}))
            .static_obstacles[0];
    for (std::size_t i = 0; i < 4; ++i) {
      const core::Vec3 expected(scale * kTetV[i][0], scale * kTetV[i][1], scale * kTetV[i][2]);
      EXPECT_LT((o.mesh.vertices[i] - expected).norm(), 1e-15) << units << " " << i;
    }
  }
}

TEST(MeshUnits, BadUnitsAndUpAxisAreNamed) {
  const std::string dir = temp_dir("meshunits-bad");
  write_file(dir + "/tet.off", std::string(kTetOffHeader) + "3 1 2 3\n");
  expect_rejected(scene_with(dir, {{"file", "tet.off"}, {"units", "km"}}),
                  "/static_obstacles/0/units", "unknown units \"km\"");
  expect_rejected(scene_with(dir, {{"file", "tet.off"}, {"units", 1000}}),
                  "/static_obstacles/0/units", "");
  expect_rejected(scene_with(dir, {{"file", "tet.off"}, {"up_axis", "x"}}),
                  "/static_obstacles/0/up_axis", "unknown up_axis \"x\"");
  expect_rejected(
      scene_with(dir, {{"box", {{"min", {1, 1, 1}}, {"max", {2, 2, 2}}}}, {"units", "mm"}}),
      "/static_obstacles/0/units", "applies only to a \"file\" object");
}

}  // namespace
}  // namespace camplace::testing
