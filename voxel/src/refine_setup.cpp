// Set-up of refinement (`refine` = L levels): the limits (refine_problem), the cells' sizes,
// the obstacle and occupying-object interiors of the octree nodes below the base voxels, and the
// cached distances from the critical objects to the nodes' boxes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "camplace/core/names.hpp"
#include "impl.hpp"
#include "solid_distance.hpp"

namespace camplace::voxel {

using core::Box3;
using core::Vec3;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

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
  constexpr double depth = 1e-9;
  for (std::size_t h = 0; h < scene.time_steps.size(); ++h) {
    std::vector<detail::IndexedSolid> obstacles;
    for (const core::SceneObject* o : obstacles_of(scene.time_steps[h]))
      obstacles.push_back(detail::index_solid(o->mesh));
    auto meets_surface = [&](const Box3& box) {
      for (const detail::IndexedSolid& o : obstacles) {
        if (detail::box_meets_surface(o, box)) return true;
      }
      return false;
    };
    auto wholly_inside = [&](const Box3& box) {
      for (const detail::IndexedSolid& o : obstacles) {
        if (detail::box_inside_solid(o, box, depth)) return true;
      }
      return false;
    };
    std::vector<int> index(grid.count(), -1);
    std::vector<std::uint8_t> table;
    for (int v = 0; v < grid.count(); ++v) {
      if (removed_by_step[h][v] || !meets_surface(grid.voxel_box(v))) continue;
      if (!node_table(v, wholly_inside, meets_surface, table)) continue;
      index[v] = static_cast<int>(removal_tables.size());
      removal_tables.push_back(table);
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
    const detail::IndexedSolid solid = detail::index_solid(*objects[o].mesh);
    auto meets_surface = [&](const Box3& box) { return detail::box_meets_surface(solid, box); };
    auto wholly_inside = [&](const Box3& box) {
      return detail::box_inside_solid(solid, box, depth);
    };
    const auto range = voxel_range(solid.bounds);
    std::vector<std::uint8_t> table;
    for (int k = range[2][0]; k <= range[2][1]; ++k) {
      for (int j = range[1][0]; j <= range[1][1]; ++j) {
        for (int i = range[0][0]; i <= range[0][1]; ++i) {
          const int v = i + grid.n[0] * (j + grid.n[1] * k);
          bool any = false;
          if (wholly_inside(node_box(v, 0, 0))) {
            table.assign(octree.nodes, 0);
            table[0] = 1;
            any = true;
          } else if (meets_surface(node_box(v, 0, 0))) {
            any = node_table(v, wholly_inside, meets_surface, table);
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

/// One byte per octree node below base voxel v (levels 1..L; `table` resized, 1 = wholly inside
/// by `wholly_inside`), depth-first over the nodes `meets_surface` meets. False when none is.
template <class Inside, class Meets>
bool VoxelEvaluator::Impl::node_table(int v, const Inside& wholly_inside,
                                      const Meets& meets_surface,
                                      std::vector<std::uint8_t>& table) const {
  table.assign(octree.nodes, 0);
  bool any = false;
  for_each_node_below(v, [&](int level, int morton, const Box3& box) {
    if (wholly_inside(box)) {
      table[octree.offset[level] + morton] = 1;
      any = true;
      return false;
    }
    return level < levels && meets_surface(box);
  });
  return any;
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
  // No cutoff: the minimum itself, the same double as with the nearest vertex's distance as
  // cutoff (an upper bound of it), found through the triangle hierarchy without that scan.
  const double value = solids.empty() ? kInf : detail::box_solids_sq_distance(solids, box, kInf);
  slot.store(value, std::memory_order_relaxed);
  return value;
}

}  // namespace camplace::voxel
