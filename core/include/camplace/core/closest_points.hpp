#pragma once
/// Closest point pairs between solids, boxes and points in double precision, for drawing the
/// distances of SPEC §4 (the distances themselves come from distance.hpp and the pipelines).
#include <vector>

#include "camplace/core/geometry.hpp"

namespace camplace::core {

/// A closest pair: `a` on the first set, `b` on the second (m, world frame), and
/// sq_distance = |a − b|² (m²). a == b when the sets meet.
struct ClosestPoints {
  Vec3 a = Vec3::Zero();
  Vec3 b = Vec3::Zero();
  double sq_distance = 0.0;
};

/// Closest points of two triangles (vertices a0..a2 and b0..b2); a common point when they meet.
ClosestPoints closest_points_of_triangles(const Vec3& a0, const Vec3& a1, const Vec3& a2,
                                          const Vec3& b0, const Vec3& b1, const Vec3& b2);

/// Closest points between two unions of closed solids (closed, outward triangle meshes; a solid
/// inside another meets it, at one of its vertices). Both sets non-empty, no mesh empty.
ClosestPoints closest_points(const std::vector<const TriangleMesh*>& a,
                             const std::vector<const TriangleMesh*>& b);
/// Closest points between a union of closed solids and the closed box `b`.
ClosestPoints closest_points(const std::vector<const TriangleMesh*>& a, const Box3& b);
/// Closest points between a union of closed solids and the point `b`.
ClosestPoints closest_points(const std::vector<const TriangleMesh*>& a, const Vec3& b);

/// The closed box as a closed, outward triangle mesh (8 vertices in Box3::corners() order, 12
/// triangles).
TriangleMesh box_mesh(const Box3& box);

}  // namespace camplace::core
