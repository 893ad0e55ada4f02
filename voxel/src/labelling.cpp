// Labelling (SPEC §3, §5): per camera the FOV test and the triangles sorted into bins of the
// image plane; per voxel and camera the label κ for all states at once, center mode (the
// voxel's centre) or conservative mode (free only when every point of the voxel is free); the
// unfiltered models.
//
// Refinement (refine.cpp) labels octree cells with these same tests: judge() and box_in_fov()
// take the cell's size (detail::CellSize, the voxel's scaled by a power of two).
//
// The fast labeller gives the labels of the plain per-voxel tests (Möller–Trumbore on the ray to
// the voxel centre; the separating-axis test of a triangle's cone against the voxel box; the FOV
// test on the centre or the 8 corners) and only skips tests that cannot change a label: image-
// plane bins (docs/design/labelling.md L1), back-face culling (L3), block clearing (L4), row
// intervals and early FOV decisions (L5), voxels an occupying object reaches into (L6), objects
// shared between states (L7), bit masks over 64 states; center mode's first hit breaks ties by
// triangle index (L8); a conservative free label is sound by L2.
#include <algorithm>
#include <cmath>
#include <limits>

#include "camplace/core/geometry.hpp"
#include "impl.hpp"

namespace camplace::voxel {

using core::Vec3;
using detail::CameraSetup;
using detail::Scratch;
using detail::StateInfo;
using detail::StateMask;
using detail::TriangleCone;
using detail::Verdict;

namespace {

constexpr double kMargin = 1e-9;
/// Relative gap below which a triangle's cone and a box are a touching configuration.
constexpr double kTouch = 1e-12;

/// The bin of image coordinate x (axis 0) or y (axis 1) (clamped: clamping keeps overlapping
/// intervals overlapping).
int bin_of(const CameraSetup& cam, double x, int axis = 0) {
  const double f = (x + cam.image_half[axis]) * cam.bin_scale[axis];
  if (!(f > 0.0)) return 0;
  if (f >= cam.bins) return cam.bins - 1;
  return static_cast<int>(f);
}

int wide_of(const CameraSetup& cam, double x, int axis = 0) {
  const double f = (x + cam.image_half[axis]) * cam.wide_scale[axis];
  if (!(f > 0.0)) return 0;
  if (f >= cam.wide_bins) return cam.wide_bins - 1;
  return static_cast<int>(f);
}

struct BinRange {
  int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
};

/// Bins overlapping [lo, hi] on each axis, padded by the margin.
BinRange bin_range(const CameraSetup& cam, double xlo, double xhi, double ylo, double yhi) {
  const double px = kMargin * (1.0 + std::max(std::abs(xlo), std::abs(xhi)));
  const double py = kMargin * (1.0 + std::max(std::abs(ylo), std::abs(yhi)));
  return {bin_of(cam, xlo - px), bin_of(cam, xhi + px), bin_of(cam, ylo - py, 1),
          bin_of(cam, yhi + py, 1)};
}

/// Whether the ball of radius `depth` about the point at w from the camera (axial coordinate z)
/// lies inside the camera's cone (half angle α < 90°): the point's distance to the cone's
/// surface, z sin α − ρ cos α with ρ its distance from the axis (in the meridian plane, to the
/// nearer generator; z > 0 there), exceeds `depth`. Squared, no root.
bool ball_in_cone(const CameraSetup& cam, const Vec3& w, double z, double depth) {
  const double inner = cam.sin_half * z - depth;
  const double lateral_sq = std::max(0.0, w.squaredNorm() - z * z);
  return inner > 0.0 && inner * inner > cam.cos_half * cam.cos_half * lateral_sq;
}

/// The rectangle (x0, x1, y0, y1) of image coordinates (X/Z, Y/Z) holding the projection of a
/// box whose centre is at (x, y, z) in the camera frame and whose half extents along ex, ey and
/// the axis are (bx, by, bz), the box lying wholly in front of the camera (z − bz > 0): each
/// bound is the min or max of (x ± bx) / (z ± bz).
std::array<double, 4> box_projection(double x, double y, double z, double bx, double by,
                                     double bz) {
  // Two divisions, then products: within a few ulps of the quotients (the triangles'
  // rectangles are padded by 2e-9 relative).
  const double i_lo = 1.0 / (z - bz), i_hi = 1.0 / (z + bz);
  const double x0 = x - bx, x1 = x + bx, y0 = y - by, y1 = y + by;
  return {x0 * (x0 >= 0 ? i_hi : i_lo), x1 * (x1 >= 0 ? i_lo : i_hi), y0 * (y0 >= 0 ? i_hi : i_lo),
          y1 * (y1 >= 0 ? i_lo : i_hi)};
}

}  // namespace

CameraSetup VoxelEvaluator::Impl::camera_setup(const core::CameraSetting& camera,
                                               const core::CameraModel& model) const {
  CameraSetup cam;
  cam.setting = camera;
  cam.fov.emplace(camera, model);
  const core::Fov& fov = *cam.fov;
  const Vec3& c = camera.position;
  cam.c = c;
  cam.axis = fov.axis();
  cam.ey = core::up_vector(camera);
  cam.ex = cam.axis.cross(cam.ey).normalized();
  cam.abs_ex = cam.ex.cwiseAbs();
  cam.abs_ey = cam.ey.cwiseAbs();
  cam.abs_axis = cam.axis.cwiseAbs();
  cam.box_x = cam.abs_ex.dot(half_step);
  cam.box_y = cam.abs_ey.dot(half_step);
  cam.box_z = cam.abs_axis.dot(half_step);
  cam.pyramid = !fov.is_cone();
  cam.normals = fov.pyramid_normals();
  cam.near = model.near;
  cam.range = model.range;
  // The cone's, or the bounding cone's half angle: every test that uses it proves a point
  // outside the FOV (or, for a cone, inside), and the pyramid and the frustum lie in it.
  const double half_angle = model.bounding_half_angle();
  cam.cos_half = std::cos(half_angle);  // as core::Fov computes it
  cam.sin_half = std::sin(half_angle);
  const double widened = half_angle + 1e-6;
  cam.row_cos_sq = widened < 0.5 * core::kPi ? std::cos(widened) * std::cos(widened) : 0.0;

  // SPEC §3.3 with one convention in both pipelines: a camera in the closed object,
  // on its surface too, is blind (its rays start on the object). The exact pipeline decides
  // this exactly; here a camera within a rounding distance of the surface counts as on it,
  // which only makes the model larger, never smaller (conservative mode stays ⊇ exact).
  cam.inside_object.assign(objects.size(), 0);
  for (std::size_t o = 0; o < objects.size(); ++o) {
    const detail::ObjectInfo& info = objects[o];
    const double d = (info.center - c).norm();
    const double on_surface = 1e-9 * (info.radius + info.center.norm() + c.norm());
    const bool near = d <= info.radius + on_surface;
    cam.inside_object[o] =
        near && core::point_solid_sq_distance(*info.mesh, c) <= on_surface * on_surface;
  }
  cam.triangles.resize(triangles.size());
  std::vector<double> tilt(triangles.size(), 0.0);  // det / scale: 0 when the camera is in-plane
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& tri = triangles[t];
    TriangleCone& tc = cam.triangles[t];
    const Vec3 a = tri[0] - c, b = tri[1] - c, e = tri[2] - c;
    const double det = a.dot(b.cross(e));
    tc.near_distance = std::sqrt(core::point_triangle_sq_distance(c, tri[0], tri[1], tri[2]));
    const double scale = a.norm() * b.norm() * e.norm();
    tc.flat = !(std::abs(det) > 1e-12 * scale);
    if (tc.flat) continue;
    tilt[t] = det / scale;
    if (!conservative) continue;  // center mode needs no cones
    const double sign = det > 0 ? 1.0 : -1.0;
    tc.edge[0] = a;
    tc.edge[1] = b;
    tc.edge[2] = e;
    tc.normal[0] = (sign * a.cross(b)).normalized();
    tc.normal[1] = (sign * b.cross(e)).normalized();
    tc.normal[2] = (sign * e.cross(a)).normalized();
    for (int i = 0; i < 3; ++i) tc.abs_normal[i] = tc.normal[i].cwiseAbs();
    // The previous labeller's `separates` on the same numbers, its voxel-independent part
    // (the edges' projections) done once per camera.
    auto add_axis = [&](const Vec3& axis) {
      const double pa = axis.dot(tc.edge[0]), pb = axis.dot(tc.edge[1]), pc = axis.dot(tc.edge[2]);
      const double radius = axis.cwiseAbs().dot(half_step);
      if (pa >= 0.0 && pb >= 0.0 && pc >= 0.0) {
        tc.axes[tc.axis_count++] = {axis, radius, 1.0, axis.norm()};
      } else if (pa <= 0.0 && pb <= 0.0 && pc <= 0.0) {
        tc.axes[tc.axis_count++] = {axis, radius, -1.0, axis.norm()};
      }
    };
    for (int i = 0; i < 3; ++i) add_axis(Vec3::Unit(i));
    for (const Vec3& edge : tc.edge) {
      for (int i = 0; i < 3; ++i) add_axis(edge.cross(Vec3::Unit(i)));
    }
  }
  // Back-face culling (both modes; docs/design/labelling.md L3): det > 0 means the camera is
  // behind the triangle's plane. An object is culled only when it is oriented outward, the
  // camera is outside it and clear of its surface, and no triangle is near edge-on; a near miss
  // of a culled object's front face makes judge() test its back faces too.
  for (std::size_t o = 0; o < objects.size(); ++o) {
    const detail::ObjectInfo& info = objects[o];
    const int end = info.first_triangle + info.triangle_count;
    double clearance = std::numeric_limits<double>::infinity();
    bool clear_tilts = true;
    for (int t = info.first_triangle; t < end; ++t) {
      clearance = std::min(clearance, cam.triangles[t].near_distance);
      clear_tilts = clear_tilts && std::abs(tilt[t]) > 1e-9;
    }
    const double scale = (info.center - c).norm() + info.radius;
    const bool cull =
        info.outward && !cam.inside_object[o] && clearance > 1e-9 * scale && clear_tilts;
    for (int t = info.first_triangle; t < end; ++t) {
      cam.triangles[t].back = cull && tilt[t] > 0;
      cam.triangles[t].touch = cull;
    }
  }
  // Bins over the FOV's section at unit depth: the cone's (which holds the pyramid), or the
  // frustum's image rectangle, tan(H/2) × tan(V/2) along ex (right) and ey (up), both turned
  // by the roll. Bins only sort: a triangle outside them lands in an edge bin.
  if (model.fov == core::FovShape::frustum) {
    cam.image_half = {std::tan(0.5 * model.horizontal), std::tan(0.5 * model.vertical)};
  } else {
    cam.image_half = {std::tan(half_angle), std::tan(half_angle)};
  }
  // Center mode looks up one bin per voxel: fine bins. Conservative mode looks up the bins under
  // the box's projection and then each triangle's rectangle: coarse bins (fewer repeats).
  const int n_max = *std::max_element(grid.n.begin(), grid.n.end());
  cam.bins = conservative ? std::clamp(n_max / 3, 8, 32) : std::clamp(n_max, 16, 64);
  for (int a = 0; a < 2; ++a) cam.bin_scale[a] = cam.bins / (2.0 * cam.image_half[a]);
  const int bin_count = cam.bins * cam.bins;
  std::vector<BinRange> ranges(triangles.size());
  std::vector<std::uint8_t> projectable(triangles.size(), 1);
  const double inf = std::numeric_limits<double>::infinity();
  cam.rect.assign(triangles.size(), {-inf, inf, -inf, inf});
  cam.lines.assign(triangles.size(), {});
  cam.bin_start.assign(bin_count + 1, 0);
  // Conservative mode never tests flat or culled triangles: leave them out.
  auto skipped = [&](std::size_t t) {
    return cam.triangles[t].back || (conservative && cam.triangles[t].flat);
  };
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    if (skipped(t)) continue;
    double xlo = std::numeric_limits<double>::infinity(), xhi = -xlo, ylo = xlo, yhi = -xlo;
    double px[3], py[3];
    for (int v = 0; v < 3; ++v) {
      const Vec3 q = triangles[t][v] - c;
      const double z = q.dot(cam.axis);
      if (!(z > kMargin * q.norm())) {
        projectable[t] = 0;
        break;
      }
      const double x = q.dot(cam.ex) / z, y = q.dot(cam.ey) / z;
      px[v] = x;
      py[v] = y;
      xlo = std::min(xlo, x);
      xhi = std::max(xhi, x);
      ylo = std::min(ylo, y);
      yhi = std::max(yhi, y);
    }
    if (!projectable[t]) {
      cam.everywhere.push_back(static_cast<int>(t));
      continue;
    }
    ranges[t] = bin_range(cam, xlo, xhi, ylo, yhi);
    const double pad_x = 2 * kMargin * (1.0 + std::max(std::abs(xlo), std::abs(xhi)));
    const double pad_y = 2 * kMargin * (1.0 + std::max(std::abs(ylo), std::abs(yhi)));
    cam.rect[t] = {xlo - pad_x, xhi + pad_x, ylo - pad_y, yhi + pad_y};
    // The projected triangle's edge lines, inside ≥ 0, unit normals, padded like the
    // rectangle; none for a (nearly) degenerate projection.
    const double area = (px[1] - px[0]) * (py[2] - py[0]) - (py[1] - py[0]) * (px[2] - px[0]);
    const double size = std::max(xhi - xlo, yhi - ylo);
    cam.lines[t].valid = std::abs(area) > 1e-9 * size * size;
    if (cam.lines[t].valid) {
      const double pad = std::max(pad_x, pad_y);
      for (int e = 0; e < 3; ++e) {
        const int f = (e + 1) % 3;
        double a = -(py[f] - py[e]), b = px[f] - px[e];
        if (area < 0) {
          a = -a;
          b = -b;
        }
        const double norm = std::hypot(a, b);
        a /= norm;
        b /= norm;
        cam.lines[t].line[e] = {a, b, -(a * px[e] + b * py[e]) + pad};
      }
    }
    for (int by = ranges[t].y0; by <= ranges[t].y1; ++by) {
      for (int bx = ranges[t].x0; bx <= ranges[t].x1; ++bx) ++cam.bin_start[by * cam.bins + bx + 1];
    }
  }
  for (int b = 0; b < bin_count; ++b) cam.bin_start[b + 1] += cam.bin_start[b];
  cam.bin_items.resize(cam.bin_start[bin_count]);
  std::vector<int> fill(cam.bin_start.begin(), cam.bin_start.end() - 1);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    if (skipped(t) || !projectable[t]) continue;
    for (int by = ranges[t].y0; by <= ranges[t].y1; ++by) {
      for (int bx = ranges[t].x0; bx <= ranges[t].x1; ++bx) {
        cam.bin_items[fill[by * cam.bins + bx]++] = static_cast<int>(t);
      }
    }
  }
  // Conservative mode: bins twice as fine with every rectangle widened by half a (coarse) bin,
  // so that a voxel whose projection is at most that wide finds every triangle it can meet in
  // the bin of its rectangle's centre, each once (no repeats to skip).
  cam.wide_bins = 2 * cam.bins;
  for (int a = 0; a < 2; ++a) {
    cam.wide_scale[a] = cam.wide_bins / (2.0 * cam.image_half[a]);
    cam.widen[a] = 0.5 / cam.bin_scale[a];
  }
  const int wide_count = cam.wide_bins * cam.wide_bins;
  cam.wide_start.assign(wide_count + 1, 0);
  cam.wide_items.clear();
  if (conservative) {
    std::vector<BinRange> wide(triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      if (skipped(t) || !projectable[t]) continue;
      const auto& r = cam.rect[t];
      wide[t] = {wide_of(cam, r[0] - cam.widen[0]), wide_of(cam, r[1] + cam.widen[0]),
                 wide_of(cam, r[2] - cam.widen[1], 1), wide_of(cam, r[3] + cam.widen[1], 1)};
      for (int by = wide[t].y0; by <= wide[t].y1; ++by) {
        for (int bx = wide[t].x0; bx <= wide[t].x1; ++bx) {
          ++cam.wide_start[by * cam.wide_bins + bx + 1];
        }
      }
    }
    for (int b = 0; b < wide_count; ++b) cam.wide_start[b + 1] += cam.wide_start[b];
    cam.wide_items.resize(cam.wide_start[wide_count]);
    std::vector<int> next(cam.wide_start.begin(), cam.wide_start.end() - 1);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      if (skipped(t) || !projectable[t]) continue;
      for (int by = wide[t].y0; by <= wide[t].y1; ++by) {
        for (int bx = wide[t].x0; bx <= wide[t].x1; ++bx) {
          cam.wide_items[next[by * cam.wide_bins + bx]++] = static_cast<int>(t);
        }
      }
    }
  }
  return cam;
}

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
    if (ball_inside && ball_in_cone(cam, w, axial, r + tol)) return true;
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

/// The candidate triangles of judge() (conservative mode) in order, until `done`.
template <class Test, class Done>
void judge_candidates(const CameraSetup& cam, double vx0, double vx1, double vy0, double vy1,
                      double z_lo, Test& test, const Done& done) {
  if (z_lo > 0.0 && vx1 - vx0 <= 2.0 * cam.widen[0] && vy1 - vy0 <= 2.0 * cam.widen[1]) {
    // A triangle whose rectangle overlaps the voxel's has its widened rectangle around the
    // voxel rectangle's centre: one wide bin holds every candidate, once.
    const int b =
        wide_of(cam, 0.5 * (vy0 + vy1), 1) * cam.wide_bins + wide_of(cam, 0.5 * (vx0 + vx1));
    for (int n = cam.wide_start[b]; n < cam.wide_start[b + 1]; ++n) {
      if (test(cam.wide_items[n], true) && done()) return;
    }
    for (int t : cam.everywhere) {
      if (test(t, true) && done()) return;
    }
    return;
  }
  // The bins under the box's projection (all of them when it is not wholly in front).
  const BinRange bins = z_lo > 0.0 ? BinRange{bin_of(cam, vx0), bin_of(cam, vx1),
                                              bin_of(cam, vy0, 1), bin_of(cam, vy1, 1)}
                                   : BinRange{0, cam.bins - 1, 0, cam.bins - 1};
  for (int by = bins.y0; by <= bins.y1; ++by) {
    for (int bx = bins.x0; bx <= bins.x1; ++bx) {
      const int b = by * cam.bins + bx;
      for (int n = cam.bin_start[b]; n < cam.bin_start[b + 1]; ++n) {
        if (test(cam.bin_items[n], false) && done()) return;
      }
    }
  }
  for (int t : cam.everywhere) {
    if (test(t, true) && done()) return;
  }
}

}  // namespace

/// κ of SPEC §3 for the voxel with centre at w from the camera (d = |w|, or < 0 when not yet
/// known), in the FOV of the camera, for the states in `interest`: adds to `out` the states where
/// it is occupied and those where it is otherwise not free. With `free_only` the split between the
/// two is not kept (the model needs no more). `size`: the voxel's (cell_sizes[0]) or, in
/// conservative mode, a refined cell's; the camera's box extents scale with size.factor.
/// `witness` (conservative mode, optional): detail::kWitnesses triangles to test first (those
/// ≥ 0; the ones that decided the cell's parent), updated with the triangles that decided states
/// here, most recent first; the verdict does not depend on the order of the tests. `sure`
/// (conservative mode, optional): adds the states whose deciding triangle decides them for every
/// box inside this one as well — its cone holds the whole box (by a margin) and it is occupying, or
/// it lies nearer to the camera than every point of the box (blocking).
void VoxelEvaluator::Impl::judge(const CameraSetup& cam, const Vec3& w, double d,
                                 StateMask interest, const StateMask* object_states,
                                 Scratch& scratch, Verdict& out, bool free_only,
                                 const detail::CellSize& size, int* witness,
                                 StateMask* sure) const {
  const double x = w.dot(cam.ex), y = w.dot(cam.ey), z = w.dot(cam.axis);
  if (!conservative) {
    // The ray from the camera through the centre: every hit in (0, d] blocks the view, and
    // the first hit along the whole ray occupies the voxel when its object is occupying.
    BinRange bins{0, cam.bins - 1, 0, cam.bins - 1};
    double px = 0.0, py = 0.0;  // the centre's projection
    bool projected = z > 0.0;
    if (projected) {
      px = x / z;
      py = y / z;
      const int bx = bin_of(cam, px), by = bin_of(cam, py, 1);
      bins = {bx, bx, by, by};
    }
    // The ray's direction, once a triangle gets to the ray test.
    Vec3 u;
    bool ray_ready = false;
    scratch.hits.clear();
    auto test = [&](int t) {
      const StateMask m = object_states[triangle_object[t]] & interest;
      if (!m) return;
      if (projected) {
        const auto& r = cam.rect[t];  // padded: a ray through the triangle projects inside
        if (px < r[0] || px > r[1] || py < r[2] || py > r[3]) return;
        const detail::EdgeLines& lines = cam.lines[t];
        if (lines.valid) {
          for (const auto& l : lines.line) {
            if (l[0] * px + l[1] * py + l[2] < 0.0) return;
          }
        }
      }
      if (!ray_ready) {
        if (d < 0.0) d = w.norm();
        u = w / d;
        ray_ready = true;
      }
      const auto& tri = triangles[t];
      const double hit = core::ray_triangle_hit(cam.c, u, tri[0], tri[1], tri[2]);
      if (!(hit > 0.0)) return;
      scratch.hits.push_back({hit, t});
      if (hit <= d) out.blocked |= m;
    };
    const bool single = bins.x0 == bins.x1 && bins.y0 == bins.y1;
    if (!single) ++scratch.visit;
    for (int by = bins.y0; by <= bins.y1; ++by) {
      for (int bx = bins.x0; bx <= bins.x1; ++bx) {
        const int b = by * cam.bins + bx;
        for (int n = cam.bin_start[b]; n < cam.bin_start[b + 1]; ++n) {
          const int t = cam.bin_items[n];
          if (!single) {
            if (scratch.stamp[t] == scratch.visit) continue;
            scratch.stamp[t] = scratch.visit;
          }
          test(t);
        }
      }
    }
    for (int t : cam.everywhere) test(t);
    if (scratch.hits.empty()) return;
    if (free_only && !(interest & ~out.blocked)) return;
    // First hit per state: by distance, ties to the lower triangle index (the previous
    // labeller's order: objects of a state ascending, their triangles in order).
    std::sort(scratch.hits.begin(), scratch.hits.end(), [](const auto& a, const auto& b) {
      return a.t < b.t || (a.t == b.t && a.triangle < b.triangle);
    });
    StateMask claimed = 0;
    for (const Scratch::Hit& h : scratch.hits) {
      const int o = triangle_object[h.triangle];
      const StateMask m = object_states[o] & interest & ~claimed;
      if (objects[o].occupying) out.occupied |= m;
      claimed |= m;
      if (claimed == interest) break;
    }
    return;
  }
  // Conservative: free for every point p of the box B when (SPEC §5) no object triangle meets
  // a segment [c, p] (its cone misses B, or it lies wholly beyond B), and no triangle of an
  // occupying object lies on any ray through B (its cone misses B).
  const double inf = std::numeric_limits<double>::infinity();
  double vx0 = -inf, vx1 = inf, vy0 = -inf, vy1 = inf;  // the box's projection lies inside
  const double box_x = cam.box_x * size.factor, box_y = cam.box_y * size.factor;
  const double box_z = cam.box_z * size.factor;
  const double z_lo = z - box_z;
  if (z_lo > 0.0) {
    // (The triangles' rectangles are padded, this one need not be.)
    const auto r = box_projection(x, y, z, box_x, box_y, box_z);
    vx0 = r[0];
    vx1 = r[1];
    vy0 = r[2];
    vy1 = r[3];
  }
  // Needed only once a triangle gets to the cone test.
  Vec3 wc;            // the previous labeller's dir · dist
  double far = -1.0;  // the box's farthest distance, once an occluding triangle needs it
  bool exact_ready = false;
  ++scratch.visit;  // the bins' lists repeat triangles; `everywhere` holds others
  // True when `out` changed. `once`: t cannot come up again for this voxel (no stamp needed).
  // Inlined into judge_candidates' loops (GCC and Clang): 5% of an evaluation at 36×27×27.
  auto test = [&](int t, bool once) __attribute__((always_inline)) {
    if (!once) {
      if (scratch.stamp[t] == scratch.visit) return false;
      scratch.stamp[t] = scratch.visit;
    }
    const int o = triangle_object[t];
    const bool occupying = objects[o].occupying;
    StateMask m = object_states[o] & interest;
    // States already decided need no more tests (occupied wins over undetectable).
    m &= (free_only || !occupying) ? ~(out.occupied | out.blocked) : ~out.occupied;
    if (!m) return false;
    // (The edge lines of the projection would repeat the cone-plane test of cone_test.)
    const auto& r = cam.rect[t];
    if (r[0] > vx1 || r[1] < vx0 || r[2] > vy1 || r[3] < vy0) return false;
    const TriangleCone& tc = cam.triangles[t];
    if (tc.flat || tc.back) return false;
    if (!exact_ready) {
      if (d < 0.0) d = w.norm();
      wc = (w / d) * d;
      exact_ready = true;
    }
    if (!occupying) {
      if (far < 0.0) far = (w.cwiseAbs() + size.half).norm();
      if (tc.near_distance >= far) return false;
    }
    const Cone cone = cone_test(tc, wc, size);
    if (cone == Cone::near_miss && tc.touch) {
      // A culled object touching the voxel within rounding: its back faces decide as they
      // did without culling (the front face through the touching point may have been
      // rounded apart). Back faces are in no bin, so each is tested here once.
      const detail::ObjectInfo& info = objects[o];
      for (int b = info.first_triangle; b < info.first_triangle + info.triangle_count; ++b) {
        const TriangleCone& back = cam.triangles[b];
        if (!back.back || (!occupying && back.near_distance >= far)) continue;
        if (cone_test(back, wc, size) == Cone::meet) {
          (occupying ? out.occupied : out.blocked) |= m;
          return true;
        }
      }
    }
    if (cone != Cone::meet) return false;
    (occupying ? out.occupied : out.blocked) |= m;
    if (sure) {
      // The cone holds the box: the box's lowest point along each inward plane normal is
      // inside by the margin. A smaller box inside is met too; a blocking triangle nearer than
      // the box's nearest point (|w| − radius) is nearer than every sub-box's `far`.
      const double margin = kMargin * (d + size.radius);
      bool holds = occupying || tc.near_distance < (d - size.radius) * (1.0 - 1e-9) - 1e-12;
      for (int i = 0; i < 3 && holds; ++i) {
        holds = tc.normal[i].dot(wc) - tc.abs_normal[i].dot(size.half) > margin;
      }
      if (holds) *sure |= m;
    }
    return true;
  };
  // With free_only, done as soon as every state of interest is decided.
  auto done = [&] { return free_only && !(interest & ~(out.occupied | out.blocked)); };
  if (witness) {
    // A repeated test finds the states it decides decided: it changes nothing.
    const auto plain = test;
    auto test = [&, plain](int t, bool once) {
      if (!plain(t, once)) return false;
      // Most recent first, each triangle once.
      int at = 0;
      while (at < detail::kWitnesses - 1 && witness[at] != t) ++at;
      for (; at > 0; --at) witness[at] = witness[at - 1];
      witness[0] = t;
      return true;
    };
    int first[detail::kWitnesses];
    std::copy(witness, witness + detail::kWitnesses, first);
    for (int t : first) {
      if (t >= 0 && test(t, true) && done()) return;
    }
    judge_candidates(cam, vx0, vx1, vy0, vy1, z_lo, test, done);
    return;
  }
  judge_candidates(cam, vx0, vx1, vy0, vy1, z_lo, test, done);
}

/// Whether the triangle's infinite cone and the voxel box (centre at w from the camera) meet,
/// by the separating-axis theorem for two convex polyhedra: the cone's 3 planes, the box's 3
/// face normals and the 9 cross products of cone edges and box edges. Exact up to rounding;
/// touching counts as meeting (Cone::meet). Cone::near_miss: separated, but by less than
/// 1e-12 of the scale (|w| + Σh) on every separating axis — a touching configuration where
/// rounding decided; back-face culling then tests the object's back faces too (see judge()).
VoxelEvaluator::Impl::Cone VoxelEvaluator::Impl::cone_test(const TriangleCone& tc, const Vec3& w,
                                                           const detail::CellSize& size) const {
  const Vec3& h = size.half;  // the box's half extents (a voxel's or a refined cell's)
  const double scale = kTouch * (w.norm() + h.sum());
  bool near_miss = false;
  // Cone planes first: cheapest and most often decisive.
  double s[3];
  for (int i = 0; i < 3; ++i) {
    s[i] = tc.normal[i].dot(w);
    const double gap = s[i] + tc.abs_normal[i].dot(h);
    if (gap < -scale) return Cone::miss;
    near_miss = near_miss || gap < 0.0;
  }
  // The box centre clearly inside the cone: they meet (no axis can separate them).
  const double inside = kMargin * w.norm();
  if (s[0] > inside && s[1] > inside && s[2] > inside) return Cone::meet;
  // Else the box corner deepest across the planes the centre is outside of: clearly inside
  // the cone, they meet too.
  Vec3 toward = Vec3::Zero();
  for (int i = 0; i < 3; ++i) {
    if (!(s[i] > inside)) toward += tc.normal[i];
  }
  const Vec3 corner = w + Vec3(toward.x() >= 0 ? h.x() : -h.x(), toward.y() >= 0 ? h.y() : -h.y(),
                               toward.z() >= 0 ? h.z() : -h.z());
  if (tc.normal[0].dot(corner) > inside && tc.normal[1].dot(corner) > inside &&
      tc.normal[2].dot(corner) > inside) {
    return Cone::meet;
  }
  // Axis L: the cone projects to [0, ∞) or (−∞, 0] (relative to the camera) when its edges
  // all project to one side, else to the whole line (such axes were dropped); the box to
  // L·w ± Σ|L_i|·h_i.
  for (int a = 0; a < tc.axis_count; ++a) {
    const TriangleCone::Axis& axis = tc.axes[a];
    const double mid = axis.axis.dot(w);
    const double radius = axis.radius * size.factor;
    const double gap = axis.side > 0 ? -(mid + radius) : mid - radius;  // > 0: apart
    if (gap > scale * axis.norm) return Cone::miss;
    near_miss = near_miss || gap > 0.0;
  }
  return near_miss ? Cone::near_miss : Cone::meet;
}

/// Conservative mode: the states of `open` where every voxel of the block [lo, hi] is free for
/// this camera, as judge() would label each of them: each test in_fov() or judge() makes per
/// voxel, made on the whole block with a larger margin (docs/design/labelling.md L4).
StateMask VoxelEvaluator::Impl::block_clear(const CameraSetup& cam, const Vec3& lo, const Vec3& hi,
                                            StateMask open, const StateMask* object_states) const {
  const Vec3 center = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  const Vec3 w = center - cam.c;
  const double d = w.norm(), r = half.norm();
  if (!(d > r * (1.0 + 1e-9))) return 0;
  const Vec3 to_centres =
      (lo + half_step - cam.c).cwiseMax(cam.c - (hi - half_step)).cwiseMax(Vec3::Zero());
  const double clear_of_balls = voxel_radius * (1.0 + 1e-9);
  if (!(to_centres.squaredNorm() > clear_of_balls * clear_of_balls)) return 0;
  const double tol = kMargin * (d + r);
  const double z = w.dot(cam.axis);
  if (cam.range && !(z + r < *cam.range - tol)) return 0;
  if (cam.near > 0.0 && !(z - r > cam.near + tol)) return 0;
  if (!(z - r > tol)) return 0;  // wholly in front (also for the projection below)
  if (cam.pyramid) {
    for (const Vec3& n : cam.normals) {
      if (!(n.dot(w) > r + tol)) return 0;
    }
  } else if (!ball_in_cone(cam, w, z, r + tol)) {
    return 0;
  }
  const double x = w.dot(cam.ex), y = w.dot(cam.ey);
  const double box_x = cam.abs_ex.dot(half), box_y = cam.abs_ey.dot(half);
  const double box_z = cam.abs_axis.dot(half);
  if (!(z - box_z > 0.0)) return 0;
  const auto proj = box_projection(x, y, z, box_x, box_y, box_z);
  double vx0 = proj[0], vx1 = proj[1], vy0 = proj[2], vy1 = proj[3];
  // Padded against rounding (a voxel's projection is computed from other numbers).
  const double px = kMargin * (1.0 + std::max(std::abs(vx0), std::abs(vx1)));
  const double py = kMargin * (1.0 + std::max(std::abs(vy0), std::abs(vy1)));
  vx0 -= px;
  vx1 += px;
  vy0 -= py;
  vy1 += py;
  const double far = (w.cwiseAbs() + half).norm() * (1.0 + 1e-12);
  const double scale = 2.0 * kTouch * (d + half.sum());
  // True when triangle t may decide some voxel of the block.
  auto decides = [&](int t) {
    const auto& rect = cam.rect[t];
    if (rect[0] > vx1 || rect[1] < vx0 || rect[2] > vy1 || rect[3] < vy0) return false;
    const TriangleCone& tc = cam.triangles[t];
    if (tc.flat || tc.back) return false;
    if (!objects[triangle_object[t]].occupying && tc.near_distance >= far) return false;
    for (int i = 0; i < 3; ++i) {
      if (tc.normal[i].dot(w) + tc.abs_normal[i].dot(half) < -scale) return false;
    }
    for (int a = 0; a < tc.axis_count; ++a) {
      const TriangleCone::Axis& axis = tc.axes[a];
      const double mid = axis.axis.dot(w);
      const double radius = axis.axis.cwiseAbs().dot(half);
      const double gap = axis.side > 0 ? -(mid + radius) : mid - radius;
      if (gap > scale * axis.norm) return false;
    }
    return true;
  };
  StateMask clear = open;
  // True when no state is left.
  auto pass = [&](int t) {
    const StateMask m = object_states[triangle_object[t]] & clear;
    if (m && decides(t)) clear &= ~m;
    return !clear;
  };
  for (int t : cam.everywhere) {
    if (pass(t)) return 0;
  }
  const BinRange bins = bin_range(cam, vx0, vx1, vy0, vy1);
  for (int by = bins.y0; by <= bins.y1; ++by) {
    for (int bx = bins.x0; bx <= bins.x1; ++bx) {
      const int b = by * cam.bins + bx;
      for (int n = cam.bin_start[b]; n < cam.bin_start[b + 1]; ++n) {
        if (pass(cam.bin_items[n])) return 0;
      }
    }
  }
  return clear;
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

void VoxelEvaluator::Impl::raw_models(const std::vector<CameraSetup>& cameras, int k_begin,
                                      int k_end,
                                      std::vector<std::vector<std::uint8_t>>& models) const {
  const int nx = grid.n[0], ny = grid.n[1];
  const int state_count = static_cast<int>(states.size());
  const int steps = static_cast<int>(removed_by_step.size());
  const std::size_t n_cam = cameras.size();
  Scratch scratch;
  scratch.stamp.assign(triangles.size(), 0);
  // Per row (j, k) of the slice and camera: row_interval's lo, hi, in_lo, in_hi, computed on
  // first use in conservative mode (lo = −1 until then: row_interval's lo is ≥ 0), where blocks
  // leave many rows without a test, up front in center mode.
  std::vector<std::array<int, 4>> rows(static_cast<std::size_t>(ny) * (k_end - k_begin) * n_cam,
                                       {-1, 0, 0, 0});
  for (int k = k_begin; k < k_end && !conservative; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (std::size_t c = 0; c < n_cam; ++c) {
        auto& r = rows[((k - k_begin) * ny + j) * n_cam + c];
        row_interval(cameras[c], j, k, r[0], r[1], r[2], r[3]);
      }
    }
  }
  for (int chunk = 0; chunk * detail::kChunk < state_count; ++chunk) {
    const int first = chunk * detail::kChunk;
    const int count = std::min(detail::kChunk, state_count - first);
    const StateMask all = count == 64 ? ~StateMask(0) : (StateMask(1) << count) - 1;
    const StateMask* object_states = chunk_object_states[chunk].data();
    const StateMask* step_states = chunk_step_states[chunk].data();
    const StateMask* reached = conservative ? chunk_reached[chunk].data() : nullptr;
    const std::vector<StateMask> seeing = seeing_states(cameras, chunk);
    std::uint8_t* out[detail::kChunk];
    for (int s = 0; s < count; ++s) out[s] = models[first + s].data();
    std::size_t hint = 0, block_hint = 0;
    auto label = [&](int i, int j, int k, StateMask clear) {
      auto* row = &rows[((k - k_begin) * ny + j) * n_cam];
      const int v = i + nx * (j + ny * k);
      StateMask pending = all & ~clear;  // not removed, not yet seen free
      for (int h = 0; h < steps && pending; ++h) {
        if (removed_by_step[h][v]) pending &= ~step_states[h];
      }
      // Conservative mode: the states where an occupying object reaches into the voxel stay in
      // M untested; no camera would see it free there (the proof is at lower_bound(), setup.cpp).
      const StateMask kept = reached ? pending & reached[v] : 0;
      pending &= ~kept;
      if (pending) {
        const Vec3 center(box_center[0][i], box_center[1][j], box_center[2][k]);
        // Cameras from the one that last freed a voxel on: neighbours tend to be seen by the
        // same camera (the order does not change the result).
        const std::size_t first_cam = hint;
        for (std::size_t step = 0; step < n_cam && pending; ++step) {
          const std::size_t c =
              first_cam + step < n_cam ? first_cam + step : first_cam + step - n_cam;
          const StateMask interest = pending & seeing[c];
          if (!interest) continue;
          auto& r = row[c];
          if (r[0] < 0) row_interval(cameras[c], j, k, r[0], r[1], r[2], r[3]);
          if (i < r[0] || i > r[1]) continue;
          const CameraSetup& cam = cameras[c];
          const Vec3 w = center - cam.c;
          double d = -1.0;  // |w|, computed when needed
          if (i < r[2] || i > r[3]) {
            d = w.norm();
            if (!in_fov(cam, i, j, k, w, d)) continue;
          }
          Verdict verdict;
          judge(cam, w, d, interest, object_states, scratch, verdict, true, cell_sizes[0]);
          const StateMask freed = interest & ~(verdict.occupied | verdict.blocked);
          if (freed) hint = c;
          pending &= ~freed;
        }
      }
      pending |= kept;
      for (StateMask m = pending; m; m &= m - 1) out[__builtin_ctzll(m)][v] = 1;
    };
    // Conservative mode: the states where some camera sees a whole block free (block_clear,
    // every camera from the one that last cleared a block on) need no test per voxel; blocks of
    // 4³ voxels, then the 2³ blocks of those that the cameras did not clear for every state;
    // then voxel by voxel.
    constexpr int kBlock = 4;
    auto visit = [&](int i0, int i1, int j0, int j1, int k0, int k1, int size, StateMask clear,
                     auto& self) -> void {
      if (conservative && (i1 - i0) * (j1 - j0) * (k1 - k0) > 1) {
        const Vec3 lo(box_min[0][i0], box_min[1][j0], box_min[2][k0]);
        const Vec3 hi(box_max[0][i1 - 1], box_max[1][j1 - 1], box_max[2][k1 - 1]);
        // Every camera, from the last one to clear a block on, until every state is cleared:
        // states one camera leaves (a triangle of theirs may decide a voxel) another may clear.
        // Which cameras are tried changes no label: block_clear holds for any camera.
        // States where an occupying object reaches into a voxel of the block: never free there
        // (chunk_reached), so block_clear cannot clear them; it need not try.
        StateMask held = 0;
        for (int k = k0; k < k1; ++k) {
          for (int j = j0; j < j1; ++j) {
            for (int i = i0; i < i1; ++i) held |= reached[i + nx * (j + ny * k)];
          }
        }
        for (std::size_t step = 0; step < n_cam && (clear | held) != all; ++step) {
          const std::size_t c = (block_hint + step) % n_cam;
          const StateMask open = seeing[c] & ~clear & ~held;
          const StateMask cleared = open ? block_clear(cameras[c], lo, hi, open, object_states) : 0;
          if (cleared) {
            clear |= cleared;
            block_hint = c;
          }
        }
      }
      if (conservative && size > 2 && clear != all) {
        const int half = size / 2;
        for (int k = k0; k < k1; k += half) {
          for (int j = j0; j < j1; j += half) {
            for (int i = i0; i < i1; i += half) {
              self(i, std::min(i + half, i1), j, std::min(j + half, j1), k, std::min(k + half, k1),
                   half, clear, self);
            }
          }
        }
        return;
      }
      for (int k = k0; k < k1; ++k) {
        for (int j = j0; j < j1; ++j) {
          for (int i = i0; i < i1; ++i) label(i, j, k, clear);
        }
      }
    };
    for (int k0 = k_begin; k0 < k_end; k0 += kBlock) {
      for (int j0 = 0; j0 < ny; j0 += kBlock) {
        for (int i0 = 0; i0 < nx; i0 += kBlock) {
          visit(i0, std::min(i0 + kBlock, nx), j0, std::min(j0 + kBlock, ny), k0,
                std::min(k0 + kBlock, k_end), kBlock, 0, visit);
        }
      }
    }
  }
}

std::vector<StateMask> VoxelEvaluator::Impl::seeing_states(const std::vector<CameraSetup>& cameras,
                                                           int chunk) const {
  // A camera inside an object of a state sees nothing in that state (SPEC §3.3).
  const int first = chunk * detail::kChunk;
  const int count = std::min(detail::kChunk, static_cast<int>(states.size()) - first);
  std::vector<StateMask> seeing(cameras.size(), 0);
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    for (int s = 0; s < count; ++s) {
      bool blind = false;
      for (int o : states[first + s].objects) blind = blind || cameras[c].inside_object[o];
      if (!blind) seeing[c] |= StateMask(1) << s;
    }
  }
  return seeing;
}

void VoxelEvaluator::Impl::all_raw_models(const core::CameraConfig& config,
                                          std::vector<std::vector<std::uint8_t>>& models,
                                          std::vector<CameraSetup>* cameras_out) const {
  core::check_configuration(scene, config);
  std::vector<CameraSetup> local;
  std::vector<CameraSetup>& cameras = cameras_out ? *cameras_out : local;
  cameras.clear();
  cameras.reserve(config.size());
  for (std::size_t i = 0; i < config.size(); ++i) {
    cameras.push_back(camera_setup(config[i], scene.cameras.models[i]));
  }
  models.resize(states.size());
  // raw_models() writes only the voxels in M.
  for (auto& model : models) model.assign(grid.count(), 0);
  // Slices of a few z-layers each, shared out among the threads (results do not depend on it).
  const int nz = grid.n[2];
  const int slices = options.threads <= 1 ? 1 : std::min(nz, 4 * options.threads);
  detail::parallel_for(slices, options.threads, [&](int s) {
    raw_models(cameras, nz * s / slices, nz * (s + 1) / slices, models);
  });
}

std::vector<Label> VoxelEvaluator::Impl::labels(const CameraSetup& cam, int state) const {
  const int nx = grid.n[0], ny = grid.n[1], nz = grid.n[2];
  std::vector<Label> out(grid.count(), Label::undetectable);
  for (int o : states.at(state).objects) {
    if (cam.inside_object[o]) return out;  // blind (SPEC §3.3)
  }
  const int chunk = state / detail::kChunk;
  const StateMask interest = StateMask(1) << (state % detail::kChunk);
  const StateMask* object_states = chunk_object_states[chunk].data();
  Scratch scratch;
  scratch.stamp.assign(triangles.size(), 0);
  int v = 0;
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i, ++v) {
        const Vec3 center(box_center[0][i], box_center[1][j], box_center[2][k]);
        const Vec3 w = center - cam.c;
        const double d = w.norm();
        if (!in_fov(cam, i, j, k, w, d)) continue;
        Verdict verdict;
        judge(cam, w, d, interest, object_states, scratch, verdict, false, cell_sizes[0]);
        out[v] = verdict.occupied  ? Label::occupied
                 : verdict.blocked ? Label::undetectable
                                   : Label::free;
      }
    }
  }
  return out;
}

}  // namespace camplace::voxel
