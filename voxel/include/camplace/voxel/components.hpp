#pragma once
/// Connected components of a voxel model and the plausibility filter (SPEC §4–5).
#include <cstdint>
#include <vector>

#include "camplace/core/scene.hpp"
#include "camplace/voxel/grid.hpp"

namespace camplace::voxel {

/// How many components the filter kept and removed.
struct ComponentCount {
  int kept = 0;
  int removed = 0;
};

/// Splits `model` (one byte per voxel of `grid`, 1 = in M) into 6-connected components and
/// clears every component the plausibility filter discards: volume = voxel count × voxel volume
/// (m³), height = z-extent of the component's voxel boxes (m).
ComponentCount filter_components(std::vector<std::uint8_t>& model, const Grid& grid,
                                 const core::Plausibility& plausibility);

/// filter_components on each of `models` (of one grid), as the evaluator filters a chunk of
/// states: the components of the voxels that all of them hold are found once, then joined to
/// each model's other voxels (docs/design/distance.md C1). The same models and counts.
std::vector<ComponentCount> filter_components_together(
    std::vector<std::vector<std::uint8_t>>& models, const Grid& grid,
    const core::Plausibility& plausibility);

/// The 6-connected component of each voxel of `model` (as filter_components forms them):
/// 0, 1, ... in the order of each component's first voxel by index, −1 outside the model.
std::vector<int> component_labels(const std::vector<std::uint8_t>& model, const Grid& grid);

}  // namespace camplace::voxel
