// The FOV tests of the labeller (SPEC §3.1): a voxel's centre (center mode) or box
// (conservative mode), any box (refined cells), and per row of voxels the interval that may be
// and the interval that surely is in the FOV (docs/design/labelling.md L5).
#include <algorithm>
#include <cmath>
#include <limits>

#include "image_plane.hpp"
#include "impl.hpp"

namespace camplace::voxel {

using core::Vec3;
using detail::CameraSetup;
using detail::kMargin;

/// The FOV test of the previous labeller: centre mode `d > 0 && fov.contains(centre)`,
/// conservative mode all 8 corners in the FOV (it is convex) and the camera not in or at the
/// voxel. w = centre − camera, d = |w|.
bool VoxelEvaluator::Impl::in_fov(const CameraSetup& cam, int i, int j, int k, const Vec3& w,
                                  double d) const {
  if (!conservative) {
    // core::Fov::contains on the same numbers (v = p − apex = w, |v| = d).
    if (!(d > 0)) return false;
    const double axial = w.dot(cam.axis);
    if (cam.range && axial > *cam.range) return false;
    if (axial < cam.near) return false;
    if (!cam.pyramid) return axial >= d * cam.cos_half;
    for (const Vec3& n : cam.normals) {
      if (n.dot(w) < 0.0) return false;
    }
    return true;
  }
  return box_in_fov(cam, Vec3(box_min[0][i], box_min[1][j], box_min[2][k]),
                    Vec3(box_max[0][i], box_max[1][j], box_max[2][k]), voxel_radius, w, d);
}

/// in_fov's conservative test for any box [lo, hi] (a voxel, or a refined cell) with radius r
/// (half its diagonal) and centre at w from the camera, d = |w|.
bool VoxelEvaluator::Impl::box_in_fov(const CameraSetup& cam, const Vec3& lo, const Vec3& hi,
                                      double r, const Vec3& w, double d) const {
  if (d <= r) return false;  // camera in or at the box: never provably free
  const double tol = kMargin * (d + r);
  const double axial = w.dot(cam.axis);
  // Decided without the corners when the centre is clearly outside (then so is a corner: the
  // FOV's inside-ness is concave) or the bounding ball clearly inside.
  bool ball_inside = true;
  if (cam.range) {
    if (axial > *cam.range + tol) return false;
    ball_inside = axial + r < *cam.range - tol;
  }
  if (cam.near > 0.0) {
    if (axial < cam.near - tol) return false;
    ball_inside = ball_inside && axial - r > cam.near + tol;
  }
  if (!cam.pyramid) {
    if (axial < d * cam.cos_half - tol) return false;
    if (ball_inside && detail::ball_in_cone(cam, w, axial, r + tol)) return true;
  } else {
    bool clear = ball_inside;
    for (const Vec3& n : cam.normals) {
      const double s = n.dot(w);
      if (s < -tol) return false;
      clear = clear && s > r + tol;
    }
    if (clear) return true;
  }
  const core::Fov& fov = *cam.fov;
  for (int q = 0; q < 8; ++q) {
    const Vec3 corner((q & 1) ? hi.x() : lo.x(), (q & 2) ? hi.y() : lo.y(),
                      (q & 4) ? hi.z() : lo.z());
    if (!fov.contains(corner)) return false;
  }
  return true;
}

namespace {

/// The u (= x − c_x) where the centre (c_x + u, c_y + dy, c_z + dz) lies in the cone of axis
/// `axis` and cos² of half angle `kk` about the camera c: [u_lo, u_hi], empty when u_lo > u_hi.
/// False when the quadratic is too flat to trust (the caller then takes the whole row).
bool cone_row(const Vec3& axis, double kk, double dy, double dz, double& u_lo, double& u_hi) {
  const double a1 = axis.x(), b0 = axis.y() * dy + axis.z() * dz;
  // (a1 u + b0)² − kk (u² + dy² + dz²) ≥ 0 and a1 u + b0 ≥ 0.
  const double A = a1 * a1 - kk, B = 2.0 * a1 * b0, C = b0 * b0 - kk * (dy * dy + dz * dz);
  u_lo = -std::numeric_limits<double>::infinity();
  u_hi = -u_lo;
  if (std::abs(A) < 1e-6) return false;
  const double disc = B * B - 4.0 * A * C;
  if (A < 0) {
    if (disc < 0) {  // the line misses the cone
      u_lo = 1.0;
      u_hi = -1.0;
      return true;
    }
    const double sq = std::sqrt(disc);
    u_lo = (-B + sq) / (2.0 * A);
    u_hi = (-B - sq) / (2.0 * A);
    if (a1 * 0.5 * (u_lo + u_hi) + b0 < 0) {  // the other nappe
      u_lo = 1.0;
      u_hi = -1.0;
    }
    return true;
  }
  // Outside the roots, on the side where the axial coordinate grows.
  if (disc >= 0) {
    const double sq = std::sqrt(disc);  // roots (−B ∓ sq) / 2A, A > 0: smaller first
    if (a1 > 0) {
      u_lo = (-B + sq) / (2.0 * A);
    } else {
      u_hi = (-B - sq) / (2.0 * A);
    }
  } else if (a1 > 0) {
    u_lo = -b0 / a1;
  } else if (a1 < 0) {
    u_hi = -b0 / a1;
  }
  return true;
}

/// Intersects [u_lo, u_hi] with {u : n_x u + rest ≥ bound}.
void half_line(double n_x, double rest, double bound, double& u_lo, double& u_hi) {
  if (n_x > 0) {
    u_lo = std::max(u_lo, (bound - rest) / n_x);
  } else if (n_x < 0) {
    u_hi = std::min(u_hi, (bound - rest) / n_x);
  } else if (rest < bound) {
    u_lo = 1.0;
    u_hi = -1.0;
  }
}

}  // namespace

/// For row (j, k) and one camera: the voxels i whose centre can be in the FOV lie in [lo, hi]
/// (the cone, widened by 1e-6 rad, and the far plane, plus one voxel on each side; the whole
/// row when the quadratic is near degenerate), and those in [in_lo, in_hi] are surely in it
/// (in_fov would say true: the centre, or in conservative mode the voxel's bounding ball,
/// inside by 1e-6 rad and 1e-9 m, less one voxel on each side). Elsewhere in_fov decides.
void VoxelEvaluator::Impl::row_interval(const CameraSetup& cam, int j, int k, int& lo, int& hi,
                                        int& in_lo, int& in_hi) const {
  const int nx = grid.n[0];
  lo = 0;
  hi = nx - 1;
  in_lo = nx;
  in_hi = -1;
  const double dy = box_center[1][j] - cam.c.y(), dz = box_center[2][k] - cam.c.z();
  const double x0 = grid.area.min.x(), step = grid.step.x();
  auto index = [&](double u) { return (u + cam.c.x() - x0) / step - 0.5; };
  const double a1 = cam.axis.x(), b0 = cam.axis.y() * dy + cam.axis.z() * dz;
  // Outer: may be in the FOV.
  double u_lo, u_hi;
  if (cam.row_cos_sq > 0.0 && cone_row(cam.axis, cam.row_cos_sq, dy, dz, u_lo, u_hi)) {
    if (cam.range) half_line(-a1, -b0, -*cam.range, u_lo, u_hi);
    if (cam.near > 0.0) half_line(a1, b0, cam.near, u_lo, u_hi);
    if (u_lo > u_hi) {
      lo = nx;
      hi = -1;
      return;
    }
    const double f_lo = index(u_lo) - 1.0, f_hi = index(u_hi) + 1.0;
    if (f_lo > lo) lo = f_lo >= nx ? nx : static_cast<int>(std::floor(f_lo));
    if (f_hi < hi) hi = f_hi < 0 ? -1 : static_cast<int>(std::ceil(f_hi));
  }
  // Inner: surely in the FOV. Every centre of the row is at least `line` from the camera.
  const double line = std::sqrt(dy * dy + dz * dz);
  const double r = conservative ? voxel_radius : 0.0;
  if (!(line > r * (1.0 + 1e-6) + 1e-9)) return;
  const double pad = 1e-9 + 1e-9 * r;
  u_lo = -std::numeric_limits<double>::infinity();
  u_hi = -u_lo;
  if (cam.pyramid) {
    for (const Vec3& n : cam.normals) {
      half_line(n.x(), n.y() * dy + n.z() * dz, r * (1.0 + 1e-6) + pad, u_lo, u_hi);
    }
  } else {
    // cos(α − β) with sin β = r / line (the largest angular radius of a voxel on the row),
    // raised by 1e-6 (at least 1e-6 rad narrower); none when β ≥ α.
    const double sin_b = r / line, cos_b = std::sqrt(1.0 - sin_b * sin_b);
    if (sin_b >= cam.sin_half) return;
    const double cos_inner = std::min(1.0, cam.cos_half * cos_b + cam.sin_half * sin_b + 1e-6);
    if (!cone_row(cam.axis, cos_inner * cos_inner, dy, dz, u_lo, u_hi)) return;
  }
  if (cam.range)
    half_line(-a1, -b0, -(*cam.range - r - pad - 1e-9 * std::abs(*cam.range)), u_lo, u_hi);
  if (cam.near > 0.0) half_line(a1, b0, cam.near + r + pad + 1e-9 * cam.near, u_lo, u_hi);
  if (!(u_lo <= u_hi)) return;
  const double f_lo = index(u_lo) + 1.0, f_hi = index(u_hi) - 1.0;
  in_lo = f_lo <= 0 ? 0 : f_lo >= nx ? nx : static_cast<int>(std::ceil(f_lo));
  in_hi = f_hi >= nx - 1 ? nx - 1 : f_hi < 0 ? -1 : static_cast<int>(std::floor(f_hi));
}

}  // namespace camplace::voxel
