// Closest point pairs against hand-computed cases and against core's independent distances
// (the exact CGAL solids distance, point/box–solid distances).
#include "camplace/core/closest_points.hpp"

#include <gtest/gtest.h>

#include <random>

#include "camplace/core/distance.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using core::Vec3;

/// Squared distance from p to the union of solids (0 inside): p lies on the set when ~0.
double to_solids(const std::vector<const core::TriangleMesh*>& solids, const Vec3& p) {
  double best = 1e300;
  for (const auto* m : solids) best = std::min(best, core::point_solid_sq_distance(*m, p));
  return best;
}

TEST(ClosestPoints, SeparatedBoxesMeetAcrossTheGap) {
  const auto a = box_object("a", {0, 0, 0}, {1, 1, 1});
  const auto b = box_object("b", {2, 0.5, 0.25}, {3, 2, 2});  // gap 1 along x only
  const auto pair = core::closest_points({&a.mesh}, {&b.mesh});
  EXPECT_NEAR(pair.sq_distance, 1.0, 1e-15);
  EXPECT_NEAR(pair.a.x(), 1.0, 1e-15);
  EXPECT_NEAR(pair.b.x(), 2.0, 1e-15);
  EXPECT_NEAR((pair.a - pair.b).squaredNorm(), pair.sq_distance, 1e-15);
  // Both ends on the facing faces' overlap: y ∈ [0.5, 1], z ∈ [0.25, 1].
  for (const Vec3& p : {pair.a, pair.b}) {
    EXPECT_GE(p.y(), 0.5 - 1e-12);
    EXPECT_LE(p.y(), 1.0 + 1e-12);
    EXPECT_GE(p.z(), 0.25 - 1e-12);
    EXPECT_LE(p.z(), 1.0 + 1e-12);
  }
}

TEST(ClosestPoints, NestedAndCrossingSolidsShareAPoint) {
  const auto outer = box_object("o", {0, 0, 0}, {2, 2, 2});
  const auto inner =
      tetra_object("i", {0.5, 0.5, 0.5}, {1, 0.5, 0.5}, {0.5, 1, 0.5}, {0.5, 0.5, 1});
  for (const auto& pair : {core::closest_points({&outer.mesh}, {&inner.mesh}),
                           core::closest_points({&inner.mesh}, {&outer.mesh})}) {
    EXPECT_EQ(pair.sq_distance, 0.0);
    EXPECT_EQ(pair.a, pair.b);
    EXPECT_LT(to_solids({&inner.mesh}, pair.a), 1e-24);
  }
  // A tetrahedron poking through the box's top face.
  const auto poke = tetra_object("p", {1, 1, 1.5}, {1.5, 1, 3}, {0.5, 1, 3}, {1, 1.5, 3});
  const auto pair = core::closest_points({&outer.mesh}, {&poke.mesh});
  EXPECT_EQ(pair.sq_distance, 0.0);
  EXPECT_LT(to_solids({&outer.mesh}, pair.a), 1e-20);
  EXPECT_LT(to_solids({&poke.mesh}, pair.a), 1e-20);
}

TEST(ClosestPoints, TrianglesCrossingAndApart) {
  // Triangle b (in the plane x = 0.25) cuts triangle a (z = 0) along x = 0.25, y ∈ [0.25, 0.75].
  const auto crossing = core::closest_points_of_triangles(
      {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.25, 0.25, -1}, {0.25, 0.25, 1}, {0.25, 3, 1});
  EXPECT_EQ(crossing.sq_distance, 0.0);
  EXPECT_EQ(crossing.a, crossing.b);
  EXPECT_NEAR(crossing.a.x(), 0.25, 1e-15);
  EXPECT_NEAR(crossing.a.z(), 0.0, 1e-15);
  EXPECT_GE(crossing.a.y(), 0.25 - 1e-15);
  EXPECT_LE(crossing.a.y(), 0.75 + 1e-15);
  // Parallel, 2 apart in z, overlapping in xy.
  const auto parallel = core::closest_points_of_triangles({0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                                          {0, 0, 2}, {1, 0, 2}, {0, 1, 2});
  EXPECT_NEAR(parallel.sq_distance, 4.0, 1e-15);
  // Skew edges: a's edge along x at z = 0, b's edge along y at z = 1 over x = 0.5.
  const auto skew = core::closest_points_of_triangles({0, 0, 0}, {1, 0, 0}, {0.5, -1, -1},
                                                      {0.5, -1, 1}, {0.5, 1, 1}, {0.5, 0, 3});
  EXPECT_NEAR(skew.sq_distance, 1.0, 1e-15);
  EXPECT_NEAR((skew.a - Vec3(0.5, 0, 0)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((skew.b - Vec3(0.5, 0, 1)).norm(), 0.0, 1e-15);
}

TEST(ClosestPoints, AgreeWithTheExactDistanceOnRandomSolids) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 3.0);
  auto point = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  for (int trial = 0; trial < 60; ++trial) {
    const auto a = tetra_object("a", point(), point(), point(), point());
    const auto b = tetra_object("b", point(), point(), point(), point());
    const Vec3 lo = point(), hi = lo + Vec3(0.3, 0.2, 0.4);
    const auto c = box_object("c", lo, hi);
    const std::vector<const core::TriangleMesh*> first{&a.mesh}, second{&b.mesh, &c.mesh};
    const auto pair = core::closest_points(first, second);
    const double exact = core::solids_squared_distance(first, second).value;
    EXPECT_NEAR(pair.sq_distance, exact, 1e-12 * (1 + exact)) << trial;
    EXPECT_NEAR((pair.a - pair.b).squaredNorm(), pair.sq_distance, 1e-12) << trial;
    EXPECT_LT(to_solids(first, pair.a), 1e-20) << trial;
    EXPECT_LT(to_solids(second, pair.b), 1e-20) << trial;

    // Box and point overloads against core's box/point–solid distances.
    const core::Box3 box{lo, hi};
    const auto to_box = core::closest_points(first, box);
    EXPECT_NEAR(to_box.sq_distance, core::box_solid_sq_distance(a.mesh, box), 1e-12) << trial;
    EXPECT_LT(core::point_box_sq_distance(to_box.b, box), 1e-24) << trial;
    const Vec3 p = point();
    const auto to_point = core::closest_points(first, p);
    EXPECT_NEAR(to_point.sq_distance, core::point_solid_sq_distance(a.mesh, p), 1e-12) << trial;
    EXPECT_EQ(to_point.b, p);
  }
}

TEST(ClosestPoints, BoxMeshIsAClosedOutwardBox) {
  const core::Box3 box{Vec3(1, 2, 3), Vec3(2, 4, 7)};
  const core::TriangleMesh mesh = core::box_mesh(box);
  EXPECT_EQ(mesh.triangles.size(), 12u);
  EXPECT_NEAR(core::signed_volume(mesh), 1.0 * 2.0 * 4.0, 1e-12);
  EXPECT_TRUE(core::inside_mesh(mesh, box.center()));
  EXPECT_FALSE(core::inside_mesh(mesh, Vec3(0, 0, 0)));
}

}  // namespace
}  // namespace camplace::testing
