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

/// The projection of a box wholly in front of the camera: the convex hull of its 8 corners'
/// image coordinates, as outward edge lines n·(x − p) ≤ 0 (counter-clockwise; at most 6 edges,
/// none when the hull is degenerate).
struct BoxOutline {
  int edges = 0;
  std::array<std::array<double, 4>, 8> line;  ///< n_x, n_y, n·p, margin (the first `edges`)
};

/// The outline of the box with centre at w from the camera and half extents `half` (world
/// axes), every corner in front of the camera (positive depth).
inline void box_outline(const CameraSetup& cam, const core::Vec3& w, const core::Vec3& half,
                        BoxOutline& out) {
  std::array<std::array<double, 2>, 8> p;
  for (int i = 0; i < 8; ++i) {
    const core::Vec3 q =
        w + core::Vec3((i & 1) ? half.x() : -half.x(), (i & 2) ? half.y() : -half.y(),
                       (i & 4) ? half.z() : -half.z());
    const double z = q.dot(cam.axis);
    p[i] = {q.dot(cam.ex) / z, q.dot(cam.ey) / z};
  }
  // Andrew's monotone chain: lower then upper hull, counter-clockwise.
  std::sort(p.begin(), p.end());
  std::array<std::array<double, 2>, 16> hull;
  int k = 0;
  auto turn = [](const std::array<double, 2>& o, const std::array<double, 2>& a,
                 const std::array<double, 2>& b) {
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
  };
  for (int i = 0; i < 8; ++i) {
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  for (int i = 6, lower = k + 1; i >= 0; --i) {
    while (k >= lower && turn(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  out.edges = 0;
  if (k - 1 < 3) return;
  for (int i = 0; i + 1 < k && out.edges < 8; ++i) {
    const double dx = hull[i + 1][0] - hull[i][0], dy = hull[i + 1][1] - hull[i][1];
    const double nx = dy, ny = -dx;
    const double scale = 1.0 + std::max(std::abs(hull[i][0]), std::abs(hull[i][1]));
    out.line[out.edges++] = {nx, ny, nx * hull[i][0] + ny * hull[i][1],
                             4 * kMargin * scale * (std::abs(nx) + std::abs(ny))};
  }
}

/// Whether the rectangle r (x0, x1, y0, y1) lies outside the outline by more than its margin
/// (far above the rounding of either): no point of it is in the box's projection, so the cone
/// over a triangle in front of the camera whose rectangle it is misses the box clearly.
inline bool outside_outline(const BoxOutline& outline, const std::array<double, 4>& r) {
  for (int e = 0; e < outline.edges; ++e) {
    const auto& l = outline.line[e];
    // The rectangle's corner deepest inside this edge.
    const double x = l[0] >= 0.0 ? r[0] : r[1], y = l[1] >= 0.0 ? r[2] : r[3];
    if (l[0] * x + l[1] * y - l[2] > l[3]) return true;
  }
  return false;
}

}  // namespace camplace::voxel::detail
