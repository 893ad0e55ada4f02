// The voxel pipeline's culled point/box–solid distances (voxel/src/solid_distance.cpp, through a
// bounding-volume hierarchy over the triangles) against core's plain scans of every triangle
// (core::point_solid_sq_distance, core::box_solid_sq_distance): the same doubles, bit for bit,
// on random fine solids and random points and boxes near, on, inside and far from them. Its
// inside test (crossings of a ray through the hierarchy) against core::inside_mesh's sum of
// solid angles, and its box tests against scans of every triangle.
#include "../../voxel/src/solid_distance.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "../core/fine_meshes.hpp"
#include "camplace/core/geometry.hpp"

namespace camplace::testing {
namespace {

using core::Box3;
using core::TriangleMesh;
using core::Vec3;

/// Two to three solids: fine ellipsoids and fine boxes, turned at random, in [−1, 1]³.
std::vector<TriangleMesh> random_solids(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<TriangleMesh> out;
  const int count = 2 + static_cast<int>(unit(rng) * 2);
  for (int k = 0; k < count; ++k) {
    const Vec3 at(2 * unit(rng) - 1, 2 * unit(rng) - 1, 2 * unit(rng) - 1);
    const Vec3 size(0.1 + 0.5 * unit(rng), 0.1 + 0.5 * unit(rng), 0.1 + 0.5 * unit(rng));
    if (k % 2 == 0) {
      out.push_back(ellipsoid(at, size, 12 + k * 7, 7 + k * 3, random_rotation(rng)));
    } else {
      out.push_back(moved(subdivided_box(-size, size, 3 + k), random_rotation(rng), at));
    }
  }
  return out;
}

/// A random point: uniform in [−1.5, 1.5]³, or a vertex of a solid moved by up to 1e-9 or
/// 1e-3 (near and on the surface).
Vec3 random_point(std::mt19937& rng, const std::vector<TriangleMesh>& solids) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double kind = unit(rng);
  if (kind < 0.5) return Vec3(3 * unit(rng) - 1.5, 3 * unit(rng) - 1.5, 3 * unit(rng) - 1.5);
  const TriangleMesh& m = solids[static_cast<std::size_t>(unit(rng) * solids.size())];
  const Vec3& v = m.vertices[static_cast<std::size_t>(unit(rng) * m.vertices.size())];
  const double scale = kind < 0.65 ? 0.0 : kind < 0.8 ? 1e-9 : 1e-3;
  return v + scale * Vec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5);
}

TEST(SolidDistanceHierarchy, PointDistancesEqualThePlainScan) {
  std::mt19937 rng(21);
  int compared = 0;
  for (int trial = 0; trial < 6; ++trial) {
    const std::vector<TriangleMesh> meshes = random_solids(rng);
    std::vector<voxel::detail::IndexedSolid> solids;
    for (const TriangleMesh& m : meshes) solids.push_back(voxel::detail::index_solid(m));
    for (int q = 0; q < 300; ++q) {
      const Vec3 p = random_point(rng, meshes);
      double scan = std::numeric_limits<double>::infinity();
      for (const TriangleMesh& m : meshes)
        scan = std::min(scan, core::point_solid_sq_distance(m, p));
      // With the cutoff the set-up gives (the nearest vertex) and with none.
      EXPECT_EQ(voxel::detail::point_solids_sq_distance(
                    solids, p, voxel::detail::vertex_upper_bound(solids, p)),
                scan)
          << "trial " << trial << " point " << q;
      EXPECT_EQ(voxel::detail::point_solids_sq_distance(solids, p,
                                                        std::numeric_limits<double>::infinity()),
                scan)
          << "trial " << trial << " point " << q;
      // With a random triangle as the hint (its distance is the cutoff): the same minimum, and
      // the triangle returned holds it.
      voxel::detail::NearestTriangle hint;
      hint.solid = static_cast<int>(rng() % solids.size());
      hint.triangle = static_cast<int>(rng() % solids[std::size_t(hint.solid)].triangles.size());
      const double surface = voxel::detail::point_solids_sq_distance(
          solids, p, std::numeric_limits<double>::infinity(), false, &hint);
      double surface_scan = std::numeric_limits<double>::infinity();
      for (const auto& s : solids)
        for (const auto& t : s.triangles)
          surface_scan =
              std::min(surface_scan, core::point_triangle_sq_distance(p, t[0], t[1], t[2]));
      EXPECT_EQ(surface, surface_scan) << "trial " << trial << " point " << q;
      const auto& held = solids[std::size_t(hint.solid)].triangles[std::size_t(hint.triangle)];
      EXPECT_EQ(core::point_triangle_sq_distance(p, held[0], held[1], held[2]), surface)
          << "trial " << trial << " point " << q;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 1800);
}

TEST(SolidDistanceHierarchy, BoxDistancesEqualThePlainScan) {
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int zero = 0, positive = 0;
  for (int trial = 0; trial < 6; ++trial) {
    const std::vector<TriangleMesh> meshes = random_solids(rng);
    std::vector<voxel::detail::IndexedSolid> solids;
    for (const TriangleMesh& m : meshes) solids.push_back(voxel::detail::index_solid(m));
    for (int q = 0; q < 150; ++q) {
      const Vec3 c = random_point(rng, meshes);
      const double half = q % 3 == 0 ? 1e-6 : 0.01 + 0.1 * unit(rng);
      const Box3 box{c - Vec3::Constant(half), c + Vec3::Constant(half * (0.5 + unit(rng)))};
      double scan = std::numeric_limits<double>::infinity();
      for (const TriangleMesh& m : meshes)
        scan = std::min(scan, core::box_solid_sq_distance(m, box));
      EXPECT_EQ(voxel::detail::box_solids_sq_distance(
                    solids, box, voxel::detail::vertex_upper_bound(solids, box)),
                scan)
          << "trial " << trial << " box " << q;
      EXPECT_EQ(voxel::detail::box_solids_sq_distance(solids, box,
                                                      std::numeric_limits<double>::infinity()),
                scan)
          << "trial " << trial << " box " << q;
      // With cutoff 0 (the reached voxels' test): 0 exactly when the scan gives 0.
      EXPECT_EQ(voxel::detail::box_solids_sq_distance(solids, box, 0.0) == 0.0, scan == 0.0)
          << "trial " << trial << " box " << q;
      ++(scan == 0.0 ? zero : positive);
    }
  }
  // Both outcomes occur (boxes on the surfaces and away from them).
  EXPECT_GT(zero, 50);
  EXPECT_GT(positive, 300);
}

/// A closed non-convex solid: an ellipsoid whose vertices are moved along the rays from its
/// centre by random factors in [0.5, 1.5] (still embedded: each ray from the centre meets the
/// surface once), turned at random.
TriangleMesh bumpy_solid(std::mt19937& rng, const Vec3& at, double radius) {
  std::uniform_real_distribution<double> factor(0.5, 1.5);
  TriangleMesh m =
      ellipsoid(Vec3::Zero(), Vec3::Constant(radius), 24, 12, Eigen::Matrix3d::Identity());
  for (Vec3& v : m.vertices) v *= factor(rng);
  return moved(std::move(m), random_rotation(rng), at);
}

TEST(SolidInsideTest, CrossingsGiveTheSolidAngleSumsAnswer) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int inside = 0, outside = 0;
  for (int trial = 0; trial < 8; ++trial) {
    std::vector<TriangleMesh> meshes = random_solids(rng);
    meshes.push_back(bumpy_solid(rng, Vec3(unit(rng) - 0.5, unit(rng) - 0.5, 0.0), 0.6));
    for (const TriangleMesh& m : meshes) {
      const voxel::detail::IndexedSolid s = voxel::detail::index_solid(m);
      ASSERT_TRUE(s.closed);
      for (int q = 0; q < 400; ++q) {
        Vec3 p = random_point(rng, meshes);
        // Every fourth point on the vertical line through a vertex of this solid: its ray runs
        // through that vertex (or near it).
        if (q % 4 == 1) {
          const Vec3& v = m.vertices[static_cast<std::size_t>(unit(rng) * m.vertices.size())];
          p.x() = v.x();
          p.y() = v.y();
        }
        const bool expected = core::inside_mesh(m, p);
        EXPECT_EQ(voxel::detail::inside_solid(s, p), expected)
            << "trial " << trial << " point " << q << ": " << p.transpose();
        ++(expected ? inside : outside);
      }
    }
  }
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 3000);
}

TEST(SolidInsideTest, AnOpenMeshIsNotClosedAndKeepsTheSolidAngleSum) {
  std::mt19937 rng(24);
  TriangleMesh m = bumpy_solid(rng, Vec3::Zero(), 0.5);
  m.triangles.pop_back();  // a hole: the winding number is no longer an integer
  const voxel::detail::IndexedSolid s = voxel::detail::index_solid(m);
  EXPECT_FALSE(s.closed);
  std::uniform_real_distribution<double> unit(-0.8, 0.8);
  for (int q = 0; q < 300; ++q) {
    const Vec3 p(unit(rng), unit(rng), unit(rng));
    EXPECT_EQ(voxel::detail::inside_solid(s, p), core::inside_mesh(m, p)) << p.transpose();
  }
}

TEST(SolidInsideTest, BoxTestsEqualScansOfEveryTriangle) {
  std::mt19937 rng(25);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int wholly_inside = 0, meets = 0, neither = 0;
  for (int trial = 0; trial < 6; ++trial) {
    std::vector<TriangleMesh> meshes = random_solids(rng);
    meshes.push_back(bumpy_solid(rng, Vec3::Zero(), 0.7));
    for (const TriangleMesh& m : meshes) {
      const voxel::detail::IndexedSolid s = voxel::detail::index_solid(m);
      auto meets_scan = [&](const Box3& box) {
        for (const auto& t : m.triangles)
          if (core::triangle_box_overlap(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]], box))
            return true;
        return false;
      };
      for (int q = 0; q < 150; ++q) {
        const Vec3 c = random_point(rng, meshes);
        const double half = q % 3 == 0 ? 1e-6 : 0.005 + 0.05 * unit(rng);
        const Box3 box{c - Vec3::Constant(half), c + Vec3::Constant(half)};
        const bool meets_expected = meets_scan(box);
        EXPECT_EQ(voxel::detail::box_meets_surface(s, box), meets_expected)
            << "trial " << trial << " box " << q;
        const double depth = 1e-9;
        const Box3 interior{box.min + Vec3::Constant(depth), box.max - Vec3::Constant(depth)};
        const bool centre_inside =
            s.bounds.contains(box.center()) && core::inside_mesh(m, box.center());
        EXPECT_EQ(voxel::detail::box_inside_solid(s, box, depth, false), centre_inside)
            << "trial " << trial << " box " << q;
        const bool inside_expected = centre_inside && !meets_scan(interior);
        EXPECT_EQ(voxel::detail::box_inside_solid(s, box, depth), inside_expected)
            << "trial " << trial << " box " << q;
        ++(inside_expected ? wholly_inside : meets_expected ? meets : neither);
      }
    }
  }
  EXPECT_GT(wholly_inside, 100);
  EXPECT_GT(meets, 300);
  EXPECT_GT(neither, 300);
}

}  // namespace
}  // namespace camplace::testing
