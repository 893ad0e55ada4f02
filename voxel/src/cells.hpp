#pragma once
// The cells of the voxel pipeline at any level L of refinement (0 = the base voxels): the
// octree numbering below one base voxel, sets of finest cells, and their components with the
// plausibility filter (components.cpp; the dense base model has filter_components).
#include <array>
#include <cstdint>
#include <vector>

#include "camplace/core/scene.hpp"
#include "camplace/voxel/components.hpp"
#include "camplace/voxel/grid.hpp"

namespace camplace::voxel::detail {

/// The cells of the octree below one base voxel. A node is (level l, Morton index
/// m < 8^l of its local coordinates (a, b, c) ∈ [0, 2^l)³ with bit t of a, b, c at bits 3t,
/// 3t + 1, 3t + 2 of m); its children are 8m + q, q = qa + 2qb + 4qc; the finest cells (level
/// L) below node (l, m) are the Morton range [m·8^(L−l), (m + 1)·8^(L−l)).
struct Octree {
  int levels = 0;
  int side = 1;                            ///< 2^L
  int cells = 1;                           ///< 8^L
  std::vector<std::array<int, 3>> coords;  ///< per finest Morton index: (a, b, c)
  /// Per axis and finest Morton index: the Morton index of the face neighbour at +1 along the
  /// axis, wrapped to coordinate 0 in the next base voxel when `crosses`.
  std::array<std::vector<int>, 3> next;
  std::array<std::vector<std::uint8_t>, 3> crosses;
  /// Per axis: the finest cells with coordinate 0 along it (the voxel's low face).
  std::array<std::vector<int>, 3> low_face;
  std::vector<int> offset;  ///< node (l, m) has index offset[l] + m, l = 0..L
  int nodes = 1;            ///< Σ 8^l, l = 0..L
};

/// Finest cells of some base voxels for one state (a model before or after the filter, or the
/// cells the lower bound proves; at level 0 one cell per voxel): `voxels` ascending, `cells` one
/// byte per finest cell of each, slot s's at [s·8^L, (s + 1)·8^L), Morton order.
struct CellSet {
  std::vector<int> voxels;
  std::vector<std::uint8_t> cells;
  /// Per slot: 1 when every cell is in the set and the slot may be taken as a whole (a kept
  /// base voxel left unrefined); 0 says nothing.
  std::vector<std::uint8_t> whole;
};

/// The octree tables of L levels (L = 0: one cell per base voxel).
Octree make_octree(int levels);

/// Components of the finest cells of `set` (6-connectivity, across base voxels) and the
/// plausibility filter, the rule filter_components applies to voxels: volume = cell count × cell
/// volume, height = z-extent of the cells' boxes. Clears the cells of removed components (and
/// the `whole` flag of their slots).
ComponentCount filter_cells(CellSet& set, const Octree& octree, const Grid& grid,
                            const core::Plausibility& plausibility);

}  // namespace camplace::voxel::detail
