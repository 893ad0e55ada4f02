// CAMPLACE_EXPENSIVE_CHECKS (CMake option; on in the asan preset): every evaluation checks its
// own stages against independent or slower computations and aborts with a message when one
// disagrees — a sample of raw-model labels against the brute-force reference of
// tests/support/reference (written without voxel/'s code), the filtered model against the raw
// one, d(C_h, M) against the plain minimum over every cell, and the refined model against the
// unrefined one. Built only with the option: these checks cost far more than the evaluation.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "impl.hpp"
#include "reference.hpp"

namespace camplace::voxel {

using detail::CameraSetup;
using detail::CellSet;

namespace {

[[noreturn]] void fail(const std::string& what, const char* file, int line) {
  core::assertion_failed(what.c_str(), file, line);
}

/// Evaluations so far (any thread): each samples different voxels.
std::atomic<unsigned> evaluations{0};

}  // namespace

void VoxelEvaluator::Impl::check_labels(
    const core::CameraConfig& config, const std::vector<std::vector<std::uint8_t>>& models) const {
  constexpr int kSamples = 12;
  const unsigned round = evaluations++;
  const int count = grid.count();
  for (int n = 0; n < kSamples; ++n) {
    // A spread of voxels that changes from one evaluation to the next.
    const int v = static_cast<int>(
        (static_cast<unsigned long>(round) * 7919UL + static_cast<unsigned long>(n) * 104729UL) %
        static_cast<unsigned long>(count));
    const core::Box3 box = grid.voxel_box(v);
    for (std::size_t s = 0; s < states.size(); ++s) {
      const detail::StateInfo& state = states[s];
      if (removed_by_step[state.time_step][v]) {
        if (models[s][v])
          fail("a voxel inside an obstacle is in the raw model", __FILE__, __LINE__);
        continue;
      }
      bool ambiguous = false, seen_free = false;
      for (std::size_t c = 0; c < config.size() && !ambiguous; ++c) {
        const int cam = static_cast<int>(c);
        const testing::ReferenceLabel ref =
            conservative ? testing::reference_box_label(scene, state.time_step, state.event,
                                                        config[c], box, 1e-7, cam)
                         : testing::reference_label(scene, state.time_step, state.event, config[c],
                                                    box.center(), 1e-7, cam);
        ambiguous = ref.ambiguous;
        seen_free = seen_free || ref.label == Label::free;
      }
      if (ambiguous) continue;
      if ((models[s][v] != 0) == !seen_free) continue;
      fail("raw model of state " + std::to_string(s) + " at voxel " + std::to_string(v) +
               (seen_free ? " keeps a voxel the reference sees free"
                          : " drops a voxel no camera of the reference sees free"),
           __FILE__, __LINE__);
    }
  }
}

void VoxelEvaluator::Impl::check_filtered(
    const std::vector<std::vector<std::uint8_t>>& raw,
    const std::vector<std::vector<std::uint8_t>>& filtered) const {
  for (std::size_t s = 0; s < raw.size(); ++s) {
    for (int v = 0; v < grid.count(); ++v) {
      if (filtered[s][v] && !raw[s][v]) {
        fail("the filtered model of state " + std::to_string(s) + " holds voxel " +
                 std::to_string(v) + ", which the raw model does not",
             __FILE__, __LINE__);
      }
    }
  }
}

void VoxelEvaluator::Impl::check_distance(const std::vector<std::uint8_t>& model, int time_step,
                                          const ModelDistance& found) const {
  double best = std::numeric_limits<double>::infinity();
  long members = 0;
  for (int v = 0; v < grid.count(); ++v) {
    if (!model[v]) continue;
    ++members;
    best = std::min(best, critical_sq(time_step, v));
  }
  const double d = members ? std::sqrt(best) : core::empty_model_distance(scene.area);
  if (d != found.d_model || static_cast<double>(members) * voxel_volume != found.volume) {
    fail("d(C, M) " + std::to_string(found.d_model) +
             " differs from the minimum over every voxel " + std::to_string(d),
         __FILE__, __LINE__);
  }
}

void VoxelEvaluator::Impl::check_refined(const std::vector<std::vector<std::uint8_t>>& models,
                                         const std::vector<CellSet>& leaves,
                                         const std::vector<ModelDistance>& distances) const {
  for (std::size_t s = 0; s < leaves.size(); ++s) {
    const CellSet& set = leaves[s];
    for (int v : set.voxels) {
      if (!models[s][v]) {
        fail("the refined model of state " + std::to_string(s) + " has cells in voxel " +
                 std::to_string(v) + ", outside the unrefined model",
             __FILE__, __LINE__);
      }
    }
    // Refined M ⊆ unrefined M: no nearer (a cell's box lies in its voxel's; up to rounding).
    detail::Rows rows;
    detail::rows_from_bytes(models[s], grid, rows);
    const ModelDistance base = model_distance(rows, states[s].time_step);
    if (distances[s].volume > base.volume * (1.0 + 1e-12) ||
        (base.volume > 0.0 && distances[s].volume > 0.0 &&
         detail::beyond(base.d_model * base.d_model,
                        distances[s].d_model * distances[s].d_model))) {
      fail("the refined model of state " + std::to_string(s) + " is larger or nearer (d " +
               std::to_string(distances[s].d_model) + " m) than the unrefined one (d " +
               std::to_string(base.d_model) + " m)",
           __FILE__, __LINE__);
    }
    // The refined distance is the minimum over its finest cells. A cell lies in its voxel's box,
    // so it is no nearer than the voxel: voxels are visited nearest first, and those farther
    // than the nearest cell found so far (with a margin for the rounding of the two box
    // distances) hold no nearer cell. The same minimum as a scan of every cell, without the
    // distance of every cell (at 3 levels, 512 per voxel).
    const int step = states[s].time_step;
    std::vector<std::pair<double, std::size_t>> nearest_first;
    nearest_first.reserve(set.voxels.size());
    for (std::size_t slot = 0; slot < set.voxels.size(); ++slot)
      nearest_first.emplace_back(critical_sq(step, set.voxels[slot]), slot);
    std::sort(nearest_first.begin(), nearest_first.end());
    double best = std::numeric_limits<double>::infinity();
    for (const auto& [voxel_sq, slot] : nearest_first) {
      if (voxel_sq > best * (1.0 + 1e-9)) break;
      for (int m = 0; m < octree.cells; ++m) {
        if (set.cells[slot * octree.cells + m]) {
          best = std::min(best, node_sq(step, set.voxels[slot], levels, m));
        }
      }
    }
    if (distances[s].volume > 0.0 && std::sqrt(best) != distances[s].d_model) {
      fail("refined d(C, M) " + std::to_string(distances[s].d_model) +
               " differs from the minimum over every cell " + std::to_string(std::sqrt(best)),
           __FILE__, __LINE__);
    }
  }
}

}  // namespace camplace::voxel
