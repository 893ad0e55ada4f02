// d(C_h, M) on voxels (SPEC §5): distance from the critical objects to the nearest model
// voxel's box (conservative mode) or centre (center mode): lower bounds per voxel from
// setup.cpp, values as needed (Impl::critical_sq).
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "impl.hpp"

namespace camplace::voxel {

VoxelEvaluator::Impl::ModelDistance VoxelEvaluator::Impl::model_distance(
    const std::vector<std::uint8_t>& model, int time_step) const {
  ModelDistance out;
  // Model bytes are 0 or 1: eight at a time, the product with 0x0101…01 adds them up into the
  // top byte (at most 8).
  long members = 0;
  const int count = grid.count();
  int v = 0;
  for (; v + 8 <= count; v += 8) {
    std::uint64_t word;
    std::memcpy(&word, model.data() + v, sizeof word);
    members += static_cast<long>((word * 0x0101010101010101ULL) >> 56);
  }
  for (; v < count; ++v) members += model[v];
  out.volume = static_cast<double>(members) * voxel_volume;
  if (members == 0) {
    out.d_model = core::empty_model_distance(scene.area);
    return out;
  }
  // Model voxels shell by shell, by their lower bound: the scan stops at the first shell whose
  // voxels' bounds all exclude them (detail::beyond: their value cannot be below the best so
  // far); within a shell, each voxel whose bound does not exclude it. The same minimum as over
  // every model voxel. Shell b's voxels have √lb ≥ b·width up to rounding, so (b − 1)·width
  // bounds them safely.
  const auto& lb = critical_lb_by_step[time_step];
  const LowerBoundShells& shells = shells_by_step[time_step];
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t b = 0; b + 1 < shells.start.size(); ++b) {
    const double below = b > 0 ? (static_cast<double>(b) - 1.0) * shells.width : 0.0;
    if (detail::beyond(below * below, best)) break;
    for (int n = shells.start[b]; n < shells.start[b + 1]; ++n) {
      const int u = shells.voxels[n];
      if (model[u] && !detail::beyond(lb[u], best))
        best = std::min(best, critical_sq(time_step, u));
    }
  }
  out.d_model = std::sqrt(best);
  return out;
}

}  // namespace camplace::voxel
