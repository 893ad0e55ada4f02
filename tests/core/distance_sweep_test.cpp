// The filtered search of core::solids_squared_distance (bounding-volume hierarchy and a
// certified double-precision filter) against measuring every triangle pair exactly with CGAL's
// exact kernel: random solids, and fine meshes at tiny gaps, near contact and with many tied
// pairs. The hand cases are in distance_test.cpp. These sweeps take seconds in a Release build
// and minutes under ASan: they are in reference_sweep_tests (label slow).
#include <CGAL/squared_distance_3.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "camplace/core/distance.hpp"
#include "camplace/core/internal/exact_kernel.hpp"
#include "scene_builder.hpp"

// ---- The filtered search against measuring every triangle pair exactly ----------------------

namespace camplace::testing {
namespace {

using core::Vec3;

/// The smallest exact squared distance over all triangle pairs of the two sets (CGAL's exact
/// kernel, no skipping): the distance of the solids when neither holds the other.
core::internal::FT all_pairs_minimum(const std::vector<const core::TriangleMesh*>& a,
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
      for (const auto& x : ma->triangles) {
        const K::Triangle_3 tx = tri(*ma, x);
        for (const auto& y : mb->triangles) {
          const K::FT d = CGAL::squared_distance(tx, tri(*mb, y));
          if (best < 0 || d < best) best = d;
        }
      }
  return best;
}

/// Every triangle pair measured exactly, no skipping (what solids_squared_distance computed
/// before its filter), as a fraction; containment is not needed for disjoint solids, which the
/// test uses.
std::string brute_force_fraction(const std::vector<const core::TriangleMesh*>& a,
                                 const std::vector<const core::TriangleMesh*>& b) {
  return core::internal::fraction_string(all_pairs_minimum(a, b));
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

// ---- The filtered search on fine meshes against every triangle pair measured exactly --------

#include "camplace/core/geometry.hpp"
#include "fine_meshes.hpp"

namespace camplace::testing {
namespace {

using core::TriangleMesh;

/// solids_squared_distance(a, b) equals the all-pairs minimum, fraction and value (the value:
/// the exact number rounded to double by the same rule, CGAL's to_double of the exact number).
void expect_all_pairs_minimum(const std::vector<const TriangleMesh*>& a,
                              const std::vector<const TriangleMesh*>& b, const std::string& what) {
  const core::ExactSquaredDistance d = core::solids_squared_distance(a, b);
  const core::internal::FT brute = all_pairs_minimum(a, b);
  EXPECT_EQ(d.fraction, core::internal::fraction_string(brute)) << what;
  CGAL::exact(brute);
  EXPECT_EQ(d.value, CGAL::to_double(brute)) << what;
  // And the other way round (a symmetric distance).
  EXPECT_EQ(core::solids_squared_distance(b, a).fraction, d.fraction) << what;
}

Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> g;
  return Vec3(g(rng), g(rng), g(rng)).normalized();
}

TEST(TrueDistanceFineMeshes, RandomTetrahedraAtAllGaps) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double gaps[] = {0.5, 1e-3, 1e-7, 1e-13, 0.0};
  for (int trial = 0; trial < 40; ++trial) {
    // a in the slab z ∈ [0, 1], b in z ∈ [1 + gap, 2 + gap]: disjoint interiors.
    const double gap = gaps[trial % 5];
    auto point = [&](double z0) { return Vec3(unit(rng), unit(rng), z0 + unit(rng)); };
    std::vector<TriangleMesh> ma, mb;
    for (int k = 0; k < 1 + trial % 3; ++k)
      ma.push_back(
          tetra_object("a", point(0), point(0), point(0), Vec3(unit(rng), unit(rng), 1.0)).mesh);
    for (int k = 0; k < 1 + trial % 2; ++k)
      mb.push_back(tetra_object("b", point(1 + gap), point(1 + gap), point(1 + gap),
                                Vec3(unit(rng), unit(rng), 1 + gap))
                       .mesh);
    std::vector<const TriangleMesh*> a, b;
    for (const auto& m : ma) a.push_back(&m);
    for (const auto& m : mb) b.push_back(&m);
    expect_all_pairs_minimum(a, b, "tetrahedra, trial " + std::to_string(trial));
  }
}

TEST(TrueDistanceFineMeshes, EllipsoidsNearTouchingAndFarApart) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> radius(0.2, 0.6);
  // Near-touching down to gaps far below the triangles' size, and far apart (the all-pairs
  // oracle costs ~80 µs a pair: sizes stay small).
  const double gaps[] = {1e-3, 1e-9, 1e-14, 30.0};
  for (int trial = 0; trial < 4; ++trial) {
    const double gap = gaps[trial];
    const Vec3 ra(radius(rng), radius(rng), radius(rng)), rb(radius(rng), radius(rng), radius(rng));
    const TriangleMesh a = ellipsoid(Vec3(0.1, -0.2, 0.3), ra, 8 + trial, 5,
                                     random_rotation(rng));  // 64–88 triangles
    // b along a random direction, at about the gap from a's circumscribed sphere.
    const Vec3 dir = random_unit(rng);
    const double reach = ra.maxCoeff() + rb.maxCoeff() + gap;
    const TriangleMesh b = ellipsoid(Vec3(0.1, -0.2, 0.3) + reach * dir, rb, 14, 7 - trial % 2,
                                     random_rotation(rng));  // 140–168 triangles
    expect_all_pairs_minimum({&a}, {&b}, "ellipsoids, trial " + std::to_string(trial));
  }
}

TEST(TrueDistanceFineMeshes, CoplanarFacesAtTinyGaps) {
  // Fine boxes whose faces lie in parallel planes: every facing pair of triangles ties at the
  // gap (adversarial: a search by bounds alone must measure them all), down to touching.
  const double gaps[] = {1e-3, 1e-7, 1e-12, 0.0};
  for (double gap : gaps) {
    const TriangleMesh a = subdivided_box(Vec3(0, 0, 0), Vec3(1, 1, 1), 3);  // 108 triangles
    const TriangleMesh b =
        subdivided_box(Vec3(0.3, 0.2, 1 + gap), Vec3(1.4, 0.9, 1.5), 2);  // 48 triangles
    expect_all_pairs_minimum({&a}, {&b}, "coplanar, gap " + std::to_string(gap));
  }
  // Tilted by 1e-9 rad about an axis in the facing planes: every facing pair within 1e-9
  // relatively of the minimum.
  const TriangleMesh a = subdivided_box(Vec3(0, 0, 0), Vec3(1, 1, 1), 4);
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(1e-9, Vec3::UnitX()).toRotationMatrix();
  const TriangleMesh b =
      moved(subdivided_box(Vec3(0, 0, 0), Vec3(1, 1, 0.5), 3), tilt, Vec3(0.05, 0.02, 1 + 1e-6));
  expect_all_pairs_minimum({&a}, {&b}, "tilted");
}

TEST(TrueDistanceFineMeshes, ManyPairsTieAtAVertex) {
  // An ellipsoid's pole (shared by 2·slices triangles) right above a fine box face at a grid
  // vertex (shared by 6 triangles): every one of those pairs ties at the minimum.
  const TriangleMesh box = subdivided_box(Vec3(-1, -1, -1), Vec3(1, 1, 0), 4);  // 192 triangles
  const TriangleMesh egg = ellipsoid(Vec3(0, 0, 0.5 + 1e-8), Vec3(0.4, 0.4, 0.5), 16, 5);
  expect_all_pairs_minimum({&box}, {&egg}, "pole");
  // And a sphere sitting on a sphere (many pairs nearly tied around the contact).
  const TriangleMesh s1 = ellipsoid(Vec3(0, 0, 0), Vec3(0.5, 0.5, 0.5), 12, 7);
  const TriangleMesh s2 = ellipsoid(Vec3(0, 0, 1 + 1e-10), Vec3(0.5, 0.5, 0.5), 12, 7);
  expect_all_pairs_minimum({&s1}, {&s2}, "spheres");
}

TEST(TrueDistanceFineMeshes, LargeMeshAgainstSmallOnes) {
  std::mt19937 rng(3);
  // 2028 triangles against a tetrahedron and a small ellipsoid beside three faces.
  const TriangleMesh box = subdivided_box(Vec3(0, 0, 0), Vec3(1, 1.2, 0.8), 13);
  const TriangleMesh tet = tetra_object("t", Vec3(1.0 + 1e-6, 0.5, 0.4), Vec3(1.3, 0.2, 0.1),
                                        Vec3(1.4, 0.9, 0.5), Vec3(1.2, 0.5, 0.9))
                               .mesh;
  const TriangleMesh egg =
      ellipsoid(Vec3(0.5, 0.6, 1.1), Vec3(0.2, 0.3, 0.25), 6, 3, random_rotation(rng));
  expect_all_pairs_minimum({&box}, {&tet, &egg}, "box vs tetrahedron and ellipsoid");
  expect_all_pairs_minimum({&box, &egg}, {&tet}, "union vs tetrahedron");
}

TEST(TrueDistanceFineMeshes, TouchingAndNestedAreZero) {
  // Values by hand: touching along a face and one solid wholly inside the other give 0.
  const TriangleMesh box = subdivided_box(Vec3(0, 0, 0), Vec3(1, 1, 1), 10);
  const TriangleMesh beside = subdivided_box(Vec3(1, 0.2, 0.3), Vec3(1.5, 0.7, 0.6), 4);
  const TriangleMesh inner = ellipsoid(Vec3(0.5, 0.5, 0.5), Vec3(0.3, 0.2, 0.25), 30, 15);
  const TriangleMesh outer = ellipsoid(Vec3(0.5, 0.5, 0.5), Vec3(2, 2, 2), 30, 15);
  for (const auto& [x, y] : {std::pair{&box, &beside}, std::pair{&box, &inner},
                             std::pair{&inner, &box}, std::pair{&outer, &box}}) {
    const auto d = core::solids_squared_distance({x}, {y});
    EXPECT_EQ(d.fraction, "0/1");
    EXPECT_EQ(d.value, 0.0);
  }
  // Crossing surfaces (a sphere about a box face's centre): 0 as well.
  const TriangleMesh crossing = ellipsoid(Vec3(1, 0.5, 0.5), Vec3(0.3, 0.3, 0.3), 20, 10);
  EXPECT_EQ(core::solids_squared_distance({&box}, {&crossing}).fraction, "0/1");
  EXPECT_EQ(core::solids_squared_distance({&crossing}, {&box}).value, 0.0);
}

}  // namespace
}  // namespace camplace::testing
