#pragma once
/// Validation of optimizer results against the exact pipeline (SPEC §8): the exact Err of each
/// voxel optimum, and the rank agreement (Kendall's τ-b) between voxel Err and exact Err over a
/// seeded sample of random configurations, per labelling mode and resolution.
#include <array>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "camplace/core/scene.hpp"

namespace camplace::compare {

struct OptimizerValidationOptions {
  std::string runs_dir;  ///< directory holding run-<seed>.json files of `camplace optimize`
  int samples = 12;      ///< random configurations for the rank agreement
  unsigned seed = 1;     ///< seeds the sample
  std::vector<std::array<int, 3>> resolutions;  ///< empty = the scene's
  std::string command;                          ///< quoted in the report
  /// Called before each exact evaluation and each voxel pipeline's set-up: the evaluations
  /// done and their total (one exact per run file and per sample, one voxel pipeline per
  /// resolution and mode). Empty: none.
  std::function<void(int done, int total)> on_progress;
  /// Held while files are written, so that a caller ending the process on a signal never cuts
  /// one short; nullptr: none.
  std::mutex* writing = nullptr;
  /// Called after files are written with what DIR then holds ("DIR/runs.csv ..."). Empty: none.
  std::function<void(const std::string& kept)> on_written;
};

/// Kendall's τ-b of two equally long samples (ties handled); NaN when undefined (one sample
/// all tied).
double kendall_tau_b(const std::vector<double>& a, const std::vector<double>& b);

/// Writes DIR/report.md, DIR/runs.csv, DIR/samples.csv, DIR/rank_agreement.csv and
/// DIR/voxel_err_vs_exact_err.png. Throws core::InputError when runs_dir has no run file, and
/// when one was made for another scene (core::check_same_scene: the scene hashes its
/// provenance recorded differ from those of `scene`'s files).
void validate_optimizer(const core::Scene& scene, const OptimizerValidationOptions& options,
                        const std::string& dir);

}  // namespace camplace::compare
