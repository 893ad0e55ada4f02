#pragma once
/// The voxel pipeline of SPEC §3–5: labelling, model, components, distances and Err for a
/// camera configuration. Build one VoxelEvaluator per (scene, options); evaluate() is const and
/// thread-safe, so one evaluator serves all threads of an optimizer.
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/evaluation.hpp"
#include "camplace/core/names.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/voxel/grid.hpp"

namespace camplace::voxel {

/// The voxel pipeline reports core's result types (one definition for both pipelines).
using core::Evaluation;
using core::LabelMode;
using core::StateResult;
using core::Timing;

/// κ of SPEC §3 for one camera and point (or voxel).
enum class Label : std::uint8_t { free, occupied, undetectable };

/// Largest `threads` an evaluator accepts.
constexpr int kMaxThreads = 256;

struct VoxelOptions {
  LabelMode mode = LabelMode::conservative;
  std::array<int, 3> resolution{0, 0, 0};  ///< nx, ny, nz; all 0 = the scene's `voxels`
  /// Threads one evaluate() call uses (labelling by slices of voxels, then components and
  /// distances by state), 1..kMaxThreads. Keep 1 when the caller runs evaluations in parallel
  /// itself (the optimizer).
  int threads = 1;
};

class VoxelEvaluator {
 public:
  /// Precomputes everything that does not depend on the cameras (obstacle interiors, true
  /// distances, voxel-to-critical distances). Throws core::InputError on a bad resolution
  /// (core::resolution_problem) or a `threads` outside 1..kMaxThreads.
  VoxelEvaluator(const core::Scene& scene, const VoxelOptions& options);
  ~VoxelEvaluator();
  VoxelEvaluator(VoxelEvaluator&&) noexcept;
  VoxelEvaluator& operator=(VoxelEvaluator&&) noexcept;

  /// Full evaluation with per-state results and timing (wall-clock per stage). Throws
  /// core::InputError when config.size() is not the scene's camera count. The result does not
  /// depend on `threads`.
  Evaluation evaluate(const core::CameraConfig& config) const;
  /// Err only (the optimizer's objective), m².
  double err(const core::CameraConfig& config) const;

  /// Labels of every voxel for one camera in one state (index into core::states()).
  /// Conservative mode reports `free` only for voxels it proves wholly free.
  std::vector<Label> labels(const core::CameraSetting& camera, int state) const;
  /// Model voxels after the plausibility filter (1 = in M) for one state.
  std::vector<std::uint8_t> model(const core::CameraConfig& config, int state) const;

  /// A lower bound of Err over all camera configurations (m²), conservative mode only. Per
  /// state: a voxel that an occupying object (a target; a dynamic obstacle in masked mode)
  /// reaches into — meets its box shrunk by 1e-9·(S's diagonal + S's largest |coordinate|) —
  /// and that does not lie wholly inside an obstacle is in M before the plausibility filter
  /// whatever the cameras (its rays meet that object; contact only at the box's boundary does
  /// not count, rounding decides there). A 6-connected group G of such voxels lies in one
  /// component of that M, whose volume and z-extent are at least G's; so when G alone passes
  /// the filter (volume |G|·voxel volume, z-extent of its boxes), G stays in M and d(C, M) ≤ U,
  /// the distance from C to the nearest voxel of such a group. The state's term is
  /// ω·(d_true − min(U, d_true))², or 0 when no group passes (the filter may then remove all of
  /// M or keep a component at d_true). Without a filter every group passes. Compare Err against
  /// it through core::lower_bound_threshold (the sums' order differs). When this bound exceeds
  /// the tolerance, no configuration can reach it. Center mode: 0 (no bound).
  double err_lower_bound() const;

  const Grid& grid() const;
  const core::Scene& scene() const;
  const VoxelOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace camplace::voxel
