// Geometric primitives against values computed by hand or by brute-force sampling.
#include "camplace/core/geometry.hpp"

#include <gtest/gtest.h>

#include <random>

#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using core::Vec3;

TEST(Geometry, PointTriangleDistanceInEveryRegion) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_DOUBLE_EQ(core::point_triangle_sq_distance({0.2, 0.2, 2}, a, b, c), 4.0);  // face
  EXPECT_DOUBLE_EQ(core::point_triangle_sq_distance({-1, -1, 0}, a, b, c), 2.0);    // vertex a
  EXPECT_DOUBLE_EQ(core::point_triangle_sq_distance({0.5, -2, 0}, a, b, c), 4.0);   // edge ab
  EXPECT_DOUBLE_EQ(core::point_triangle_sq_distance({1, 1, 0}, a, b, c), 0.5);      // edge bc
  EXPECT_DOUBLE_EQ(core::point_triangle_sq_distance({3, 0, 0}, a, b, c), 4.0);      // vertex b
}

TEST(Geometry, SegmentDistanceParallelSkewAndDegenerate) {
  EXPECT_DOUBLE_EQ(core::segment_segment_sq_distance({0, 0, 0}, {1, 0, 0}, {0, 1, 1}, {1, 1, 1}),
                   2.0);
  EXPECT_DOUBLE_EQ(core::segment_segment_sq_distance({0, 0, 0}, {2, 0, 0}, {1, -1, 3}, {1, 1, 3}),
                   9.0);
  EXPECT_DOUBLE_EQ(core::segment_segment_sq_distance({0, 0, 0}, {0, 0, 0}, {3, 4, 0}, {3, 4, 0}),
                   25.0);
  EXPECT_DOUBLE_EQ(core::segment_segment_sq_distance({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}),
                   1.0);
}

TEST(Geometry, TriangleBoxDistanceMatchesSampling) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2, 2);
  const core::Box3 box{Vec3(0, 0, 0), Vec3(1, 0.5, 0.75)};
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    const double d = core::triangle_box_sq_distance(a, b, c, box);
    // Sampled upper bound: points of the triangle against the box.
    double sampled = 1e300;
    for (int i = 0; i <= 60; ++i) {
      for (int j = 0; i + j <= 60; ++j) {
        const Vec3 p = a + (b - a) * (i / 60.0) + (c - a) * (j / 60.0);
        sampled = std::min(sampled, core::point_box_sq_distance(p, box));
      }
    }
    EXPECT_LE(d, sampled + 1e-12);
    EXPECT_GE(std::sqrt(d) + 0.1, std::sqrt(sampled)) << trial;  // lattice step < 0.1 m
    EXPECT_EQ(d == 0.0, core::triangle_box_overlap(a, b, c, box));
  }
}

TEST(Geometry, TriangleBoxOverlapByHand) {
  const core::Box3 box{Vec3(0, 0, 0), Vec3(1, 1, 1)};
  EXPECT_TRUE(core::triangle_box_overlap({-1, 0.5, 0.5}, {2, 0.5, 0.5}, {0.5, 3, 0.5}, box));
  EXPECT_FALSE(core::triangle_box_overlap({2, 0, 0}, {3, 0, 0}, {2, 1, 0}, box));
  // The plane x + y + z = 3.5 misses the box (max 3) though the triangle's bounds overlap it.
  EXPECT_FALSE(core::triangle_box_overlap({3.5, 0, 0}, {0, 3.5, 0}, {0, 0, 3.5}, box));
  EXPECT_TRUE(core::triangle_box_overlap({3, 0, 0}, {0, 3, 0}, {0, 0, 3}, box));  // touches corner
}

TEST(Geometry, InsideVolumeAndRayHits) {
  const auto cube = box_object("cube", {0, 0, 0}, {2, 2, 2});
  EXPECT_NEAR(core::signed_volume(cube.mesh), 8.0, 1e-12);
  EXPECT_TRUE(core::inside_mesh(cube.mesh, {1, 1, 1}));
  EXPECT_FALSE(core::inside_mesh(cube.mesh, {3, 1, 1}));
  const auto tet = tetra_object("t", {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
  EXPECT_NEAR(core::signed_volume(tet.mesh), 1.0 / 6.0, 1e-12);
  EXPECT_TRUE(core::inside_mesh(tet.mesh, {0.2, 0.2, 0.2}));
  EXPECT_FALSE(core::inside_mesh(tet.mesh, {0.4, 0.4, 0.4}));
  EXPECT_NEAR(core::ray_triangle_hit({0.2, 0.2, -1}, {0, 0, 1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}),
              1.0, 1e-15);
  EXPECT_LT(core::ray_triangle_hit({0.8, 0.8, -1}, {0, 0, 1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}),
            0.0);
  EXPECT_DOUBLE_EQ(core::point_solid_sq_distance(cube.mesh, {1, 1, 1}), 0.0);
  EXPECT_DOUBLE_EQ(core::point_solid_sq_distance(cube.mesh, {5, 1, 6}), 9.0 + 16.0);
  EXPECT_DOUBLE_EQ(core::box_solid_sq_distance(cube.mesh, {Vec3(0.5, 0.5, 0.5), Vec3(1, 1, 1)}),
                   0.0);
  EXPECT_DOUBLE_EQ(core::box_solid_sq_distance(cube.mesh, {Vec3(3, 3, 0), Vec3(4, 4, 1)}), 2.0);
}

TEST(Geometry, BoxBoxDistanceByHand) {
  const core::Box3 unit{Vec3(0, 0, 0), Vec3(1, 1, 1)};
  // Apart along one axis, along two (corner to edge), along three (corner to corner).
  EXPECT_DOUBLE_EQ(core::box_box_sq_distance(unit, {Vec3(3, 0.5, 0.5), Vec3(4, 2, 2)}), 4.0);
  EXPECT_DOUBLE_EQ(core::box_box_sq_distance({Vec3(2, 3, 0), Vec3(5, 5, 1)}, unit), 1.0 + 4.0);
  EXPECT_DOUBLE_EQ(core::box_box_sq_distance(unit, {Vec3(-3, -2, 3), Vec3(-1, -1, 4)}),
                   1.0 + 1.0 + 4.0);
  // Touching, overlapping and nested boxes: 0.
  EXPECT_EQ(core::box_box_sq_distance(unit, {Vec3(1, 0, 0), Vec3(2, 1, 1)}), 0.0);
  EXPECT_EQ(core::box_box_sq_distance(unit, {Vec3(0.5, 0.5, 0.5), Vec3(2, 2, 2)}), 0.0);
  EXPECT_EQ(core::box_box_sq_distance(unit, {Vec3(0.2, 0.2, 0.2), Vec3(0.3, 0.3, 0.3)}), 0.0);
}

}  // namespace
}  // namespace camplace::testing
