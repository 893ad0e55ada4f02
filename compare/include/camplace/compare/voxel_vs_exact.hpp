#pragma once
/// Validation of the voxel pipeline against the exact one for one camera configuration
/// (SPEC §8): per state and per (mode, resolution) the distances, volumes, Err, and the checks
/// that the conservative voxel model contains the exact model and never over-estimates d.
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::compare {

struct CompareOptions {
  /// Voxel resolutions to compare; empty = the scene's resolution.
  std::vector<std::array<int, 3>> resolutions;
  /// Refinement levels of conservative mode (voxel::VoxelOptions::refine) at every resolution;
  /// empty = {0}. Center mode runs once per resolution (it takes no refinement).
  std::vector<int> refine_levels;
  /// The command that produced the report, quoted in report.md.
  std::string command;
  /// Called before each evaluation (the exact one first, then each voxel pipeline): the
  /// evaluations done and their total. Empty: none.
  std::function<void(int done, int total)> on_progress;
  /// Called as the exact evaluation advances: its (state, camera) steps done and their total
  /// (exact::ExactOptions::on_progress). Empty: none.
  std::function<void(long done, long total)> on_exact_progress;
};

/// One state at one (mode, resolution) against the exact pipeline. Metres, m³.
struct CompareRow {
  int time_step = 0, event = 0;
  double weight = 0.0;
  std::string mode;  ///< "center" or "conservative"
  std::array<int, 3> resolution{0, 0, 0};
  double voxel_diagonal = 0.0;
  int refine = 0;              ///< refinement levels L (conservative mode)
  double cell_diagonal = 0.0;  ///< the finest cell's diagonal: voxel diagonal / 2^L
  double d_true = 0.0, d_exact = 0.0, d_voxel = 0.0;
  double volume_exact = 0.0, volume_voxel = 0.0;
  /// Voxels outside the voxel model that hold points of the exact model (0 = it contains the
  /// exact model): a boundary triangle of the exact model reaching more than 1e-9 m into the
  /// voxel, or its centre in the exact model; with refinement, counted in finest cells.
  int exact_outside = 0;
  bool distance_over_estimated = false;  ///< d_voxel > d_exact (+1e-9 m)
  /// The plausibility filter removed a component of the voxel model and the voxel model kept
  /// fewer components than the exact one: a target (the person) lost to the filter, not a
  /// voxelisation error of a kept one (the report marks these states apart).
  bool filter_lost_component = false;
};

/// Err of one pipeline (m²) and its evaluation time (ms).
struct ErrRow {
  /// "exact", "voxel-center", "voxel-conservative", "voxel-conservative-refineL" (L ≥ 1 levels)
  std::string pipeline;
  std::array<int, 3> resolution{0, 0, 0};
  int refine = 0;
  double err = 0.0;
  double ms = 0.0;
};

struct CompareResult;
/// Called after each voxel evaluation with the result so far (a checkpoint to write).
using ComparePartial = std::function<void(const CompareResult&)>;

struct CompareResult {
  /// Evaluations done and planned (1 exact + per resolution one center and one conservative
  /// per refinement level); the report marks itself incomplete while done < total.
  int evaluations_done = 0, evaluations_total = 0;
  std::vector<CompareRow> rows;
  std::vector<ErrRow> errs;
  int conservative_violations = 0;  ///< rows of conservative mode failing either check
  int center_violations = 0;        ///< the same for center mode (expected: it is not conservative)
  std::string started;  ///< when the comparison started (ISO 8601), for the report's header
};

/// Runs the exact pipeline once and the voxel pipeline in both modes at every resolution (and in
/// conservative mode at every refinement level), all with the scene's inscribed k-sided pyramid
/// as FOV (SPEC §1). Throws core::OptionError("refine", ...) before any work when a level is
/// one voxel::refine_problem() refuses at some resolution. `on_partial` (if set) receives the
/// result after each voxel evaluation, the last time complete.
CompareResult compare_voxel_exact(const core::Scene& scene, const core::CameraConfig& config,
                                  const CompareOptions& options,
                                  const ComparePartial& on_partial = {});

/// The scene with its cone FOV replaced by the inscribed pyramid (SPEC §1).
core::Scene with_pyramid_fov(const core::Scene& scene);

/// Writes DIR/report.md, DIR/compare.csv, DIR/err.csv and the plots (gnuplot, PNG):
/// DIR/error_vs_resolution.png (against the finest cell's diagonal: the effective resolution)
/// and DIR/d_voxel_vs_d_exact.png; with refinement levels also
/// DIR/time_vs_effective_resolution.png. Timing only in err.csv's `ms` column, the report's
/// timing table and that plot. A result with evaluations_done < evaluations_total (an
/// interrupted compare) is marked incomplete at the top of report.md.
void write_compare_report(const core::Scene& scene, const CompareResult& result,
                          const CompareOptions& options, const std::string& dir);

}  // namespace camplace::compare
