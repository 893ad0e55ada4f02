// d(C_h, M) on voxels (SPEC §5): distance from the critical objects to the nearest model
// voxel's box (conservative mode) or centre (center mode): lower bounds per voxel from
// setup.cpp, values as needed (Impl::critical_sq).
#include <cmath>
#include <limits>

#include "impl.hpp"

namespace camplace::voxel {

VoxelEvaluator::Impl::ModelDistance VoxelEvaluator::Impl::model_distance(
    const std::vector<std::uint8_t>& model, int time_step) const {
  // The nearest model voxel by the lower bounds first; then only voxels whose bound does not
  // exclude them (detail::beyond: their value cannot be below the best so far).
  const auto& lb = critical_lb_by_step[time_step];
  thread_local std::vector<int> members;
  members.clear();
  int first = -1;
  for (int v = 0; v < grid.count(); ++v) {
    if (!model[v]) continue;
    members.push_back(v);
    if (first < 0 || lb[v] < lb[first]) first = v;
  }
  ModelDistance out;
  out.volume = static_cast<double>(members.size()) * voxel_volume;
  if (members.empty()) {
    out.d_model = core::empty_model_distance(scene.area);
    return out;
  }
  double best = critical_sq(time_step, first);
  for (int v : members) {
    if (v == first || detail::beyond(lb[v], best)) continue;
    best = std::min(best, critical_sq(time_step, v));
  }
  out.d_model = std::sqrt(best);
  return out;
}

}  // namespace camplace::voxel
