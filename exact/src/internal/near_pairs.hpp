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

/// A point of each triangle, nearly the closest pair (exact up to rounding when the triangles
/// do not cross): the best of the vertex–triangle and edge–edge candidates (core's closest
/// points). A degenerate triangle may give no vertex–triangle candidate (core divides by its
/// zero area: the candidate is not finite and never taken); its edges still give the pair. Any
/// pair will do: pair_bounds' lower bound holds for every direction.
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
  for (const auto& a : A.v) take(a, core::closest_point_on_triangle(a, B.v[0], B.v[1], B.v[2]));
  for (const auto& b : B.v) take(core::closest_point_on_triangle(b, A.v[0], A.v[1], A.v[2]), b);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const auto [s, t] =
          core::closest_points_of_segments(A.v[i], A.v[(i + 1) % 3], B.v[j], B.v[(j + 1) % 3]);
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
