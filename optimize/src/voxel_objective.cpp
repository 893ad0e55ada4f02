#include "camplace/optimize/voxel_objective.hpp"

#include "camplace/core/err.hpp"

namespace camplace::optimize {

VoxelObjective::VoxelObjective(const core::Scene& scene, const voxel::VoxelOptions& options)
    : evaluator_(scene, options) {}

double VoxelObjective::evaluate(const core::CameraConfig& config, core::Timing& timing) const {
  const core::Evaluation evaluation = evaluator_.evaluate(config);
  timing = evaluation.timing;
  return evaluation.err;
}

double VoxelObjective::default_tolerance() const {
  return core::default_tolerance(evaluator_.grid().area, evaluator_.grid().n);
}

double VoxelObjective::err_lower_bound() const { return evaluator_.err_lower_bound(); }

}  // namespace camplace::optimize
