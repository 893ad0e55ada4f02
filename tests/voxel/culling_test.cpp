// Back-face culling (voxel/src/labelling.cpp) and its degenerate cases:
// a camera in the plane of a face, on an edge and on a vertex of an obstacle or a target, and
// rays grazing a face. In every case the labels must equal the labeller without culling
// (tests/support/legacy_labeller.cpp) or be less free, and every voxel labelled free must be
// free at sampled points by the brute-force reference. Several cases put a voxel corner exactly
// on a ray through an object's vertex or edge (touching), where the rounding of the cone test
// decides; culling then tests the back faces as well, so the labels stay the same.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "legacy_labeller.hpp"
#include "reference.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using core::Vec3;
using voxel::Label;
using voxel::LabelMode;

// A 4×3×3 m room with a static box obstacle [1,2]×[1,2]×[0,1], a box target
// [2.5,3]×[1.25,1.75]×[0,0.5] and a tetrahedral target; 16×12×12 voxels.
core::Scene room() {
  core::Scene scene = simple_scene(
      {Vec3(0, 0, 0), Vec3(4, 3, 3)}, {16, 12, 12}, 1, 35.0,
      {box_object("critical", {0.2, 2.5, 0}, {0.4, 2.7, 0.5})},
      {box_object("box target", {2.5, 1.25, 0}, {3, 1.75, 0.5}),
       tetra_object("tetra target", {3.2, 0.4, 0}, {3.8, 0.4, 0}, {3.5, 0.9, 0}, {3.5, 0.6, 0.8})});
  scene.static_obstacles.push_back(box_object("block", {1, 1, 0}, {2, 2, 1}));
  return scene;
}

// Compares the conservative labels of one camera with the labeller without culling and checks
// the free voxels at 27 lattice points and 8 random points each. Returns the free count. A camera
// on an object's surface is blind (SPEC §3.3, the exact pipeline's convention too),
// where the old labeller let it see: its labels may only be non-free.
long check_camera(const core::Scene& scene, const core::CameraSetting& camera,
                  const std::string& what, bool on_surface) {
  const voxel::VoxelEvaluator fast(scene, {LabelMode::conservative, {0, 0, 0}});
  const LegacyLabeller old(scene, {LabelMode::conservative, {0, 0, 0}});
  const auto labels = fast.labels(camera, 0);
  const auto expected = old.labels(camera, 0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  long free_voxels = 0;
  for (int v = 0; v < fast.grid().count(); ++v) {
    if (on_surface) {
      EXPECT_NE(labels[v], Label::free) << what << ": voxel " << v;
      continue;
    }
    EXPECT_EQ(labels[v], expected[v])
        << what << ": voxel " << v << " old " << static_cast<int>(expected[v]) << " new "
        << static_cast<int>(labels[v]);
    if (labels[v] != Label::free) continue;
    ++free_voxels;
    const core::Box3 box = fast.grid().voxel_box(v);
    for (int a = 0; a < 35; ++a) {
      const Vec3 f =
          a < 27 ? Vec3(a % 3, (a / 3) % 3, a / 9) / 2.0 : Vec3(unit(rng), unit(rng), unit(rng));
      const Vec3 p = box.min + box.size().cwiseProduct(f);
      const ReferenceLabel ref = reference_label(scene, 0, 0, camera, p);
      EXPECT_TRUE(ref.ambiguous || ref.label == Label::free)
          << what << ": voxel " << v << " point " << p.transpose();
    }
  }
  return free_voxels;
}

// Center mode culls the same back faces (the first hit along a ray from outside a closed,
// outward solid is on a face toward the camera, and a back face hit at t ≤ d follows a front
// face hit before it): its labels must equal the labeller without culling except where the
// ray through the voxel centre touches an edge or a vertex (the reference flags the tie), and
// equal the brute-force reference at every centre it does not flag. A camera on an object's
// surface is blind (as in check_camera). Returns the free count.
long check_camera_center(const core::Scene& scene, const core::CameraSetting& camera,
                         const std::string& what, bool on_surface) {
  const voxel::VoxelEvaluator fast(scene, {LabelMode::center, {0, 0, 0}});
  const LegacyLabeller old(scene, {LabelMode::center, {0, 0, 0}});
  const auto labels = fast.labels(camera, 0);
  const auto expected = old.labels(camera, 0);
  long free_voxels = 0;
  for (int v = 0; v < fast.grid().count(); ++v) {
    free_voxels += labels[v] == Label::free;
    if (on_surface) {
      EXPECT_EQ(labels[v], Label::undetectable) << what << ": voxel " << v;
      continue;
    }
    const ReferenceLabel ref = reference_label(scene, 0, 0, camera, fast.grid().voxel_center(v));
    if (ref.ambiguous) continue;
    EXPECT_EQ(labels[v], expected[v])
        << what << ": voxel " << v << " old " << static_cast<int>(expected[v]) << " new "
        << static_cast<int>(labels[v]);
    EXPECT_EQ(labels[v], ref.label) << what << ": voxel " << v;
  }
  return free_voxels;
}

TEST(Culling, CameraInTheBlocksFacePlanesOnItsEdgesAndVertices) {
  const core::Scene scene = room();
  struct Case {
    const char* what;
    Vec3 position;
    double yaw, pitch;
    bool on_surface;
  };
  const Case cases[] = {
      {"in the plane of the top face, looking across it", {0.2, 1.5, 1.0}, 0, 0, false},
      {"in the plane of the top face, looking down past it", {0.5, 1.5, 1.0}, 0, -30, false},
      {"in the plane of the front face x = 1", {1.0, 0.2, 0.5}, 60, 0, false},
      {"on the top edge x = 1, z = 1", {1.0, 1.5, 1.0}, 0, -20, true},
      {"on the top vertex (2, 2, 1)", {2.0, 2.0, 1.0}, -60, -30, true},
      {"on the top face (1.5, 1.5, 1)", {1.5, 1.5, 1.0}, 0, -40, true},
      {"on the box target's top edge", {2.5, 1.5, 0.5}, 0, -10, true},
      {"on the tetrahedron's apex", {3.5, 0.6, 0.8}, 180, -20, true},
      {"in the plane of the tetrahedron's base", {2.0, 0.6, 0.0}, 0, 10, false},
      {"generic, far", {0.1, 0.1, 2.9}, 35, -30, false},
  };
  long free_voxels = 0, center_free = 0;
  for (const Case& c : cases) {
    const auto camera = camera_at(c.position, c.yaw, c.pitch);
    free_voxels += check_camera(scene, camera, c.what, c.on_surface);
    center_free +=
        check_camera_center(scene, camera, std::string("center mode, ") + c.what, c.on_surface);
  }
  EXPECT_GT(free_voxels, 1000);  // the checks are not vacuous
  EXPECT_GT(center_free, 1000);
}

TEST(Culling, RaysGrazingAFaceOfATargetStayOccupied) {
  // The camera at the height of the box target's top face z = 0.5, looking along +x: voxels
  // whose rays graze the top face touch the target, so they may not be free.
  const core::Scene scene = room();
  const auto camera = camera_at({0.1, 1.5, 0.5}, 0, 0);
  check_camera(scene, camera, "grazing", false);
  check_camera_center(scene, camera, "grazing, center mode", false);
  const voxel::VoxelEvaluator fast(scene, {LabelMode::conservative, {0, 0, 0}});
  const auto labels = fast.labels(camera, 0);
  // Voxel (13, 5, 1): x ∈ [3.25, 3.5], y ∈ [1.25, 1.5], z ∈ [0.25, 0.5], behind the target on
  // the camera's axis: its rays cross the target.
  EXPECT_EQ(labels[13 + 16 * (5 + 12 * 1)], Label::occupied);
  // Voxel (13, 5, 2): z ∈ [0.5, 0.75]: its lowest rays graze the top face (touching counts).
  EXPECT_EQ(labels[13 + 16 * (5 + 12 * 2)], Label::occupied);
}

TEST(Culling, AFineTargetWithANearEdgeOnTriangleIsCulledWithTheSameLabels) {
  // A fine ellipsoid target (occupying): the camera lies 1e-10 (tilt) in front of the plane of one
  // triangle on its equator, 1.2 m away along the plane, looking at the ellipsoid. That triangle
  // is near edge-on but not flat, so conservative mode culls the target's clear back faces and
  // keeps it a slot (L3); the labels must equal the labeller without culling.
  const core::Box3 box{Vec3(1.5, 1.0, 0.5), Vec3(2.5, 2.0, 1.5)};
  core::Scene scene = simple_scene({Vec3(0, 0, 0), Vec3(4, 3, 3)}, {16, 12, 12}, 1, 35.0,
                                   {box_object("critical", {0.2, 2.5, 0}, {0.4, 2.7, 0.5})},
                                   {ellipsoid_object("ellipsoid target", box, 4000)});
  const core::TriangleMesh& mesh = scene.time_steps[0].events[0].targets[0].mesh;
  // The triangle whose outward normal is closest to −x, near the equator.
  int chosen = 0;
  double best = 2.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& v = mesh.triangles[t];
    const Vec3 n = (mesh.vertices[v[1]] - mesh.vertices[v[0]])
                       .cross(mesh.vertices[v[2]] - mesh.vertices[v[0]])
                       .normalized();
    if (n.x() < -0.9 && std::abs(n.z()) < best) {
      best = std::abs(n.z());
      chosen = static_cast<int>(t);
    }
  }
  const auto& v = mesh.triangles[chosen];
  const Vec3 a = mesh.vertices[v[0]], b = mesh.vertices[v[1]], e = mesh.vertices[v[2]];
  const Vec3 cross = (b - a).cross(e - a);
  const Vec3 n = cross.normalized();
  const Vec3 along = n.cross(Vec3::UnitZ()).normalized();  // in the plane, horizontal
  const Vec3 centroid = (a + b + e) / 3.0;
  const double reach = 1.2;
  // det ≈ −δ |cross| for an offset δ along n, |a − c||b − c||e − c| ≈ reach³: tilt ≈ −1e-10.
  const double offset = 1e-10 * reach * reach * reach / cross.norm();
  const Vec3 c = centroid + reach * along + offset * n;
  const Vec3 ac = a - c, bc = b - c, ec = e - c;
  const double tilt = ac.dot(bc.cross(ec)) / (ac.norm() * bc.norm() * ec.norm());
  EXPECT_LT(std::abs(tilt), 1e-9);   // near edge-on: the stricter guard would not cull
  EXPECT_GT(std::abs(tilt), 1e-12);  // not flat
  const Vec3 look = box.center() - c;
  const double yaw = std::atan2(look.y(), look.x()) * 180.0 / core::kPi;
  const double pitch = std::atan2(look.z(), look.head<2>().norm()) * 180.0 / core::kPi;
  EXPECT_GT(check_camera(scene, camera_at(c, yaw, pitch), "near edge-on", false), 50);
}

}  // namespace
}  // namespace camplace::testing
