// The voxel pipeline (SPEC §3–5). Hot path: plain arrays and Eigen, no CGAL.
#include "camplace/voxel/evaluator.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "camplace/core/distance.hpp"
#include "camplace/core/err.hpp"
#include "camplace/core/error.hpp"

namespace camplace::voxel {

using core::Box3;
using core::Vec3;

core::Box3 Grid::voxel_box(int index) const {
  const int i = index % n[0], j = (index / n[0]) % n[1], k = index / (n[0] * n[1]);
  Box3 box;
  box.min = area.min + Vec3(i * step.x(), j * step.y(), k * step.z());
  box.max = box.min + step;
  return box;
}

core::Vec3 Grid::voxel_center(int index) const { return voxel_box(index).center(); }

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// One object of the scene with its fixed role (SPEC §3: what a first hit on it means).
struct ObjectInfo {
  const core::TriangleMesh* mesh = nullptr;
  bool occupying = false;  ///< target, or dynamic obstacle in masked mode
  Vec3 center = Vec3::Zero();
  double radius = 0.0;  ///< bounding sphere
  int first_triangle = 0;
  int triangle_count = 0;
};

/// Per camera and object: the cone from the camera around the object's bounding sphere.
struct ObjectCone {
  Vec3 axis = Vec3::UnitX();
  double cos_b = -1.0, sin_b = 0.0;
  bool no_cull = true;          ///< camera inside the bounding sphere
  bool contains_camera = false;  ///< camera inside the solid: it is blind in this state
};

/// Per camera and triangle: the infinite cone from the camera over the triangle, as its three
/// edge rays (vertex − camera) and the inward unit normals of its three planes, and the
/// triangle's nearest distance.
struct TriangleCone {
  Vec3 edge[3];
  Vec3 normal[3];
  double near_distance = 0.0;
  bool flat = false;  ///< camera in the triangle's plane: the cone has no volume
};

/// Everything about one camera that does not depend on the state.
struct CameraView {
  core::CameraSetting setting;
  std::vector<std::uint8_t> in_fov;  ///< per voxel
  std::vector<Vec3> dir;             ///< unit direction camera → voxel centre
  std::vector<double> dist;          ///< camera → voxel centre
  std::vector<double> cos_b, sin_b;  ///< angular radius of the voxel's bounding ball (0 centre)
  std::vector<double> far;           ///< farthest voxel point from the camera
  std::vector<ObjectCone> objects;
  std::vector<TriangleCone> triangles;
};

struct StateInfo {
  int time_step = 0, event = 0;
  double weight = 0.0;
  double d_true = 0.0;
  std::vector<int> objects;  ///< indices into Impl::objects
};

}  // namespace

struct VoxelEvaluator::Impl {
  core::Scene scene;
  VoxelOptions options;
  Grid grid;
  bool conservative = true;
  Vec3 half_step = Vec3::Zero();
  double voxel_radius = 0.0;
  double voxel_volume = 0.0;
  std::vector<ObjectInfo> objects;
  std::vector<std::array<Vec3, 3>> triangles;  ///< all objects' triangles, world frame
  std::vector<StateInfo> states;
  std::vector<std::vector<std::uint8_t>> removed_by_step;  ///< obstacle interiors per step
  std::vector<std::vector<double>> critical_sq_by_step;    ///< d(C_h, voxel)² per step
  double err_lower_bound = 0.0;                            ///< conservative mode only

  int add_object(const core::SceneObject& object, bool occupying) {
    ObjectInfo info;
    info.mesh = &object.mesh;
    info.occupying = occupying;
    info.center = object.bounds.center();
    for (const Vec3& v : object.mesh.vertices) {
      info.radius = std::max(info.radius, (v - info.center).norm());
    }
    info.first_triangle = static_cast<int>(triangles.size());
    info.triangle_count = static_cast<int>(object.mesh.triangles.size());
    for (const auto& t : object.mesh.triangles) {
      triangles.push_back({object.mesh.vertices[t[0]], object.mesh.vertices[t[1]],
                           object.mesh.vertices[t[2]]});
    }
    objects.push_back(info);
    return static_cast<int>(objects.size()) - 1;
  }

  void build() {
    const bool masked = scene.dynamic_mode == core::DynamicMode::masked;
    std::vector<int> static_ids;
    for (const auto& o : scene.static_obstacles) static_ids.push_back(add_object(o, false));
    const auto all_states = core::states(scene);
    for (std::size_t h = 0; h < scene.time_steps.size(); ++h) {
      const core::TimeStep& step = scene.time_steps[h];
      std::vector<int> dynamic_ids;
      for (const auto& o : step.dynamic_obstacles) dynamic_ids.push_back(add_object(o, masked));
      for (std::size_t l = 0; l < step.events.size(); ++l) {
        StateInfo state;
        state.time_step = static_cast<int>(h);
        state.event = static_cast<int>(l);
        state.weight = step.events[l].weight;
        state.objects = static_ids;
        state.objects.insert(state.objects.end(), dynamic_ids.begin(), dynamic_ids.end());
        for (const auto& o : step.events[l].targets) state.objects.push_back(add_object(o, true));
        state.d_true = std::sqrt(core::true_squared_distance(scene, {state.time_step, state.event}).value);
        states.push_back(std::move(state));
      }
      removed_by_step.push_back(obstacle_interiors(step));
      critical_sq_by_step.push_back(critical_distances(step));
    }
    if (conservative) err_lower_bound = lower_bound();
  }

  /// Err if the model held only the voxels touching a target (see err_lower_bound()).
  double lower_bound() const {
    std::vector<core::ErrTerm> terms;
    for (const StateInfo& state : states) {
      const core::Event& event = scene.time_steps[state.time_step].events[state.event];
      const auto& critical = critical_sq_by_step[state.time_step];
      double best = std::numeric_limits<double>::infinity();
      for (int v = 0; v < grid.count(); ++v) {
        if (critical[v] >= best) continue;
        const Box3 box = grid.voxel_box(v);
        for (const core::SceneObject& target : event.targets) {
          if (core::box_solid_sq_distance(target.mesh, box) == 0.0) {
            best = critical[v];
            break;
          }
        }
      }
      terms.push_back({state.weight, state.d_true, std::sqrt(best)});
    }
    return core::error_functional(terms);
  }

  /// Voxels removed as obstacle interior (SPEC §4–5): centre inside (center mode) or the
  /// whole voxel inside (conservative mode) an obstacle of the time step.
  std::vector<std::uint8_t> obstacle_interiors(const core::TimeStep& step) const {
    std::vector<std::uint8_t> removed(grid.count(), 0);
    std::vector<const core::SceneObject*> obstacles;
    for (const auto& o : scene.static_obstacles) obstacles.push_back(&o);
    for (const auto& o : step.dynamic_obstacles) obstacles.push_back(&o);
    for (int v = 0; v < grid.count(); ++v) {
      const Box3 box = grid.voxel_box(v);
      // The voxel is inside the closed solid when its centre is and no triangle reaches into
      // its interior: test against the box shrunk by 1e-9 m so that faces lying on the voxel's
      // boundary (grid-aligned obstacles) do not count.
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

  /// Squared distance from the critical objects C_h to each voxel's box (conservative) or
  /// centre (center mode), SPEC §5.
  std::vector<double> critical_distances(const core::TimeStep& step) const {
    std::vector<double> out(grid.count(), std::numeric_limits<double>::infinity());
    for (int v = 0; v < grid.count(); ++v) {
      for (const core::SceneObject& c : step.critical) {
        const double d = conservative ? core::box_solid_sq_distance(c.mesh, grid.voxel_box(v))
                                      : core::point_solid_sq_distance(c.mesh, grid.voxel_center(v));
        out[v] = std::min(out[v], d);
      }
    }
    return out;
  }

  CameraView view(const core::CameraSetting& camera) const {
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

  bool box_in_fov(const core::Fov& fov, const Box3& box) const {
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
  bool blind(const CameraView& view, const StateInfo& state) const {
    for (int o : state.objects) {
      if (view.objects[o].contains_camera) return true;
    }
    return false;
  }

  /// κ of SPEC §3 for voxel v seen by one (not blind) camera in one state. Conservative mode
  /// answers `free` only when every point of the voxel is free. With `free_only` the answer
  /// is exact only as free / not free (the model needs no more), which allows early exits.
  Label label(const CameraView& view, const StateInfo& state, int v, bool free_only) const {
    if (!view.in_fov[v]) return Label::undetectable;
    return conservative ? label_conservative(view, state, v, free_only)
                        : label_center(view, state, v, free_only);
  }

  bool may_meet(const CameraView& view, int o, int v) const {
    // Bounding cones disjoint ⇔ angle(axes) > β_v + β_o ⇔ cos(angle) < cos(β_v + β_o).
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
  bool cone_misses_box(const TriangleCone& tc, const Vec3& w) const {
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

  struct FilterResult {
    int kept = 0, removed = 0;
  };

  /// 6-connected components; removes those below the plausibility thresholds (SPEC §4–5).
  FilterResult filter(std::vector<std::uint8_t>& model) const {
    const int nx = grid.n[0], ny = grid.n[1], nz = grid.n[2];
    const double min_volume = scene.plausibility.min_volume;
    const double min_height = scene.plausibility.min_height;
    std::vector<int> component(model.size(), -1);
    std::vector<int> stack, members;
    FilterResult result;
    int next = 0;
    for (int start = 0; start < grid.count(); ++start) {
      if (!model[start] || component[start] >= 0) continue;
      members.clear();
      stack.assign(1, start);
      component[start] = next;
      int kmin = nz, kmax = -1;
      while (!stack.empty()) {
        const int v = stack.back();
        stack.pop_back();
        members.push_back(v);
        const int i = v % nx, j = (v / nx) % ny, k = v / (nx * ny);
        kmin = std::min(kmin, k);
        kmax = std::max(kmax, k);
        auto visit = [&](int w) {
          if (model[w] && component[w] < 0) {
            component[w] = next;
            stack.push_back(w);
          }
        };
        if (i > 0) visit(v - 1);
        if (i + 1 < nx) visit(v + 1);
        if (j > 0) visit(v - nx);
        if (j + 1 < ny) visit(v + nx);
        if (k > 0) visit(v - nx * ny);
        if (k + 1 < nz) visit(v + nx * ny);
      }
      ++next;
      const double volume = static_cast<double>(members.size()) * voxel_volume;
      const double height = (kmax - kmin + 1) * grid.step.z();
      if (volume < min_volume || height < min_height) {
        for (int v : members) model[v] = 0;
        ++result.removed;
      } else {
        ++result.kept;
      }
    }
    return result;
  }

  std::vector<CameraView> views(const core::CameraConfig& config) const {
    if (static_cast<int>(config.size()) != scene.cameras.count) {
      throw core::InputError(scene.file, "/cameras/count",
                             "the configuration has " + std::to_string(config.size()) +
                                 " cameras, the scene " + std::to_string(scene.cameras.count));
    }
    std::vector<CameraView> out;
    out.reserve(config.size());
    for (const auto& camera : config) out.push_back(view(camera));
    return out;
  }
};

VoxelEvaluator::VoxelEvaluator(const core::Scene& scene, const VoxelOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.scene = scene;
  m.options = options;
  std::array<int, 3> n = options.resolution;
  if (n[0] == 0 && n[1] == 0 && n[2] == 0) n = scene.voxels;
  for (int i = 0; i < 3; ++i) {
    if (n[i] < 1 || n[i] > 4096) {
      throw core::InputError(scene.file, "resolution", "every voxel count must lie in [1, 4096]");
    }
  }
  if (static_cast<long long>(n[0]) * n[1] * n[2] > core::kMaxVoxels) {
    throw core::InputError(scene.file, "resolution",
                           "too many voxels (" + std::to_string(static_cast<long long>(n[0]) * n[1] * n[2]) +
                               "); at most " + std::to_string(core::kMaxVoxels));
  }
  m.options.resolution = n;
  m.conservative = options.mode == LabelMode::conservative;
  m.grid.area = scene.area;
  m.grid.n = n;
  m.grid.step = scene.area.size().cwiseQuotient(Vec3(n[0], n[1], n[2]));
  m.half_step = 0.5 * m.grid.step;
  m.voxel_radius = m.half_step.norm();
  m.voxel_volume = m.grid.step.prod();
  m.build();
}

VoxelEvaluator::~VoxelEvaluator() = default;
VoxelEvaluator::VoxelEvaluator(VoxelEvaluator&&) noexcept = default;
VoxelEvaluator& VoxelEvaluator::operator=(VoxelEvaluator&&) noexcept = default;

Evaluation VoxelEvaluator::evaluate(const core::CameraConfig& config) const {
  const Impl& m = *impl_;
  const auto start = Clock::now();
  Evaluation result;
  auto t0 = Clock::now();
  const std::vector<CameraView> views = m.views(config);
  result.timing.labelling_ms += ms_since(t0);
  std::vector<core::ErrTerm> terms;
  const double diagonal = m.scene.area.diagonal();
  for (const StateInfo& state : m.states) {
    t0 = Clock::now();
    std::vector<std::uint8_t> model = m.raw_model(views, state);
    result.timing.labelling_ms += ms_since(t0);
    t0 = Clock::now();
    const Impl::FilterResult filtered = m.filter(model);
    result.timing.clustering_ms += ms_since(t0);
    t0 = Clock::now();
    const auto& critical = m.critical_sq_by_step[state.time_step];
    double best = std::numeric_limits<double>::infinity();
    int count = 0;
    for (int v = 0; v < m.grid.count(); ++v) {
      if (!model[v]) continue;
      ++count;
      best = std::min(best, critical[v]);
    }
    StateResult out;
    out.time_step = state.time_step;
    out.event = state.event;
    out.weight = state.weight;
    out.d_true = state.d_true;
    out.d_model = count > 0 ? std::sqrt(best) : diagonal;  // d(C, ∅) := diagonal (SPEC §4)
    out.model_volume = count * m.voxel_volume;
    out.components = filtered.kept;
    out.components_removed = filtered.removed;
    terms.push_back({out.weight, out.d_true, out.d_model});
    result.states.push_back(out);
    result.timing.distance_ms += ms_since(t0);
  }
  result.err = core::error_functional(terms);
  result.timing.total_ms = ms_since(start);
  return result;
}

double VoxelEvaluator::err(const core::CameraConfig& config) const { return evaluate(config).err; }

std::vector<Label> VoxelEvaluator::labels(const core::CameraSetting& camera, int state) const {
  const Impl& m = *impl_;
  const CameraView view = m.view(camera);
  const StateInfo& info = m.states.at(state);
  std::vector<Label> out(m.grid.count(), Label::undetectable);
  if (m.blind(view, info)) return out;
  for (int v = 0; v < m.grid.count(); ++v) out[v] = m.label(view, info, v, false);
  return out;
}

std::vector<std::uint8_t> VoxelEvaluator::model(const core::CameraConfig& config,
                                                int state) const {
  const Impl& m = *impl_;
  std::vector<std::uint8_t> out = m.raw_model(m.views(config), m.states.at(state));
  m.filter(out);
  return out;
}

double VoxelEvaluator::err_lower_bound() const { return impl_->err_lower_bound; }
const Grid& VoxelEvaluator::grid() const { return impl_->grid; }
const core::Scene& VoxelEvaluator::scene() const { return impl_->scene; }
const VoxelOptions& VoxelEvaluator::options() const { return impl_->options; }

}  // namespace camplace::voxel
