#include "camplace/core/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace camplace::core {

Box3 bounding_box(const TriangleMesh& mesh) {
  Box3 box;
  if (mesh.vertices.empty()) return box;
  box.min = box.max = mesh.vertices.front();
  for (const Vec3& v : mesh.vertices) {
    box.min = box.min.cwiseMin(v);
    box.max = box.max.cwiseMax(v);
  }
  return box;
}

double signed_volume(const TriangleMesh& mesh) {
  // Sum of signed tetrahedra (0, a, b, c): a·(b×c) / 6.
  double six_volume = 0.0;
  for (const auto& t : mesh.triangles) {
    six_volume += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]]));
  }
  return six_volume / 6.0;
}

bool inside_mesh(const TriangleMesh& mesh, const Vec3& p) {
  // Generalised winding number: sum of signed solid angles (Van Oosterom & Strackee).
  double total = 0.0;
  for (const auto& t : mesh.triangles) {
    const Vec3 a = mesh.vertices[t[0]] - p;
    const Vec3 b = mesh.vertices[t[1]] - p;
    const Vec3 c = mesh.vertices[t[2]] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    total += 2.0 * std::atan2(numerator, denominator);
  }
  return total / (4.0 * kPi) > 0.5;
}

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Voronoi regions (Ericson, Real-Time Collision Detection 5.1.5).
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

double point_triangle_sq_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return (p - closest_point_on_triangle(p, a, b, c)).squaredNorm();
}

std::pair<Vec3, Vec3> closest_points_of_segments(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                                 const Vec3& q1) {
  // Ericson 5.1.9, with the degenerate cases handled.
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  constexpr double kEps = 1e-300;
  double s = 0.0, t = 0.0;
  if (a <= kEps && e <= kEps) return {p0, q0};
  if (a <= kEps) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= kEps) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2);
      const double denom = a * e - b * b;
      s = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return {p0 + d1 * s, q0 + d2 * t};
}

double segment_segment_sq_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  const auto [p, q] = closest_points_of_segments(p0, p1, q0, q1);
  return (p - q).squaredNorm();
}

double point_box_sq_distance(const Vec3& p, const Box3& box) {
  const Vec3 clamped = p.cwiseMax(box.min).cwiseMin(box.max);
  return (p - clamped).squaredNorm();
}

double box_box_sq_distance(const Box3& a, const Box3& b) {
  const Vec3 gap = (a.min - b.max).cwiseMax(b.min - a.max).cwiseMax(0.0);
  return gap.squaredNorm();
}

bool triangle_box_overlap(const Vec3& a, const Vec3& b, const Vec3& c, const Box3& box) {
  // Separating-axis test (Akenine-Möller): 3 box normals, the triangle normal and the 9 cross
  // products of box axes with triangle edges. Closed sets: touching counts as overlap.
  const Vec3 center = box.center();
  const Vec3 half = 0.5 * box.size();
  const Vec3 v[3] = {a - center, b - center, c - center};
  const Vec3 edges[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  auto separated = [&](const Vec3& axis) {
    if (axis.squaredNorm() < 1e-30) return false;
    const double p0 = axis.dot(v[0]), p1 = axis.dot(v[1]), p2 = axis.dot(v[2]);
    const double radius = half.x() * std::abs(axis.x()) + half.y() * std::abs(axis.y()) +
                          half.z() * std::abs(axis.z());
    return std::min({p0, p1, p2}) > radius || std::max({p0, p1, p2}) < -radius;
  };
  for (int i = 0; i < 3; ++i) {
    if (separated(Vec3::Unit(i))) return false;
  }
  if (separated(edges[0].cross(edges[1]))) return false;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (separated(Vec3::Unit(i).cross(edges[j]))) return false;
    }
  }
  return true;
}

namespace {
std::array<Vec3, 8> box_corners(const Box3& box) { return box.corners(); }
}  // namespace

double triangle_box_sq_distance(const Vec3& a, const Vec3& b, const Vec3& c, const Box3& box) {
  if (triangle_box_overlap(a, b, c, box)) return 0.0;
  // Disjoint convex polytopes: the closest pair is vertex–feature or edge–edge.
  double best = std::min({point_box_sq_distance(a, box), point_box_sq_distance(b, box),
                          point_box_sq_distance(c, box)});
  const auto corners = box_corners(box);
  for (const Vec3& q : corners) best = std::min(best, point_triangle_sq_distance(q, a, b, c));
  static constexpr int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                        {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  const Vec3 tri[3] = {a, b, c};
  for (const auto& e : kEdges) {
    for (int i = 0; i < 3; ++i) {
      best = std::min(best, segment_segment_sq_distance(corners[e[0]], corners[e[1]], tri[i],
                                                        tri[(i + 1) % 3]));
    }
  }
  return best;
}

double ray_triangle_hit(const Vec3& origin, const Vec3& dir, const Vec3& a, const Vec3& b,
                        const Vec3& c) {
  // Möller–Trumbore.
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 pvec = dir.cross(e2);
  const double det = e1.dot(pvec);
  if (std::abs(det) < 1e-300) return -1.0;
  const double inv = 1.0 / det;
  const Vec3 tvec = origin - a;
  const double u = tvec.dot(pvec) * inv;
  if (u < 0.0 || u > 1.0) return -1.0;
  const Vec3 qvec = tvec.cross(e1);
  const double v = dir.dot(qvec) * inv;
  if (v < 0.0 || u + v > 1.0) return -1.0;
  const double t = e2.dot(qvec) * inv;
  return t > 0.0 ? t : -1.0;
}

double point_solid_sq_distance(const TriangleMesh& mesh, const Vec3& p) {
  if (inside_mesh(mesh, p)) return 0.0;
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.triangles) {
    best = std::min(best, point_triangle_sq_distance(p, mesh.vertices[t[0]], mesh.vertices[t[1]],
                                                     mesh.vertices[t[2]]));
  }
  return best;
}

double box_solid_sq_distance(const TriangleMesh& mesh, const Box3& box) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.triangles) {
    const double d = triangle_box_sq_distance(mesh.vertices[t[0]], mesh.vertices[t[1]],
                                              mesh.vertices[t[2]], box);
    if (d == 0.0) return 0.0;
    best = std::min(best, d);
  }
  // No triangle meets the box: the box is wholly inside or wholly outside the solid.
  if (inside_mesh(mesh, box.center())) return 0.0;
  return best;
}

}  // namespace camplace::core
