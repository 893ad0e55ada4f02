#pragma once
/// The voxel pipeline of SPEC §3–5: labelling, model, components, distances and Err for a
/// camera configuration. Build one VoxelEvaluator per (scene, options); evaluate() is const and
/// thread-safe, so one evaluator serves all threads of an optimizer.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/evaluation.hpp"
#include "camplace/core/names.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/core/threads.hpp"
#include "camplace/voxel/grid.hpp"

namespace camplace::voxel {

/// The voxel pipeline reports core's result types (one definition for both pipelines).
using core::Evaluation;
using core::LabelMode;
using core::StateResult;
using core::Timing;

/// κ of SPEC §3 for one camera and point (or voxel).
enum class Label : std::uint8_t { free, occupied, undetectable };

/// Largest `threads` an evaluator accepts (the project-wide limit).
using core::kMaxThreads;

/// Largest `refine` an evaluator accepts (levels); the memory limit below refuses most grids
/// well before it.
constexpr int kMaxRefine = 10;
/// The most memory (bytes) refinement may need in the worst case (refine_memory_estimate()):
/// 2 GiB.
constexpr double kRefineMemoryLimit = 2.0 * 1024 * 1024 * 1024;

/// Worst-case memory (bytes) of refinement to `levels` levels on an n[0]·n[1]·n[2] grid with
/// `time_steps` time steps and `states` states: every base voxel refined, so n[0]·n[1]·n[2]·8^L
/// finest cells, each with a state mask (8 bytes), union–find and component labels (8 bytes,
/// per evaluating thread), one byte per state, and per time step a cached distance and an
/// obstacle-interior flag per octree node (≤ 8/7 nodes per cell: 10 bytes). 0 when L ≤ 0.
double refine_memory_estimate(const std::array<int, 3>& n, int levels, int time_steps, int states);

struct VoxelOptions {
  LabelMode mode = LabelMode::conservative;
  std::array<int, 3> resolution{0, 0, 0};  ///< nx, ny, nz; all 0 = the scene's `voxels`
  /// Threads one evaluate() call uses (labelling by slices of voxels, then components and
  /// distances by state), 1..kMaxThreads. Keep 1 when the caller runs evaluations in parallel
  /// itself (the optimizer).
  int threads = 1;
  /// Adaptive refinement, conservative mode only: levels L ≥ 0 (0 = none). A base voxel of a
  /// component the filter keeps is split into 8 cells when it lies near the critical objects
  /// (nearer than the state's d(C, M) so far plus a voxel diagonal, a radius that grows until
  /// the nearest kept cell lies within it), and every cell no camera proves free and no obstacle
  /// holds wholly is split again, down to cells of 1/2^L of the voxel's edge; the other kept
  /// voxels stay whole. M is the union of those finest cells and whole voxels; components
  /// (6-connectivity of the finest cells, across base voxels) and the filter work on them, and
  /// d(C, M) uses their boxes. Refined M ⊆ unrefined M and still ⊇ the exact model. See
  /// refine_problem() for the limits.
  int refine = 0;
};

/// Why `refine` levels cannot be used for `scene` with these options ("" when they can):
/// negative, above kMaxRefine, center mode (refinement is for conservative labels), or more
/// memory than kRefineMemoryLimit by refine_memory_estimate(). The evaluator throws it as
/// core::OptionError("refine", ...).
std::string refine_problem(const core::Scene& scene, const VoxelOptions& options);

class VoxelEvaluator {
 public:
  /// Precomputes everything that does not depend on the cameras (obstacle interiors, true
  /// distances, voxel-to-critical distances; with refinement the obstacle interiors of the
  /// octree cells and the refined lower bound). Throws core::InputError on a bad resolution
  /// (core::resolution_problem) or a `threads` outside 1..kMaxThreads, core::OptionError
  /// ("refine") on a `refine` that refine_problem() refuses.
  VoxelEvaluator(const core::Scene& scene, const VoxelOptions& options);
  ~VoxelEvaluator();
  VoxelEvaluator(VoxelEvaluator&&) noexcept;
  VoxelEvaluator& operator=(VoxelEvaluator&&) noexcept;

  /// Full evaluation with per-state results and timing (wall-clock per stage). Throws
  /// core::InputError when config.size() is not the scene's camera count. The result does not
  /// depend on `threads`. With refinement, a state's `components_removed` counts the base
  /// components the filter removes before refinement (each may hold several cell components)
  /// plus the cell components it removes after; the timing adds refinement's labelling,
  /// components and distances to the stages'.
  Evaluation evaluate(const core::CameraConfig& config) const;
  /// Err only (the optimizer's objective), m².
  double err(const core::CameraConfig& config) const;

  /// Labels of every voxel for one camera in one state (index into core::states()), the camera
  /// having the model of the scene's camera `camera_index` (0 ≤ camera_index < n).
  /// Conservative mode reports `free` only for voxels it proves wholly free.
  std::vector<Label> labels(const core::CameraSetting& camera, int state,
                            int camera_index = 0) const;
  /// Model voxels after the plausibility filter (1 = in M) for one state. With refinement: the
  /// base voxels that hold at least one finest cell of M (leaf_model() has the cells).
  std::vector<std::uint8_t> model(const core::CameraConfig& config, int state) const;
  /// model() of every state (index of core::states()), from one labelling of all states.
  std::vector<std::vector<std::uint8_t>> models(const core::CameraConfig& config) const;
  /// The grid of the finest cells: S cut into n·2^L cells per axis (grid() when L = 0).
  Grid leaf_grid() const;
  /// M after the filter for one state on leaf_grid() (1 = in M); model() when L = 0.
  std::vector<std::uint8_t> leaf_model(const core::CameraConfig& config, int state) const;
  /// leaf_model() of every state, from one labelling of all states.
  std::vector<std::vector<std::uint8_t>> leaf_models(const core::CameraConfig& config) const;

  /// A lower bound of Err over all camera configurations (m²), conservative mode only; center
  /// mode: 0 (no bound). Per state, the voxels an occupying object (a target; a dynamic obstacle
  /// in masked mode) reaches into and no obstacle holds wholly are in M before the filter
  /// whatever the cameras; a 6-connected group of them that passes the filter alone stays in M,
  /// so d(C, M) ≤ U, the distance to the nearest such group, and the state's term is
  /// ω·(d_true − min(U, d_true))² (0 when no group passes). With refinement the same rule applies
  /// to the finest cells, so the bound shrinks with L toward the true minimum. Proofs:
  /// docs/design/lower-bound.md B1, B2. Compare Err against it through
  /// core::lower_bound_threshold (the sums' order differs); when it exceeds the tolerance, no
  /// configuration can reach the tolerance.
  double err_lower_bound() const;

  const Grid& grid() const;
  const core::Scene& scene() const;
  const VoxelOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace camplace::voxel
