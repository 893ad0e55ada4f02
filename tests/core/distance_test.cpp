// The exact true distance d(C, O_u) against hand-computed values.
#include "camplace/core/distance.hpp"

#include <gtest/gtest.h>

#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using core::Vec3;

TEST(TrueDistance, SeparatedBoxesGiveExactFraction) {
  const auto a = box_object("a", {0, 0, 0}, {1, 1, 1});
  const auto b = box_object("b", {1.5, 2, 0}, {2, 3, 1});  // gap 0.5 in x, 1 in y
  const auto d = core::solids_squared_distance({&a.mesh}, {&b.mesh});
  EXPECT_EQ(d.fraction, "5/4");
  EXPECT_DOUBLE_EQ(d.value, 1.25);
}

TEST(TrueDistance, TouchingNestedAndOverlappingAreZero) {
  const auto a = box_object("a", {0, 0, 0}, {1, 1, 1});
  const auto touching = box_object("t", {1, 0, 0}, {2, 1, 1});
  const auto nested = box_object("n", {0.25, 0.25, 0.25}, {0.5, 0.5, 0.5});
  EXPECT_EQ(core::solids_squared_distance({&a.mesh}, {&touching.mesh}).value, 0.0);
  EXPECT_EQ(core::solids_squared_distance({&a.mesh}, {&nested.mesh}).value, 0.0);
  EXPECT_EQ(core::solids_squared_distance({&nested.mesh}, {&a.mesh}).fraction, "0/1");
}

TEST(TrueDistance, TetrahedronApexAboveBoxFace) {
  const auto box = box_object("box", {0, 0, 0}, {1, 1, 1});
  const auto tet = tetra_object("t", {0.5, 0.5, 1.1}, {0.2, 0.2, 2}, {0.8, 0.2, 2}, {0.5, 0.9, 2});
  const auto d = core::solids_squared_distance({&box.mesh}, {&tet.mesh});
  EXPECT_NEAR(d.value, 0.01, 1e-15);  // apex 0.1 above the top face
  // The union's distance is its nearest member's.
  const auto far = box_object("far", {3, 3, 3}, {3.5, 3.5, 3.5});
  EXPECT_NEAR(core::solids_squared_distance({&far.mesh, &box.mesh}, {&tet.mesh}).value, 0.01,
              1e-15);
}

}  // namespace
}  // namespace camplace::testing

// ---- The branch and bound against measuring every triangle pair exactly ---------------------

#include <CGAL/squared_distance_3.h>

#include <Eigen/Geometry>
#include <random>

#include "camplace/core/internal/exact_kernel.hpp"

namespace camplace::testing {
namespace {

/// Every triangle pair measured exactly, no skipping (what solids_squared_distance computed
/// before its filter); containment is not needed for disjoint solids, which the test uses.
std::string brute_force_fraction(const std::vector<const core::TriangleMesh*>& a,
                                 const std::vector<const core::TriangleMesh*>& b) {
  using K = core::internal::Kernel;
  auto tri = [](const core::TriangleMesh& m, const std::array<int, 3>& t) {
    return K::Triangle_3(core::internal::to_point(m.vertices[t[0]]),
                         core::internal::to_point(m.vertices[t[1]]),
                         core::internal::to_point(m.vertices[t[2]]));
  };
  K::FT best = -1;
  for (const auto* ma : a)
    for (const auto* mb : b)
      for (const auto& x : ma->triangles)
        for (const auto& y : mb->triangles) {
          const K::FT d = CGAL::squared_distance(tri(*ma, x), tri(*mb, y));
          if (best < 0 || d < best) best = d;
        }
  return core::internal::fraction_string(best);
}

/// A box of random size, rotated at random and placed at `at`, its 12 triangles each split
/// into 4 (so that many triangle pairs lie close to the nearest pair).
core::TriangleMesh random_solid(std::mt19937& rng, const Vec3& at, bool axis_aligned) {
  std::uniform_real_distribution<double> size(0.1, 0.8), angle(-3.14, 3.14);
  const Vec3 half(size(rng) / 2, size(rng) / 2, size(rng) / 2);
  core::TriangleMesh m = box_object("x", -half, half).mesh;
  const Eigen::Matrix3d r = axis_aligned ? Eigen::Matrix3d::Identity()
                                         : (Eigen::AngleAxisd(angle(rng), Vec3::UnitZ()) *
                                            Eigen::AngleAxisd(angle(rng), Vec3::UnitY()) *
                                            Eigen::AngleAxisd(angle(rng), Vec3::UnitX()))
                                               .toRotationMatrix();
  for (Vec3& v : m.vertices) v = r * v + at;
  core::TriangleMesh split;
  split.vertices = m.vertices;
  for (const auto& t : m.triangles) {
    const int c = static_cast<int>(split.vertices.size());
    split.vertices.push_back((m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3);
    split.triangles.push_back({t[0], t[1], c});
    split.triangles.push_back({t[1], t[2], c});
    split.triangles.push_back({t[2], t[0], c});
  }
  return split;
}

TEST(TrueDistance, BranchAndBoundGivesTheExactMinimumOfEveryPair) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> pos(0.0, 3.0);
  int compared = 0;
  for (int trial = 0; trial < 15; ++trial) {
    const bool aligned = trial % 3 == 0;  // parallel faces: many pairs tie at the minimum
    std::vector<core::TriangleMesh> ma, mb;
    for (int k = 0; k < 3; ++k)
      ma.push_back(random_solid(rng, Vec3(pos(rng), pos(rng), 0), aligned));
    for (int k = 0; k < 2; ++k)
      mb.push_back(random_solid(rng, Vec3(pos(rng), pos(rng), 2.0 + pos(rng)), aligned));
    std::vector<const core::TriangleMesh*> a, b;
    for (const auto& m : ma) a.push_back(&m);
    for (const auto& m : mb) b.push_back(&m);
    // Disjoint by construction (z ranges ≤ 0.57 and ≥ 1.43): the minimum is a triangle pair's.
    const auto d = core::solids_squared_distance(a, b);
    EXPECT_EQ(d.fraction, brute_force_fraction(a, b)) << "trial " << trial;
    ++compared;
  }
  EXPECT_EQ(compared, 15);
}

}  // namespace
}  // namespace camplace::testing
