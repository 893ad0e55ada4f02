// Labelling (SPEC §3, §5): per camera the voxels in its FOV and the cones over every object
// triangle; per voxel and state the label κ, center mode (the voxel's centre) or conservative
// mode (free only when every point of the voxel is free); the unfiltered model.
#include <cmath>
#include <limits>

#include "camplace/core/geometry.hpp"
#include "impl.hpp"

namespace camplace::voxel {

using core::Box3;
using core::Vec3;
using detail::CameraView;
using detail::ObjectCone;
using detail::ObjectInfo;
using detail::StateInfo;
using detail::TriangleCone;

CameraView VoxelEvaluator::Impl::view(const core::CameraSetting& camera) const {
  CameraView view;
  view.setting = camera;
  const core::Fov fov(camera, scene.cameras);
  const Vec3& c = camera.position;
  const int n = grid.count();
  view.in_fov.assign(n, 0);
  view.dir.resize(n);
  view.dist.resize(n);
  view.cos_b.assign(n, 1.0);
  view.sin_b.assign(n, 0.0);
  view.far.resize(n);
  for (int v = 0; v < n; ++v) {
    const Vec3 center = grid.voxel_center(v);
    const Vec3 w = center - c;
    const double d = w.norm();
    view.dist[v] = d;
    view.dir[v] = d > 0 ? Vec3(w / d) : Vec3(Vec3::UnitX());
    if (!conservative) {
      view.in_fov[v] = d > 0 && fov.contains(center);
      view.far[v] = d;
      continue;
    }
    view.far[v] = (w.cwiseAbs() + half_step).norm();
    if (d <= voxel_radius) continue;  // camera in or at the voxel: never provably free
    view.sin_b[v] = voxel_radius / d;
    view.cos_b[v] = std::sqrt(1.0 - view.sin_b[v] * view.sin_b[v]);
    view.in_fov[v] = box_in_fov(fov, grid.voxel_box(v));
  }
  view.objects.resize(objects.size());
  view.triangles.resize(triangles.size());
  for (std::size_t o = 0; o < objects.size(); ++o) {
    const ObjectInfo& info = objects[o];
    ObjectCone& cone = view.objects[o];
    const Vec3 w = info.center - c;
    const double d = w.norm();
    cone.no_cull = d <= info.radius * (1.0 + 1e-12) + 1e-12;
    if (!cone.no_cull) {
      cone.axis = w / d;
      cone.sin_b = info.radius / d;
      cone.cos_b = std::sqrt(1.0 - cone.sin_b * cone.sin_b);
    }
    cone.contains_camera = cone.no_cull && core::inside_mesh(*info.mesh, c);
  }
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& tri = triangles[t];
    TriangleCone& tc = view.triangles[t];
    const Vec3 a = tri[0] - c, b = tri[1] - c, e = tri[2] - c;
    const double det = a.dot(b.cross(e));
    tc.near_distance = std::sqrt(core::point_triangle_sq_distance(c, tri[0], tri[1], tri[2]));
    const double scale = a.norm() * b.norm() * e.norm();
    tc.flat = !(std::abs(det) > 1e-12 * scale);
    if (tc.flat) continue;
    const double sign = det > 0 ? 1.0 : -1.0;
    tc.edge[0] = a;
    tc.edge[1] = b;
    tc.edge[2] = e;
    tc.normal[0] = (sign * a.cross(b)).normalized();
    tc.normal[1] = (sign * b.cross(e)).normalized();
    tc.normal[2] = (sign * e.cross(a)).normalized();
  }
  return view;
}

bool VoxelEvaluator::Impl::box_in_fov(const core::Fov& fov, const Box3& box) const {
  // The FOV (cone with α < 90°, or pyramid, with optional far plane) is convex, so the box
  // is inside when its 8 corners are.
  for (int i = 0; i < 8; ++i) {
    const Vec3 corner((i & 1) ? box.max.x() : box.min.x(), (i & 2) ? box.max.y() : box.min.y(),
                      (i & 4) ? box.max.z() : box.min.z());
    if (!fov.contains(corner)) return false;
  }
  return true;
}

/// True when the camera stands inside an object of the state: it sees nothing (SPEC §3.3).
bool VoxelEvaluator::Impl::blind(const CameraView& view, const StateInfo& state) const {
  for (int o : state.objects) {
    if (view.objects[o].contains_camera) return true;
  }
  return false;
}

/// κ of SPEC §3 for voxel v seen by one (not blind) camera in one state. Conservative mode
/// answers `free` only when every point of the voxel is free. With `free_only` the answer
/// is exact only as free / not free (the model needs no more), which allows early exits.
Label VoxelEvaluator::Impl::label(const CameraView& view, const StateInfo& state, int v,
                                  bool free_only) const {
  if (!view.in_fov[v]) return Label::undetectable;
  return conservative ? label_conservative(view, state, v, free_only)
                      : label_center(view, state, v, free_only);
}

bool VoxelEvaluator::Impl::may_meet(const CameraView& view, int o, int v) const {
  // Bounding cones disjoint ⇔ angle(axes) > β_v + β_o ⇔ cos(angle) < cos(β_v + β_o).
  const ObjectCone& cone = view.objects[o];
  if (cone.no_cull) return true;
  const double cos_sum = view.cos_b[v] * cone.cos_b - view.sin_b[v] * cone.sin_b;
  return view.dir[v].dot(cone.axis) >= cos_sum - 1e-12;
}

Label VoxelEvaluator::Impl::label_center(const CameraView& view, const StateInfo& state, int v,
                                         bool free_only) const {
  const Vec3& c = view.setting.position;
  const Vec3& u = view.dir[v];
  double first = std::numeric_limits<double>::infinity();
  bool first_occupying = false;
  for (int o : state.objects) {
    if (!may_meet(view, o, v)) continue;
    const ObjectInfo& info = objects[o];
    for (int t = info.first_triangle; t < info.first_triangle + info.triangle_count; ++t) {
      const auto& tri = triangles[t];
      const double hit = core::ray_triangle_hit(c, u, tri[0], tri[1], tri[2]);
      if (free_only && hit > 0.0 && hit <= view.dist[v]) return Label::undetectable;
      if (hit > 0.0 && hit < first) {
        first = hit;
        first_occupying = info.occupying;
      }
    }
  }
  if (first_occupying) return Label::occupied;
  return view.dist[v] < first ? Label::free : Label::undetectable;
}

Label VoxelEvaluator::Impl::label_conservative(const CameraView& view, const StateInfo& state,
                                               int v, bool free_only) const {
  // Free for every point p of the box B when (SPEC §5): no object triangle meets a segment
  // [c, p] (its cone misses B's cone, or it lies wholly beyond B), and no triangle of an
  // occupying object lies on any ray through B (its cone misses B's cone).
  const Vec3 w = view.dir[v] * view.dist[v];  // camera → voxel centre
  Label verdict = Label::free;
  for (int o : state.objects) {
    if (!may_meet(view, o, v)) continue;
    const ObjectInfo& info = objects[o];
    for (int t = info.first_triangle; t < info.first_triangle + info.triangle_count; ++t) {
      const TriangleCone& tc = view.triangles[t];
      if (tc.flat) continue;
      if (!info.occupying && tc.near_distance >= view.far[v]) continue;
      if (cone_misses_box(tc, w)) continue;
      if (info.occupying) return Label::occupied;
      if (free_only) return Label::undetectable;
      verdict = Label::undetectable;
    }
  }
  return verdict;
}

/// True when the triangle's infinite cone and the voxel box (centre at w from the camera) are
/// disjoint, by the separating-axis theorem for two convex polyhedra: the cone's 3 planes,
/// the box's 3 face normals and the 9 cross products of cone edges and box edges. Exact up to
/// rounding; touching counts as meeting.
bool VoxelEvaluator::Impl::cone_misses_box(const TriangleCone& tc, const Vec3& w) const {
  // Cone planes first: cheapest and most often decisive.
  for (const Vec3& n : tc.normal) {
    if (n.dot(w) + n.cwiseAbs().dot(half_step) < 0.0) return true;
  }
  // Axis L: the cone projects to [0, ∞) or (−∞, 0] (relative to the camera) when its edges
  // all project to one side, else to the whole line; the box to L·w ± Σ|L_i|·h_i.
  auto separates = [&](const Vec3& axis) {
    const double pa = axis.dot(tc.edge[0]), pb = axis.dot(tc.edge[1]), pc = axis.dot(tc.edge[2]);
    const double radius = axis.cwiseAbs().dot(half_step);
    const double mid = axis.dot(w);
    if (pa >= 0.0 && pb >= 0.0 && pc >= 0.0) return mid + radius < 0.0;
    if (pa <= 0.0 && pb <= 0.0 && pc <= 0.0) return mid - radius > 0.0;
    return false;
  };
  for (int i = 0; i < 3; ++i) {
    if (separates(Vec3::Unit(i))) return true;
  }
  for (const Vec3& e : tc.edge) {
    for (int i = 0; i < 3; ++i) {
      if (separates(e.cross(Vec3::Unit(i)))) return true;
    }
  }
  return false;
}

/// Model before filtering: 1 where no camera sees the voxel free, minus obstacle interiors.
std::vector<std::uint8_t> VoxelEvaluator::Impl::raw_model(const std::vector<CameraView>& views,
                                                          const StateInfo& state) const {
  std::vector<const CameraView*> seeing;
  for (const CameraView& view : views) {
    if (!blind(view, state)) seeing.push_back(&view);
  }
  const auto& removed = removed_by_step[state.time_step];
  std::vector<std::uint8_t> model(grid.count(), 0);
  for (int v = 0; v < grid.count(); ++v) {
    if (removed[v]) continue;
    bool seen_free = false;
    for (const CameraView* view : seeing) {
      if (label(*view, state, v, true) == Label::free) {
        seen_free = true;
        break;
      }
    }
    model[v] = !seen_free;
  }
  return model;
}

std::vector<CameraView> VoxelEvaluator::Impl::views(const core::CameraConfig& config) const {
  core::check_configuration(scene, config);
  std::vector<CameraView> out;
  out.reserve(config.size());
  for (const auto& camera : config) out.push_back(view(camera));
  return out;
}
}  // namespace camplace::voxel
