// The voxel labeller before the fast one (see legacy_labeller.hpp): a copy of
// voxel/src/labelling.cpp and of the obstacle interiors of voxel/src/setup.cpp at commit 6f1df84.
// Do not optimise.
#include "legacy_labeller.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>

#include "camplace/core/geometry.hpp"
#include "camplace/core/sensor_model.hpp"

namespace camplace::testing {

using core::Box3;
using core::Vec3;
using voxel::Label;

namespace {

struct ObjectInfo {
  const core::TriangleMesh* mesh = nullptr;
  bool occupying = false;
  Vec3 center = Vec3::Zero();
  double radius = 0.0;
  int first_triangle = 0;
  int triangle_count = 0;
};

struct ObjectCone {
  Vec3 axis = Vec3::UnitX();
  double cos_b = -1.0, sin_b = 0.0;
  bool no_cull = true;
  bool contains_camera = false;
};

struct TriangleCone {
  Vec3 edge[3];
  Vec3 normal[3];
  double near_distance = 0.0;
  bool flat = false;
};

struct CameraView {
  core::CameraSetting setting;
  std::vector<std::uint8_t> in_fov;
  std::vector<Vec3> dir;
  std::vector<double> dist;
  std::vector<double> cos_b, sin_b;
  std::vector<double> far;
  std::vector<ObjectCone> objects;
  std::vector<TriangleCone> triangles;
};

struct StateInfo {
  int time_step = 0;
  std::vector<int> objects;
};

}  // namespace

struct LegacyLabeller::Impl {
  core::Scene scene;
  voxel::Grid grid;
  bool conservative = true;
  Vec3 half_step = Vec3::Zero();
  double voxel_radius = 0.0;
  std::vector<ObjectInfo> objects;
  std::vector<std::array<Vec3, 3>> triangles;
  std::vector<StateInfo> states;
  std::vector<std::vector<std::uint8_t>> removed_by_step;

  int add_object(const core::SceneObject& object, core::ObjectRole role) {
    ObjectInfo info;
    info.mesh = &object.mesh;
    info.occupying = role == core::ObjectRole::occupying;
    info.center = object.bounds.center();
    for (const Vec3& v : object.mesh.vertices) {
      info.radius = std::max(info.radius, (v - info.center).norm());
    }
    info.first_triangle = static_cast<int>(triangles.size());
    info.triangle_count = static_cast<int>(object.mesh.triangles.size());
    for (const auto& t : object.mesh.triangles) {
      triangles.push_back(
          {object.mesh.vertices[t[0]], object.mesh.vertices[t[1]], object.mesh.vertices[t[2]]});
    }
    objects.push_back(info);
    return static_cast<int>(objects.size()) - 1;
  }

  void build() {
    using core::ObjectKind;
    const core::DynamicMode mode = scene.dynamic_mode;
    std::vector<int> static_ids;
    for (const auto& o : scene.static_obstacles) {
      static_ids.push_back(add_object(o, core::role_of(ObjectKind::static_obstacle, mode)));
    }
    for (std::size_t h = 0; h < scene.time_steps.size(); ++h) {
      const core::TimeStep& step = scene.time_steps[h];
      std::vector<int> dynamic_ids;
      for (const auto& o : step.dynamic_obstacles) {
        dynamic_ids.push_back(add_object(o, core::role_of(ObjectKind::dynamic_obstacle, mode)));
      }
      for (std::size_t l = 0; l < step.events.size(); ++l) {
        StateInfo state;
        state.time_step = static_cast<int>(h);
        state.objects = static_ids;
        state.objects.insert(state.objects.end(), dynamic_ids.begin(), dynamic_ids.end());
        for (const auto& o : step.events[l].targets) {
          state.objects.push_back(add_object(o, core::role_of(ObjectKind::target, mode)));
        }
        states.push_back(std::move(state));
      }
      removed_by_step.push_back(obstacle_interiors(step));
    }
  }

  std::vector<std::uint8_t> obstacle_interiors(const core::TimeStep& step) const {
    std::vector<std::uint8_t> removed(grid.count(), 0);
    std::vector<const core::SceneObject*> obstacles;
    for (const auto& o : scene.static_obstacles) obstacles.push_back(&o);
    for (const auto& o : step.dynamic_obstacles) obstacles.push_back(&o);
    for (int v = 0; v < grid.count(); ++v) {
      const Box3 box = grid.voxel_box(v);
      const Box3 interior{box.min + Vec3::Constant(1e-9), box.max - Vec3::Constant(1e-9)};
      for (const core::SceneObject* o : obstacles) {
        if (!o->bounds.contains(box.center())) continue;
        if (!core::inside_mesh(o->mesh, box.center())) continue;
        bool whole = true;
        if (conservative) {
          for (const auto& t : o->mesh.triangles) {
            if (core::triangle_box_overlap(o->mesh.vertices[t[0]], o->mesh.vertices[t[1]],
                                           o->mesh.vertices[t[2]], interior)) {
              whole = false;
              break;
            }
          }
        }
        if (whole) {
          removed[v] = 1;
          break;
        }
      }
    }
    return removed;
  }

  CameraView view(const core::CameraSetting& camera, int camera_index = 0) const {
    CameraView view;
    view.setting = camera;
    const core::Fov fov(camera, scene.cameras.models.at(camera_index));
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
      if (d <= voxel_radius) continue;
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

  static bool box_in_fov(const core::Fov& fov, const Box3& box) {
    for (int i = 0; i < 8; ++i) {
      const Vec3 corner((i & 1) ? box.max.x() : box.min.x(), (i & 2) ? box.max.y() : box.min.y(),
                        (i & 4) ? box.max.z() : box.min.z());
      if (!fov.contains(corner)) return false;
    }
    return true;
  }

  static bool blind(const CameraView& view, const StateInfo& state) {
    for (int o : state.objects) {
      if (view.objects[o].contains_camera) return true;
    }
    return false;
  }

  Label label(const CameraView& view, const StateInfo& state, int v, bool free_only) const {
    if (!view.in_fov[v]) return Label::undetectable;
    return conservative ? label_conservative(view, state, v, free_only)
                        : label_center(view, state, v, free_only);
  }

  static bool may_meet(const CameraView& view, int o, int v) {
    const ObjectCone& cone = view.objects[o];
    if (cone.no_cull) return true;
    const double cos_sum = view.cos_b[v] * cone.cos_b - view.sin_b[v] * cone.sin_b;
    return view.dir[v].dot(cone.axis) >= cos_sum - 1e-12;
  }

  Label label_center(const CameraView& view, const StateInfo& state, int v, bool free_only) const {
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

  Label label_conservative(const CameraView& view, const StateInfo& state, int v,
                           bool free_only) const {
    const Vec3 w = view.dir[v] * view.dist[v];
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

  bool cone_misses_box(const TriangleCone& tc, const Vec3& w) const {
    for (const Vec3& n : tc.normal) {
      if (n.dot(w) + n.cwiseAbs().dot(half_step) < 0.0) return true;
    }
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

  std::vector<std::uint8_t> raw_model(const std::vector<CameraView>& views,
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
};

LegacyLabeller::LegacyLabeller(const core::Scene& scene, const voxel::VoxelOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.scene = scene;
  std::array<int, 3> n = options.resolution;
  if (n[0] == 0 && n[1] == 0 && n[2] == 0) n = scene.voxels;
  m.conservative = options.mode == voxel::LabelMode::conservative;
  m.grid = voxel::make_grid(scene.area, n);
  m.half_step = 0.5 * m.grid.step;
  m.voxel_radius = m.half_step.norm();
  m.build();
}

LegacyLabeller::~LegacyLabeller() = default;
LegacyLabeller::LegacyLabeller(LegacyLabeller&&) noexcept = default;
LegacyLabeller& LegacyLabeller::operator=(LegacyLabeller&&) noexcept = default;

std::vector<Label> LegacyLabeller::labels(const core::CameraSetting& camera, int state) const {
  const Impl& m = *impl_;
  const CameraView view = m.view(camera);
  const StateInfo& info = m.states.at(state);
  std::vector<Label> out(m.grid.count(), Label::undetectable);
  if (Impl::blind(view, info)) return out;
  for (int v = 0; v < m.grid.count(); ++v) out[v] = m.label(view, info, v, false);
  return out;
}

std::vector<std::vector<std::uint8_t>> LegacyLabeller::raw_models(
    const core::CameraConfig& config) const {
  const Impl& m = *impl_;
  core::check_configuration(m.scene, config);
  std::vector<CameraView> views;
  views.reserve(config.size());
  for (std::size_t i = 0; i < config.size(); ++i) views.push_back(m.view(config[i], int(i)));
  std::vector<std::vector<std::uint8_t>> out;
  for (const StateInfo& state : m.states) out.push_back(m.raw_model(views, state));
  return out;
}

const voxel::Grid& LegacyLabeller::grid() const { return impl_->grid; }

}  // namespace camplace::testing
