#pragma once
/// `camplace plan`: how many cameras a cell needs. The scene with each camera count of a range
/// (its cameras cycled), R optimiser runs per count (run by the caller as `camplace optimize`
/// processes), the best run of each count checked by the exact pipeline, and a report that
/// recommends the smallest count whose best configuration reaches the tolerance by its exact Err.
#include <optional>
#include <string>
#include <vector>

#include "camplace/core/provenance.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::compare {

/// The scene with `count` cameras (≥ 1): camera i takes the model and the placement domain of
/// the scene's camera i mod n (n its camera count), so the first n keep theirs and further ones
/// repeat the scene's cameras in order (a `cameras.list` is cycled). The rest of the scene is
/// unchanged.
core::Scene scene_with_cameras(const core::Scene& scene, int count);

/// The total cost of the scene's cameras (Σ of their models' `cost`), none unless every model
/// has one.
std::optional<double> cameras_cost(const core::Scene& scene);

/// The runs of one camera count, as their run files and exact checks found them.
struct PlanRow {
  int cameras = 0;
  /// The cameras' total cost (Σ of their models' `cost`), none unless every model has one.
  std::optional<double> cost;
  int runs_planned = 0;               ///< R
  int runs_done = 0;                  ///< finished run files (not interrupted)
  std::optional<unsigned> best_seed;  ///< the run of least voxel Err (ties: the lowest seed)
  std::string best_run_file;          ///< its path
  double voxel_err = 0.0;             ///< m², the best run's (the scene's FOV)
  double voxel_err_pyramid = 0.0;     ///< m², same cameras with the exact pipeline's FOV
  std::optional<double> exact_err;    ///< m², the best run's exact Err (when checked)
  double err_lower_bound = 0.0;       ///< m², conservative voxel lower bound (0 in center mode)
  double tolerance = 0.0;             ///< m²
  double max_overestimate = 0.0;      ///< m, largest d_voxel − d_exact of the best run
  double median_voxel_err = 0.0;      ///< m², over the finished runs
  double median_evaluations = 0.0;
  double median_seconds = 0.0;
  std::string check_error;  ///< non-empty: the exact check failed, and why
  bool reached_exact() const { return exact_err && *exact_err <= tolerance; }
};

/// What the report says about how it was made.
struct PlanReport {
  std::string command;
  core::Provenance provenance;  ///< of the scene given
  std::string settings;         ///< one line: solver, mode, budget per run
  bool interrupted = false;
  std::vector<std::string> missing;  ///< runs without a finished run file ("4 cameras seed 2")
};

/// The smallest count whose best configuration reaches the tolerance by its exact Err, if any.
std::optional<int> recommended_count(const std::vector<PlanRow>& rows);

/// True when every count up to the recommended one (or every count, when none is recommended)
/// has all its runs and its exact check; otherwise the recommendation is provisional.
bool recommendation_is_final(const std::vector<PlanRow>& rows);

/// Writes DIR/plan.md, DIR/plan.csv, DIR/plan.json (with the provenance) and DIR/plan.png
/// (exact Err, voxel Err, the lower bound and the tolerance against the camera count; gnuplot,
/// its data and script beside it) and, when every count has a cost, DIR/plan_cost.png (the same
/// against the total cost), each atomically. Throws std::runtime_error when a file cannot
/// be written or gnuplot fails.
void write_plan_report(const std::string& dir, const std::vector<PlanRow>& rows,
                       const PlanReport& report);

}  // namespace camplace::compare
