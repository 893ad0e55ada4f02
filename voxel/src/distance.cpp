// d(C_h, M) on voxels (SPEC §5): distance from the critical objects to the nearest model
// voxel's box (conservative mode) or centre (center mode), precomputed per voxel in setup.cpp.
#include <cmath>
#include <limits>

#include "impl.hpp"

namespace camplace::voxel {

VoxelEvaluator::Impl::ModelDistance VoxelEvaluator::Impl::model_distance(
    const std::vector<std::uint8_t>& model, int time_step) const {
  const auto& critical = critical_sq_by_step[time_step];
  double best = std::numeric_limits<double>::infinity();
  int count = 0;
  for (int v = 0; v < grid.count(); ++v) {
    if (!model[v]) continue;
    ++count;
    best = std::min(best, critical[v]);
  }
  ModelDistance out;
  out.d_model = count > 0 ? std::sqrt(best) : core::empty_model_distance(scene.area);
  out.volume = count * voxel_volume;
  return out;
}

}  // namespace camplace::voxel
