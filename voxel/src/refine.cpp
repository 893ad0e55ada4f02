// Adaptive refinement of the conservative voxel model (`refine` = L levels): kept base voxels
// near the critical objects are split into octree cells down to 1/2^L of the voxel's edge with
// the base labeller's own tests; M is the union of the finest cells and the whole voxels left
// unrefined. Why M stays between the exact and the unrefined model, why the shortcuts change
// nothing, which voxels must be refined and why cells tile exactly: docs/design/refinement.md
// R1–R4; the distance: docs/design/distance.md D2.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <string>

#include "camplace/core/distance.hpp"
#include "camplace/core/err.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/core/names.hpp"
#include "impl.hpp"
#include "solid_distance.hpp"
#include "union_find.hpp"

namespace camplace::voxel {

using core::Box3;
using core::Vec3;
using detail::CameraSetup;
using detail::CellSet;
using detail::StateMask;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

using detail::find;
using detail::unite;

}  // namespace

double refine_memory_estimate(const std::array<int, 3>& n, int levels, int time_steps, int states) {
  if (levels <= 0) return 0.0;
  const double cells = static_cast<double>(n[0]) * n[1] * n[2] * std::pow(8.0, levels);
  return cells * (8.0 + 8.0 + states + 10.0 * time_steps);
}

std::string refine_problem(const core::Scene& scene, const VoxelOptions& options) {
  const int levels = options.refine;
  if (levels == 0) return "";
  if (levels < 0) return "must not be negative, got " + std::to_string(levels);
  if (levels > kMaxRefine) {
    return "must be at most " + std::to_string(kMaxRefine) + ", got " + std::to_string(levels);
  }
  if (options.mode != LabelMode::conservative) {
    return "refinement needs conservative labels (mode conservative), not mode " +
           core::name_of(options.mode);
  }
  std::array<int, 3> n = options.resolution;
  if (n[0] == 0 && n[1] == 0 && n[2] == 0) n = scene.voxels;
  int state_count = 0;
  for (const auto& step : scene.time_steps) state_count += static_cast<int>(step.events.size());
  const double bytes =
      refine_memory_estimate(n, levels, static_cast<int>(scene.time_steps.size()), state_count);
  if (bytes > kRefineMemoryLimit) {
    char text[256];
    std::snprintf(text, sizeof text,
                  "%d levels on the %dx%dx%d grid may need up to %.1f GiB (%d time steps, %d "
                  "states; limit %.0f GiB); use fewer levels or a coarser grid",
                  levels, n[0], n[1], n[2], bytes / (1024.0 * 1024 * 1024),
                  static_cast<int>(scene.time_steps.size()), state_count,
                  kRefineMemoryLimit / (1024.0 * 1024 * 1024));
    return text;
  }
  return "";
}

namespace detail {

NodeDistanceCache::NodeDistanceCache(int voxels, int block_size)
    : voxels_(voxels),
      block_size_(block_size),
      blocks_(new std::atomic<std::atomic<double>*>[static_cast<std::size_t>(voxels)]) {
  for (int v = 0; v < voxels_; ++v) blocks_[v].store(nullptr, std::memory_order_relaxed);
}

NodeDistanceCache::~NodeDistanceCache() {
  for (int v = 0; v < voxels_; ++v) delete[] blocks_[v].load(std::memory_order_relaxed);
}

std::atomic<double>* NodeDistanceCache::block(int v) {
  std::atomic<double>* known = blocks_[v].load(std::memory_order_acquire);
  if (known) return known;
  auto* fresh = new std::atomic<double>[static_cast<std::size_t>(block_size_)];
  for (int n = 0; n < block_size_; ++n) {
    fresh[n].store(std::numeric_limits<double>::quiet_NaN(), std::memory_order_relaxed);
  }
  if (blocks_[v].compare_exchange_strong(known, fresh, std::memory_order_acq_rel)) return fresh;
  delete[] fresh;  // another thread was first; `known` holds its block
  return known;
}

}  // namespace detail

void VoxelEvaluator::Impl::build_refinement() {
  for (int l = 1; l <= levels; ++l) {
    const double f = std::ldexp(1.0, -l);
    cell_sizes.push_back({half_step * f, voxel_radius * f, f});
  }
  // Obstacle interiors below the base voxels (as obstacle_interiors tests a voxel, on each
  // cell): a cell wholly inside an obstacle of the step is marked and not descended (refinement
  // never reaches its children); a cell no obstacle surface meets holds no such cell below it.
  const double depth = 1e-9;
  for (std::size_t h = 0; h < scene.time_steps.size(); ++h) {
    const core::TimeStep& step = scene.time_steps[h];
    std::vector<const core::SceneObject*> obstacles;
    for (const auto& o : scene.static_obstacles) obstacles.push_back(&o);
    for (const auto& o : step.dynamic_obstacles) obstacles.push_back(&o);
    auto meets_surface = [&](const Box3& box) {
      for (const core::SceneObject* o : obstacles) {
        if ((o->bounds.min.array() > box.max.array()).any() ||
            (o->bounds.max.array() < box.min.array()).any()) {
          continue;
        }
        for (const auto& t : o->mesh.triangles) {
          if (core::triangle_box_overlap(o->mesh.vertices[t[0]], o->mesh.vertices[t[1]],
                                         o->mesh.vertices[t[2]], box)) {
            return true;
          }
        }
      }
      return false;
    };
    auto wholly_inside = [&](const Box3& box) {
      const Box3 interior{box.min + Vec3::Constant(depth), box.max - Vec3::Constant(depth)};
      for (const core::SceneObject* o : obstacles) {
        if (!o->bounds.contains(box.center())) continue;
        if (!core::inside_mesh(o->mesh, box.center())) continue;
        bool whole = true;
        for (const auto& t : o->mesh.triangles) {
          if (core::triangle_box_overlap(o->mesh.vertices[t[0]], o->mesh.vertices[t[1]],
                                         o->mesh.vertices[t[2]], interior)) {
            whole = false;
            break;
          }
        }
        if (whole) return true;
      }
      return false;
    };
    std::vector<int> index(grid.count(), -1);
    std::vector<std::uint8_t> table;
    for (int v = 0; v < grid.count(); ++v) {
      if (removed_by_step[h][v] || !meets_surface(grid.voxel_box(v))) continue;
      table.assign(octree.nodes, 0);
      bool any = false;
      // Depth-first over the nodes that an obstacle surface meets.
      struct Node {
        int level, morton;
      };
      std::vector<Node> stack{{0, 0}};
      while (!stack.empty()) {
        const Node node = stack.back();
        stack.pop_back();
        for (int q = 0; q < 8; ++q) {
          const Node child{node.level + 1, 8 * node.morton + q};
          const Box3 box = node_box(v, child.level, child.morton);
          if (wholly_inside(box)) {
            table[octree.offset[child.level] + child.morton] = 1;
            any = true;
          } else if (child.level < levels && meets_surface(box)) {
            stack.push_back(child);
          }
        }
      }
      if (any) {
        index[v] = static_cast<int>(removal_tables.size());
        removal_tables.push_back(table);
      }
    }
    removal_index.push_back(std::move(index));
    node_sq_by_step.push_back(
        std::make_unique<detail::NodeDistanceCache>(grid.count(), octree.nodes - 1));
  }
  // Interiors of the occupying objects, the same way: a node wholly inside one is never free in
  // that object's states (every ray to a point inside meets the object's surface at or before
  // it, SPEC §3; a camera inside it is blind), nor is any cell below it.
  inside_by_voxel.assign(grid.count(), {});
  for (std::size_t o = 0; o < objects.size(); ++o) {
    if (!objects[o].occupying) continue;
    const core::TriangleMesh& mesh = *objects[o].mesh;
    Box3 bounds{Vec3::Constant(kInf), Vec3::Constant(-kInf)};
    for (const Vec3& p : mesh.vertices) {
      bounds.min = bounds.min.cwiseMin(p);
      bounds.max = bounds.max.cwiseMax(p);
    }
    auto meets_surface = [&](const Box3& box) {
      if ((bounds.min.array() > box.max.array()).any() ||
          (bounds.max.array() < box.min.array()).any()) {
        return false;
      }
      for (const auto& t : mesh.triangles) {
        if (core::triangle_box_overlap(mesh.vertices[t[0]], mesh.vertices[t[1]],
                                       mesh.vertices[t[2]], box)) {
          return true;
        }
      }
      return false;
    };
    auto wholly_inside = [&](const Box3& box) {
      if (!bounds.contains(box.center()) || !core::inside_mesh(mesh, box.center())) return false;
      const Box3 interior{box.min + Vec3::Constant(depth), box.max - Vec3::Constant(depth)};
      for (const auto& t : mesh.triangles) {
        if (core::triangle_box_overlap(mesh.vertices[t[0]], mesh.vertices[t[1]],
                                       mesh.vertices[t[2]], interior)) {
          return false;
        }
      }
      return true;
    };
    std::array<int, 3> lo{}, hi{};
    for (int a = 0; a < 3; ++a) {
      const double first = std::floor((bounds.min[a] - grid.area.min[a]) / grid.step[a]) - 1.0;
      const double last = std::floor((bounds.max[a] - grid.area.min[a]) / grid.step[a]) + 1.0;
      lo[a] = static_cast<int>(std::clamp(first, 0.0, grid.n[a] - 1.0));
      hi[a] = static_cast<int>(std::clamp(last, 0.0, grid.n[a] - 1.0));
    }
    std::vector<std::uint8_t> table;
    for (int k = lo[2]; k <= hi[2]; ++k) {
      for (int j = lo[1]; j <= hi[1]; ++j) {
        for (int i = lo[0]; i <= hi[0]; ++i) {
          const int v = i + grid.n[0] * (j + grid.n[1] * k);
          const Box3 voxel = node_box(v, 0, 0);
          table.assign(octree.nodes, 0);
          bool any = false;
          if (wholly_inside(voxel)) {
            table[0] = 1;
            any = true;
          } else if (meets_surface(voxel)) {
            std::vector<std::pair<int, int>> stack{{0, 0}};
            while (!stack.empty()) {
              const auto [level, morton] = stack.back();
              stack.pop_back();
              for (int q = 0; q < 8; ++q) {
                const int child = 8 * morton + q;
                const Box3 box = node_box(v, level + 1, child);
                if (wholly_inside(box)) {
                  table[octree.offset[level + 1] + child] = 1;
                  any = true;
                } else if (level + 1 < levels && meets_surface(box)) {
                  stack.push_back({level + 1, child});
                }
              }
            }
          }
          if (!any) continue;
          inside_by_voxel[v].push_back(
              {static_cast<int>(o), static_cast<int>(inside_tables.size())});
          inside_tables.push_back(table);
        }
      }
    }
  }
}

Box3 VoxelEvaluator::Impl::node_box(int v, int level, int morton) const {
  const int nx = grid.n[0], ny = grid.n[1];
  const int i = v % nx, j = (v / nx) % ny, k = v / (nx * ny);
  const int shift = levels - level;
  const auto& local = octree.coords[static_cast<std::size_t>(morton) << (3 * shift)];
  const Vec3 s = grid.step * std::ldexp(1.0, -level);
  const double I = static_cast<double>((static_cast<long>(i) << level) + (local[0] >> shift));
  const double J = static_cast<double>((static_cast<long>(j) << level) + (local[1] >> shift));
  const double K = static_cast<double>((static_cast<long>(k) << level) + (local[2] >> shift));
  Box3 box;
  box.min = grid.area.min + Vec3(I * s.x(), J * s.y(), K * s.z());
  box.max = grid.area.min + Vec3((I + 1) * s.x(), (J + 1) * s.y(), (K + 1) * s.z());
  return box;
}

double VoxelEvaluator::Impl::node_sq(int time_step, int v, int level, int morton) const {
  if (level == 0) return critical_sq(time_step, v);
  std::atomic<double>& slot =
      node_sq_by_step[time_step]->block(v)[octree.offset[level] + morton - 1];
  const double known = slot.load(std::memory_order_relaxed);
  if (!std::isnan(known)) return known;
  const auto& solids = critical_solids_by_step[time_step];
  const Box3 box = node_box(v, level, morton);
  const double value = solids.empty() ? kInf
                                      : detail::box_solids_sq_distance(
                                            solids, box, detail::vertex_upper_bound(solids, box));
  slot.store(value, std::memory_order_relaxed);
  return value;
}

void VoxelEvaluator::Impl::refine_voxel(detail::RefineContext& ctx, const StateMask* step_states,
                                        int v, StateMask pending, StateMask* out) const {
  const std::vector<CameraSetup>& cameras = *ctx.cameras;
  const int cells = octree.cells;
  const int nx = grid.n[0], ny = grid.n[1];
  ctx.removal.clear();
  for (std::size_t h = 0; h < removal_index.size(); ++h) {
    const int table = removal_index[h][v];
    if (table >= 0 && (pending & step_states[h])) {
      ctx.removal.push_back({step_states[h], removal_tables[table].data()});
    }
  }
  ctx.inside.clear();
  for (const auto& [o, table] : inside_by_voxel[v]) {
    const StateMask mask = ctx.object_states[o];
    if (pending & mask) ctx.inside.push_back({mask, inside_tables[table].data()});
  }
  ctx.out = out;
  ctx.witness.assign((levels + 1) * cameras.size() * detail::kWitnesses, -1);
  ctx.sure.assign((levels + 1) * cameras.size(), 0);
  // The base voxel itself: states where it lies wholly inside an occupying object, or outside
  // every seeing camera's FOV, need no refinement; cameras whose FOV holds it.
  StateMask fixed = 0, open = pending;
  for (const auto& [mask, table] : ctx.inside) {
    if (table[0]) {
      fixed |= open & mask;
      open &= ~mask;
    }
  }
  std::uint64_t in_view = 0;
  if (open) {
    const Box3 box = node_box(v, 0, 0);
    const Vec3 center = 0.5 * (box.min + box.max);
    StateMask maybe_seen = 0;
    for (std::size_t c = 0; c < cameras.size(); ++c) {
      if (!(open & ctx.seeing[c])) continue;
      const Vec3 w = center - cameras[c].c;
      const double d = w.norm();
      if (ball_outside_fov(cameras[c], w, d, cell_sizes[0].radius)) continue;
      maybe_seen |= ctx.seeing[c];
      if (c < 64 && box_in_fov(cameras[c], box.min, box.max, cell_sizes[0].radius, w, d)) {
        in_view |= std::uint64_t(1) << c;
      }
    }
    fixed |= open & ~maybe_seen;
    open &= maybe_seen;
  }
  if (open) {
    const int i = v % nx, j = (v / nx) % ny, k = v / (nx * ny);
    refine_node(ctx, 0, 0, i, j, k, fixed, open, in_view);
  } else {
    for (int c = 0; c < cells; ++c) out[c] |= fixed;
  }
  // Obstacle interiors below cells filled without descending (the descent skipped the others
  // already; bits of the step's states set in an earlier call were cleared then).
  for (const auto& [mask, table] : ctx.removal) {
    for (int l = 1; l <= levels; ++l) {
      const int span = 1 << (3 * (levels - l));
      for (int m = 0; m < (1 << (3 * l)); ++m) {
        if (!table[octree.offset[l] + m]) continue;
        for (int c = m * span; c < (m + 1) * span; ++c) out[c] &= ~mask;
      }
    }
  }
}

void VoxelEvaluator::Impl::refined_states(const std::vector<CameraSetup>& cameras,
                                          const std::vector<std::vector<std::uint8_t>>& models,
                                          std::vector<CellSet>& leaves,
                                          std::vector<ComponentCount>& counts,
                                          std::vector<ModelDistance>& distances,
                                          core::Timing& timing) const {
  using detail::Clock;
  using detail::ms_since;
  const int state_count = static_cast<int>(states.size());
  const int cells = octree.cells;
  leaves.resize(state_count);
  counts.assign(state_count, {});
  distances.assign(state_count, {});
  // Per calling thread, reused; references, so that the worker threads below see this
  // thread's buffers (a thread_local named in a lambda would be each worker's own).
  thread_local std::vector<StateMask> mask_buffer, refined_buffer;
  thread_local std::vector<int> slot_buffer;
  std::vector<StateMask>& cell_masks = mask_buffer;  // per slot: its cells' states
  std::vector<StateMask>& refined = refined_buffer;  // per base voxel: states refined
  std::vector<int>& slot_of = slot_buffer;           // per base voxel: its slot, or −1
  const double diagonal = grid.step.norm();
  for (int chunk = 0; chunk * detail::kChunk < state_count; ++chunk) {
    const int first = chunk * detail::kChunk;
    const int count = std::min(detail::kChunk, state_count - first);
    const std::vector<StateMask> seeing = seeing_states(cameras, chunk);
    const StateMask* step_states = chunk_step_states[chunk].data();
    refined.assign(grid.count(), 0);
    slot_of.assign(grid.count(), -1);
    cell_masks.clear();
    int slot_count = 0;
    // The radius per state: kept base voxels nearer than it to C_h are refined. It starts at
    // the unrefined d(C_h, M) plus a voxel diagonal and grows until the nearest kept cell lies
    // within it, so that every voxel that could hold a nearer cell is refined.
    std::vector<double> radius(count, 0.0);
    std::vector<int> active;
    auto t0 = Clock::now();
    for (int s = 0; s < count; ++s) {
      const std::vector<std::uint8_t>& model = models[first + s];
      const ModelDistance base = model_distance(model, states[first + s].time_step);
      CellSet& set = leaves[first + s];
      set.voxels.clear();
      set.cells.clear();
      set.whole.clear();
      if (base.volume == 0.0) {
        distances[first + s] = base;  // empty: nothing to refine
        continue;
      }
      radius[s] = base.d_model + diagonal;
      active.push_back(s);
    }
    timing.distance_ms += ms_since(t0);
    std::vector<std::pair<int, StateMask>> work;  // (slot, states to refine)
    while (!active.empty()) {
      t0 = Clock::now();
      work.clear();
      for (int v = 0; v < grid.count(); ++v) {
        StateMask add = 0;
        for (int s : active) {
          const StateMask bit = StateMask(1) << s;
          if (!models[first + s][v] || (refined[v] & bit)) continue;
          const int h = states[first + s].time_step;
          const double r2 = radius[s] * radius[s];
          if (critical_lb_by_step[h][v] >= r2 || !(critical_sq(h, v) < r2)) continue;
          add |= bit;
        }
        if (!add) continue;
        if (slot_of[v] < 0) {
          slot_of[v] = slot_count++;
          cell_masks.resize(static_cast<std::size_t>(slot_count) * cells, 0);
        }
        refined[v] |= add;
        work.push_back({v, add});
      }
      const int items = static_cast<int>(work.size());
      const int pieces =
          options.threads <= 1 ? std::min(items, 1) : std::min(items, 4 * options.threads);
      detail::parallel_for(pieces, options.threads, [&](int piece) {
        detail::Scratch scratch;
        scratch.stamp.assign(triangles.size(), 0);
        detail::RefineContext ctx;
        ctx.cameras = &cameras;
        ctx.seeing = seeing.data();
        ctx.object_states = chunk_object_states[chunk].data();
        ctx.scratch = &scratch;
        for (int n = items * piece / pieces; n < items * (piece + 1) / pieces; ++n) {
          const auto [v, add] = work[n];
          refine_voxel(ctx, step_states, v, add,
                       cell_masks.data() + static_cast<std::size_t>(slot_of[v]) * cells);
        }
      });
      timing.labelling_ms += ms_since(t0);
      // Per active state: the model (refined cells, the other kept voxels whole), its
      // components and filter, and d(C_h, M).
      t0 = Clock::now();
      const int n_active = static_cast<int>(active.size());
      detail::parallel_for(n_active, options.threads, [&](int a) {
        const int s = active[a];
        const StateMask bit = StateMask(1) << s;
        CellSet& set = leaves[first + s];
        set.voxels.clear();
        set.cells.clear();
        set.whole.clear();
        const std::vector<std::uint8_t>& model = models[first + s];
        for (int v = 0; v < grid.count(); ++v) {
          if (model[v]) set.voxels.push_back(v);
        }
        set.cells.resize(set.voxels.size() * cells, 1);
        set.whole.resize(set.voxels.size(), 1);
        for (std::size_t slot = 0; slot < set.voxels.size(); ++slot) {
          const int v = set.voxels[slot];
          if (!(refined[v] & bit)) continue;
          set.whole[slot] = 0;
          const std::size_t at = slot * cells;
          const StateMask* masks = cell_masks.data() + static_cast<std::size_t>(slot_of[v]) * cells;
          for (int c = 0; c < cells; ++c) set.cells[at + c] = (masks[c] & bit) != 0;
        }
        counts[first + s] = detail::filter_cells(set, octree, grid, scene.plausibility);
      });
      timing.clustering_ms += ms_since(t0);
      t0 = Clock::now();
      detail::parallel_for(n_active, options.threads, [&](int a) {
        const int s = active[a];
        distances[first + s] = model_distance(leaves[first + s], states[first + s].time_step);
      });
      timing.distance_ms += ms_since(t0);
      std::vector<int> next;
      for (int s : active) {
        const double d = distances[first + s].d_model;
        if (!(d > radius[s])) continue;
        radius[s] = d + diagonal;
        next.push_back(s);
      }
      active.swap(next);
    }
  }
}

void VoxelEvaluator::Impl::refine_node(detail::RefineContext& ctx, int level, int morton, long I,
                                       long J, long K, StateMask fixed, StateMask open,
                                       std::uint64_t in_view) const {
  const int child_level = level + 1;
  const detail::CellSize& size = cell_sizes[child_level];
  const Vec3 s = grid.step * size.factor;
  const std::vector<CameraSetup>& cameras = *ctx.cameras;
  const std::size_t n_cam = cameras.size();
  const int node = octree.offset[child_level];
  for (int q = 0; q < 8; ++q) {
    const long CI = 2 * I + (q & 1), CJ = 2 * J + ((q >> 1) & 1), CK = 2 * K + ((q >> 2) & 1);
    const int child = 8 * morton + q;
    StateMask f = fixed, o = open;
    for (const auto& [mask, table] : ctx.removal) {
      if (((f | o) & mask) && table[node + child]) {
        f &= ~mask;
        o &= ~mask;
      }
    }
    for (const auto& [mask, table] : ctx.inside) {
      if ((o & mask) && table[node + child]) {
        f |= o & mask;
        o &= ~mask;
      }
    }
    std::uint64_t child_in_view = 0;
    if (o) {
      const double x = static_cast<double>(CI), y = static_cast<double>(CJ),
                   z = static_cast<double>(CK);
      const Vec3 lo = grid.area.min + Vec3(x * s.x(), y * s.y(), z * s.z());
      const Vec3 hi = grid.area.min + Vec3((x + 1) * s.x(), (y + 1) * s.y(), (z + 1) * s.z());
      const Vec3 center = 0.5 * (lo + hi);
      // States some camera may still free in a cell below this one.
      StateMask open_below = 0;
      const StateMask* parent_sure = ctx.sure.data() + level * n_cam;
      StateMask* child_sure = ctx.sure.data() + child_level * n_cam;
      std::copy(parent_sure, parent_sure + n_cam, child_sure);
      const std::size_t first_cam = ctx.hint;
      for (std::size_t step = 0; step < n_cam && o; ++step) {
        const std::size_t c =
            first_cam + step < n_cam ? first_cam + step : first_cam + step - n_cam;
        // States the camera is known not to free anywhere in the parent need no test.
        const StateMask interest = o & ctx.seeing[c] & ~child_sure[c];
        if (!interest) continue;
        const CameraSetup& cam = cameras[c];
        const Vec3 w = center - cam.c;
        const double d = w.norm();
        // The parent's box in the FOV holds the child's (children tile their parent exactly).
        bool seen = c < 64 && ((in_view >> c) & 1);
        if (!seen) {
          if (ball_outside_fov(cam, w, d, size.radius)) {
            child_sure[c] = ~StateMask(0);  // no cell below is in this camera's FOV
            continue;
          }
          seen = box_in_fov(cam, lo, hi, size.radius, w, d);
        }
        if (!seen) {
          open_below |= interest;
          continue;
        }
        if (c < 64) child_in_view |= std::uint64_t(1) << c;
        int* witness = ctx.witness.data() + (child_level * n_cam + c) * detail::kWitnesses;
        const int* parent_witness = ctx.witness.data() + (level * n_cam + c) * detail::kWitnesses;
        std::copy(parent_witness, parent_witness + detail::kWitnesses, witness);
        // States where judge_conservative() would find the cell occupied because a triangle that
        // decided the parent holds it in its cone (and so every cell below): no test needed.
        StateMask held = 0;
        for (int n = 0; n < detail::kWitnesses && witness[n] >= 0; ++n) {
          held |= contained(cam, witness[n], w, d, size, interest & ~held, ctx.object_states);
        }
        child_sure[c] |= held;
        if (held == interest) continue;
        detail::Witnesses witnesses{witness};
        const detail::Verdict verdict = judge_conservative(
            cam, w, d, size, interest & ~held, ctx.object_states, *ctx.scratch, true, &witnesses);
        const StateMask freed = interest & ~held & ~(verdict.occupied | verdict.blocked);
        if (freed) ctx.hint = c;
        o &= ~freed;
        child_sure[c] |= witnesses.sure;
        open_below |= interest & ~freed & ~witnesses.sure;
      }
      // No camera can free any cell below in these states: all of them stay in M.
      f |= o & ~open_below;
      o &= open_below;
    }
    if (!(f | o)) continue;
    if (child_level == levels) {
      ctx.out[child] |= f | o;
    } else if (!o) {
      const int span = 1 << (3 * (levels - child_level));
      for (int c = child * span; c < (child + 1) * span; ++c) ctx.out[c] |= f;
    } else {
      refine_node(ctx, child_level, child, CI, CJ, CK, f, o, child_in_view);
    }
  }
}

StateMask VoxelEvaluator::Impl::contained(const CameraSetup& cam, int t, const Vec3& w, double d,
                                          const detail::CellSize& size, StateMask interest,
                                          const StateMask* object_states) const {
  const int o = triangle_object[t];
  const StateMask states = interest & object_states[o];
  if (!objects[o].occupying || !states) return 0;
  const detail::TriangleCone& tc = cam.triangles[t];
  if (tc.flat || tc.back) return 0;
  // judge_conservative()'s `sure` test (detail::Witnesses): the box's lowest point along each
  // inward plane normal is inside by the margin (then the cone test meets it: the centre is inside
  // too).
  const double margin = 1e-9 * (d + size.radius);
  for (int i = 0; i < 3; ++i) {
    if (!(tc.normal[i].dot(w) - tc.abs_normal[i].dot(size.half) > margin)) return 0;
  }
  return states;
}

bool VoxelEvaluator::Impl::ball_outside_fov(const CameraSetup& cam, const Vec3& w, double d,
                                            double r) const {
  if (!(d > r * (1.0 + 1e-6) + 1e-9)) return false;  // the camera may be in the ball
  const double axial = w.dot(cam.axis);
  const double tol = 1e-9 * (d + r);
  if (cam.range && axial > *cam.range + r + tol) return true;
  if (cam.near > 0.0 && axial < cam.near - r - tol) return true;
  // The centre's angle θ off the axis exceeds the half angle α plus the ball's angular radius
  // β (sin β = r/d; α + β < π): cos θ < cos(α + β), with a margin.
  const double sin_b = r / d, cos_b = std::sqrt(1.0 - sin_b * sin_b);
  const double cos_limit = cam.cos_half * cos_b - cam.sin_half * sin_b;
  return axial < d * cos_limit - 1e-6 * d - tol;
}

}  // namespace camplace::voxel
