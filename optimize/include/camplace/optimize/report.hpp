#pragma once
/// Files and tables of `camplace optimize` (SPEC §7): DIR/run-<seed>.json per run,
/// DIR/summary.json and DIR/summary.csv, and the printed summary table. The files are written
/// with core::write_file_atomically.
#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "camplace/core/provenance.hpp"
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
  /// What made the run (build, scene content hashes, host, start time); absent in files of
  /// formats 1 and 2.
  std::optional<core::Provenance> provenance;
};

/// The format of the run files run_json writes ("format_version"). Files without the key are
/// format 1, the same layout without it. Format 3 adds "provenance".
constexpr int kRunFileFormat = 3;

/// The run file's JSON: "format_version" (kRunFileFormat), "cameras" (the load_camera_config
/// format), "err", "evaluations", "reached_tolerance", "seconds", "stop_reason", "history",
/// "time_per_evaluation_ms", "memory_kb" and the context.
nlohmann::ordered_json run_json(const RunResult& run, const RunContext& context);

/// A run file read back: the run and the context it was made in.
struct RunFile {
  RunResult run;
  RunContext context;
};

/// The inverse of run_json: run_json(run_from_json(j).run, ...context) gives j again (apart
/// from "format_version", which is always kRunFileFormat). Angles are read as
/// core::load_camera_config reads them, so `best` is the configuration `camplace evaluate`
/// reads from the file. Throws core::InputError naming `file` (used only in messages), the
/// entry and the reason for a run file of an unknown format version, a missing, extra or
/// mistyped entry.
RunFile run_from_json(const nlohmann::json& j, const std::string& file);

/// Reads and parses the run file `path` with run_from_json. Throws core::InputError when the
/// file cannot be read, is not JSON or is not a run file this version reads.
RunFile read_run_file(const std::string& path);

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
