#pragma once
/// The voxel pipeline of SPEC §3–5: labelling, model, components, distances and Err for a
/// camera configuration. Build one VoxelEvaluator per (scene, options); evaluate() is const and
/// thread-safe, so one evaluator serves all threads of an optimizer.
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::voxel {

/// How a voxel takes its label (SPEC §5).
enum class LabelMode {
  center,       ///< the label of the voxel's centre (the paper's basic version)
  conservative  ///< free only when every point of the voxel is free
};

/// κ of SPEC §3 for one camera and point (or voxel).
enum class Label : std::uint8_t { free, occupied, undetectable };

struct VoxelOptions {
  LabelMode mode = LabelMode::conservative;
  std::array<int, 3> resolution{0, 0, 0};  ///< nx, ny, nz; all 0 = the scene's `voxels`
};

/// Result for one state (time step h, event l); distances in m, volume in m³.
struct StateResult {
  int time_step = 0;
  int event = 0;
  double weight = 0.0;
  double d_true = 0.0;
  double d_model = 0.0;  ///< S's diagonal when the model is empty (SPEC §4)
  double model_volume = 0.0;
  int components = 0;          ///< components kept by the plausibility filter
  int components_removed = 0;  ///< components the filter discarded
};

/// Wall-clock split of one evaluation in milliseconds (SPEC §5).
struct Timing {
  double labelling_ms = 0.0;
  double clustering_ms = 0.0;
  double distance_ms = 0.0;
  double total_ms = 0.0;
};

struct Evaluation {
  double err = 0.0;  ///< m²
  std::vector<StateResult> states;
  Timing timing;
};

/// The voxel grid over S: voxel (i, j, k) has index i + nx·(j + ny·k).
struct Grid {
  core::Box3 area;
  std::array<int, 3> n{0, 0, 0};
  core::Vec3 step = core::Vec3::Zero();  ///< voxel edge lengths (m)
  int count() const { return n[0] * n[1] * n[2]; }
  core::Box3 voxel_box(int index) const;
  core::Vec3 voxel_center(int index) const;
};

class VoxelEvaluator {
 public:
  /// Precomputes everything that does not depend on the cameras (obstacle interiors, true
  /// distances, voxel-to-critical distances). Throws core::InputError on a bad resolution.
  VoxelEvaluator(const core::Scene& scene, const VoxelOptions& options);
  ~VoxelEvaluator();
  VoxelEvaluator(VoxelEvaluator&&) noexcept;
  VoxelEvaluator& operator=(VoxelEvaluator&&) noexcept;

  /// Full evaluation with per-state results and timing. config.size() must equal the camera
  /// count.
  Evaluation evaluate(const core::CameraConfig& config) const;
  /// Err only (the optimizer's objective), m².
  double err(const core::CameraConfig& config) const;

  /// Labels of every voxel for one camera in one state (index into core::states()).
  /// Conservative mode reports `free` only for voxels it proves wholly free.
  std::vector<Label> labels(const core::CameraSetting& camera, int state) const;
  /// Model voxels after the plausibility filter (1 = in M) for one state.
  std::vector<std::uint8_t> model(const core::CameraConfig& config, int state) const;

  /// A lower bound of Err over all camera configurations (m²), conservative mode only: every
  /// voxel that touches a target is in M whatever the cameras (its rays meet the target), so
  /// d(C, M) never exceeds the distance to the nearest such voxel. When this bound exceeds the
  /// tolerance, no configuration can reach it. Center mode: 0 (no bound).
  double err_lower_bound() const;

  const Grid& grid() const;
  const core::Scene& scene() const;
  const VoxelOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace camplace::voxel
