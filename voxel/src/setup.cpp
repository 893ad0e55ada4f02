// Set-up of the voxel evaluator: everything that does not depend on the cameras — the objects
// with their roles, obstacle interiors, true distances, voxel-to-critical distances and the
// conservative lower bound of Err.
#include <algorithm>
#include <cmath>
#include <limits>

#include "camplace/core/distance.hpp"
#include "camplace/core/err.hpp"
#include "impl.hpp"
#include "solid_distance.hpp"

namespace camplace::voxel {

using core::Box3;
using core::Vec3;

int VoxelEvaluator::Impl::add_object(const core::SceneObject& object, core::ObjectRole role) {
  detail::ObjectInfo info;
  info.mesh = &object.mesh;
  info.occupying = role == core::ObjectRole::occupying;
  info.center = object.bounds.center();
  for (const Vec3& v : object.mesh.vertices) {
    info.radius = std::max(info.radius, (v - info.center).norm());
  }
  info.outward = core::signed_volume(object.mesh) > 0.0;
  info.first_triangle = static_cast<int>(triangles.size());
  info.triangle_count = static_cast<int>(object.mesh.triangles.size());
  for (const auto& t : object.mesh.triangles) {
    triangles.push_back(
        {object.mesh.vertices[t[0]], object.mesh.vertices[t[1]], object.mesh.vertices[t[2]]});
    triangle_object.push_back(static_cast<int>(objects.size()));
  }
  objects.push_back(info);
  return static_cast<int>(objects.size()) - 1;
}

void VoxelEvaluator::Impl::build() {
  using core::ObjectKind;
  // Voxel bounds per axis exactly as Grid::voxel_box computes them.
  for (int a = 0; a < 3; ++a) {
    for (int i = 0; i < grid.n[a]; ++i) {
      const double lo = grid.area.min[a] + i * grid.step[a];
      const double hi = lo + grid.step[a];
      box_min[a].push_back(lo);
      box_max[a].push_back(hi);
      box_center[a].push_back(0.5 * (lo + hi));
    }
  }
  const core::DynamicMode mode = scene.dynamic_mode;
  // Objects are shared by the states they belong to, in the order of core::state_objects:
  // static obstacles, the step's dynamic obstacles, the event's targets.
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
      detail::StateInfo state;
      state.time_step = static_cast<int>(h);
      state.event = static_cast<int>(l);
      state.weight = step.events[l].weight;
      state.objects = static_ids;
      state.objects.insert(state.objects.end(), dynamic_ids.begin(), dynamic_ids.end());
      for (const auto& o : step.events[l].targets) {
        state.objects.push_back(add_object(o, core::role_of(ObjectKind::target, mode)));
      }
      state.d_true =
          std::sqrt(core::true_squared_distance(scene, {state.time_step, state.event}).value);
      states.push_back(std::move(state));
    }
    removed_by_step.push_back(obstacle_interiors(step));
    std::vector<detail::IndexedSolid> solids;
    for (const core::SceneObject& c : step.critical) solids.push_back(detail::index_solid(c.mesh));
    critical_lb_by_step.push_back(critical_distances(solids));
    critical_solids_by_step.push_back(std::move(solids));
    critical_by_step.emplace_back(new std::atomic<double>[conservative ? grid.count() : 0]);
    for (int v = 0; conservative && v < grid.count(); ++v) {
      critical_by_step.back()[v].store(std::numeric_limits<double>::quiet_NaN(),
                                       std::memory_order_relaxed);
    }
  }
  // State bit masks per chunk of 64 states: per object and per time step.
  for (std::size_t first = 0; first < states.size(); first += detail::kChunk) {
    std::vector<detail::StateMask> by_object(objects.size(), 0);
    std::vector<detail::StateMask> by_step(scene.time_steps.size(), 0);
    for (std::size_t s = first; s < std::min(states.size(), first + detail::kChunk); ++s) {
      const detail::StateMask bit = detail::StateMask(1) << (s - first);
      for (int o : states[s].objects) by_object[o] |= bit;
      by_step[states[s].time_step] |= bit;
    }
    chunk_object_states.push_back(std::move(by_object));
    chunk_step_states.push_back(std::move(by_step));
  }
  if (conservative) err_lower_bound = lower_bound();
}

/// Err if the model held only the voxels touching a target (see err_lower_bound()).
double VoxelEvaluator::Impl::lower_bound() const {
  std::vector<core::ErrTerm> terms;
  for (const detail::StateInfo& state : states) {
    const core::Event& event = scene.time_steps[state.time_step].events[state.event];
    const auto& lb = critical_lb_by_step[state.time_step];
    std::vector<detail::IndexedSolid> targets;
    for (const core::SceneObject& target : event.targets) {
      targets.push_back(detail::index_solid(target.mesh));
    }
    double best = std::numeric_limits<double>::infinity();
    for (int v = 0; v < grid.count(); ++v) {
      if (lb[v] >= best) continue;  // so is the value
      // Touching (core::box_solid_sq_distance == 0): the culled distance is exact at 0.
      if (detail::box_solids_sq_distance(targets, grid.voxel_box(v), 0.0) == 0.0) {
        best = std::min(best, critical_sq(state.time_step, v));
      }
    }
    terms.push_back({state.weight, state.d_true, std::sqrt(best)});
  }
  return core::error_functional(terms);
}

/// Voxels removed as obstacle interior (SPEC §4–5): centre inside (center mode) or the whole
/// voxel inside (conservative mode) an obstacle of the time step (core::is_obstacle: static and
/// dynamic obstacles, not targets).
std::vector<std::uint8_t> VoxelEvaluator::Impl::obstacle_interiors(
    const core::TimeStep& step) const {
  std::vector<std::uint8_t> removed(grid.count(), 0);
  std::vector<const core::SceneObject*> obstacles;
  for (const auto& o : scene.static_obstacles) obstacles.push_back(&o);
  for (const auto& o : step.dynamic_obstacles) obstacles.push_back(&o);
  for (int v = 0; v < grid.count(); ++v) {
    const Box3 box = grid.voxel_box(v);
    // The voxel is inside the closed solid when its centre is and no triangle reaches into its
    // interior: test against the box shrunk by 1e-9 m so that faces lying on the voxel's
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

/// Lower bounds of d(C_h, voxel)² (SPEC §5) for one step: from the distance of the voxel's
/// centre to the critical solids (core::point_solid_sq_distance, min over C_h, the same doubles
/// by culling below the vertices' bound), less the voxel's radius in conservative mode (every
/// point of the box is within it of the centre; margins of 1e-12 cover rounding). In center
/// mode they are the values themselves.
std::vector<double> VoxelEvaluator::Impl::critical_distances(
    const std::vector<detail::IndexedSolid>& solids) const {
  std::vector<double> out(grid.count(), std::numeric_limits<double>::infinity());
  if (solids.empty()) return out;
  const int nx = grid.n[0], ny = grid.n[1], nz = grid.n[2];
  detail::parallel_for(nz, options.threads, [&](int k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const Vec3 p(box_center[0][i], box_center[1][j], box_center[2][k]);
        const double sq =
            detail::point_solids_sq_distance(solids, p, detail::vertex_upper_bound(solids, p));
        double& lb = out[i + nx * (j + ny * k)];
        if (!conservative) {
          lb = sq;
          continue;
        }
        const double gap = std::sqrt(sq) * (1.0 - 1e-12) - voxel_radius * (1.0 + 1e-12) - 1e-12;
        lb = gap > 0.0 ? gap * gap : 0.0;
      }
    }
  });
  return out;
}

double VoxelEvaluator::Impl::critical_sq(int time_step, int v) const {
  if (!conservative) return critical_lb_by_step[time_step][v];
  std::atomic<double>& slot = critical_by_step[time_step][v];
  const double known = slot.load(std::memory_order_relaxed);
  if (!std::isnan(known)) return known;
  const auto& solids = critical_solids_by_step[time_step];
  const int nx = grid.n[0], ny = grid.n[1];
  const int i = v % nx, j = (v / nx) % ny, k = v / (nx * ny);
  const Box3 box{Vec3(box_min[0][i], box_min[1][j], box_min[2][k]),
                 Vec3(box_max[0][i], box_max[1][j], box_max[2][k])};
  const double value = solids.empty() ? std::numeric_limits<double>::infinity()
                                      : detail::box_solids_sq_distance(
                                            solids, box, detail::vertex_upper_bound(solids, box));
  slot.store(value, std::memory_order_relaxed);
  return value;
}

}  // namespace camplace::voxel
