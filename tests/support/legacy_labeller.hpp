#pragma once
// The voxel labeller as it was before the fast labeller (commit 6f1df84, voxel/src/labelling.cpp
// and the obstacle interiors of voxel/src/setup.cpp), kept verbatim apart from names so that tests
// can compare every label of the fast labeller against it and bench/evaluate_bench can report the
// speed-up over it in the same process. Not used by the application.
#include <cstdint>
#include <memory>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "camplace/voxel/grid.hpp"

namespace camplace::testing {

/// The labeller before the fast one, for one scene, mode and resolution.
class LegacyLabeller {
 public:
  /// Same arguments as voxel::VoxelEvaluator (resolution all 0 = the scene's voxels).
  LegacyLabeller(const core::Scene& scene, const voxel::VoxelOptions& options);
  ~LegacyLabeller();
  LegacyLabeller(LegacyLabeller&&) noexcept;
  LegacyLabeller& operator=(LegacyLabeller&&) noexcept;

  /// κ of every voxel for one camera in state `state` (index into core::states()).
  std::vector<voxel::Label> labels(const core::CameraSetting& camera, int state) const;
  /// Model of every state before the plausibility filter (1 = in M), as the old evaluate()
  /// built it: the labelling stage of one evaluation.
  std::vector<std::vector<std::uint8_t>> raw_models(const core::CameraConfig& config) const;
  const voxel::Grid& grid() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace camplace::testing
