#pragma once
// The exact pipeline's kernel and number type, and the exact conversions from and to camplace's
// double-precision types. Private to exact/src: included only by exact_pipeline.cpp, the one Nef
// translation unit (STYLE.md).
#include <CGAL/Nef_polyhedron_3.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>

#include "camplace/core/geometry.hpp"
#include "camplace/core/internal/exact_kernel.hpp"

namespace camplace::exact::internal {

// Kernel, FT, Point, Vector, to_point, to_vector and fraction_string: shared with core's exact
// true distance (core/internal/camplace/core/internal/exact_kernel.hpp).
using core::internal::fraction_string;
using core::internal::FT;
using core::internal::Kernel;
using core::internal::Point;
using core::internal::to_point;
using core::internal::to_vector;
using core::internal::Vector;
using Plane = Kernel::Plane_3;
using Triangle = Kernel::Triangle_3;
using Segment = Kernel::Segment_3;
using Tetrahedron = Kernel::Tetrahedron_3;
using Nef = CGAL::Nef_polyhedron_3<Kernel>;
using SurfaceMesh = CGAL::Surface_mesh<Point>;

/// x rounded to a neighbouring double: the nearer one (the lower on a tie) when the exact
/// interval is tight. Unlike CGAL::to_double on a lazy number, the result does not depend on
/// how far x happens to have been refined, so reports are reproducible.
inline double nearest_double(const FT& x) {
  const auto& e = CGAL::exact(x);
  using ET = std::decay_t<decltype(e)>;
  const std::pair<double, double> i = CGAL::to_interval(e);
  if (i.first == i.second) return i.first;
  return e - ET(i.first) <= ET(i.second) - e ? i.first : i.second;
}

/// p rounded to double, coordinate by coordinate (nearest_double).
inline core::Vec3 to_vec3(const Point& p) {
  return {nearest_double(p.x()), nearest_double(p.y()), nearest_double(p.z())};
}

/// A lower bound (m) of sqrt of an exact non-negative squared length.
inline double sqrt_lower(const FT& sq) {
  const double lo = CGAL::to_interval(CGAL::exact(sq)).first;
  return lo <= 0.0 ? 0.0 : std::sqrt(lo) * (1.0 - 1e-12);
}

}  // namespace camplace::exact::internal
