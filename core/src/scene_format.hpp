#pragma once
// The meshes the scene loader makes of "box" and "tetrahedron" objects (SPEC §2), shared with
// the scene writer, which recognises them to write such objects back in the same form, and the
// rotation convention of "rotate_deg" (objects and robot bases). Private to core.
#include <Eigen/Geometry>
#include <vector>

#include "camplace/core/geometry.hpp"

namespace camplace::core::detail {

/// The box [lo, hi] (lo < hi on every axis): corner i at x = (i & 1 ? hi : lo), y = (i & 2 ?
/// hi : lo), z = (i & 4 ? hi : lo), 12 outward triangles.
inline TriangleMesh box_mesh(const Vec3& lo, const Vec3& hi) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) {
    m.vertices.emplace_back((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(),
                            (i & 4) ? hi.z() : lo.z());
  }
  // Outward (counter-clockwise seen from outside) faces: -x, +x, -y, +y, -z, +z.
  m.triangles = {{0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}};
  return m;
}

/// The tetrahedron over 4 points in the given order, its triangles oriented as the order gives
/// (validate_and_orient turns them outward).
inline TriangleMesh tetrahedron_mesh(const std::vector<Vec3>& points) {
  TriangleMesh m;
  m.vertices = points;
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

/// The rotation of "rotate_deg": Rz · Ry · Rx, i.e. about x first, then y, then z (extrinsic,
/// world axes), angles in degrees (docs/scene-format.md).
inline Eigen::Matrix3d rotation_deg(const Vec3& deg) {
  return (Eigen::AngleAxisd(deg.z() * kDegree, Vec3::UnitZ()) *
          Eigen::AngleAxisd(deg.y() * kDegree, Vec3::UnitY()) *
          Eigen::AngleAxisd(deg.x() * kDegree, Vec3::UnitX()))
      .toRotationMatrix();
}

}  // namespace camplace::core::detail
