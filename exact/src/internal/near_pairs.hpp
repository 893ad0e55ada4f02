#pragma once
// Closest points of two triangles in double precision, and certified lower bounds of the
// distance between exact triangles known through double enclosures: the floating-point filter
// of the exact distance d(C, M) (model.hpp, filtered_squared_distance). No CGAL type here.
#include <algorithm>
#include <array>
#include <cmath>

#include "camplace/core/geometry.hpp"

namespace camplace::exact::internal {

/// A triangle of double vertices (m) standing for an exact one: every exact coordinate lies
/// within `error` (m) of the corresponding double one.
struct ApproxTriangle {
  std::array<core::Vec3, 3> v;
  double error = 0.0;
};

/// The point of segment [p, q] closest to x.
inline core::Vec3 closest_on_segment(const core::Vec3& x, const core::Vec3& p,
                                     const core::Vec3& q) {
  const core::Vec3 d = q - p;
  const double dd = d.squaredNorm();
  if (dd <= 0.0) return p;
  return p + std::clamp((x - p).dot(d) / dd, 0.0, 1.0) * d;
}

/// The point of triangle abc closest to x (Ericson, Real-Time Collision Detection, 5.1.5).
inline core::Vec3 closest_on_triangle(const core::Vec3& x, const core::Vec3& a, const core::Vec3& b,
                                      const core::Vec3& c) {
  const core::Vec3 ab = b - a, ac = c - a, ax = x - a;
  const double d1 = ab.dot(ax), d2 = ac.dot(ax);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const core::Vec3 bx = x - b;
  const double d3 = ab.dot(bx), d4 = ac.dot(bx);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + d1 / (d1 - d3) * ab;
  const core::Vec3 cx = x - c;
  const double d5 = ab.dot(cx), d6 = ac.dot(cx);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = va + vb + vc;
  if (!(denom > 0.0)) {  // degenerate triangle: its edges
    core::Vec3 best = closest_on_segment(x, a, b);
    for (const core::Vec3& y : {closest_on_segment(x, b, c), closest_on_segment(x, c, a)})
      if ((y - x).squaredNorm() < (best - x).squaredNorm()) best = y;
    return best;
  }
  return a + ab * (vb / denom) + ac * (vc / denom);
}

/// Closest points of segments [p1, q1] and [p2, q2] (Ericson 5.1.9): s on the first, t on the
/// second.
inline void closest_segments(const core::Vec3& p1, const core::Vec3& q1, const core::Vec3& p2,
                             const core::Vec3& q2, core::Vec3& s, core::Vec3& t) {
  const core::Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double u = 0.0, v = 0.0;
  if (a <= 0.0 && e <= 0.0) {
  } else if (a <= 0.0) {
    v = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 0.0) {
      u = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      u = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      v = (b * u + f) / e;
      if (v < 0.0) {
        v = 0.0;
        u = std::clamp(-c / a, 0.0, 1.0);
      } else if (v > 1.0) {
        v = 1.0;
        u = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  s = p1 + d1 * u;
  t = p2 + d2 * v;
}

/// A point of each triangle, nearly the closest pair (exact up to rounding when the triangles
/// do not cross): the best of the vertex–triangle and edge–edge candidates.
inline void near_points(const ApproxTriangle& A, const ApproxTriangle& B, core::Vec3& pa,
                        core::Vec3& pb) {
  double best = HUGE_VAL;
  auto take = [&](const core::Vec3& a, const core::Vec3& b) {
    const double d = (b - a).squaredNorm();
    if (d < best) {
      best = d;
      pa = a;
      pb = b;
    }
  };
  for (const auto& a : A.v) take(a, closest_on_triangle(a, B.v[0], B.v[1], B.v[2]));
  for (const auto& b : B.v) take(closest_on_triangle(b, A.v[0], A.v[1], A.v[2]), b);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      core::Vec3 s, t;
      closest_segments(A.v[i], A.v[(i + 1) % 3], B.v[j], B.v[(j + 1) % 3], s, t);
      take(s, t);
    }
}

/// Bounds of the squared distance between the exact triangles that A and B stand for.
struct PairBounds {
  double lower = 0.0;  ///< certified: ≤ the exact squared distance
  double upper = 0.0;  ///< approximate: the squared distance of two points near the triangles
};

/// PairBounds of A and B. The lower bound is the gap between the triangles' projections onto
/// the direction n joining the near points (any direction's gap, divided by |n|, is a lower
/// bound of the distance of two sets; for the closest pair's direction it is the distance), less
/// the vertices' `error` and a bound of the rounding of the double dot products.
inline PairBounds pair_bounds(const ApproxTriangle& A, const ApproxTriangle& B) {
  core::Vec3 pa = core::Vec3::Zero(), pb = core::Vec3::Zero();
  near_points(A, B, pa, pb);
  PairBounds out;
  const core::Vec3 n = pb - pa;
  out.upper = n.squaredNorm();
  const double nn = out.upper;
  if (!(nn > 1e-300)) return out;
  double hi_a = -HUGE_VAL, lo_b = HUGE_VAL, magnitude = 0.0;
  for (const auto& a : A.v) {
    hi_a = std::max(hi_a, n.dot(a));
    magnitude = std::max(magnitude, a.cwiseAbs().maxCoeff());
  }
  for (const auto& b : B.v) {
    lo_b = std::min(lo_b, n.dot(b));
    magnitude = std::max(magnitude, b.cwiseAbs().maxCoeff());
  }
  // |n·x − fl(n·x)| ≤ 3u·|n|₁·max|x| (u = 2⁻⁵³) for each dot product, and |n·(x − x')| ≤
  // |n|₁·error for the exact x near the double x'; the factors below are generous.
  const double n1 = n.cwiseAbs().sum();
  const double gap = (lo_b - hi_a) - n1 * (A.error + B.error) - 1e-14 * n1 * magnitude;
  if (gap <= 0.0) return out;
  out.lower = gap * gap / nn * (1.0 - 1e-12);
  return out;
}

}  // namespace camplace::exact::internal
