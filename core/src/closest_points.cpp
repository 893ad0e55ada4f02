// Closest point pairs for drawing distances (SPEC §4): the same case analysis as geometry.cpp's
// distance routines, keeping the points.
#include "camplace/core/closest_points.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "camplace/core/error.hpp"

namespace camplace::core {

namespace {

/// Keeps the nearer of the pairs offered.
struct Nearest {
  ClosestPoints best{Vec3::Zero(), Vec3::Zero(), std::numeric_limits<double>::infinity()};
  void offer(const Vec3& a, const Vec3& b) {
    const double d = (a - b).squaredNorm();
    if (d < best.sq_distance) best = {a, b, d};
  }
};

/// The point where the closed segment [p0, p1] crosses triangle (a, b, c), if it does and is
/// not parallel to it (Möller–Trumbore; parallel contacts show up as edge–edge or
/// vertex–triangle pairs).
bool segment_crosses_triangle(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b,
                              const Vec3& c, Vec3* at) {
  const Vec3 dir = p1 - p0;
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 pvec = dir.cross(e2);
  const double det = e1.dot(pvec);
  if (std::abs(det) <= 1e-12 * dir.norm() * e1.norm() * e2.norm()) return false;
  const double inv = 1.0 / det;
  const Vec3 tvec = p0 - a;
  const double u = tvec.dot(pvec) * inv;
  if (u < 0.0 || u > 1.0) return false;
  const Vec3 qvec = tvec.cross(e1);
  const double v = dir.dot(qvec) * inv;
  if (v < 0.0 || u + v > 1.0) return false;
  const double t = e2.dot(qvec) * inv;
  if (t < 0.0 || t > 1.0) return false;
  *at = p0 + t * dir;
  return true;
}

Box3 triangle_bounds(const Vec3& a, const Vec3& b, const Vec3& c) {
  return {a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c)};
}

}  // namespace

ClosestPoints closest_points_of_triangles(const Vec3& a0, const Vec3& a1, const Vec3& a2,
                                          const Vec3& b0, const Vec3& b1, const Vec3& b2) {
  const std::array<Vec3, 3> a{a0, a1, a2}, b{b0, b1, b2};
  // Crossing triangles: an edge of one passes through the other (coplanar overlaps show up
  // below as a vertex–triangle or edge–edge pair at distance 0).
  Vec3 at;
  for (int i = 0; i < 3; ++i) {
    if (segment_crosses_triangle(a[i], a[(i + 1) % 3], b0, b1, b2, &at)) return {at, at, 0.0};
    if (segment_crosses_triangle(b[i], b[(i + 1) % 3], a0, a1, a2, &at)) return {at, at, 0.0};
  }
  // Disjoint: the closest pair is vertex–triangle or edge–edge.
  Nearest nearest;
  for (int i = 0; i < 3; ++i) {
    nearest.offer(a[i], closest_point_on_triangle(a[i], b0, b1, b2));
    nearest.offer(closest_point_on_triangle(b[i], a0, a1, a2), b[i]);
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const auto [p, q] = closest_points_of_segments(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]);
      nearest.offer(p, q);
    }
  }
  return nearest.best;
}

ClosestPoints closest_points(const std::vector<const TriangleMesh*>& a,
                             const std::vector<const TriangleMesh*>& b) {
  CAMPLACE_ASSERT(!a.empty() && !b.empty());
  Nearest nearest;
  for (const TriangleMesh* ma : a) {
    for (const TriangleMesh* mb : b) {
      CAMPLACE_ASSERT(!ma->triangles.empty() && !mb->triangles.empty());
      std::vector<Box3> b_bounds;
      for (const auto& t : mb->triangles) {
        b_bounds.push_back(
            triangle_bounds(mb->vertices[t[0]], mb->vertices[t[1]], mb->vertices[t[2]]));
      }
      for (const auto& ta : ma->triangles) {
        const Vec3 &p0 = ma->vertices[ta[0]], &p1 = ma->vertices[ta[1]], &p2 = ma->vertices[ta[2]];
        const Box3 a_bounds = triangle_bounds(p0, p1, p2);
        for (std::size_t j = 0; j < mb->triangles.size(); ++j) {
          // The gap between bounding boxes bounds the pair's distance from below.
          if (box_box_sq_distance(a_bounds, b_bounds[j]) > nearest.best.sq_distance) continue;
          const auto& tb = mb->triangles[j];
          const ClosestPoints pair = closest_points_of_triangles(
              p0, p1, p2, mb->vertices[tb[0]], mb->vertices[tb[1]], mb->vertices[tb[2]]);
          nearest.offer(pair.a, pair.b);
          if (nearest.best.sq_distance == 0.0) return nearest.best;
        }
      }
    }
  }
  // Surfaces apart: one solid may still hold another whole (then any of its vertices is a
  // common point).
  for (const TriangleMesh* ma : a) {
    for (const TriangleMesh* mb : b) {
      const Vec3& va = ma->vertices[ma->triangles.front()[0]];
      const Vec3& vb = mb->vertices[mb->triangles.front()[0]];
      if (inside_mesh(*mb, va)) return {va, va, 0.0};
      if (inside_mesh(*ma, vb)) return {vb, vb, 0.0};
    }
  }
  return nearest.best;
}

ClosestPoints closest_points(const std::vector<const TriangleMesh*>& a, const Box3& b) {
  const TriangleMesh box = box_mesh(b);
  return closest_points(a, std::vector<const TriangleMesh*>{&box});
}

ClosestPoints closest_points(const std::vector<const TriangleMesh*>& a, const Vec3& b) {
  CAMPLACE_ASSERT(!a.empty());
  Nearest nearest;
  for (const TriangleMesh* mesh : a) {
    if (inside_mesh(*mesh, b)) return {b, b, 0.0};
    for (const auto& t : mesh->triangles) {
      nearest.offer(closest_point_on_triangle(b, mesh->vertices[t[0]], mesh->vertices[t[1]],
                                              mesh->vertices[t[2]]),
                    b);
    }
  }
  return nearest.best;
}

TriangleMesh box_mesh(const Box3& box) {
  TriangleMesh mesh;
  const auto corners = box.corners();
  mesh.vertices.assign(corners.begin(), corners.end());
  // Two triangles per face: the face of axis `axis` at its min (side 0) or max (side 1) holds
  // the corners whose bit `axis` equals `side`.
  const Vec3 center = box.center();
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const int u = 1 << ((axis + 1) % 3), v = 1 << ((axis + 2) % 3);
      const int base = side << axis;
      const int quad[4] = {base, base | u, base | u | v, base | v};
      for (const auto& tri : {std::array<int, 3>{quad[0], quad[1], quad[2]},
                              std::array<int, 3>{quad[0], quad[2], quad[3]}}) {
        const Vec3 n = (corners[tri[1]] - corners[tri[0]]).cross(corners[tri[2]] - corners[tri[0]]);
        const Vec3 outward = corners[tri[0]] - center;
        if (n.dot(outward) >= 0) {
          mesh.triangles.push_back(tri);
        } else {
          mesh.triangles.push_back({tri[0], tri[2], tri[1]});
        }
      }
    }
  }
  return mesh;
}

}  // namespace camplace::core
