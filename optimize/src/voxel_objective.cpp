#include "camplace/optimize/voxel_objective.hpp"

#include <algorithm>

#include "camplace/core/err.hpp"

namespace camplace::optimize {

VoxelObjective::VoxelObjective(const core::Scene& scene, const voxel::VoxelOptions& options)
    : evaluator_(scene, options) {}

double VoxelObjective::evaluate(const core::CameraConfig& config, core::Timing& timing) const {
  const core::Evaluation evaluation = evaluator_.evaluate(config);
  timing = evaluation.timing;
  return evaluation.err;
}

Score VoxelObjective::score(const core::CameraConfig& config, core::Timing& timing) const {
  const core::Evaluation evaluation = evaluator_.evaluate(config);
  timing = evaluation.timing;
  const core::Box3& area = evaluator_.scene().area;
  return {evaluation.err, volume_fraction(evaluation.states, area),
          touching_volume_excess(evaluation.states, area)};
}

double VoxelObjective::default_tolerance() const {
  return core::default_tolerance(evaluator_.grid().area, evaluator_.grid().n);
}

double VoxelObjective::err_lower_bound() const { return evaluator_.err_lower_bound(); }

double volume_fraction(const std::vector<core::StateResult>& states, const core::Box3& area) {
  const core::Vec3 size = area.size();
  const double volume = size.x() * size.y() * size.z();
  double weights = 0.0, weighted = 0.0;
  for (const core::StateResult& s : states) {
    if (s.weight <= 0.0) continue;  // no part of Err
    // Off the plateau Err alone decides (see the header): no tie-breaker.
    if (s.d_model != 0.0) return 0.0;
    weights += s.weight;
    weighted += s.weight * s.model_volume;
  }
  if (!(weights > 0.0 && volume > 0.0)) return 0.0;
  return std::clamp(weighted / (weights * volume), 0.0, 1.0);
}

double touching_volume_excess(const std::vector<core::StateResult>& states,
                              const core::Box3& area) {
  const core::Vec3 size = area.size();
  const double volume = size.x() * size.y() * size.z();
  if (!(volume > 0.0)) return 0.0;
  double excess = 0.0;
  for (const core::StateResult& s : states) {
    if (s.weight <= 0.0 || s.d_model != 0.0) continue;
    excess += s.weight * s.d_true * s.d_true * std::clamp(s.model_volume / volume, 0.0, 1.0);
  }
  return excess;
}

}  // namespace camplace::optimize
