#pragma once
/// What the optimizer minimises. The optimizer sees only this interface (STYLE: dependencies),
/// so another pipeline can stand in for the voxel one (voxel_objective.hpp).
#include "camplace/core/camera.hpp"
#include "camplace/core/evaluation.hpp"

namespace camplace::optimize {

/// Err of a camera configuration (m², SPEC §4) with the time split of the evaluation.
/// evaluate() must be thread-safe and deterministic.
class Objective {
 public:
  virtual ~Objective() = default;
  /// Err (m²) of config (one setting per camera); writes the evaluation's time split (ms).
  virtual double evaluate(const core::CameraConfig& config, core::Timing& timing) const = 0;
  /// The default optimisation tolerance for this objective (m², SPEC §4).
  virtual double default_tolerance() const = 0;
  /// A lower bound of Err over all configurations (m²); 0 when none is known.
  virtual double err_lower_bound() const { return 0.0; }
};

}  // namespace camplace::optimize
