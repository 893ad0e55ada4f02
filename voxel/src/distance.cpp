// d(C_h, M) (SPEC §5) at every level, one rule: the distance from the critical objects to the
// nearest cell of M — the voxel's box (conservative mode) or centre (center mode) at level 0, a
// finest cell's box with refinement. Base voxels are scanned in shells of their lower bound
// (setup.cpp) and stop at the first shell beyond the best so far; within a refined voxel, branch
// and bound down its octree (docs/design/distance.md D1, D2). The base model's bit rows (rows.hpp)
// and a set of cells (cells.hpp) are two views of M for the same scan.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "impl.hpp"

namespace camplace::voxel {

using detail::CellSet;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// M as bit rows of the base voxels (level 0; detail::Rows).
struct RowMembers {
  const std::uint64_t* rows = nullptr;
  std::size_t words = 0;  ///< all rows'
  int nx = 1, words_per_row = 1;
  long cells() const {
    long members = 0;
    for (std::size_t w = 0; w < words; ++w) members += detail::bit_count(rows[w]);
    return members;
  }
  bool holds(int v) const { return detail::row_bit(rows, nx, words_per_row, v); }
  /// f(v) for each voxel v of M, ascending.
  template <class F>
  void for_each(const F& f) const {
    for (std::size_t at = 0; at < words; ++at) {
      const int first =
          static_cast<int>(at / words_per_row) * nx + 64 * static_cast<int>(at % words_per_row);
      for (std::uint64_t b = rows[at]; b; b &= b - 1) f(first + __builtin_ctzll(b));
    }
  }
  double cell_fraction(const detail::Octree&) const { return 1.0; }  ///< of a voxel's volume
};

/// M as finest cells per base voxel (CellSet), with a dense map base voxel → slot.
struct CellMembers {
  const CellSet* set = nullptr;
  const int* slot_of = nullptr;  ///< per base voxel: its slot, or −1
  int cells_per_slot = 1;
  bool whole(int slot) const {
    return slot < static_cast<int>(set->whole.size()) && set->whole[slot];
  }
  /// The cells in M of a slot.
  long cells_of(int slot) const {
    if (whole(slot)) return cells_per_slot;
    const auto begin = set->cells.begin() + static_cast<std::ptrdiff_t>(slot) * cells_per_slot;
    return std::count(begin, begin + cells_per_slot, std::uint8_t(1));
  }
  long cells() const {
    long count = 0;
    for (std::size_t slot = 0; slot < set->voxels.size(); ++slot) {
      count += cells_of(static_cast<int>(slot));
    }
    return count;
  }
  bool holds(int v) const { return slot_of[v] >= 0; }
  double cell_fraction(const detail::Octree& octree) const {
    return std::ldexp(1.0, -3 * octree.levels);
  }
};

}  // namespace

template <class Members>
VoxelEvaluator::Impl::ModelDistance VoxelEvaluator::Impl::nearest(const Members& members,
                                                                  long count, int time_step) const {
  ModelDistance out;
  out.volume = static_cast<double>(count) * voxel_volume * members.cell_fraction(octree);
  if (count == 0) {
    out.d_model = core::empty_model_distance(scene.area);
    return out;
  }
  // Base voxels of M shell by shell, by their lower bound: the scan stops at the first shell
  // whose voxels' bounds all exclude them (detail::beyond: their value cannot be below the best
  // so far); within a shell, each voxel whose bound does not exclude it. Shell b's voxels have
  // √lb ≥ b·width up to rounding, so (b − 1)·width bounds them safely. With cells, the voxel's
  // box distance bounds its cells' (a cell lies in it).
  const auto& lb = critical_lb_by_step[time_step];
  const LowerBoundShells& shells = shells_by_step[time_step];
  double best = kInf;
  // Bit rows: once the scan has passed as many voxels as M holds, M's own voxels are cheaper to
  // walk; each one whose bound does not exclude it is taken (D1, 4: the same minimum).
  long budget = std::is_same_v<Members, RowMembers> ? count : -1;
  for (std::size_t b = 0; b + 1 < shells.start.size(); ++b) {
    const double below = b > 0 ? (static_cast<double>(b) - 1.0) * shells.width : 0.0;
    if (detail::beyond(below * below, best)) break;
    if constexpr (std::is_same_v<Members, RowMembers>) {
      budget -= shells.start[b + 1] - shells.start[b];
      if (budget < 0) {
        members.for_each([&](int u) {
          if (!detail::beyond(lb[u], best)) best = std::min(best, critical_sq(time_step, u));
        });
        break;
      }
    }
    for (int n = shells.start[b]; n < shells.start[b + 1]; ++n) {
      const int u = shells.voxels[n];
      if (!members.holds(u) || detail::beyond(lb[u], best)) continue;
      if constexpr (std::is_same_v<Members, CellMembers>) {
        const int slot = members.slot_of[u];
        if (members.cells_of(slot) == 0) continue;  // (cleared by the filter)
        if (octree.levels > 0) {
          if (detail::beyond(critical_sq(time_step, u), best)) continue;
          best = nearest_cell(*members.set, slot, time_step, best);
          continue;
        }
      }
      best = std::min(best, critical_sq(time_step, u));
    }
  }
  out.d_model = std::sqrt(best);
  return out;
}

/// min(best, the distance² of the nearest cell of M in `slot`): branch and bound down the
/// voxel's octree, children nearest first. A node's box holds its cells' boxes, so its distance
/// bounds theirs (detail::beyond allows for rounding); nodes with no cell are skipped.
double VoxelEvaluator::Impl::nearest_cell(const CellSet& set, int slot, int time_step,
                                          double best) const {
  const int levels = octree.levels, cells = octree.cells;
  const int v = set.voxels[slot];
  thread_local std::vector<std::uint8_t> filled;
  filled.resize(octree.nodes);
  const std::uint8_t* leaf = set.cells.data() + static_cast<std::size_t>(slot) * cells;
  std::copy(leaf, leaf + cells, filled.begin() + octree.offset[levels]);
  for (int l = levels - 1; l >= 0; --l) {  // (all ones for a whole slot: cheap enough)
    const int n = 1 << (3 * l);
    const std::uint8_t* below = filled.data() + octree.offset[l + 1];
    for (int m = 0; m < n; ++m) {
      std::uint8_t any = 0;
      for (int q = 0; q < 8; ++q) any |= below[8 * m + q];
      filled[octree.offset[l] + m] = any;
    }
  }
  struct Candidate {
    double sq;
    int morton;
  };
  auto descend = [&](auto& self, int level, int morton, [[maybe_unused]] double node) -> void {
    Candidate children[8];
    int n = 0;
    for (int q = 0; q < 8; ++q) {
      const int child = 8 * morton + q;
      if (!filled[octree.offset[level + 1] + child]) continue;
      const double sq = node_sq(time_step, v, level + 1, child);
      // A node's distance bounds its children's, which branch and bound relies on (D2).
      CAMPLACE_ASSERT(!detail::beyond(node, sq));
      if (detail::beyond(sq, best)) continue;
      // Insertion into the sorted list (at most 8).
      int at = n++;
      for (; at > 0 && children[at - 1].sq > sq; --at) children[at] = children[at - 1];
      children[at] = {sq, child};
    }
    for (int c = 0; c < n; ++c) {
      if (detail::beyond(children[c].sq, best)) break;
      if (level + 1 == levels) {
        best = std::min(best, children[c].sq);
      } else {
        self(self, level + 1, children[c].morton, children[c].sq);
      }
    }
  };
  descend(descend, 0, 0, critical_sq(time_step, v));
  return best;
}

VoxelEvaluator::Impl::ModelDistance VoxelEvaluator::Impl::model_distance(const detail::Rows& model,
                                                                         int time_step) const {
  const int nx = grid.n[0];
  CAMPLACE_ASSERT(model.size() ==
                  static_cast<std::size_t>(grid.n[1]) * grid.n[2] * detail::words_per_row(nx));
  // The filter often leaves a few voxels, far from C_h: the shell scan would walk every voxel
  // nearer than them. Few voxels are taken directly, by increasing lower bound, until the bound
  // excludes the rest (D1, 3: the same minimum).
  constexpr long kFew = 128;
  const RowMembers members{model.data(), model.size(), nx, detail::words_per_row(nx)};
  const long count = members.cells();
  if (count == 0 || count > kFew) return nearest(members, count, time_step);
  thread_local std::vector<int> few;
  few.clear();
  members.for_each([&](int u) { few.push_back(u); });
  ModelDistance out;
  out.volume = static_cast<double>(count) * voxel_volume;
  const auto& lb = critical_lb_by_step[time_step];
  std::sort(few.begin(), few.end(), [&](int a, int b) { return lb[a] < lb[b]; });
  double best = kInf;
  for (int u : few) {
    if (detail::beyond(lb[u], best)) break;  // and every voxel after it
    best = std::min(best, critical_sq(time_step, u));
  }
  out.d_model = std::sqrt(best);
  return out;
}

VoxelEvaluator::Impl::ModelDistance VoxelEvaluator::Impl::model_distance(const CellSet& set,
                                                                         int time_step) const {
  CAMPLACE_ASSERT(set.cells.size() == set.voxels.size() * octree.cells);
  // Base voxel → slot (−1: none), reset to −1 before returning.
  thread_local std::vector<int> slot_of;
  if (slot_of.size() != static_cast<std::size_t>(grid.count())) slot_of.assign(grid.count(), -1);
  for (std::size_t slot = 0; slot < set.voxels.size(); ++slot) {
    slot_of[set.voxels[slot]] = static_cast<int>(slot);
  }
  const CellMembers members{&set, slot_of.data(), octree.cells};
  const ModelDistance out = nearest(members, members.cells(), time_step);
  for (int v : set.voxels) slot_of[v] = -1;
  return out;
}

}  // namespace camplace::voxel
