// Set-up of the voxel evaluator: everything that does not depend on the cameras — the objects
// with their roles, obstacle interiors, true distances, voxel-to-critical distances and the
// conservative lower bound of Err.
#include <algorithm>
#include <cmath>
#include <limits>

#include "camplace/core/distance.hpp"
#include "camplace/core/err.hpp"
#include "camplace/voxel/components.hpp"
#include "impl.hpp"
#include "solid_distance.hpp"

namespace camplace::voxel {

using core::Box3;
using core::Vec3;

namespace {
// No cutoff for the culled distances: they then return the minimum itself, the same double as
// with the nearest vertex's distance as cutoff (which bounds the minimum from above); the
// triangle hierarchy finds the near triangles without that bound, whose scan of every vertex
// cost more than the distance itself on fine meshes.
constexpr double kNoCutoff = std::numeric_limits<double>::infinity();

/// Triangles per cluster at most (cluster_triangles): a choice (a group's ball stays near the size
/// of its triangles), not measured against others.
constexpr int kClusterSize = 16;

Box3 empty_box() {
  const double inf = std::numeric_limits<double>::infinity();
  return {Vec3::Constant(inf), Vec3::Constant(-inf)};
}
void extend(Box3& box, const Vec3& p) {
  box.min = box.min.cwiseMin(p);
  box.max = box.max.cwiseMax(p);
}

/// The bounds of the triangles info.cluster_order[begin .. end − 1] of `mesh` as a cluster: the
/// ball about their vertices' box centre that holds them all, the cone of their unit normals
/// (widened against rounding, θ by at least ~1e-6) and their least |cross|. `unit` and `length`:
/// per triangle its cross's unit vector and length.
detail::TriangleCluster cluster_bounds(const core::TriangleMesh& mesh,
                                       const detail::ObjectInfo& info, int begin, int end,
                                       const std::vector<Vec3>& unit,
                                       const std::vector<double>& length) {
  detail::TriangleCluster cluster;
  cluster.begin = begin;
  cluster.end = end;
  Box3 box = empty_box();
  for (int i = begin; i < end; ++i) {
    for (int v : mesh.triangles[info.cluster_order[i]]) extend(box, mesh.vertices[v]);
  }
  cluster.ball.center = box.center();
  for (int i = begin; i < end; ++i) {
    for (int v : mesh.triangles[info.cluster_order[i]]) {
      cluster.ball.radius =
          std::max(cluster.ball.radius, (mesh.vertices[v] - cluster.ball.center).norm());
    }
  }
  Vec3 sum = Vec3::Zero();
  cluster.min_cross = std::numeric_limits<double>::infinity();
  for (int i = begin; i < end; ++i) {
    const int t = info.cluster_order[i];
    cluster.min_cross = std::min(cluster.min_cross, length[t]);
    if (length[t] > 0.0) sum += unit[t];
  }
  if (cluster.min_cross > 0.0 && sum.norm() > 0.0) {
    cluster.normal_axis = sum.normalized();
    double cos = 1.0;
    for (int i = begin; i < end; ++i) {
      cos = std::min(cos, cluster.normal_axis.dot(unit[info.cluster_order[i]]));
    }
    cluster.normal_cos = cos - 1e-12;
  } else {
    cluster.min_cross = 0.0;
  }
  return cluster;
}

/// The clusters of `mesh`'s triangles into info.cluster_order and info.clusters, and the tree over
/// them into info.nodes: the triangles split at the median of their centroids along the longest
/// axis of the centroids' box, until at most kClusterSize remain (a cluster, a leaf). Every node,
/// leaf or not, has its triangles' bounds (cluster_bounds); nodes are stored in pre-order (a
/// node's first child follows it, `next` is the node after its subtree), so a node's clusters are
/// consecutive and come in the order of the splits. Any split is correct (the labeller tests every
/// triangle of a cluster it does not rule out as a whole, and rules out a node only as it would
/// rule out each of its triangles); near triangles in one cluster let it rule out more.
void cluster_triangles(const core::TriangleMesh& mesh, detail::ObjectInfo& info) {
  const int n = static_cast<int>(mesh.triangles.size());
  std::vector<Vec3> centroid(n), unit(n);
  std::vector<double> length(n);
  for (int t = 0; t < n; ++t) {
    const auto& tv = mesh.triangles[t];
    centroid[t] = (mesh.vertices[tv[0]] + mesh.vertices[tv[1]] + mesh.vertices[tv[2]]) / 3.0;
    const Vec3 cross = (mesh.vertices[tv[1]] - mesh.vertices[tv[0]])
                           .cross(mesh.vertices[tv[2]] - mesh.vertices[tv[0]]);
    length[t] = cross.norm();
    unit[t] = length[t] > 0.0 ? Vec3(cross / length[t]) : Vec3::Zero();
  }
  info.cluster_order.resize(n);
  for (int t = 0; t < n; ++t) info.cluster_order[t] = t;
  info.clusters.clear();
  info.nodes.clear();
  // Depth first, first half first: (begin, end) of the node to make.
  auto make = [&](auto& self, int begin, int end) -> void {
    const int at = static_cast<int>(info.nodes.size());
    info.nodes.emplace_back();
    info.nodes[at].cluster_begin = static_cast<int>(info.clusters.size());
    if (end - begin > kClusterSize) {
      Box3 box = empty_box();
      for (int i = begin; i < end; ++i) extend(box, centroid[info.cluster_order[i]]);
      int axis = 0;
      (box.max - box.min).maxCoeff(&axis);
      const int mid = begin + (end - begin) / 2;
      std::nth_element(info.cluster_order.begin() + begin, info.cluster_order.begin() + mid,
                       info.cluster_order.begin() + end, [&](int a, int b) {
                         return centroid[a][axis] < centroid[b][axis] ||
                                (centroid[a][axis] == centroid[b][axis] && a < b);
                       });
      self(self, begin, mid);
      self(self, mid, end);
    } else {
      info.clusters.push_back(cluster_bounds(mesh, info, begin, end, unit, length));
    }
    detail::ClusterNode& node = info.nodes[at];
    node.bounds = info.clusters.size() == static_cast<std::size_t>(node.cluster_begin + 1)
                      ? info.clusters.back()
                      : cluster_bounds(mesh, info, begin, end, unit, length);
    node.cluster_end = static_cast<int>(info.clusters.size());
    node.next = static_cast<int>(info.nodes.size());
  };
  make(make, 0, n);
}
}  // namespace

int VoxelEvaluator::Impl::add_object(const core::SceneObject& object, core::ObjectRole role) {
  detail::ObjectInfo info;
  info.mesh = &object.mesh;
  info.occupying = role == core::ObjectRole::occupying;
  // An object is shared between the states that hold an equal one: the same role and the same
  // mesh (equal vertices, same triangles), as a robot link that does not move or a target that
  // appears in several time steps. Every test the labeller makes on an object depends on its
  // role and its triangles' numbers only, and ORs the verdict into the states of the object: a
  // shared object gives each state the verdict its own copy gave, with one test instead of one
  // per copy (docs/design/labelling.md L7; center mode's ties, L8, depend on roles only).
  for (std::size_t o = 0; o < objects.size(); ++o) {
    // Vertices first: copies of a mesh elsewhere (robot links, boxes) share their triangles.
    if (objects[o].occupying == info.occupying &&
        objects[o].mesh->vertices == object.mesh.vertices &&
        objects[o].mesh->triangles == object.mesh.triangles) {
      return static_cast<int>(o);
    }
  }
  info.center = object.bounds.center();
  for (const Vec3& v : object.mesh.vertices) {
    info.radius = std::max(info.radius, (v - info.center).norm());
  }
  // Its family: the first object (a family's first) with the same role and triangles whose
  // vertices each lie within a quarter of that object's radius of this one's, as a robot link
  // moved a little from one time step to the next. Only which slot groups are tested together
  // depends on it, never a label.
  info.family = static_cast<int>(objects.size());
  for (std::size_t o = 0; o < objects.size(); ++o) {
    const detail::ObjectInfo& first = objects[o];
    if (first.family != static_cast<int>(o) || first.occupying != info.occupying ||
        first.mesh->vertices.size() != object.mesh.vertices.size() ||
        first.mesh->triangles != object.mesh.triangles) {
      continue;
    }
    const double reach_sq = 0.0625 * first.radius * first.radius;
    bool near = true;
    for (std::size_t v = 0; v < object.mesh.vertices.size() && near; ++v) {
      near = (object.mesh.vertices[v] - first.mesh->vertices[v]).squaredNorm() <= reach_sq;
    }
    if (near) {
      info.family = static_cast<int>(o);
      break;
    }
  }
  info.outward = core::signed_volume(object.mesh) > 0.0;
  cluster_triangles(object.mesh, info);
  info.cluster_corners.reserve(info.cluster_order.size());
  for (const int i : info.cluster_order) {
    const auto& t = object.mesh.triangles[i];
    info.cluster_corners.push_back(
        {object.mesh.vertices[t[0]], object.mesh.vertices[t[1]], object.mesh.vertices[t[2]]});
  }
  info.first_triangle = static_cast<int>(triangles.size());
  info.triangle_count = static_cast<int>(object.mesh.triangles.size());
  for (const auto& t : object.mesh.triangles) {
    triangles.push_back(
        {object.mesh.vertices[t[0]], object.mesh.vertices[t[1]], object.mesh.vertices[t[2]]});
    triangle_object.push_back(static_cast<int>(objects.size()));
    const auto& tri = triangles.back();
    detail::Ball ball;
    ball.center = (tri[0] + tri[1] + tri[2]) / 3.0;
    for (const Vec3& v : tri) ball.radius = std::max(ball.radius, (v - ball.center).norm());
    triangle_balls.push_back(ball);
  }
  objects.push_back(info);
  return static_cast<int>(objects.size()) - 1;
}

void VoxelEvaluator::Impl::build() {
  using core::ObjectKind;
  cell_sizes.assign(1, {half_step, voxel_radius, 1.0});
  octree = detail::make_octree(levels);
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
      state.objects.reserve(static_ids.size() + dynamic_ids.size() + step.events[l].targets.size());
      state.objects.insert(state.objects.end(), static_ids.begin(), static_ids.end());
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
    shells_by_step.push_back(lower_bound_shells(critical_lb_by_step.back()));
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
    // Only the steps with states in the chunk (a step's states are consecutive): the set-up
    // reads each step's interiors once or twice, not once per chunk.
    std::vector<detail::StateMask> removed(grid.count(), 0);
    for (std::size_t h = 0; h < by_step.size(); ++h) {
      if (!by_step[h]) continue;
      for (int v = 0; v < grid.count(); ++v) {
        if (removed_by_step[h][v]) removed[v] |= by_step[h];
      }
    }
    std::vector<int> chunk_objects_here;
    for (std::size_t o = 0; o < objects.size(); ++o) {
      if (by_object[o]) chunk_objects_here.push_back(static_cast<int>(o));
    }
    chunk_objects.push_back(std::move(chunk_objects_here));
    chunk_object_states.push_back(std::move(by_object));
    chunk_step_states.push_back(std::move(by_step));
    chunk_removed.push_back(std::move(removed));
  }
  if (conservative) {
    reached_by_object.assign(objects.size(), {});
    for (std::size_t o = 0; o < objects.size(); ++o) {
      if (objects[o].occupying) reached_by_object[o] = voxels_reached(*objects[o].mesh);
    }
    for (const auto& by_object : chunk_object_states) {
      std::vector<detail::StateMask> reached(grid.count(), 0);
      for (std::size_t o = 0; o < objects.size(); ++o) {
        for (int v : reached_by_object[o]) reached[v] |= by_object[o];
      }
      chunk_reached.push_back(std::move(reached));
    }
  }
  if (levels > 0) build_refinement();
  if (conservative) err_lower_bound = lower_bound();
}

/// Voxels removed as obstacle interior (SPEC §4–5): centre inside (center mode) or the whole
/// voxel inside (conservative mode) an obstacle of the time step (core::is_obstacle: static and
/// dynamic obstacles, not targets).
std::vector<std::uint8_t> VoxelEvaluator::Impl::obstacle_interiors(
    const core::TimeStep& step) const {
  std::vector<std::uint8_t> removed(grid.count(), 0);
  std::vector<detail::IndexedSolid> obstacles;
  for (const core::SceneObject* o : obstacles_of(step))
    obstacles.push_back(detail::index_solid(o->mesh));
  for (int v = 0; v < grid.count(); ++v) {
    const Box3 box = grid.voxel_box(v);
    // Shrunk by 1e-9 m so that faces lying on the voxel's boundary (grid-aligned obstacles) do
    // not count; center mode needs the centre only.
    for (const detail::IndexedSolid& o : obstacles) {
      if (detail::box_inside_solid(o, box, 1e-9, conservative)) {
        removed[v] = 1;
        break;
      }
    }
  }
  return removed;
}

std::vector<const core::SceneObject*> VoxelEvaluator::Impl::obstacles_of(
    const core::TimeStep& step) const {
  std::vector<const core::SceneObject*> obstacles;
  for (const auto& o : scene.static_obstacles) obstacles.push_back(&o);
  for (const auto& o : step.dynamic_obstacles) obstacles.push_back(&o);
  return obstacles;
}

std::array<std::array<int, 2>, 3> VoxelEvaluator::Impl::voxel_range(const Box3& bounds) const {
  std::array<std::array<int, 2>, 3> range{};
  for (int a = 0; a < 3; ++a) {
    const double first = std::floor((bounds.min[a] - grid.area.min[a]) / grid.step[a]) - 1.0;
    const double last = std::floor((bounds.max[a] - grid.area.min[a]) / grid.step[a]) + 1.0;
    range[a][0] = static_cast<int>(std::clamp(first, 0.0, grid.n[a] - 1.0));
    range[a][1] = static_cast<int>(std::clamp(last, 0.0, grid.n[a] - 1.0));
  }
  return range;
}

/// Lower bounds of d(C_h, voxel)² (SPEC §5) for one step: from the distance of the voxel's
/// centre to the critical solids (core::point_solid_sq_distance, min over C_h, the same doubles
/// through the triangle hierarchy), less the voxel's radius in conservative mode (every
/// point of the box is within it of the centre; margins of 1e-12 cover rounding). In center
/// mode they are the values themselves.
std::vector<double> VoxelEvaluator::Impl::critical_distances(
    const std::vector<detail::IndexedSolid>& solids) const {
  std::vector<double> out(grid.count(), std::numeric_limits<double>::infinity());
  if (solids.empty()) return out;
  const int nx = grid.n[0], ny = grid.n[1], nz = grid.n[2];
  detail::parallel_for(nz, options.threads, [&](int k) {
    for (int j = 0; j < ny; ++j) {
      // The previous centre's nearest triangle gives a cutoff that holds the minimum (its
      // distance is a candidate): point_solids_sq_distance returns the same minimum, sooner.
      detail::NearestTriangle hint;
      for (int i = 0; i < nx; ++i) {
        const Vec3 p(box_center[0][i], box_center[1][j], box_center[2][k]);
        const double surface = detail::point_solids_sq_distance(solids, p, kNoCutoff, false, &hint);
        // core::point_solid_sq_distance is 0 inside a solid (a point outside its bounds is not),
        // else the distance to its surface: the same as the search with its inside test.
        auto inside = [&] {
          return std::any_of(solids.begin(), solids.end(), [&](const detail::IndexedSolid& s) {
            return s.bounds.contains(p) && detail::inside_solid(s, p);
          });
        };
        double& lb = out[i + nx * (j + ny * k)];
        if (!conservative) {
          lb = surface > 0.0 && inside() ? 0.0 : surface;
          continue;
        }
        // The bound is monotonic in the distance, and the distance to the surfaces is at least
        // the distance to the solids (0 inside): when the surfaces already give 0, so does the
        // solid, and the inside test is not needed.
        const double gap =
            std::sqrt(surface) * (1.0 - 1e-12) - voxel_radius * (1.0 + 1e-12) - 1e-12;
        lb = gap > 0.0 && !inside() ? gap * gap : 0.0;
      }
    }
  });
  return out;
}

VoxelEvaluator::Impl::LowerBoundShells VoxelEvaluator::Impl::lower_bound_shells(
    const std::vector<double>& lb) const {
  LowerBoundShells out;
  // Shells half the smallest voxel step wide, as many as S's diagonal needs and a few more for
  // rounding. Critical objects may lie partly or wholly outside S (SPEC §2), so √lb can exceed
  // the diagonal: such voxels go to the last shell, whose bound ((shells − 2)·width in
  // model_distance) stays below their √lb, so the scan stays exact.
  out.width = 0.5 * grid.step.minCoeff();
  const double diagonal = (scene.area.max - scene.area.min).norm();
  const int shells = static_cast<int>(diagonal / out.width) + 3;
  auto shell = [&](double sq) {
    const double f = std::sqrt(sq) / out.width;
    return f < shells - 1 ? static_cast<int>(f) : shells - 1;
  };
  out.start.assign(shells + 1, 0);
  for (double sq : lb) ++out.start[shell(sq) + 1];
  for (int b = 0; b < shells; ++b) out.start[b + 1] += out.start[b];
  out.voxels.resize(lb.size());
  std::vector<int> next(out.start.begin(), out.start.end() - 1);
  for (int v = 0; v < static_cast<int>(lb.size()); ++v) out.voxels[next[shell(lb[v])]++] = v;
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
                                      : detail::box_solids_sq_distance(solids, box, kNoCutoff);
  // The lower bound that lets model_distance skip voxels bounds the value (distance.md D1).
  CAMPLACE_ASSERT(!detail::beyond(critical_lb_by_step[time_step][v], value));
  slot.store(value, std::memory_order_relaxed);
  return value;
}

}  // namespace camplace::voxel
