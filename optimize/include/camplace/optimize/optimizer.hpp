#pragma once
/// One optimisation run of SPEC §7: a pagmo solver minimising an Objective over the camera
/// settings, stopped at the first of tolerance, time limit, evaluation budget and interrupt.
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/optimize/objective.hpp"

namespace camplace::optimize {

/// Why a run ended.
enum class StopReason {
  tolerance,        ///< the best Err reached the tolerance
  time_limit,       ///< the wall-clock limit passed
  max_evaluations,  ///< the evaluation budget was used up
  interrupted,      ///< the interrupt flag was raised (Ctrl-C)
  lower_bound       ///< the best Err equals the objective's lower bound: provably optimal
};
/// "tolerance", "time_limit", "max_evaluations", "interrupted" or "lower_bound".
const char* to_string(StopReason reason);

/// Where a run starts (SPEC §7).
enum class StartKind {
  random,   ///< a random population (seeded)
  corners,  ///< corner_start(): cameras high in the corners looking at S's centre
  file      ///< a camera configuration file (load_camera_config format)
};

struct StartOptions {
  StartKind kind = StartKind::random;
  std::string file;  ///< the configuration file when kind == file
};

/// A snapshot for progress displays.
struct Progress {
  std::uint64_t evaluations = 0;
  double best_err = 0.0;  ///< m²
  double seconds = 0.0;   ///< since the run started
};

/// The grid of `optimize --snap POS_M,ANGLE_DEG`: positions to multiples of
/// position_m (metres; world coordinates in a box domain, along the edges from the corner on a
/// mount), angles to multiples of angle (radians).
struct SnapGrid {
  double position_m = 0.0;
  double angle = 0.0;
};

/// The best configuration snapped to a SnapGrid and improved by a coordinate search on it.
struct SnappedResult {
  SnapGrid grid;
  core::CameraConfig cameras;     ///< on the grid (as re-read from its JSON form)
  double err = 0.0;               ///< Err of `cameras` (m²), as `camplace evaluate` computes it
  double rounded_err = 0.0;       ///< Err right after rounding, before the search on the grid
  std::uint64_t evaluations = 0;  ///< objective evaluations of the search on the grid
};

struct OptimizeOptions {
  std::string algorithm = "gaco";             ///< one of algorithm_names()
  std::string objective = kDefaultObjective;  ///< one of objective_names() (objective.hpp)
  unsigned seed = 1;                          ///< seeds the population and the solver
  double time_limit = 0.0;                    ///< seconds of wall clock; 0 = none
  std::uint64_t max_evaluations = 0;          ///< objective evaluations; 0 = none
  std::optional<double> tolerance;            ///< m²; none = the objective's default
  StartOptions start;
  int threads = 0;     ///< threads for batch evaluation; 0 = all cores
  int population = 0;  ///< population size; 0 = the solver's default
  /// Raised (from a signal handler, say) to stop the run; the best result so far is returned.
  const std::atomic<bool>* interrupt = nullptr;
  /// Stop when the best Err reaches the objective's lower bound (nothing better exists, so
  /// going on cannot improve it; the tolerance may lie below the bound, SPEC §5).
  bool stop_at_lower_bound = true;
  /// Called after evaluations with the current state (from the evaluating thread, serialised).
  std::function<void(const Progress&)> on_progress;
  /// Snap the best configuration to this grid after the run (RunResult::snapped).
  std::optional<SnapGrid> snap;
};

/// One point of the best-Err history: the best Err after `evaluations` evaluations.
struct HistoryPoint {
  std::uint64_t evaluations = 0;
  double seconds = 0.0;
  double err = 0.0;  ///< m²
};

/// Peak memory of the process from /proc/self/status (kB; 0 where unavailable).
struct MemoryUsage {
  std::uint64_t vm_hwm_kb = 0;   ///< peak resident set size
  std::uint64_t vm_peak_kb = 0;  ///< peak virtual memory (the paper's figure)
};
MemoryUsage peak_memory();

struct RunResult {
  std::string algorithm;
  std::string objective = kDefaultObjective;  ///< OptimizeOptions::objective
  unsigned seed = 0;
  int threads = 0;
  int population = 0;
  std::size_t dimension = 0;     ///< free decision variables
  core::CameraConfig best;       ///< best configuration (as re-read from its JSON form)
  double err = 0.0;              ///< Err of `best` (m²), as `camplace evaluate` computes it
  double search_err = 0.0;       ///< best Err seen during the search (m²); equals err unless the
                                 ///< JSON round trip of the angles moved a voxel label
  double start_err = 0.0;        ///< best Err of the initial population (holds the start) (m²)
  double tie_breaker = 0.0;      ///< Score::tie_breaker of `best`, with either
                                 ///< objective; with "err+volume" the least among the best Err
  double tolerance = 0.0;        ///< m²
  double err_lower_bound = 0.0;  ///< the objective's lower bound of Err (m²); 0 = none known
  bool reached_tolerance = false;
  StopReason stop_reason = StopReason::time_limit;
  std::uint64_t evaluations = 0;          ///< objective evaluations performed
  std::uint64_t evaluations_to_best = 0;  ///< index (1-based) of the evaluation that found best
  std::uint64_t restarts = 0;             ///< solver restarts after it stopped evaluating
  double seconds = 0.0;                   ///< wall clock of the run
  std::vector<HistoryPoint> history;      ///< one point per improvement of the best Err
  core::Timing mean_timing;               ///< mean per evaluation (ms), summed over threads
  double wall_ms_per_evaluation = 0.0;    ///< seconds · 1000 / evaluations
  MemoryUsage memory;                     ///< at the end of the run
  std::optional<SnappedResult> snapped;   ///< with OptimizeOptions::snap
};

/// Names accepted by OptimizeOptions::algorithm, default first.
const std::vector<std::string>& algorithm_names();
/// One line per solver: name, pagmo algorithm, batch-parallel or not, default population.
std::string algorithm_help();

/// The population size a run of `algorithm` uses over `dimension` (> 0) free variables:
/// `population`, or the solver's default when it is 0 (RunResult::population). Throws
/// core::InputError for a bad algorithm name or population size, as optimize() does.
int population_size(const std::string& algorithm, int population, std::size_t dimension);

/// Refuses a configuration whose cameras do not all lie in their placement domains (on their
/// mounts, within the mounts' ranges, up to the rounding of camera files) and in no keep-out
/// box: throws core::InputError naming `file` (the configuration's file), the camera's entry and
/// the reason. What optimize() asks of a start file, and `robustness` of its cameras.
void check_inside_domains(const core::CameraConfig& config, const core::Scene& scene,
                          const std::string& file);

/// Runs one optimisation of `objective` over the scene's camera domains. Results depend only on
/// (scene, objective, options without time limit/interrupt, seed), not on the thread count.
/// Throws core::InputError for a bad algorithm or objective name, start file or population size.
RunResult optimize(const core::Scene& scene, const Objective& objective,
                   const OptimizeOptions& options);

}  // namespace camplace::optimize
