#pragma once
/// Files and tables of `camplace optimize` (SPEC §7): DIR/run-<seed>.json per run,
/// DIR/summary.json and DIR/summary.csv, and the printed summary table. The files are written
/// with core::write_file_atomically.
#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "camplace/optimize/optimizer.hpp"

namespace camplace::optimize {

/// What the run files record about the invocation besides each run's result.
struct RunContext {
  std::string scene_file;
  std::string mode;  ///< voxel labelling mode ("center", "conservative")
  std::array<int, 3> resolution{0, 0, 0};
  std::string start;  ///< "random", "corners" or the start file
  double time_limit = 0.0;
  std::uint64_t max_evaluations = 0;
};

/// The run file's JSON: "cameras" (the load_camera_config format), "err", "evaluations",
/// "reached_tolerance", "seconds", "stop_reason", "history", "time_per_evaluation_ms",
/// "memory_kb" and the context.
nlohmann::ordered_json run_json(const RunResult& run, const RunContext& context);

/// Aggregates over R runs.
struct Summary {
  int runs = 0;
  int reached = 0;              ///< runs that reached the tolerance
  int reached_lower_bound = 0;  ///< runs stopped at the proven optimum (StopReason::lower_bound)
  double median_evaluations = 0.0;          ///< over all runs
  double median_seconds = 0.0;              ///< over all runs
  double median_evaluations_reached = 0.0;  ///< over the runs that reached it (0 if none)
  double median_seconds_reached = 0.0;
  int best_run = -1;  ///< index of the run with the least Err
};
Summary summarize(const std::vector<RunResult>& runs);

nlohmann::ordered_json summary_json(const std::vector<RunResult>& runs, const RunContext& context,
                                    bool interrupted);
/// One header line and one row per run.
std::string summary_csv(const std::vector<RunResult>& runs);
/// The printed table: one row per run, success rate, medians, the best configuration and Err.
void print_summary(std::ostream& out, const std::vector<RunResult>& runs);

}  // namespace camplace::optimize
