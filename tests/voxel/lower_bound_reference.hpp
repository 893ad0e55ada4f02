#pragma once
// A brute-force reference of the conservative lower bound of Err (VoxelEvaluator::
// err_lower_bound(), SPEC §4), written independently of voxel/src: core's distance formulas on
// every voxel, its own flood fill for 6-connected groups, its own obstacle-interior test.
// Obstacles must be convex (boxes, tetrahedra): a voxel then lies wholly inside one exactly when
// its 8 corners do.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "camplace/core/distance.hpp"
#include "camplace/core/err.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/core/sensor_model.hpp"
#include "camplace/voxel/grid.hpp"

namespace camplace::testing {

/// Per state (core::states order): 1 for the voxels that are provably in the filtered
/// conservative model whatever the cameras: a target (or, in masked mode, a dynamic obstacle)
/// of the state reaches into them (meets the box shrunk by 1e-9·(S's diagonal + S's largest
/// |coordinate|), the evaluator's contact depth), they lie not wholly inside an obstacle of the
/// state, and belong to a 6-connected group of such voxels that passes the plausibility filter
/// on its own.
inline std::vector<std::vector<std::uint8_t>> reference_proven_voxels(const core::Scene& scene,
                                                                      const voxel::Grid& grid) {
  const int nx = grid.n[0], ny = grid.n[1], nz = grid.n[2];
  const double depth =
      1e-9 * (grid.area.diagonal() +
              std::max(grid.area.min.cwiseAbs().maxCoeff(), grid.area.max.cwiseAbs().maxCoeff()));
  std::vector<std::vector<std::uint8_t>> out;
  for (const core::StateIndex& st : core::states(scene)) {
    const core::TimeStep& step = scene.time_steps[st.time_step];
    std::vector<const core::SceneObject*> obstacles, occupying;
    for (const auto& o : scene.static_obstacles) obstacles.push_back(&o);
    for (const auto& o : step.dynamic_obstacles) {
      obstacles.push_back(&o);
      if (scene.dynamic_mode == core::DynamicMode::masked) occupying.push_back(&o);
    }
    for (const auto& o : step.events[st.event].targets) occupying.push_back(&o);
    std::vector<std::uint8_t> in(grid.count(), 0);
    for (int v = 0; v < grid.count(); ++v) {
      const core::Box3 box = grid.voxel_box(v);
      const core::Box3 inner{box.min + core::Vec3::Constant(depth),
                             box.max - core::Vec3::Constant(depth)};
      bool reached = false;
      for (const auto* o : occupying) {
        reached = reached || core::box_solid_sq_distance(o->mesh, inner) == 0.0;
      }
      if (!reached) continue;
      bool inside_obstacle = false;
      for (const auto* o : obstacles) {
        bool all = true;
        for (int c = 0; c < 8 && all; ++c) {
          const core::Vec3 corner((c & 1) ? box.max.x() : box.min.x(),
                                  (c & 2) ? box.max.y() : box.min.y(),
                                  (c & 4) ? box.max.z() : box.min.z());
          all = core::point_solid_sq_distance(o->mesh, corner) == 0.0;
        }
        inside_obstacle = inside_obstacle || all;
      }
      in[v] = !inside_obstacle;
    }
    // Flood fill over face neighbours; keep the groups that pass the filter alone.
    std::vector<std::uint8_t> keep(grid.count(), 0), seen(grid.count(), 0);
    for (int start = 0; start < grid.count(); ++start) {
      if (!in[start] || seen[start]) continue;
      std::vector<int> group{start};
      seen[start] = 1;
      for (std::size_t n = 0; n < group.size(); ++n) {
        const int v = group[n];
        const int i = v % nx, j = (v / nx) % ny, k = v / (nx * ny);
        const std::array<std::array<int, 3>, 6> next{{{i - 1, j, k},
                                                      {i + 1, j, k},
                                                      {i, j - 1, k},
                                                      {i, j + 1, k},
                                                      {i, j, k - 1},
                                                      {i, j, k + 1}}};
        for (const auto& q : next) {
          if (q[0] < 0 || q[0] >= nx || q[1] < 0 || q[1] >= ny || q[2] < 0 || q[2] >= nz) continue;
          const int w = q[0] + nx * (q[1] + ny * q[2]);
          if (in[w] && !seen[w]) {
            seen[w] = 1;
            group.push_back(w);
          }
        }
      }
      int kmin = nz, kmax = -1;
      for (int v : group) {
        kmin = std::min(kmin, v / (nx * ny));
        kmax = std::max(kmax, v / (nx * ny));
      }
      const double volume = static_cast<double>(group.size()) * grid.voxel_volume();
      const double height = (kmax - kmin + 1) * grid.step.z();
      if (scene.plausibility.keeps(volume, height)) {
        for (int v : group) keep[v] = 1;
      }
    }
    out.push_back(std::move(keep));
  }
  return out;
}

/// The lower bound from the proven voxels: per state ω·(d_true − min(U, d_true))² with U the
/// distance from the critical objects to the nearest proven voxel (box), 0 without one (m²).
inline double reference_lower_bound(const core::Scene& scene, const voxel::Grid& grid) {
  const auto proven = reference_proven_voxels(scene, grid);
  const auto all = core::states(scene);
  std::vector<core::ErrTerm> terms;
  for (std::size_t s = 0; s < all.size(); ++s) {
    const core::TimeStep& step = scene.time_steps[all[s].time_step];
    const double d_true = std::sqrt(core::true_squared_distance(scene, all[s]).value);
    double best = std::numeric_limits<double>::infinity();
    for (int v = 0; v < grid.count(); ++v) {
      if (!proven[s][v]) continue;
      for (const core::SceneObject& c : step.critical) {
        best = std::min(best, core::box_solid_sq_distance(c.mesh, grid.voxel_box(v)));
      }
    }
    terms.push_back({step.events[all[s].event].weight, d_true, std::min(d_true, std::sqrt(best))});
  }
  return core::error_functional(terms);
}

}  // namespace camplace::testing
