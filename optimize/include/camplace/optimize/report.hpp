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

#include "camplace/core/error.hpp"
#include "camplace/core/provenance.hpp"
#include "camplace/optimize/optimizer.hpp"

namespace camplace::optimize {

/// What the run files record about the invocation besides each run's result.
struct RunContext {
  std::string scene_file;
  std::string mode;  ///< voxel labelling mode ("center", "conservative")
  std::array<int, 3> resolution{0, 0, 0};
  /// voxel::VoxelOptions::refine (levels; 0 = none). Written as "refine" only when > 0, so
  /// files without refinement keep their layout; a file without the key has 0.
  int refine = 0;
  std::string start;  ///< "random", "corners" or the start file
  double time_limit = 0.0;
  std::uint64_t max_evaluations = 0;
  /// What made the run (build, scene content hashes, host, start time); absent in files of
  /// formats 1 and 2.
  std::optional<core::Provenance> provenance;
  /// Each camera's model name, written as "model" in every camera entry; empty (no "model")
  /// when the scene's models are not named (the single-model form). camera_models(scene).
  std::vector<std::string> camera_models;
};

/// The scene's model name of every camera, or none when the models are not named.
std::vector<std::string> camera_models(const core::Scene& scene);

/// The format of the run files run_json writes ("format_version"). Files without the key are
/// format 1, the same layout without it. Format 3 adds "provenance", format 4 "objective" and
/// "tie_breaker" (a file without them minimised Err alone: "err", tie-breaker 0).
constexpr int kRunFileFormat = 4;

/// The run file's JSON: "format_version" (kRunFileFormat), "cameras" (the load_camera_config
/// format), "err", "tie_breaker", "objective", "evaluations", "reached_tolerance", "seconds",
/// "stop_reason", "history", "time_per_evaluation_ms", "memory_kb" and the context.
nlohmann::ordered_json run_json(const RunResult& run, const RunContext& context);

/// A run file read back: the run and the context it was made in.
struct RunFile {
  RunResult run;
  RunContext context;
  int format_version = kRunFileFormat;  ///< as the file says (1 when it does not)
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

/// The seed of a run file's name as camplace writes it ("run-<seed>.json"); none for any other
/// name ("run-1 copy.json", "summary.json").
std::optional<unsigned> run_file_seed(const std::string& file_name);

/// The settings that determine a run's result: what the runs of one folder share, so that a
/// job resuming the folder adds only runs like them. Optional members are compared
/// only when set on both sides (settings_changes).
struct RunSettings {
  std::string scene_file;  ///< for messages only: the same content at another path is the same
  std::optional<core::SceneHashes> scene;  ///< none in run files of formats 1 and 2
  std::string mode;                        ///< voxel labelling mode
  std::optional<std::array<int, 3>> resolution;
  int refine = 0;  ///< voxel::VoxelOptions::refine
  std::string algorithm;
  std::string objective = kDefaultObjective;  ///< "err" in run files of formats 1–3
  std::string start;                          ///< "random", "corners" or the start file's path
  double time_limit = 0.0;                    ///< s; 0 = none
  std::uint64_t max_evaluations = 0;
  std::optional<double> tolerance;  ///< m², as the run used it (the default resolved)
  std::optional<int> population;    ///< as the run used it (the solver's default resolved)
  std::optional<unsigned> seed;
  /// Threads of batch evaluation. The Err does not depend on them (optimize()), the timings do:
  /// `study` compares them (its report states them and plots timings), `optimize` does not.
  std::optional<int> threads;
  /// The run file's format (recorded), or kRunFileFormat (now).
  int format = kRunFileFormat;
  /// Now: some camera's domain has the ceiling preset's pitch range (core::has_ceiling_pitch),
  /// which formats 1–3 did not have (their ceiling cameras could look up).
  bool ceiling_pitch = false;
};

/// What a run file records about its settings (all members but `scene` of a file without
/// provenance).
RunSettings recorded_settings(const RunFile& file);

/// How `now` differs from `recorded`, one line per setting in run-file terms, old → new
/// ("algorithm: gaco → cmaes", "max_evaluations: 3000 → 200", the lines of core::scene_changes);
/// empty when they agree.
std::vector<std::string> settings_changes(const RunSettings& recorded, const RunSettings& now);

/// A run file of a folder whose settings differ from those of the job about to resume it.
struct SettingsConflict {
  std::string run_file;              ///< as the message names it (e.g. relative to the folder)
  std::vector<std::string> changes;  ///< settings_changes(), or why the run does not belong
};

/// A job would resume a folder holding runs made with other settings. The message names the
/// folder and lists each distinct change once, with the first run file showing it and how many
/// more do.
class SettingsChanged : public core::InputError {
 public:
  SettingsChanged(const std::string& dir, const std::vector<SettingsConflict>& conflicts);
};

/// Checks every run file of the `optimize` folder `dir` (run-<seed>.json) against `now`, the
/// seed aside (a run of any seed may join the folder). Throws SettingsChanged listing the
/// differences, core::InputError for a run file it cannot read; a folder without run files (or
/// none at all) passes.
void check_resume(const std::string& dir, const RunSettings& now);

/// Removes what `camplace optimize` wrote into `dir`: every run-<seed>.json, summary.json and
/// summary.csv, nothing else (so never a file of the user's). Returns how many run files it
/// removed; a missing folder removes none. Throws std::runtime_error naming a file it cannot
/// remove.
int discard_runs(const std::string& dir);

/// Every run of the folder `dir`: its run files (run-<seed>.json) read back, with `mine` (this
/// process's runs) instead of the files of their seeds, in ascending seed order. Files that
/// cannot be read are left out. What a summary of `dir` covers when several `optimize`
/// processes write runs into one folder (a study on a cluster): each rebuilds the summary from
/// all of them, under FolderLock, so that none loses another's runs.
std::vector<RunResult> runs_in_folder(const std::string& dir, const std::vector<RunResult>& mine);

/// An exclusive lock (flock) on the folder `dir` for its lifetime; waits for another
/// process's. Throws std::runtime_error naming the folder when it cannot be opened or locked.
class FolderLock {
 public:
  explicit FolderLock(const std::string& dir);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_ = -1;
};

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
