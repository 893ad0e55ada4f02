#pragma once
/// `camplace validate`: every optimizer result in a folder checked against the exact solution
/// (SPEC §8). For each run file (an `optimize` folder's run-<seed>.json, or a study folder's
/// runs/<group>/run-<seed>.json) the run's best configuration is evaluated by the exact
/// pipeline, and by the voxel pipeline with the exact pipeline's FOV (the inscribed pyramid,
/// SPEC §1), so that over-estimates compare like with like.
#include <array>
#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "camplace/core/scene.hpp"
#include "camplace/optimize/report.hpp"

namespace camplace::compare {

/// One run's exact check. Err in m², distances in m.
struct RunValidation {
  std::string run;    ///< the run file's path relative to the folder
  std::string scene;  ///< the scene file as the run recorded it
  std::string mode;   ///< voxel labelling mode of the run
  std::array<int, 3> resolution{0, 0, 0};
  double voxel_err = 0.0;           ///< as the run recorded it (the scene's own FOV)
  double voxel_err_same_fov = 0.0;  ///< recomputed with the exact pipeline's pyramid FOV
  double exact_err = 0.0;           ///< `camplace evaluate --pipeline exact` of the run file
  double tolerance = 0.0;           ///< what the run had to reach (see `target`)
  double err_lower_bound = 0.0;     ///< the run's conservative lower bound (0 in center mode)
  /// Success threshold: the tolerance, or in conservative mode max(tolerance, lower bound)
  /// (SPEC §4); the same threshold judges voxel and exact Err.
  double target = 0.0;
  bool reached_voxel = false;  ///< voxel_err ≤ target
  bool reached_exact = false;  ///< exact_err ≤ target
  /// max over states of d_voxel − d_exact (same FOV); > 0: the voxel result over-estimated a
  /// distance (not conservative).
  double max_overestimate = 0.0;
  double seconds = 0.0;  ///< wall time of the check (from the cache: when it was computed)
  bool cached = false;   ///< taken from DIR/validation-cache
  std::string error;     ///< non-empty: this run could not be checked, and why
};

/// Progress after each finished run, and as the exact checks under way advance.
struct ValidationProgress {
  int done = 0, total = 0;
  int from_cache = 0;    ///< of `done`: read from the cache (cost no time)
  double seconds = 0.0;  ///< since the start
  /// The (state, camera) steps of the exact checks under way: done and their total (both 0
  /// when none is under way; exact::ExactOptions::on_progress).
  long exact_done = 0, exact_total = 0;
};

struct ValidateOptions {
  std::string dir;      ///< an `optimize` or `study` output folder
  std::string command;  ///< the command line, quoted in the report
  /// Threads in all; 0 = all cores. Runs are checked in parallel, one thread each; when fewer
  /// runs are left to start than threads are idle, a check's exact evaluation gets the idle
  /// threads (exact::ExactOptions::threads), so that a single large run uses every core.
  int threads = 0;
  /// Called after each finished run and after each (state, camera) step of an exact check, from
  /// the worker threads, one call at a time.
  std::function<void(const ValidationProgress&)> on_progress;
  /// Called before a check's exact evaluation with the scene and the exact threads it gets; may
  /// throw std::runtime_error (e.g. the exact memory estimate exceeds what is available), which
  /// makes the run a row with that error. Empty: none.
  std::function<void(const core::Scene& scene, int exact_threads)> before_exact;
  const std::atomic<bool>* interrupt = nullptr;  ///< set (e.g. by Ctrl-C): stop after the runs
                                                 ///< under way; the finished ones are kept
  /// Check nothing now: take each run's check from the cache, and leave out the runs without
  /// one (as after an interrupt), e.g. after RunChecker checks on MPI ranks were interrupted.
  bool cache_only = false;
};

struct ValidationOutcome {
  std::vector<RunValidation> rows;  ///< one per run file, in path order (checked or failed)
  int from_cache = 0;
  int failed = 0;            ///< rows with an error
  bool interrupted = false;  ///< rows holds the runs finished before the interrupt
};

/// Checks every run file under options.dir (cached per run file content and scene content in
/// DIR/validation-cache/, so a rerun is instant and an interrupted one resumes) and writes
/// DIR/validation.csv and DIR/validation.md atomically. A run whose scene is missing or has
/// changed since the run (its recorded SHA-256), or whose run file is corrupt, becomes a row
/// with an error; the others are still checked. Throws core::InputError when the folder holds
/// no run file.
ValidationOutcome validate_runs(const ValidateOptions& options);

/// The run files validate_runs checks in `dir` (every run-*.json below it, outside its cache),
/// sorted. Throws core::InputError when the folder cannot be listed.
std::vector<std::string> find_validation_runs(const std::string& dir);

/// Checks single run files of one folder as validate_runs does, through and into its cache
/// (DIR/validation-cache), keeping the scenes it loaded for the next: for checks spread over
/// processes (`camplace validate` under MPI), after which validate_runs finds every check in the
/// cache. One check at a time per checker.
class RunChecker {
 public:
  explicit RunChecker(std::string dir);  ///< `dir`: as ValidateOptions::dir
  ~RunChecker();
  RunChecker(const RunChecker&) = delete;
  RunChecker& operator=(const RunChecker&) = delete;
  /// The check of `run_file` (a path below dir, as find_validation_runs gives it); errors are
  /// in the row's `error`, as in validate_runs.
  RunValidation check(const std::string& run_file);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Throws core::InputError naming `file` and its "/cameras" when the run file `run` holds
/// another number of cameras than `scene` (loaded from `scene_path`) has.
void check_run_cameras(const std::string& file, const optimize::RunFile& run,
                       const core::Scene& scene, const std::string& scene_path);

/// Throws core::InputError naming `file` and its "/err" when the Err the run file `run`
/// records differs from `recomputed`, the voxel Err of its recorded cameras recomputed with the
/// settings it records (the scene's own FOV, mode, resolution, refinement): a run file changed
/// after the run. validate_runs makes such a run an error row; a study reading runs from disk
/// refuses it.
void check_recorded_err(const std::string& file, const optimize::RunFile& run, double recomputed);

/// The rows of DIR/validation.csv (for reports), fields as RFC 4180 quotes them (a field may hold
/// commas, quotes and line breaks); empty when the file does not exist or has another header.
/// Throws core::InputError naming the file, the record and the field when it is damaged.
std::vector<RunValidation> read_validation_csv(const std::string& dir);

/// Removes what validate_runs wrote into `dir` (validation.csv, validation.md and the
/// validation-cache/<SHA-256>.json entries, then the cache folder when that leaves it empty),
/// nothing else. Returns how many files it removed. Throws std::runtime_error naming a file it
/// cannot remove.
int discard_validation(const std::string& dir);

}  // namespace camplace::compare
