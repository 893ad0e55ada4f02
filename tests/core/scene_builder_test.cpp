// The ellipsoid meshes of tests/support/scene_builder (the scale benchmark's finer robots and
// people): the triangle count asked for, closed and outward by an edge count and by core's mesh
// checks, every vertex on the ellipsoid, and the volume against a hand-computed solid.
#include "scene_builder.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

#include "../../core/src/mesh_checks.hpp"
#include "camplace/core/geometry.hpp"

namespace camplace::testing {
namespace {

using core::Box3;
using core::Vec3;

const Box3 kBox{Vec3(2.15, 0.5, 0.0), Vec3(3.1, 1.3, 0.98)};

// Every directed edge once and its reverse once: closed and consistently oriented.
void expect_closed_consistent(const core::TriangleMesh& mesh) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : mesh.triangles) {
    for (int e = 0; e < 3; ++e) ++directed[{t[e], t[(e + 1) % 3]}];
  }
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1) << edge.first << "-" << edge.second;
    const auto reverse = directed.find({edge.second, edge.first});
    ASSERT_NE(reverse, directed.end()) << "open edge " << edge.first << "-" << edge.second;
    EXPECT_EQ(reverse->second, 1);
  }
}

TEST(EllipsoidMesh, CountsClosedOutwardOnTheEllipsoid) {
  const Vec3 c = kBox.center(), r = 0.5 * kBox.size();
  const double ellipsoid_volume = 4.0 / 3.0 * core::kPi * r.prod();
  for (int triangles : {1000, 3000, 10000, 30000}) {
    SCOPED_TRACE(triangles);
    core::TriangleMesh mesh = ellipsoid_mesh(kBox, triangles);
    ASSERT_EQ(static_cast<int>(mesh.triangles.size()), triangles);
    // A closed surface of genus 0: V − E + F = 2 with E = 3F/2.
    EXPECT_EQ(static_cast<int>(mesh.vertices.size()), 2 + triangles / 2);
    expect_closed_consistent(mesh);
    for (const Vec3& v : mesh.vertices) {
      EXPECT_NEAR((v - c).cwiseQuotient(r).squaredNorm(), 1.0, 1e-12);
    }
    // Inscribed (convex, vertices on the surface): a little less than the ellipsoid.
    const double volume = core::signed_volume(mesh);
    EXPECT_LT(volume, ellipsoid_volume);
    EXPECT_GT(volume, 0.97 * ellipsoid_volume);
    // core's checks: valid, and nothing to turn (already outward).
    const auto triangles_before = mesh.triangles;
    EXPECT_FALSE(core::detail::check_and_orient(mesh).has_value());
    EXPECT_EQ(mesh.triangles, triangles_before);
  }
}

TEST(EllipsoidMesh, SixTrianglesAreTheTriangularBipyramid) {
  // m = 3 segments, 2 bands: an equilateral triangle inscribed in the unit circle (area
  // 3√3/4) with apexes at ±1, volume 2 · (1/3) · 3√3/4 = √3/2 for the unit sphere, times the
  // semi-axes' product.
  const core::TriangleMesh mesh = ellipsoid_mesh(kBox, 6);
  ASSERT_EQ(mesh.triangles.size(), 6u);
  EXPECT_EQ(mesh.vertices.size(), 5u);
  expect_closed_consistent(mesh);
  const Vec3 r = 0.5 * kBox.size();
  EXPECT_NEAR(core::signed_volume(mesh), std::sqrt(3.0) / 2.0 * r.prod(), 1e-12);
}

TEST(EllipsoidMesh, ObjectBoundsAndRefusals) {
  const core::SceneObject o = ellipsoid_object("robot", kBox, 1000);
  EXPECT_EQ(o.name, "robot");
  // Poles on the box's top and bottom; the other extents within the box.
  EXPECT_DOUBLE_EQ(o.bounds.min.z(), kBox.min.z());
  EXPECT_DOUBLE_EQ(o.bounds.max.z(), kBox.max.z());
  EXPECT_TRUE(kBox.contains(o.bounds.min + Vec3::Constant(1e-12)));
  EXPECT_TRUE(kBox.contains(o.bounds.max - Vec3::Constant(1e-12)));
  EXPECT_THROW(ellipsoid_mesh(kBox, 1001), std::invalid_argument);
  EXPECT_THROW(ellipsoid_mesh(kBox, 4), std::invalid_argument);
  EXPECT_THROW(ellipsoid_mesh(Box3{Vec3(0, 0, 0), Vec3(1, 0, 1)}, 100), std::invalid_argument);
}

}  // namespace
}  // namespace camplace::testing
