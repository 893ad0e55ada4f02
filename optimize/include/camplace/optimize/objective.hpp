#pragma once
/// What the optimizer minimises. The optimizer sees only this interface (STYLE: dependencies),
/// so another pipeline can stand in for the voxel one.
#include <array>
#include <memory>

#include "camplace/core/camera.hpp"
#include "camplace/voxel/evaluator.hpp"

namespace camplace::optimize {

/// Err of a camera configuration (m², SPEC §4) with the time split of the evaluation.
/// evaluate() must be thread-safe and deterministic.
class Objective {
 public:
  virtual ~Objective() = default;
  /// Err (m²) of config (one setting per camera); writes the evaluation's time split (ms).
  virtual double evaluate(const core::CameraConfig& config, voxel::Timing& timing) const = 0;
  /// The default optimisation tolerance for this objective (m², SPEC §4).
  virtual double default_tolerance() const = 0;
  /// A lower bound of Err over all configurations (m²); 0 when none is known.
  virtual double err_lower_bound() const { return 0.0; }
};

/// The voxel Err of SPEC §5 (mode and resolution from the options).
class VoxelObjective : public Objective {
 public:
  VoxelObjective(const core::Scene& scene, const voxel::VoxelOptions& options);
  double evaluate(const core::CameraConfig& config, voxel::Timing& timing) const override;
  /// (½ · voxel diagonal)² at the evaluator's resolution.
  double default_tolerance() const override;
  /// VoxelEvaluator::err_lower_bound(): conservative mode only (0 in center mode).
  double err_lower_bound() const override;
  const voxel::VoxelEvaluator& evaluator() const { return evaluator_; }

 private:
  voxel::VoxelEvaluator evaluator_;
};

}  // namespace camplace::optimize
