#pragma once
// CGAL's exact kernel as camplace uses it, shared by the modules that compute exactly (core's
// true distance, the exact pipeline). Private to the modules: this directory is on no public
// include path (target camplace_core_exact_kernel, linked PRIVATE), so no CGAL type reaches a
// public header (STYLE).
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <sstream>
#include <string>
#include <type_traits>

#include "camplace/core/geometry.hpp"

namespace camplace::core::internal {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using FT = Kernel::FT;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;

/// The double coordinates as an exact point (every double is a rational: no rounding).
inline Point to_point(const Vec3& v) { return Point(v.x(), v.y(), v.z()); }
inline Vector to_vector(const Vec3& v) { return Vector(v.x(), v.y(), v.z()); }
/// "p/q" of an exact rational, in lowest terms.
inline std::string fraction_string(const FT& x) {
  const auto& e = CGAL::exact(x);
  using Exact = std::decay_t<decltype(e)>;
  typename CGAL::Fraction_traits<Exact>::Numerator_type num;
  typename CGAL::Fraction_traits<Exact>::Denominator_type den;
  typename CGAL::Fraction_traits<Exact>::Decompose()(e, num, den);
  std::ostringstream out;
  out << num << "/" << den;
  return out.str();
}

}  // namespace camplace::core::internal
