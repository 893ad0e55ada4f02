#pragma once
// `optimize --snap`: the best configuration rounded to a grid and improved by a
// coordinate search on that grid.
#include <cstdint>
#include <functional>
#include <vector>

#include "camplace/optimize/encoding.hpp"
#include "camplace/optimize/objective.hpp"
#include "camplace/optimize/optimizer.hpp"

namespace camplace::optimize::detail {

/// The decision vector x rounded to the grid: each variable to the nearest multiple of its
/// step (Encoding::steps), clamped into its bounds (so a bound is a grid value too). A camera
/// whose rounded position lies in a keep-out box takes the free grid position nearest to its
/// position in x, within 5 steps per variable; without one it stays (decode repairs it, off the
/// grid).
std::vector<double> round_to_grid(const Encoding& encoding, const std::vector<double>& x,
                                  const SnapGrid& grid);

/// Rounds `x` to the grid and improves it by a coordinate search on the grid: each variable in
/// turn moves one step up or down (clamped), a move is kept when Err strictly decreases and no
/// camera enters a keep-out box; sweeps repeat until none improves or max_evaluations are spent.
/// `round_trip` maps a configuration to its re-read JSON form (the cameras reported). The search
/// also ends, keeping its best so far, as soon as `should_stop` says so (a signal, the run's
/// time limit): it is asked before every evaluation.
SnappedResult snap_and_search(
    const Encoding& encoding, const Objective& objective, const std::vector<double>& x,
    const SnapGrid& grid, std::uint64_t max_evaluations,
    const std::function<core::CameraConfig(const core::CameraConfig&)>& round_trip,
    const std::function<bool()>& should_stop);

}  // namespace camplace::optimize::detail
