// Mesh repair (docs/scene-format.md#repair): a mesh that fails the checks is refused with the
// repair option that would accept it, and accepted with it; the alpha wrap encloses the input
// (checked by an independent ray-parity point-in-mesh test) and passes the mesh checks; the
// convex hull is convex, contains every input vertex and has the hand-computed volume.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>

#include "camplace/core/error.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/core/scene.hpp"
#include "scene_builder.hpp"
#include "scene_fixtures.hpp"

namespace camplace::testing {
namespace {

using core::Vec3;
using nlohmann::json;
using Vertices = std::vector<std::array<double, 3>>;
using Triangles = std::vector<std::array<int, 3>>;

// The 8 corners (index x + 2y + 4z) and 12 outward triangles of the box lo–hi, appended to v, t.
void add_box(Vertices& v, Triangles& t, const Vec3& lo, const Vec3& hi) {
  const int base = static_cast<int>(v.size());
  for (int i = 0; i < 8; ++i) {
    v.push_back({(i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(), (i & 4) ? hi.z() : lo.z()});
  }
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    t.push_back({base + q[0], base + q[1], base + q[2]});
    t.push_back({base + q[0], base + q[2], base + q[3]});
  }
}

// Two overlapping boxes as one mesh: closed and outward, but each box's faces cut the other's.
json overlapping_boxes(Vertices* v_out = nullptr, Triangles* t_out = nullptr) {
  Vertices v;
  Triangles t;
  add_box(v, t, Vec3(1, 1, 0), Vec3(2, 2, 1));
  add_box(v, t, Vec3(1.5, 1.5, 0.5), Vec3(2.5, 2.5, 1.5));
  if (v_out) *v_out = v;
  if (t_out) *t_out = t;
  return inline_mesh(v, t);
}

// The box [1, 2] × [1, 2] × [0, 0.8] with its last triangle missing (open).
json open_box(Vertices* v_out = nullptr, Triangles* t_out = nullptr) {
  Vertices v;
  Triangles t;
  add_box(v, t, Vec3(1, 1, 0), Vec3(2, 2, 0.8));
  t.pop_back();
  if (v_out) *v_out = v;
  if (t_out) *t_out = t;
  return inline_mesh(v, t);
}

std::string scene_with_obstacle(const std::string& name, const json& object,
                                const json& scene_repair = nullptr) {
  json s = base_scene();
  s["static_obstacles"][0] = object;
  if (!scene_repair.is_null()) s["repair"] = scene_repair;
  return write_file(temp_dir("repair-" + name) + "/scene.json", s.dump());
}

json with(json object, const std::string& key, const json& value) {
  object[key] = value;
  return object;
}

// ---- An independent point-in-mesh test: ray parity (Möller–Trumbore), majority of 3 rays --

// Whether the ray o + s d (s > 0) crosses triangle abc in its interior.
bool ray_crosses(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a, p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-15) return false;
  const Vec3 s = o - a;
  const double u = s.dot(p) / det;
  if (u < 0 || u > 1) return false;
  const Vec3 q = s.cross(e1);
  const double w = d.dot(q) / det;
  if (w < 0 || u + w > 1) return false;
  return e2.dot(q) / det > 0;
}

bool inside(const core::TriangleMesh& mesh, const Vec3& p) {
  const Vec3 dirs[3] = {Vec3(0.5773, 0.5774, 0.5775).normalized(),
                        Vec3(-0.3141, 0.8414, 0.4398).normalized(),
                        Vec3(0.7071, -0.1234, -0.6960).normalized()};
  int votes = 0;
  for (const Vec3& d : dirs) {
    int crossings = 0;
    for (const auto& t : mesh.triangles) {
      crossings += ray_crosses(p, d, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
    }
    votes += crossings % 2;
  }
  return votes >= 2;
}

// The input's vertices and 300 random points on its triangles, all strictly inside `wrap`.
void expect_encloses(const core::TriangleMesh& wrap, const Vertices& v, const Triangles& t) {
  for (const auto& p : v) EXPECT_TRUE(inside(wrap, Vec3(p[0], p[1], p[2])));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0, 1);
  std::uniform_int_distribution<std::size_t> pick(0, t.size() - 1);
  for (int k = 0; k < 300; ++k) {
    const auto& tri = t[pick(rng)];
    double r1 = unit(rng), r2 = unit(rng);
    if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;
    const auto& a = v[tri[0]];
    const auto& b = v[tri[1]];
    const auto& c = v[tri[2]];
    const Vec3 A(a[0], a[1], a[2]), B(b[0], b[1], b[2]), C(c[0], c[1], c[2]);
    const Vec3 p = A + r1 * (B - A) + r2 * (C - A);
    EXPECT_TRUE(inside(wrap, p)) << p.transpose();
  }
}

// A scene whose static obstacle is `mesh` as an inline mesh, with no repair, loads.
void expect_passes_checks_alone(const std::string& name, const core::TriangleMesh& mesh) {
  json m = {{"mesh", {{"vertices", json::array()}, {"triangles", mesh.triangles}}}};
  for (const Vec3& p : mesh.vertices) m["mesh"]["vertices"].push_back({p.x(), p.y(), p.z()});
  EXPECT_NO_THROW(core::load_scene(scene_with_obstacle(name + "-alone", m)));
}

const char* kHint = "to accept it, add \"repair\": \"wrap\"";

// ---- Refusal names the repair ---------------------------------------------------------------

TEST(MeshRepair, SelfIntersectingMeshIsRefusedNamingTheRepair) {
  expect_rejected(scene_with_obstacle("selfx", overlapping_boxes()), "/static_obstacles/0",
                  std::string("mesh intersects itself; ") + kHint);
}

TEST(MeshRepair, OpenMeshIsRefusedNamingTheRepair) {
  expect_rejected(scene_with_obstacle("open", open_box()), "/static_obstacles/0",
                  std::string("mesh is open (it has border edges); ") + kHint);
}

// ---- Wrap ------------------------------------------------------------------------------------

TEST(MeshRepair, WrapOfSelfIntersectingMeshEnclosesItAndPassesTheChecks) {
  Vertices v;
  Triangles t;
  const json object = with(overlapping_boxes(&v, &t), "repair", "wrap");
  const core::Scene scene = core::load_scene(scene_with_obstacle("wrap-selfx", object));
  const core::TriangleMesh& wrap = scene.static_obstacles[0].mesh;
  expect_encloses(wrap, v, t);
  expect_passes_checks_alone("wrap-selfx", wrap);
  ASSERT_EQ(scene.repairs.size(), 1u);
  const core::MeshRepair& r = scene.repairs[0];
  EXPECT_EQ(r.entry, "/static_obstacles/0");
  EXPECT_EQ(r.role, "static obstacle");
  EXPECT_EQ(r.method, "wrap");
  EXPECT_EQ(r.defect, "mesh intersects itself");
  EXPECT_EQ(r.triangles_before, 24);
  EXPECT_EQ(r.triangles_after, static_cast<int>(wrap.triangles.size()));
  // Default offset: bounding-box diagonal / 20 / 30; the box [1, 2.5]² × [0, 1.5] has diagonal
  // 1.5·√3.
  EXPECT_NEAR(r.offset, 1.5 * std::sqrt(3.0) / 600.0, 1e-12);
  // The wrap stays near the input: within its bounding box grown by alpha = diagonal / 20.
  const core::Box3 box = core::bounding_box(wrap);
  const double alpha = 1.5 * std::sqrt(3.0) / 20;
  EXPECT_GT(box.min.minCoeff(), -alpha);
  EXPECT_LT(box.max.x(), 2.5 + alpha);
  EXPECT_LT(box.max.z(), 1.5 + alpha);
}

TEST(MeshRepair, WrapOfOpenMeshEnclosesItAndPassesTheChecks) {
  Vertices v;
  Triangles t;
  const json object =
      with(open_box(&v, &t), "repair", {{"method", "wrap"}, {"offset_m", 0.01}, {"alpha_m", 0.1}});
  const core::Scene scene = core::load_scene(scene_with_obstacle("wrap-open", object));
  expect_encloses(scene.static_obstacles[0].mesh, v, t);
  expect_passes_checks_alone("wrap-open", scene.static_obstacles[0].mesh);
  ASSERT_EQ(scene.repairs.size(), 1u);
  EXPECT_EQ(scene.repairs[0].offset, 0.01);
  EXPECT_EQ(scene.repairs[0].defect, "mesh is open (it has border edges)");
}

// Expects loading `object` as the static obstacle to fail naming the object and `reason`.
void expect_repair_refused(const std::string& name, const json& object, const std::string& reason) {
  expect_rejected(scene_with_obstacle(name, object), "/static_obstacles/0", reason);
}

TEST(MeshRepair, WrapOverItsTriangleBudgetIsRefusedWithTheCount) {
  const core::Scene scene = core::load_scene(scene_with_obstacle(
      "wrap-budget-ok", with(overlapping_boxes(), "repair", {{"method", "wrap"}})));
  const int count = scene.repairs.at(0).triangles_after;
  EXPECT_LE(count, 20000);
  // Exactly the wrap's count is within budget; one less is refused, naming the count.
  EXPECT_NO_THROW(core::load_scene(scene_with_obstacle(
      "wrap-budget-exact",
      with(overlapping_boxes(), "repair", {{"method", "wrap"}, {"max_triangles", count}}))));
  expect_repair_refused(
      "wrap-budget-less",
      with(overlapping_boxes(), "repair", {{"method", "wrap"}, {"max_triangles", count - 1}}),
      "mesh repaired by wrap (mesh intersects itself) has " + std::to_string(count) +
          " triangles, more than max_triangles = " + std::to_string(count - 1) +
          "; raise \"max_triangles\" or give a larger \"alpha_m\" in the repair object");
  // A budget far too small stops the wrap while it runs (its vertices alone exceed it).
  expect_repair_refused(
      "wrap-budget-tiny",
      with(overlapping_boxes(), "repair", {{"method", "wrap"}, {"max_triangles", 10}}),
      "needs more than max_triangles = 10 vertices, so more triangles than that; raise "
      "\"max_triangles\" or give a larger \"alpha_m\"");
}

TEST(MeshRepair, TinyAlphaIsRefusedBeforeAnyWork) {
  expect_rejected(scene_with_obstacle("wrap-tiny", with(overlapping_boxes(), "repair",
                                                        {{"method", "wrap"}, {"alpha_m", 1e-6}})),
                  "/static_obstacles/0", "alpha_m 1e-06 m is too small for this mesh");
  expect_rejected(
      scene_with_obstacle("wrap-tiny-offset", with(overlapping_boxes(), "repair",
                                                   {{"method", "wrap"}, {"offset_m", 1e-9}})),
      "/static_obstacles/0", "offset_m 1e-09 m is too small for alpha");
}

// ---- Hull ------------------------------------------------------------------------------------

TEST(MeshRepair, HullOfOpenBoxIsTheBoxConvexAndContainsTheInput) {
  Vertices v;
  Triangles t;
  const core::Scene scene =
      core::load_scene(scene_with_obstacle("hull-open", with(open_box(&v, &t), "repair", "hull")));
  const core::TriangleMesh& hull = scene.static_obstacles[0].mesh;
  EXPECT_NEAR(core::signed_volume(hull), 1.0 * 1.0 * 0.8, 1e-12);  // outward, the whole box
  // Convex and containing: every vertex (of the input and of the hull) lies on the inner side
  // of (or on) every face plane.
  for (const auto& tri : hull.triangles) {
    const Vec3& a = hull.vertices[tri[0]];
    const Vec3 n = (hull.vertices[tri[1]] - a).cross(hull.vertices[tri[2]] - a).normalized();
    for (const Vec3& p : hull.vertices) EXPECT_LE(n.dot(p - a), 1e-12);
    for (const auto& p : v) EXPECT_LE(n.dot(Vec3(p[0], p[1], p[2]) - a), 1e-12);
  }
  ASSERT_EQ(scene.repairs.size(), 1u);
  EXPECT_EQ(scene.repairs[0].method, "hull");
  EXPECT_EQ(scene.repairs[0].triangles_before, 11);
  EXPECT_EQ(scene.repairs[0].triangles_after, static_cast<int>(hull.triangles.size()));
}

TEST(MeshRepair, HullOfOverlappingBoxesHasTheHandComputedVolume) {
  // The hull of [1, 2]³-like boxes A = [1, 2]² × [0, 1] and B = A + 0.5: the unit-cube hull of
  // two cubes offset by (s, s, s), s = 0.5, has volume 1 + 3 s (each of the three
  // face-sweeps adds a prism of volume s; the edge and corner regions add nothing because the
  // offset is along the cube diagonal — the hull of a cube and its translate by t is the
  // Minkowski sum cube ⊕ segment(t), volume 1 + |t_x| + |t_y| + |t_z|).
  const core::Scene scene = core::load_scene(
      scene_with_obstacle("hull-selfx", with(overlapping_boxes(), "repair", "hull")));
  EXPECT_NEAR(core::signed_volume(scene.static_obstacles[0].mesh), 1.0 + 3 * 0.5, 1e-12);
  expect_passes_checks_alone("hull-selfx", scene.static_obstacles[0].mesh);
}

// The same input gives the same repaired mesh, vertex for vertex and triangle for triangle,
// whatever the process did before: the hull's faces are triangulated from the input's geometry
// alone (CGAL's hull orders its output by memory addresses, which differ with the heap's
// history, and would otherwise change the triangulation of its flat faces and so the
// conservative labels). The input is given in 6 vertex orders, each loaded after a different
// pattern of live allocations.
TEST(MeshRepair, HullDoesNotDependOnTheInputOrderOrTheProcessHistory) {
  Vertices v;
  Triangles t;
  overlapping_boxes(&v, &t);
  std::mt19937 rng(11);
  std::vector<std::vector<char>> ballast;
  std::optional<core::TriangleMesh> first;
  for (int trial = 0; trial < 6; ++trial) {
    std::vector<int> order(v.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    if (trial > 0) std::shuffle(order.begin(), order.end(), rng);
    Vertices pv(v.size());
    std::vector<int> where(v.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
      pv[i] = v[order[i]];
      where[order[i]] = static_cast<int>(i);
    }
    Triangles pt;
    for (const auto& tri : t) pt.push_back({where[tri[0]], where[tri[1]], where[tri[2]]});
    for (int k = 0; k < 50 * trial; ++k) ballast.emplace_back(16 + 24 * (k % 7));
    const core::Scene scene = core::load_scene(scene_with_obstacle(
        "hull-order-" + std::to_string(trial), with(inline_mesh(pv, pt), "repair", "hull")));
    const core::TriangleMesh& hull = scene.static_obstacles[0].mesh;
    if (!first) {
      first = hull;
      continue;
    }
    EXPECT_EQ(hull.vertices, first->vertices) << "trial " << trial;
    EXPECT_EQ(hull.triangles, first->triangles) << "trial " << trial;
  }
}

TEST(MeshRepair, HullOfAFlatMeshIsRefusedAndWrapAccepted) {
  // Two triangles back to back: closed, but flat.
  const json flat = inline_mesh({{1, 1, 1}, {2, 1, 1}, {1, 2, 1}}, {{0, 1, 2}, {0, 2, 1}});
  expect_rejected(scene_with_obstacle("flat", flat), "/static_obstacles/0",
                  "(it is flat); to accept it, add \"repair\": \"wrap\" (an enclosing alpha wrap) "
                  "to the object");
  expect_rejected(scene_with_obstacle("flat-hull", with(flat, "repair", "hull")),
                  "/static_obstacles/0", "its vertices are coplanar");
  const core::Scene scene = core::load_scene(scene_with_obstacle(
      "flat-wrap", with(flat, "repair", {{"method", "wrap"}, {"offset_m", 0.01}})));
  EXPECT_GT(core::signed_volume(scene.static_obstacles[0].mesh), 0.0);
}

// ---- Scene-wide default, overrides, "always" --------------------------------------------------

TEST(MeshRepair, SceneWideRepairAppliesAndObjectNoneOverridesIt) {
  const core::Scene scene =
      core::load_scene(scene_with_obstacle("scene-wide", overlapping_boxes(), "hull"));
  ASSERT_EQ(scene.repairs.size(), 1u);
  EXPECT_EQ(scene.repairs[0].method, "hull");
  // Valid objects of the same scene are not repaired.
  EXPECT_EQ(scene.time_steps[0].dynamic_obstacles[0].mesh.triangles.size(), 4u);
  expect_rejected(
      scene_with_obstacle("scene-wide-none", with(overlapping_boxes(), "repair", "none"), "hull"),
      "/static_obstacles/0", "mesh intersects itself");
}

TEST(MeshRepair, AlwaysRepairsAValidMesh) {
  const json box = {{"box", {{"min", {1, 1, 0}}, {"max", {2, 2, 1}}}},
                    {"repair", {{"method", "hull"}, {"always", true}}}};
  const core::Scene scene = core::load_scene(scene_with_obstacle("always", box));
  ASSERT_EQ(scene.repairs.size(), 1u);
  EXPECT_EQ(scene.repairs[0].defect, "");
  EXPECT_NEAR(core::signed_volume(scene.static_obstacles[0].mesh), 1.0, 1e-12);
  // Without "always" the valid box is left alone.
  EXPECT_TRUE(core::load_scene(scene_with_obstacle("not-always", with(box, "repair", "hull")))
                  .repairs.empty());
}

TEST(MeshRepair, BadRepairValuesAreNamed) {
  const json m = overlapping_boxes();
  expect_rejected(scene_with_obstacle("bad-name", with(m, "repair", "glue")),
                  "/static_obstacles/0/repair", "unknown repair method \"glue\"");
  expect_rejected(scene_with_obstacle("bad-method", with(m, "repair", {{"method", "glue"}})),
                  "/static_obstacles/0/repair/method", "unknown repair method");
  expect_rejected(scene_with_obstacle("bad-hull-offset",
                                      with(m, "repair", {{"method", "hull"}, {"offset_m", 0.1}})),
                  "/static_obstacles/0/repair/offset_m", "applies only to \"method\": \"wrap\"");
  expect_rejected(scene_with_obstacle(
                      "bad-budget", with(m, "repair", {{"method", "wrap"}, {"max_triangles", 0}})),
                  "/static_obstacles/0/repair/max_triangles", "");
  expect_rejected(
      scene_with_obstacle("bad-alpha", with(m, "repair", {{"method", "wrap"}, {"alpha_m", -1}})),
      "/static_obstacles/0/repair/alpha_m", "");
  expect_rejected(
      scene_with_obstacle("bad-always", with(m, "repair", {{"method", "wrap"}, {"always", "yes"}})),
      "/static_obstacles/0/repair/always", "true or false");
  expect_rejected(
      scene_with_obstacle("bad-key", with(m, "repair", {{"method", "wrap"}, {"ofset_m", 0.1}})),
      "/static_obstacles/0/repair/ofset_m", "");
  expect_rejected(scene_with_obstacle("bad-root", m, 5), "/repair", "");
}

// ---- The report --------------------------------------------------------------------------------

TEST(MeshRepair, WarningsNameFileEntryMethodCountsAndWhatItMeansForTheRole) {
  json s = base_scene();
  s["static_obstacles"][0] = with(overlapping_boxes(), "name", "conveyor");
  // The person as an open box (missing a triangle), repaired by hull.
  Vertices v;
  Triangles t;
  add_box(v, t, Vec3(2, 0.5, 0), Vec3(2.4, 0.9, 1.8));
  t.pop_back();
  json person = inline_mesh(v, t);
  person["name"] = "person";
  person["repair"] = "hull";
  s["time_steps"][0]["events"][0]["targets"][0] = person;
  s["repair"] = {{"method", "wrap"}, {"offset_m", 0.005}};
  const std::string path = write_file(temp_dir("repair-warnings") + "/scene.json", s.dump());
  const core::Scene scene = core::load_scene(path);
  const std::vector<std::string> lines = core::repair_warnings(scene);
  ASSERT_EQ(lines.size(), 2u);
  const std::string wrap_after = std::to_string(scene.repairs[0].triangles_after);
  EXPECT_EQ(lines[0].rfind(path + ": /static_obstacles/0: mesh \"conveyor\" repaired by wrap "
                                  "(offset 0.005 m, 24 → ",
                           0),
            0u)
      << lines[0];
  EXPECT_NE(lines[0].find("triangles): it failed the checks (mesh intersects itself); as a "
                          "static obstacle the wrap occludes more and leaves less room for a "
                          "person than the mesh it replaces"),
            std::string::npos)
      << lines[0];
  EXPECT_EQ(lines[1], path +
                          ": /time_steps/0/events/0/targets/0: mesh \"person\" repaired by hull "
                          "(11 → 12 triangles): it failed the checks (mesh is open (it has border "
                          "edges)); as a target the hull is conservative: it contains the mesh it "
                          "replaces, so distances can only shrink");
  EXPECT_EQ(scene.repairs[1].role, "target");
}

TEST(MeshRepair, WarningCountsHaveThousandsSeparators) {
  core::Scene scene;
  scene.file = "cell.json";
  core::MeshRepair r;
  r.object = "conveyor";
  r.entry = "/static_obstacles/2";
  r.role = "critical object";
  r.method = "wrap";
  r.defect = "mesh intersects itself";
  r.triangles_before = 1234567;
  r.triangles_after = 1980;
  r.offset = 0.005;
  scene.repairs.push_back(r);
  EXPECT_EQ(core::repair_warnings(scene).at(0),
            "cell.json: /static_obstacles/2: mesh \"conveyor\" repaired by wrap (offset 0.005 m, "
            "1,234,567 → 1,980 triangles): it failed the checks (mesh intersects itself); as a "
            "critical object the wrap is conservative: it contains the mesh it replaces, so "
            "distances can only shrink");
}

}  // namespace
}  // namespace camplace::testing
