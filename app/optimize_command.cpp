// `camplace optimize`: R seeded runs of a pagmo solver minimising the voxel Err (SPEC §7), with
// run files, a summary and progress on stderr. Thin: parse, call camplace::optimize, print.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "camplace/compare/evaluation_json.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/provenance.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/core/threads.hpp"
#include "camplace/jobs/interrupt.hpp"
#include "camplace/optimize/encoding.hpp"
#include "camplace/optimize/optimizer.hpp"
#include "camplace/optimize/report.hpp"
#include "camplace/optimize/voxel_objective.hpp"
#include "cli_checks.hpp"
#include "commands.hpp"
#include "memory_estimate.hpp"
#include "scene_input.hpp"
#ifdef CAMPLACE_HAVE_STUDY
#include "camplace/compare/run_validation.hpp"
#endif

namespace camplace::app {
namespace {

struct OptimizeArgs {
  std::string scene, algorithm = "gaco", objective = optimize::kDefaultObjective, start = "random",
                     mode = "conservative", resolution, out;
  unsigned seed = 1;
  int runs = 1, threads = 0, population = 0, refine = 0;
  double time_limit = 300.0;
  long long max_evals = 0;
  double tolerance = 0.0;
  bool tolerance_given = false;
  bool quiet = false;
  bool restart = false;
  double max_seconds = 0.0;  ///< the whole command's bound; 0 = none
  std::string snap;          ///< --snap POS_M,ANGLE_DEG ("" = none)
};

/// Parses --snap POS_M,ANGLE_DEG: two finite numbers > 0 (metres, degrees).
optimize::SnapGrid parse_snap(const std::string& text) {
  const auto bad = [&]() {
    return core::OptionError("snap",
                             "expected POS_M,ANGLE_DEG with both finite and > 0 (e.g. "
                             "0.1,5), got \"" +
                                 text + "\"");
  };
  const std::size_t comma = text.find(',');
  if (comma == std::string::npos) throw bad();
  double values[2];
  const std::string parts[2] = {text.substr(0, comma), text.substr(comma + 1)};
  for (int i = 0; i < 2; ++i) {
    std::size_t used = 0;
    try {
      values[i] = std::stod(parts[i], &used);
    } catch (const std::exception&) {
      throw bad();
    }
    if (used != parts[i].size() || !std::isfinite(values[i]) || !(values[i] > 0.0)) throw bad();
  }
  if (!(values[1] <= 360.0)) {
    throw core::OptionError("snap", "ANGLE_DEG must not exceed 360, got \"" + text + "\"");
  }
  return {values[0], values[1] * core::kDegree};
}

/// Progress on stderr: a redrawn line on a terminal (≤ 10 per second), plain lines every 5 s
/// otherwise.
class ProgressPrinter {
 public:
  ProgressPrinter(bool quiet, int run, int runs, unsigned seed)
      : quiet_(quiet), tty_(::isatty(STDERR_FILENO) == 1), run_(run), runs_(runs), seed_(seed) {}

  void update(const optimize::Progress& p) {
    if (quiet_) return;
    const auto now = std::chrono::steady_clock::now();
    const auto interval = tty_ ? std::chrono::milliseconds(100) : std::chrono::milliseconds(5000);
    if (printed_ && now - last_ < interval) return;
    last_ = now;
    printed_ = true;
    print(p, false);
  }

  void finish(const optimize::RunResult& r) {
    if (quiet_) return;
    print({r.evaluations, r.err, r.seconds}, true);
    std::fprintf(stderr, "  %s\n", optimize::to_string(r.stop_reason));
  }

 private:
  void print(const optimize::Progress& p, bool final_line) {
    if (tty_) std::fprintf(stderr, "\r\033[K");
    std::fprintf(stderr, "run %d/%d seed %u | %llu evaluations | best Err %.5f m² | %.1f s", run_,
                 runs_, seed_, static_cast<unsigned long long>(p.evaluations), p.best_err,
                 p.seconds);
    if (!tty_ && !final_line) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  }

  bool quiet_, tty_;
  int run_, runs_;
  unsigned seed_;
  bool printed_ = false;
  std::chrono::steady_clock::time_point last_;
};

/// Every run file of `dir` must hold the scene's number of cameras (its summary and diagnostics
/// use their cameras): else an error naming the file.
void check_run_cameras(const std::string& dir, const std::vector<optimize::RunResult>& runs,
                       const core::Scene& scene) {
  for (const optimize::RunResult& r : runs) {
    if (r.best.size() == static_cast<std::size_t>(scene.cameras.count)) continue;
    const std::string file =
        (std::filesystem::path(dir) / ("run-" + std::to_string(r.seed) + ".json")).string();
    throw core::InputError(file, "/cameras",
                           "holds " + std::to_string(r.best.size()) + " cameras, the scene " +
                               scene.file + " has " + std::to_string(scene.cameras.count) +
                               " (a damaged run file?)");
  }
}

/// Removes the runs of an earlier `optimize --out DIR` and what `validate DIR` made of them.
/// Returns the number of run files removed.
int discard_output(const std::string& dir) {
  const int runs = optimize::discard_runs(dir);
#ifdef CAMPLACE_HAVE_STUDY
  compare::discard_validation(dir);
#endif
  return runs;
}

void run_optimize(const OptimizeArgs& args) {
  // The first SIGINT, SIGTERM or SIGHUP stops the run and writes its result (interrupt.hpp).
  // Until the evaluator is set up nothing is written, and a signal ends the process at once
  // (jobs::StopAtOnce below).
  const jobs::InterruptSignals signals;
  std::atomic<bool>& stop = jobs::InterruptSignals::flag();
  // --max-seconds bounds everything from here: loading and set-up (which then end the process,
  // nothing written), the runs and their snapping (cut at it, no further run starts) and the
  // diagnostics (left out of the summary when no time is left).
  const std::string over_time =
      "optimize stopped: --max-seconds " + core::format_number(args.max_seconds) + " exceeded";
  jobs::set_deadline(args.max_seconds, over_time);

  const core::Scene scene = load_scene_and_report(args.scene);
  voxel::VoxelOptions voxel_options;
  voxel_options.mode = parse_enum<core::LabelMode>(args.mode);
  if (!args.resolution.empty()) {
    voxel_options.resolution = core::parse_resolution(args.resolution, "--resolution");
  }
  voxel_options.refine = args.refine;

  optimize::OptimizeOptions options;
  options.algorithm = args.algorithm;
  options.objective = args.objective;
  options.time_limit = args.time_limit;
  options.max_evaluations = static_cast<std::uint64_t>(args.max_evals);
  if (args.tolerance_given) options.tolerance = args.tolerance;
  options.threads = args.threads;
  options.population = args.population;
  options.interrupt = &stop;
  if (!args.snap.empty()) options.snap = parse_snap(args.snap);
  if (args.start == "random") {
    options.start.kind = optimize::StartKind::random;
  } else if (args.start == "corners") {
    options.start.kind = optimize::StartKind::corners;
  } else {
    // Neither keyword: a camera file, which must exist (else the error would name only "bogus").
    if (!std::filesystem::is_regular_file(args.start)) {
      throw core::OptionError("start", "\"" + args.start +
                                           "\" is neither random, corners nor a camera "
                                           "configuration file that exists");
    }
    options.start = {optimize::StartKind::file, args.start};
  }

  // The memory estimate before the set-up; the set-up itself (up to minutes on fine grids)
  // ends at once on a signal: nothing is written yet.
  const std::string resolution_option =
      args.resolution.empty() ? "the scene's voxels" : "--resolution";
  const unsigned cores = std::max(std::thread::hardware_concurrency(), 1u);
  const VoxelWork work =
      voxel_work(scene, voxel_options.resolution, args.refine,
                 args.threads > 0 ? args.threads : static_cast<int>(cores), false);
  jobs::set_work_description("optimize " + resolution_option + " " + std::to_string(work.n[0]) +
                             "x" + std::to_string(work.n[1]) + "x" + std::to_string(work.n[2]) +
                             " with " + std::to_string(work.cameras) + " cameras" +
                             (args.refine > 0 ? ", --refine " + std::to_string(args.refine) : ""));
  check_memory(work, resolution_option);
  // The folder (or where it would be made) is probed before the set-up and the runs: a
  // read-only or full one is found before the work, not when its result is written.
  core::probe_output_directory(args.out, "--out");
  auto set_up_at_once = std::make_unique<jobs::StopAtOnce>(jobs::StopAtOnce::Options{});
  const optimize::VoxelObjective objective(scene, voxel_options);
  set_up_at_once.reset();
  optimize::RunContext context;
  context.scene_file = args.scene;
  context.mode = args.mode;
  context.resolution = objective.evaluator().grid().n;
  context.refine = args.refine;
  context.start = args.start;
  context.time_limit = args.time_limit;
  context.max_evaluations = static_cast<std::uint64_t>(args.max_evals);
  context.provenance = core::make_provenance(scene);
  context.camera_models = optimize::camera_models(scene);

  // Runs already in --out must have been made like these, or --restart discards them.
  optimize::RunSettings now;
  now.scene_file = args.scene;
  now.scene = context.provenance->scene;
  now.mode = context.mode;
  now.resolution = context.resolution;
  now.refine = context.refine;
  now.algorithm = args.algorithm;
  now.objective = args.objective;
  now.start = args.start;
  now.time_limit = args.time_limit;
  now.max_evaluations = context.max_evaluations;
  now.ceiling_pitch = core::has_ceiling_pitch(scene.cameras);
  now.tolerance = options.tolerance.value_or(objective.default_tolerance());
  const std::size_t dimension = optimize::Encoding(scene).dimension();
  // No free variable: optimize() refuses the scene below.
  if (dimension > 0) {
    now.population = optimize::population_size(args.algorithm, args.population, dimension);
  }
  if (args.restart) {
    const int discarded = discard_output(args.out);
    if (!args.quiet) std::fprintf(stderr, "restart: discarded %d run files\n", discarded);
  } else {
    try {
      optimize::check_resume(args.out, now);
    } catch (const optimize::SettingsChanged& e) {
      throw std::runtime_error(std::string(e.what()) + "\n" + restart_hint(args.out));
    }
    check_run_cameras(args.out, optimize::runs_in_folder(args.out, {}), scene);
  }
  core::create_output_directory(args.out, "--out");

  std::vector<optimize::RunResult> results;
  bool out_of_time = false;
  // The first run always starts (and stops at once after an early Ctrl-C); Ctrl-C ends the job.
  for (int i = 0; i < args.runs && (i == 0 || !stop.load()); ++i) {
    const double left = jobs::seconds_left();
    if (!(left > 0.0)) {
      out_of_time = true;
      break;
    }
    options.seed = args.seed + static_cast<unsigned>(i);
    // The run's own limit, cut to what --max-seconds leaves (the run files record --time-limit:
    // a cut run stops with "time_limit").
    options.time_limit = args.time_limit;
    if (std::isfinite(left) && (args.time_limit <= 0.0 || left < args.time_limit)) {
      options.time_limit = left;
      out_of_time = true;  // unless the run ends before the cut (below)
    }
    ProgressPrinter progress(args.quiet, i + 1, args.runs, options.seed);
    options.on_progress = [&progress](const optimize::Progress& p) { progress.update(p); };
    optimize::RunResult result = optimize::optimize(scene, objective, options);
    progress.finish(result);
    if (out_of_time && result.stop_reason != optimize::StopReason::time_limit &&
        jobs::seconds_left() > 0.0) {
      out_of_time = false;
    }
    const std::string file =
        (std::filesystem::path(args.out) / ("run-" + std::to_string(result.seed) + ".json"))
            .string();
    {
      // Another process may have written runs into the folder since the check above: under the
      // folder's lock, this run joins it only if every run there was made with these settings.
      const optimize::FolderLock lock(args.out);
      try {
        optimize::check_resume(args.out, now);
      } catch (const optimize::SettingsChanged& e) {
        throw std::runtime_error(std::string(e.what()) +
                                 "\n(written there by another process while this one ran; the "
                                 "run of seed " +
                                 std::to_string(result.seed) + " was not written)");
      }
      const std::lock_guard<std::mutex> writing(jobs::StopAtOnce::writing());
      core::write_file_atomically(file, optimize::run_json(result, context).dump(2) + "\n");
    }
    results.push_back(std::move(result));
    if (out_of_time) break;
  }
  const bool interrupted = stop.load();
  const std::filesystem::path out(args.out);
  // Other optimize processes may write runs into the same folder (a study on a cluster, or two
  // jobs of overlapping seeds): the summary is built from the run files there, under the
  // folder's lock, so that it describes exactly the files.
  const optimize::FolderLock lock(args.out);
  const std::vector<optimize::RunResult> all_runs = optimize::runs_in_folder(args.out, {});
  check_run_cameras(args.out, all_runs, scene);
  auto summary = optimize::summary_json(all_runs, context, interrupted);
  // First without the diagnostics, so that running out of time while they are computed keeps a
  // summary of every run.
  core::write_file_atomically((out / "summary.json").string(), summary.dump(2) + "\n");
  core::write_file_atomically((out / "summary.csv").string(), optimize::summary_csv(all_runs));
  // The diagnostics of `evaluate` for the best configuration, in the summary and below
  // the table.
  nlohmann::json diagnostics;
  if (summary.contains("best") && !out_of_time) {
    const auto best = std::min_element(all_runs.begin(), all_runs.end(),
                                       [](const auto& a, const auto& b) { return a.err < b.err; });
    compare::EvaluationOptions eval;
    eval.mode = voxel_options.mode;
    eval.resolution = voxel_options.resolution;
    eval.refine = voxel_options.refine;
    eval.threads = 1;
    jobs::StopAtOnce::Options at_deadline;
    at_deadline.kept =
        "the run files and summary.json (without the best configuration's "
        "diagnostics) are in " +
        args.out;
    at_deadline.temp_dirs.push_back(args.out);
    const jobs::StopAtOnce at_once(at_deadline);
    diagnostics = compare::evaluate_json(scene, best->best, eval).result.at("diagnostics");
    summary["best"]["diagnostics"] = diagnostics;
    const std::lock_guard<std::mutex> writing(jobs::StopAtOnce::writing());
    core::write_file_atomically((out / "summary.json").string(), summary.dump(2) + "\n");
  }
  if (interrupted) {
    std::cout << "interrupted: the best result so far is in " << args.out << "\n\n";
  }
  if (all_runs.size() > results.size()) {
    std::cout << "summary of all " << all_runs.size() << " runs in " << args.out << " ("
              << results.size() << " by this process):\n";
  }
  optimize::print_summary(std::cout, all_runs);
  for (const optimize::RunResult& r : results) {
    if (!r.snapped) continue;
    const optimize::SnappedResult& snap = *r.snapped;
    std::cout << "snapped to " << snap.grid.position_m << " m, " << snap.grid.angle / core::kDegree
              << "° (seed " << r.seed << "): Err " << snap.err << " m² (continuous " << r.err
              << " m², right after rounding " << snap.rounded_err << " m², " << snap.evaluations
              << " evaluations on the grid)\n";
  }
  if (!diagnostics.is_null()) {
    std::cout << "\nbest configuration:\n";
    for (const auto& s : diagnostics["states"]) {
      const auto& c = s["nearest_component"];
      if (c.is_null()) continue;
      std::cout << "  step " << s["time_step"].get<int>() << " event " << s["event"].get<int>()
                << ": nearest model component at " << c["distance"].get<double>()
                << " m, observed by " << c["cameras_observing"].get<int>() << " of "
                << diagnostics["cameras"].size() << " cameras\n";
    }
    for (const auto& w : diagnostics["warnings"])
      std::cout << "  warning: " << w.get<std::string>() << "\n";
  }
  std::cout << "\nrun files, summary.json and summary.csv in " << args.out << "\n";
  if (interrupted) throw jobs::Interrupted("the best result so far is in " + args.out);
  if (out_of_time) {
    throw std::runtime_error(over_time + "; " + std::to_string(results.size()) + " of " +
                             std::to_string(args.runs) +
                             " runs were made (the last one cut short); the run files and "
                             "summary.json (without the best configuration's diagnostics) are "
                             "in " +
                             args.out);
  }
}

}  // namespace

void register_optimize_command(CLI::App& app) {
  auto args = std::make_shared<OptimizeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "optimize", "find camera settings that minimise the voxel Err (pagmo solvers)");
  cmd->footer(
      "A run stops at the first of: tolerance reached, the conservative lower bound of Err\n"
      "reached (provably optimal), time limit, evaluation budget, Ctrl-C. Ctrl-C and the time\n"
      "limit write the best result so far.\n\nObjectives (--objective):\n" +
      optimize::objective_help() + "\nSolvers:\n" + optimize::algorithm_help());
  cmd->add_option("scene", args->scene, "scene JSON file")->required();
  cmd->add_option("--out", args->out, "directory for run-<seed>.json, summary.json, summary.csv")
      ->required();
  cmd->add_option("--algorithm", args->algorithm, "solver (see below)")
      ->check(CLI::IsMember(optimize::algorithm_names()));
  cmd->add_option("--objective", args->objective,
                  "what the solvers minimise (see below); runs report the true Err either way")
      ->check(CLI::IsMember(optimize::objective_names()));
  cmd->add_option("--seed", args->seed, "seed of the first run; run i uses seed+i");
  cmd->add_option("--runs", args->runs, "number of runs R")->check(in_range(1, 100000));
  cmd->add_option("--time-limit", args->time_limit, "seconds per run, 0 = none (default 300)")
      ->check(in_range(0.0, 1e7, "must be a number of seconds in [0, 1e7] (0 = no limit)"));
  cmd->add_option("--max-evals", args->max_evals, "objective evaluations per run, 0 = none")
      ->check(in_range(0LL, 1000000000000LL, "must lie in [0, 1e12] (0 = no limit)"));
  CLI::Option* tolerance = cmd->add_option("--tolerance", args->tolerance,
                                           "stop when Err <= X m² (default (½ voxel diagonal)²)")
                               ->check(in_range(0.0, std::numeric_limits<double>::max(),
                                                "must be a finite number >= 0 (m²)"));
  cmd->add_option("--start", args->start, "random, corners or a camera configuration FILE");
  cmd->add_option("--threads", args->threads,
                  "threads for batch evaluation (gaco, pso_gen), 0 = all cores")
      ->check(
          in_range(0, core::kMaxThreads,
                   "must lie in [0, " + std::to_string(core::kMaxThreads) + "] (0 = all cores)"));
  cmd->add_option("--population", args->population, "population size, 0 = the solver's default")
      ->check(in_range(0, 100000, "must lie in [0, 100000] (0 = the solver's default)"));
  cmd->add_option("--mode", args->mode, "voxel labelling mode")->check(one_of<core::LabelMode>());
  cmd->add_option("--resolution", args->resolution,
                  "voxel resolution NXxNYxNZ (default: the scene's)");
  cmd->add_option("--refine", args->refine,
                  "conservative mode: refine the model's voxels L levels (cells of 1/2^L of the "
                  "voxel's edge; default 0 = none); the tolerance stays the voxels'")
      ->check(in_range(0, voxel::kMaxRefine));
  cmd->add_option("--snap", args->snap,
                  "POS_M,ANGLE_DEG: snap each run's best to this grid (positions to multiples of "
                  "POS_M m, angles of ANGLE_DEG°) and search on the grid; both results are "
                  "reported");
  cmd->add_option("--max-seconds", args->max_seconds,
                  "bound the whole command to S seconds (loading, set-up, runs, snapping, "
                  "diagnostics): runs are cut at it and no further run starts; the runs made are "
                  "written, the exit status is 1 (default 0: no bound)")
      ->check(in_range(0.0, 1e9, "must be a number of seconds in [0, 1e9] (0 = no bound)"));
  cmd->add_flag("--quiet", args->quiet, "no progress on stderr");
  cmd->add_flag("--restart", args->restart,
                "discard the run files and summaries already in --out (and validate's results) "
                "instead of refusing runs made with other settings");
  cmd->callback([args, tolerance] {
    args->tolerance_given = tolerance->count() > 0;
    run_optimize(*args);
  });
}

}  // namespace camplace::app
