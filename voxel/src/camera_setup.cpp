// Per camera, once per evaluation (SPEC §3): everything the labeller needs that does not depend
// on the voxel, in five steps — the camera's frame and FOV numbers, the objects that hold the
// camera (blind in their states), the cone over each triangle, back-face culling, and the
// triangles' projections sorted into bins of the image plane (docs/design/labelling.md L1, L3).
#include <algorithm>
#include <cmath>
#include <limits>

#include "camplace/core/geometry.hpp"
#include "image_plane.hpp"
#include "impl.hpp"

namespace camplace::voxel {

using core::Vec3;
using detail::BinRange;
using detail::CameraSetup;
using detail::kMargin;
using detail::ObjectInfo;
using detail::TriangleCone;

namespace {

using Triangles = std::vector<std::array<Vec3, 3>>;

/// The camera's frame (axis, ex right, ey up), a voxel box's half extents in it, and the FOV's
/// numbers: near and far planes, the (bounding) cone's half angle, the row test's widened cone.
CameraSetup camera_frame(const core::CameraSetting& camera, const core::CameraModel& model,
                         const Vec3& half_step) {
  CameraSetup cam;
  cam.setting = camera;
  cam.fov.emplace(camera, model);
  const core::Fov& fov = *cam.fov;
  cam.c = camera.position;
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
  // Bins over the FOV's section at unit depth: the cone's (which holds the pyramid), or the
  // frustum's image rectangle, tan(H/2) × tan(V/2) along ex (right) and ey (up), both turned
  // by the roll. Bins only sort: a triangle outside them lands in an edge bin.
  if (model.fov == core::FovShape::frustum) {
    cam.image_half = {std::tan(0.5 * model.horizontal), std::tan(0.5 * model.vertical)};
  } else {
    cam.image_half = {std::tan(half_angle), std::tan(half_angle)};
  }
  return cam;
}

/// Per object: whether it holds the camera at c. SPEC §3.3 with one convention in both
/// pipelines: a camera in the closed object, on its surface too, is blind (its rays start on the
/// object). The exact pipeline decides this exactly; here a camera within a rounding distance of
/// the surface counts as on it, which only makes the model larger, never smaller (conservative
/// mode stays ⊇ exact).
std::vector<std::uint8_t> objects_holding(const std::vector<ObjectInfo>& objects, const Vec3& c) {
  std::vector<std::uint8_t> inside(objects.size(), 0);
  for (std::size_t o = 0; o < objects.size(); ++o) {
    const ObjectInfo& info = objects[o];
    const double d = (info.center - c).norm();
    const double on_surface = 1e-9 * (info.radius + info.center.norm() + c.norm());
    const bool near = d <= info.radius + on_surface;
    inside[o] = near && core::point_solid_sq_distance(*info.mesh, c) <= on_surface * on_surface;
  }
  return inside;
}

/// The cone from the camera over each triangle (conservative mode; center mode needs only the
/// nearest distance and flatness). Returns per triangle det / scale, 0 when the camera is in its
/// plane (the tilt that back-face culling reads).
std::vector<double> triangle_cones(CameraSetup& cam, const Triangles& triangles,
                                   const Vec3& half_step, bool conservative) {
  const Vec3& c = cam.c;
  cam.triangles.resize(triangles.size());
  std::vector<double> tilt(triangles.size(), 0.0);
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
    // The voxel-independent part of the separating-axis test (the edges' projections), once
    // per camera.
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
  return tilt;
}

/// Back-face culling (both modes; docs/design/labelling.md L3): det > 0 means the camera is
/// behind the triangle's plane. An object is culled only when it is oriented outward, the camera
/// is outside it and clear of its surface, and no triangle is near edge-on; a near miss of a
/// culled object's front face makes judge_conservative() test its back faces too.
void cull_back_faces(CameraSetup& cam, const std::vector<ObjectInfo>& objects,
                     const std::vector<double>& tilt) {
  for (std::size_t o = 0; o < objects.size(); ++o) {
    const ObjectInfo& info = objects[o];
    const int end = info.first_triangle + info.triangle_count;
    double clearance = std::numeric_limits<double>::infinity();
    bool clear_tilts = true;
    for (int t = info.first_triangle; t < end; ++t) {
      clearance = std::min(clearance, cam.triangles[t].near_distance);
      clear_tilts = clear_tilts && std::abs(tilt[t]) > 1e-9;
    }
    const double scale = (info.center - cam.c).norm() + info.radius;
    const bool cull =
        info.outward && !cam.inside_object[o] && clearance > 1e-9 * scale && clear_tilts;
    for (int t = info.first_triangle; t < end; ++t) {
      cam.triangles[t].back = cull && tilt[t] > 0;
      cam.triangles[t].touch = cull;
    }
  }
}

/// Each triangle's projection (X/Z, Y/Z): its padded bounding rectangle and edge lines, or the
/// `everywhere` list when it is not wholly in front of the camera; then the coarse bins (the
/// triangles whose rectangle, padded by the margin, covers each bin). Conservative mode leaves
/// out the triangles it never tests (flat or culled).
void project_into_bins(CameraSetup& cam, const Triangles& triangles, int bins, bool conservative) {
  cam.bins = bins;
  for (int a = 0; a < 2; ++a) cam.bin_scale[a] = cam.bins / (2.0 * cam.image_half[a]);
  const int bin_count = cam.bins * cam.bins;
  std::vector<BinRange> ranges(triangles.size());
  const double inf = std::numeric_limits<double>::infinity();
  cam.rect.assign(triangles.size(), {-inf, inf, -inf, inf});
  cam.lines.assign(triangles.size(), {});
  cam.bin_start.assign(bin_count + 1, 0);
  cam.binned.assign(triangles.size(), 0);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    if (cam.triangles[t].back || (conservative && cam.triangles[t].flat)) continue;
    double xlo = inf, xhi = -inf, ylo = inf, yhi = -inf;
    double px[3], py[3];
    bool projectable = true;
    for (int v = 0; v < 3; ++v) {
      const Vec3 q = triangles[t][v] - cam.c;
      const double z = q.dot(cam.axis);
      if (!(z > kMargin * q.norm())) {
        projectable = false;
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
    if (!projectable) {
      cam.everywhere.push_back(static_cast<int>(t));
      continue;
    }
    cam.binned[t] = 1;
    ranges[t] = detail::bin_range(cam, xlo, xhi, ylo, yhi);
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
    if (!cam.binned[t]) continue;
    for (int by = ranges[t].y0; by <= ranges[t].y1; ++by) {
      for (int bx = ranges[t].x0; bx <= ranges[t].x1; ++bx) {
        cam.bin_items[fill[by * cam.bins + bx]++] = static_cast<int>(t);
      }
    }
  }
}

/// Conservative mode: bins twice as fine with every rectangle widened by half a (coarse) bin, so
/// that a voxel whose projection is at most that wide finds every triangle it can meet in the
/// bin of its rectangle's centre, each once (no repeats to skip). Center mode: none.
void fill_wide_bins(CameraSetup& cam, bool conservative) {
  cam.wide_bins = 2 * cam.bins;
  for (int a = 0; a < 2; ++a) {
    cam.wide_scale[a] = cam.wide_bins / (2.0 * cam.image_half[a]);
    cam.widen[a] = 0.5 / cam.bin_scale[a];
  }
  const int wide_count = cam.wide_bins * cam.wide_bins;
  cam.wide_start.assign(wide_count + 1, 0);
  cam.wide_items.clear();
  if (!conservative) return;
  const std::size_t count = cam.rect.size();
  std::vector<BinRange> wide(count);
  for (std::size_t t = 0; t < count; ++t) {
    if (!cam.binned[t]) continue;
    const auto& r = cam.rect[t];
    wide[t] = {detail::wide_of(cam, r[0] - cam.widen[0]), detail::wide_of(cam, r[1] + cam.widen[0]),
               detail::wide_of(cam, r[2] - cam.widen[1], 1),
               detail::wide_of(cam, r[3] + cam.widen[1], 1)};
    for (int by = wide[t].y0; by <= wide[t].y1; ++by) {
      for (int bx = wide[t].x0; bx <= wide[t].x1; ++bx) {
        ++cam.wide_start[by * cam.wide_bins + bx + 1];
      }
    }
  }
  for (int b = 0; b < wide_count; ++b) cam.wide_start[b + 1] += cam.wide_start[b];
  cam.wide_items.resize(cam.wide_start[wide_count]);
  std::vector<int> next(cam.wide_start.begin(), cam.wide_start.end() - 1);
  for (std::size_t t = 0; t < count; ++t) {
    if (!cam.binned[t]) continue;
    for (int by = wide[t].y0; by <= wide[t].y1; ++by) {
      for (int bx = wide[t].x0; bx <= wide[t].x1; ++bx) {
        cam.wide_items[next[by * cam.wide_bins + bx]++] = static_cast<int>(t);
      }
    }
  }
}

}  // namespace

CameraSetup VoxelEvaluator::Impl::camera_setup(const core::CameraSetting& camera,
                                               const core::CameraModel& model) const {
  CameraSetup cam = camera_frame(camera, model, half_step);
  cam.inside_object = objects_holding(objects, cam.c);
  const std::vector<double> tilt = triangle_cones(cam, triangles, half_step, conservative);
  cull_back_faces(cam, objects, tilt);
  // Center mode looks up one bin per voxel: fine bins. Conservative mode looks up the bins under
  // the box's projection and then each triangle's rectangle: coarse bins (fewer repeats).
  const int n_max = *std::max_element(grid.n.begin(), grid.n.end());
  const int bins = conservative ? std::clamp(n_max / 3, 8, 32) : std::clamp(n_max, 16, 64);
  project_into_bins(cam, triangles, bins, conservative);
  fill_wide_bins(cam, conservative);
  return cam;
}

}  // namespace camplace::voxel
