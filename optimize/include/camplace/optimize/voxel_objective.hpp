#pragma once
/// The optimizer's default objective: the voxel Err of SPEC §5.
#include "camplace/optimize/objective.hpp"
#include "camplace/voxel/evaluator.hpp"

namespace camplace::optimize {

/// The voxel Err of SPEC §5 (mode and resolution from the options).
class VoxelObjective : public Objective {
 public:
  VoxelObjective(const core::Scene& scene, const voxel::VoxelOptions& options);
  double evaluate(const core::CameraConfig& config, core::Timing& timing) const override;
  /// (½ · voxel diagonal)² at the evaluator's resolution.
  double default_tolerance() const override;
  /// VoxelEvaluator::err_lower_bound(): conservative mode only (0 in center mode).
  double err_lower_bound() const override;
  const voxel::VoxelEvaluator& evaluator() const { return evaluator_; }

 private:
  voxel::VoxelEvaluator evaluator_;
};

}  // namespace camplace::optimize
