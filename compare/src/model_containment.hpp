#pragma once
/// Does a voxel model hold the exact model? Counted voxel by voxel (SPEC §8).
#include <cstdint>
#include <vector>

#include "camplace/exact/evaluator.hpp"
#include "camplace/voxel/grid.hpp"

namespace camplace::compare::detail {

/// How the centres of the voxels are placed inside or outside the exact model.
enum class CentreLocation {
  /// Centres joined by a grid segment that no boundary triangle meets lie on the same side of
  /// the boundary: one centre per such connected set is located in the Nef polyhedron, and a
  /// set reaching outside the model's bounding box is outside without any location.
  by_connected_sets,
  /// Every centre in the model's bounding box is located (the tests' reference; on fine grids
  /// with refinement it takes hours).
  every_centre,
};

/// Counts the voxels of `grid` outside `voxel_model` (one byte per voxel, non-zero = in the
/// model) that hold points of the exact model: a boundary triangle of the exact model reaching
/// into the voxel's interior (shrunk by 1e-9 m), or the voxel's centre in the closed exact
/// model. 0 means the voxel model contains the exact model.
int exact_outside_voxel_model(const exact::ExactModel& model, const voxel::Grid& grid,
                              const std::vector<std::uint8_t>& voxel_model,
                              CentreLocation location = CentreLocation::by_connected_sets);

}  // namespace camplace::compare::detail
