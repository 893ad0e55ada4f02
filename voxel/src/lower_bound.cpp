// The conservative lower bound of Err (SPEC §5, VoxelEvaluator::err_lower_bound): per state the
// cells that an occupying object reaches into are in M whatever the cameras; the groups of them
// that pass the filter bound d(C, M) from above. One rule at every level: the same cell sets,
// filter (detail::filter_cells) and distance (model_distance) as the evaluation.
#include <algorithm>
#include <cmath>
#include <limits>

#include "camplace/core/err.hpp"
#include "impl.hpp"
#include "solid_distance.hpp"

namespace camplace::voxel {

using core::Box3;
using core::Vec3;
using detail::CellSet;

/// The conservative lower bound of Err (the rule at VoxelEvaluator::err_lower_bound()), on the
/// finest cells at every level (level 0: the voxels): it holds for every configuration by
/// docs/design/lower-bound.md B1 (level 0; reached voxels: labelling.md L6) and B2 (refined).
/// Cells are found by descending from the base voxels voxels_reached() gives, through the nodes
/// whose shrunk box meets the object (a cell left out only makes the bound smaller). Err and the
/// bound add the same terms in different orders: compare through core::lower_bound_threshold.
double VoxelEvaluator::Impl::lower_bound() const {
  const double depth = contact_depth();
  const int cells = octree.cells;
  std::vector<core::ErrTerm> terms;
  // Per occupying object: its reached finest cells, per reached base voxel (ascending).
  struct Reached {
    std::vector<int> voxels;
    std::vector<std::uint8_t> cells;  ///< voxels.size() × cells
  };
  std::vector<Reached> reached(objects.size());
  std::vector<std::uint8_t> known(objects.size(), 0);
  const bool measurable = 2.0 * depth < (grid.step * cell_sizes[levels].factor).minCoeff();
  auto compute = [&](int o) {
    Reached r;
    if (!measurable) return r;  // cells too small to tell
    if (levels == 0) {
      r.voxels = reached_by_object[o];
      r.cells.assign(r.voxels.size(), 1);
      return r;
    }
    const std::vector<detail::IndexedSolid> solid{detail::index_solid(*objects[o].mesh)};
    for (int v : reached_by_object[o]) {
      std::vector<std::uint8_t> flags(cells, 0);
      bool any = false;
      for_each_node_below(v, [&](int level, int morton, const Box3& box) {
        const Box3 inner{box.min + Vec3::Constant(depth), box.max - Vec3::Constant(depth)};
        if (detail::box_solids_sq_distance(solid, inner, 0.0) != 0.0) return false;
        if (level < levels) return true;
        flags[morton] = 1;
        any = true;
        return false;
      });
      if (!any) continue;
      r.voxels.push_back(v);
      r.cells.insert(r.cells.end(), flags.begin(), flags.end());
    }
    return r;
  };
  for (const detail::StateInfo& state : states) {
    const int h = state.time_step;
    // The union of the state's occupying objects' cells, less obstacle interiors.
    std::vector<int> voxels;
    for (int o : state.objects) {
      if (!objects[o].occupying) continue;
      if (!known[o]) {
        reached[o] = compute(o);
        known[o] = 1;
      }
      voxels.insert(voxels.end(), reached[o].voxels.begin(), reached[o].voxels.end());
    }
    std::sort(voxels.begin(), voxels.end());
    voxels.erase(std::unique(voxels.begin(), voxels.end()), voxels.end());
    voxels.erase(std::remove_if(voxels.begin(), voxels.end(),
                                [&](int v) { return removed_by_step[h][v] != 0; }),
                 voxels.end());
    CellSet set;
    set.voxels = voxels;
    set.cells.assign(voxels.size() * cells, 0);
    for (int o : state.objects) {
      if (!objects[o].occupying) continue;
      const Reached& r = reached[o];
      for (std::size_t n = 0; n < r.voxels.size(); ++n) {
        const auto it = std::lower_bound(voxels.begin(), voxels.end(), r.voxels[n]);
        if (it == voxels.end() || *it != r.voxels[n]) continue;  // removed
        const std::size_t slot = it - voxels.begin();
        for (int c = 0; c < cells; ++c) set.cells[slot * cells + c] |= r.cells[n * cells + c];
      }
    }
    for (std::size_t slot = 0; slot < voxels.size() && levels > 0; ++slot) {
      const int table = removal_index[h][voxels[slot]];
      if (table < 0) continue;
      const std::uint8_t* removed = removal_tables[table].data();
      for (int l = 1; l <= levels; ++l) {
        const int span = 1 << (3 * (levels - l));
        for (int m = 0; m < (1 << (3 * l)); ++m) {
          if (!removed[octree.offset[l] + m]) continue;
          std::fill_n(set.cells.begin() + slot * cells + static_cast<std::size_t>(m) * span, span,
                      std::uint8_t(0));
        }
      }
    }
    detail::filter_cells(set, octree, grid, scene.plausibility);
    const bool kept = std::find(set.cells.begin(), set.cells.end(), 1) != set.cells.end();
    // No kept group: d' = d_true, the term is 0.
    const double bound =
        kept ? std::min(state.d_true, model_distance(set, h).d_model) : state.d_true;
    terms.push_back({state.weight, state.d_true, bound});
  }
  return core::error_functional(terms);
}

double VoxelEvaluator::Impl::contact_depth() const {
  // Far above the labeller's touching tolerance (1e-12 of the camera's distance plus the
  // voxel's half extents: below 2e-12 of S's diagonal for cameras in S, where the domains put
  // them; `evaluate` accepts cameras outside S, still below this depth within ~1000 diagonals of
  // S) and far above the rounding of coordinates as large as S's corners. Objects outside S do
  // not enter: only points inside a voxel of S are proven.
  const double far =
      std::max(grid.area.min.cwiseAbs().maxCoeff(), grid.area.max.cwiseAbs().maxCoeff());
  return 1e-9 * (grid.area.diagonal() + far);
}

/// The voxels whose box, shrunk by contact_depth() on every side, meets the closed solid `mesh`
/// (core::box_solid_sq_distance == 0; the culled distance is exact at 0), ascending. Only
/// voxels within one voxel of the solid's bounding box are tested.
std::vector<int> VoxelEvaluator::Impl::voxels_reached(const core::TriangleMesh& mesh) const {
  const double depth = contact_depth();
  std::vector<int> out;
  if (!(2.0 * depth < grid.step.minCoeff())) return out;  // voxels too small to tell
  const std::vector<detail::IndexedSolid> solid{detail::index_solid(mesh)};
  const Box3& bounds = solid.front().bounds;
  const auto range = voxel_range(bounds);
  for (int k = range[2][0]; k <= range[2][1]; ++k) {
    for (int j = range[1][0]; j <= range[1][1]; ++j) {
      for (int i = range[0][0]; i <= range[0][1]; ++i) {
        const int v = i + grid.n[0] * (j + grid.n[1] * k);
        const Box3 box = grid.voxel_box(v);
        const Box3 inner{box.min + Vec3::Constant(depth), box.max - Vec3::Constant(depth)};
        if (detail::box_solids_sq_distance(solid, inner, 0.0) == 0.0) out.push_back(v);
      }
    }
  }
  return out;
}

}  // namespace camplace::voxel
