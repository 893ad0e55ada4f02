#pragma once
// The image plane of one camera (detail::CameraSetup's bins) and the margins shared by the
// labelling stages: which bins an image rectangle covers, a box's projection, a ball in the cone.
#include <algorithm>
#include <array>
#include <cmath>

#include "impl.hpp"

namespace camplace::voxel::detail {

/// Relative margin of the labeller's tests (of a distance, a projection, a plane).
inline constexpr double kMargin = 1e-9;
/// Relative gap below which a triangle's cone and a box are a touching configuration.
inline constexpr double kTouch = 1e-12;

/// The bin of image coordinate x (axis 0) or y (axis 1) in `grid` (clamped: clamping keeps
/// overlapping intervals overlapping).
inline int bin_of(const BinGrid& grid, double x, int axis) {
  const double f = (x - grid.origin[axis]) * grid.scale[axis];
  if (!(f > 0.0)) return 0;
  if (f >= grid.n[axis]) return grid.n[axis] - 1;
  return static_cast<int>(f);
}

struct BinRange {
  int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
};

/// Bins of `grid` overlapping [xlo, xhi] × [ylo, yhi].
inline BinRange bins_under(const BinGrid& grid, double xlo, double xhi, double ylo, double yhi) {
  return {bin_of(grid, xlo, 0), bin_of(grid, xhi, 0), bin_of(grid, ylo, 1), bin_of(grid, yhi, 1)};
}

/// Bins overlapping [lo, hi] on each axis, padded by the margin.
inline BinRange bin_range(const BinGrid& grid, double xlo, double xhi, double ylo, double yhi) {
  const double px = kMargin * (1.0 + std::max(std::abs(xlo), std::abs(xhi)));
  const double py = kMargin * (1.0 + std::max(std::abs(ylo), std::abs(yhi)));
  return bins_under(grid, xlo - px, xhi + px, ylo - py, yhi + py);
}

/// Whether [x0, x1] × [y0, y1] misses the rectangle the bins of `grid` cover: no binned slot's
/// rectangle meets it (the bins cover every one of them).
inline bool outside_bins(const BinGrid& grid, double x0, double x1, double y0, double y1) {
  return x1 < grid.origin[0] || x0 > grid.origin[0] + grid.n[0] / grid.scale[0] ||
         y1 < grid.origin[1] || y0 > grid.origin[1] + grid.n[1] / grid.scale[1];
}

/// Whether the ball of radius `depth` about the point at w from the camera (axial coordinate z)
/// lies inside the camera's cone (half angle α < 90°): the point's distance to the cone's
/// surface, z sin α − ρ cos α with ρ its distance from the axis (in the meridian plane, to the
/// nearer generator; z > 0 there), exceeds `depth`. Squared, no root.
inline bool ball_in_cone(const CameraSetup& cam, const core::Vec3& w, double z, double depth) {
  const double inner = cam.sin_half * z - depth;
  const double lateral_sq = std::max(0.0, w.squaredNorm() - z * z);
  return inner > 0.0 && inner * inner > cam.cos_half * cam.cos_half * lateral_sq;
}

/// The rectangle (x0, x1, y0, y1) of image coordinates (X/Z, Y/Z) holding the projection of a
/// box whose centre is at (x, y, z) in the camera frame and whose half extents along ex, ey and
/// the axis are (bx, by, bz), the box lying wholly in front of the camera (z − bz > 0): each
/// bound is the min or max of (x ± bx) / (z ± bz).
inline std::array<double, 4> box_projection(double x, double y, double z, double bx, double by,
                                            double bz) {
  // Two divisions, then products: within a few ulps of the quotients (the triangles'
  // rectangles are padded by 2e-9 relative).
  const double i_lo = 1.0 / (z - bz), i_hi = 1.0 / (z + bz);
  const double x0 = x - bx, x1 = x + bx, y0 = y - by, y1 = y + by;
  return {x0 * (x0 >= 0 ? i_hi : i_lo), x1 * (x1 >= 0 ? i_lo : i_hi), y0 * (y0 >= 0 ? i_hi : i_lo),
          y1 * (y1 >= 0 ? i_lo : i_hi)};
}

}  // namespace camplace::voxel::detail
