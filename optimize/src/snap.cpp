#include "snap.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "problem.hpp"

namespace camplace::optimize::detail {
namespace {

bool is_angle(Component c) {
  return c == Component::yaw || c == Component::pitch || c == Component::roll;
}

}  // namespace

std::vector<double> round_to_grid(const Encoding& encoding, const std::vector<double>& x,
                                  const SnapGrid& grid) {
  const std::vector<Variable>& vars = encoding.variables();
  const std::vector<double> steps = encoding.steps(grid.position_m, grid.angle);
  std::vector<double> out(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    out[k] = std::clamp(std::round(x[k] / steps[k]) * steps[k], vars[k].lo, vars[k].hi);
  }
  if (encoding.keeps_out(out)) return out;
  // Some rounded positions lie in keep-out boxes: per such camera, search the grid positions
  // within kRadius steps of the rounded one for the free one nearest to the continuous position.
  constexpr int kRadius = 5;
  const core::CameraConfig continuous = encoding.decode(x);
  const int n = static_cast<int>(continuous.size());
  for (int camera = 0; camera < n; ++camera) {
    if (encoding.keeps_out(out, camera)) continue;
    std::vector<std::size_t> position_vars;
    for (std::size_t k = 0; k < vars.size(); ++k) {
      if (vars[k].camera == camera && !is_angle(vars[k].component)) position_vars.push_back(k);
    }
    const int m = static_cast<int>(position_vars.size());
    if (m == 0) continue;
    std::vector<int> offset(m, -kRadius);
    double best_distance = std::numeric_limits<double>::infinity();
    std::vector<double> best = out, trial = out;
    for (;;) {
      for (int j = 0; j < m; ++j) {
        const std::size_t k = position_vars[j];
        trial[k] = std::clamp(out[k] + offset[j] * steps[k], vars[k].lo, vars[k].hi);
      }
      if (encoding.keeps_out(trial, camera)) {
        const double d =
            (encoding.decode(trial, false)[camera].position - continuous[camera].position).norm();
        if (d < best_distance) {
          best_distance = d;
          best = trial;
        }
      }
      int j = 0;
      while (j < m && ++offset[j] > kRadius) offset[j++] = -kRadius;
      if (j == m) break;
    }
    out = best;  // unchanged when no free grid position is near: decode repairs it
  }
  return out;
}

SnappedResult snap_and_search(
    const Encoding& encoding, const Objective& objective, const std::vector<double>& x,
    const SnapGrid& grid, std::uint64_t max_evaluations,
    const std::function<core::CameraConfig(const core::CameraConfig&)>& round_trip,
    const std::function<bool()>& should_stop) {
  SnappedResult result;
  result.grid = grid;
  const std::vector<Variable>& vars = encoding.variables();
  const std::vector<double> steps = encoding.steps(grid.position_m, grid.angle);
  std::vector<double> current = round_to_grid(encoding, x, grid);
  const auto err_of = [&](const std::vector<double>& v) {
    core::Timing timing;
    ++result.evaluations;
    return checked_err(objective.evaluate(encoding.decode(v), timing));
  };
  double current_err = err_of(current);
  result.rounded_err = current_err;
  bool improved = true;
  bool stopped = false;
  while (improved && !stopped && result.evaluations < max_evaluations) {
    improved = false;
    for (std::size_t k = 0; k < vars.size() && !stopped && result.evaluations < max_evaluations;
         ++k) {
      for (const double direction : {1.0, -1.0}) {
        std::vector<double> trial = current;
        trial[k] = std::clamp(current[k] + direction * steps[k], vars[k].lo, vars[k].hi);
        if (trial[k] == current[k] || !encoding.keeps_out(trial, vars[k].camera)) continue;
        if (result.evaluations >= max_evaluations) break;
        if (should_stop()) {
          stopped = true;
          break;
        }
        const double err = err_of(trial);
        if (err < current_err) {
          current = std::move(trial);
          current_err = err;
          improved = true;
          break;
        }
      }
    }
  }
  result.cameras = round_trip(encoding.decode(current));
  core::Timing timing;
  result.err = checked_err(objective.evaluate(result.cameras, timing));
  return result;
}

}  // namespace camplace::optimize::detail
