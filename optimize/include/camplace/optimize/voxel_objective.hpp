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
  /// Err and, as tie-breaker, volume_fraction() of the same evaluation.
  Score score(const core::CameraConfig& config, core::Timing& timing) const override;
  /// (½ · voxel diagonal)² at the evaluator's resolution.
  double default_tolerance() const override;
  /// VoxelEvaluator::err_lower_bound(): conservative mode only (0 in center mode).
  double err_lower_bound() const override;
  const voxel::VoxelEvaluator& evaluator() const { return evaluator_; }

 private:
  voxel::VoxelEvaluator evaluator_;
};

/// The tie-breaker of VoxelObjective. On the plateau, where the filtered model
/// touches the critical objects (d_model = 0) in every state of positive weight, so that
/// Err = Σ ω d_true² whatever the cameras: the ω-weighted mean fraction of S the model fills,
/// Σ ω·model_volume / (Σ ω · volume(S)) ∈ [0, 1] (model_volume in m³ per state). A smaller model
/// is a configuration whose cameras prove more of S free, one step nearer to cutting the model
/// off the critical objects. Off the plateau (some weighted state with d_model ≠ 0), and when
/// every weight is 0: 0, so Err alone decides there (a tie-breaker over every state's volume
/// led gaco into worse optima on paper_basic; README, "The plateau and the tie-breaker").
double volume_fraction(const std::vector<core::StateResult>& states, const core::Box3& area);

/// Score::touching_excess of VoxelObjective (m²): Σ over the states whose model touches the
/// critical objects (d_model = 0) of ω·d_true²·(model_volume / volume(S)), the fraction clamped
/// to [0, 1]. Err + this excess equals Err when no state touches, lies in [Err, 2·Err], and
/// falls as the cameras prove more of such a state's S free, before the model comes off the
/// critical objects (Err alone is flat there: each such term is ω·d_true² whatever the cameras).
double touching_volume_excess(const std::vector<core::StateResult>& states, const core::Box3& area);

}  // namespace camplace::optimize
