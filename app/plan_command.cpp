// `camplace plan`: how many cameras. Per camera count R `camplace optimize` processes (as a
// study runs them: resumable, spread over MPI ranks under mpirun, or a shard of them), the best
// run of each count checked by the exact pipeline, and a report (compare/plan.hpp).
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "camplace/compare/plan.hpp"
#include "camplace/compare/run_validation.hpp"
#include "camplace/core/err.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/provenance.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/core/scene_writer.hpp"
#include "camplace/core/statistics.hpp"
#include "camplace/jobs/interrupt.hpp"
#include "camplace/jobs/mpi_runs.hpp"
#include "camplace/jobs/mpi_work.hpp"
#include "camplace/jobs/process.hpp"
#include "camplace/optimize/encoding.hpp"
#include "camplace/optimize/optimizer.hpp"
#include "camplace/optimize/report.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "cli_checks.hpp"
#include "commands.hpp"
#include "memory_estimate.hpp"
#include "scene_input.hpp"

namespace camplace::app {
namespace {

namespace fs = std::filesystem;

/// The most cameras a scene may have (docs/scene-format.md, `count`).
constexpr int kMaxCameras = 256;

struct PlanArgs {
  std::string scene, counts, out = "plan", algorithm = "gaco", mode = "conservative", resolution,
                             shard;
  int runs = 3, refine = 0, threads = 1;
  unsigned seed = 1;
  double time_limit = 120.0;
  double max_seconds = 0.0;  // the whole command's bound; 0 = none
  long long max_evals = 10000;
  bool restart = false, report_only = false;
};

/// --counts A..B (or one count N): 1 ≤ A ≤ B ≤ 256. Throws core::OptionError naming --counts.
std::pair<int, int> parse_counts(const std::string& text) {
  const auto number = [&](const std::string& digits) {
    if (digits.empty() || digits.size() > 6 ||
        digits.find_first_not_of("0123456789") != std::string::npos) {
      throw core::OptionError("counts", "must be A..B with whole numbers 1 ≤ A ≤ B ≤ " +
                                            std::to_string(kMaxCameras) +
                                            " (e.g. 2..8) or one count N, not \"" + text + "\"");
    }
    return std::stoi(digits);
  };
  const std::size_t dots = text.find("..");
  const int a = number(dots == std::string::npos ? text : text.substr(0, dots));
  const int b = dots == std::string::npos ? a : number(text.substr(dots + 2));
  if (a < 1) throw core::OptionError("counts", "a camera count must be at least 1, got " + text);
  if (a > b) {
    throw core::OptionError("counts", "the range " + text + " is reversed (" + std::to_string(a) +
                                          " > " + std::to_string(b) + "); write " +
                                          std::to_string(b) + ".." + std::to_string(a));
  }
  if (b > kMaxCameras) {
    throw core::OptionError("counts", std::to_string(b) + " cameras exceed the scene format's " +
                                          std::to_string(kMaxCameras));
  }
  return {a, b};
}

std::string number_text(double v) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

/// One run to do.
struct PlanRun {
  int cameras = 0;
  unsigned seed = 0;
  jobs::ProcessLaunch launch;
  std::string run_file;
  std::string label;
};

/// The finished run file of a seed (not interrupted), or none.
std::optional<optimize::RunFile> finished_run(const std::string& file) {
  if (!fs::is_regular_file(file)) return std::nullopt;
  optimize::RunFile run = optimize::read_run_file(file);
  if (run.run.stop_reason == optimize::StopReason::interrupted) return std::nullopt;
  return run;
}

void run_plan(const PlanArgs& args) {
  const auto [first, last] = parse_counts(args.counts);
  int shard_index = 0, shard_count = 0;
  if (!args.shard.empty()) {
    std::tie(shard_index, shard_count) = parse_shard(args.shard);
    if (args.restart) throw core::OptionError("shard", "cannot go with --restart");
    if (args.report_only) throw core::OptionError("shard", "cannot go with --report-only");
  }
  if (args.report_only && args.restart) {
    throw core::OptionError("report-only", "cannot go with --restart");
  }
  const jobs::InterruptSignals signals;
  std::atomic<bool>& stop = jobs::InterruptSignals::flag();
  jobs::set_deadline(args.max_seconds, "plan stopped: --max-seconds " +
                                           core::format_number(args.max_seconds) + " exceeded");
  const core::Scene scene = load_scene_and_report(args.scene);
  std::array<int, 3> resolution = scene.voxels;
  if (!args.resolution.empty()) {
    resolution = core::parse_resolution(args.resolution, "--resolution");
  }
  // Every count's work must fit before anything starts: the largest needs the most memory.
  const std::string resolution_option =
      args.resolution.empty() ? "the scene's voxels" : "--resolution";
  {
    const core::Scene largest = compare::scene_with_cameras(scene, last);
    const VoxelWork work = voxel_work(largest, resolution, args.refine, args.threads, false);
    jobs::set_work_description("plan " + resolution_option + " with " + std::to_string(last) +
                               " cameras");
    check_memory(work, resolution_option);
    voxel::VoxelOptions v;
    v.mode = parse_enum<core::LabelMode>(args.mode);
    v.resolution = resolution;
    v.refine = args.refine;
    const std::string problem = voxel::refine_problem(largest, v);
    if (!problem.empty()) throw core::OptionError("refine", problem);
    (void)optimize::population_size(args.algorithm, 0, optimize::Encoding(largest).dimension());
  }
  core::create_output_directory(args.out, "--out");
  const fs::path out(args.out);
  const jobs::StopAtOnce at_once(runs_folder_deadline(args.out));
  if (args.restart) {
    std::error_code ec;
    int removed = 0;
    for (const char* sub : {"runs", "scenes"}) removed += fs::remove_all(out / sub, ec) > 0;
    compare::discard_validation(args.out);
    for (const char* f : {"plan.md", "plan.csv", "plan.json", "plan.png", "plan.dat", "plan.gp",
                          "plan_cost.png", "plan_cost.gp"}) {
      fs::remove(out / f, ec);
    }
    std::cout << "restart: discarded the runs, scenes, exact checks and report in " << args.out
              << "\n";
  }

  // The scene of each count, written where its runs find it, and the runs' settings.
  std::vector<PlanRun> pending;
  std::vector<std::string> missing;
  std::map<int, std::string> scene_files;
  int canonical = 0;
  const std::string mode = args.mode;
  for (int n = first; n <= last; ++n) {
    const core::Scene count_scene = compare::scene_with_cameras(scene, n);
    const std::string scene_file =
        (out / "scenes" / ("cameras-" + std::to_string(n) + ".json")).string();
    if (!args.report_only) {
      core::write_scene(count_scene, scene_file,
                        "The scene " + args.scene + " with " + std::to_string(n) +
                            " cameras (its cameras cycled), written by camplace plan.");
    }
    scene_files[n] = scene_file;
    const fs::path run_dir = out / "runs" / std::to_string(n);
    if (!args.report_only && fs::is_directory(run_dir)) {
      const core::Scene written = core::load_scene(scene_file);
      optimize::RunSettings now;
      now.scene_file = scene_file;
      now.scene = core::hash_scene(written);
      now.mode = mode;
      now.resolution = resolution;
      now.refine = args.refine;
      now.algorithm = args.algorithm;
      now.start = "random";
      now.time_limit = args.time_limit;
      now.max_evaluations = static_cast<std::uint64_t>(args.max_evals);
      now.ceiling_pitch = core::has_ceiling_pitch(written.cameras);
      now.tolerance = core::default_tolerance(written.area, resolution);
      const std::size_t dimension = optimize::Encoding(written).dimension();
      if (dimension > 0) now.population = optimize::population_size(args.algorithm, 0, dimension);
      try {
        optimize::check_resume(run_dir.string(), now);
      } catch (const optimize::SettingsChanged& e) {
        throw std::runtime_error(std::string(e.what()) + "\n" + restart_hint(args.out));
      }
    }
    for (int r = 0; r < args.runs; ++r, ++canonical) {
      const unsigned seed = args.seed + static_cast<unsigned>(r);
      const std::string run_file = (run_dir / ("run-" + std::to_string(seed) + ".json")).string();
      const std::string label = std::to_string(n) + " cameras seed " + std::to_string(seed);
      if (finished_run(run_file)) continue;
      missing.push_back(label);
      if (shard_count > 0 && canonical % shard_count != shard_index - 1) continue;
      PlanRun run;
      run.cameras = n;
      run.seed = seed;
      run.run_file = run_file;
      run.label = label;
      run.launch.args = {"optimize",     scene_file,
                         "--out",        run_dir.string(),
                         "--seed",       std::to_string(seed),
                         "--runs",       "1",
                         "--algorithm",  args.algorithm,
                         "--mode",       mode,
                         "--time-limit", number_text(args.time_limit),
                         "--max-evals",  std::to_string(args.max_evals),
                         "--threads",    std::to_string(args.threads),
                         "--quiet"};
      if (!args.resolution.empty()) {
        run.launch.args.insert(run.launch.args.end(), {"--resolution", args.resolution});
      }
      if (args.refine > 0) {
        run.launch.args.insert(run.launch.args.end(), {"--refine", std::to_string(args.refine)});
      }
      run.launch.output_file = (run_dir / ("output-" + std::to_string(seed) + ".txt")).string();
      pending.push_back(std::move(run));
    }
  }

  // The running binary, so that the runs use the same camplace as the plan.
  std::error_code ec;
  std::string program = fs::read_symlink("/proc/self/exe", ec).string();
  if (ec || program.empty()) program = "/proc/self/exe";
  std::unique_ptr<jobs::mpi::Session> session;
  if (jobs::mpi::launched_by_mpirun()) session = std::make_unique<jobs::mpi::Session>();
  if (session && session->rank() > 0) {
    jobs::mpi::serve_runs(*session, program);
    return;
  }
  bool interrupted = false;
  int done_now = 0;
  if (!args.report_only && !pending.empty()) {
    for (const PlanRun& run : pending) fs::create_directories(fs::path(run.run_file).parent_path());
    std::vector<jobs::ProcessOutcome> outcomes;
    if (session && session->size() > 1) {
      std::vector<jobs::mpi::RankRun> rank_runs;
      for (const PlanRun& run : pending) rank_runs.push_back({run.launch, run.run_file, run.label});
      outcomes = jobs::mpi::run_on_ranks(*session, program, rank_runs, "plan");
    } else {
      for (std::size_t i = 0; i < pending.size() && !stop.load(); ++i) {
        std::cerr << "plan: " << pending[i].label << " (" << i + 1 << " of " << pending.size()
                  << ")\n";
        outcomes.push_back(jobs::run_process(program, pending[i].launch));
        if (outcomes.back().interrupted) break;
      }
    }
    for (std::size_t i = 0; i < outcomes.size(); ++i) {
      interrupted = interrupted || outcomes[i].interrupted;
      if (!outcomes[i].failure.empty() && !outcomes[i].interrupted) {
        throw std::runtime_error("plan: the run " + pending[i].label + " failed (" +
                                 outcomes[i].failure + "); its output is in " +
                                 pending[i].launch.output_file);
      }
      done_now += outcomes[i].failure.empty() && !outcomes[i].interrupted;
    }
    interrupted = interrupted || stop.load() || outcomes.size() < pending.size();
  }
  if (shard_count > 0) {
    std::cout << "shard " << args.shard << ": " << pending.size() << " runs to do, " << done_now
              << " done now" << (interrupted ? ", interrupted" : "")
              << "\nno report: a shard writes none; when every shard is done, run the same "
                 "command with --report-only instead of --shard\n";
    if (interrupted) throw jobs::Interrupted("plan shard interrupted; rerun it to resume");
    return;
  }

  // The rows: each count's finished runs, its best exact-checked (cached per run file).
  std::vector<compare::PlanRow> rows;
  compare::RunChecker checker(args.out);
  missing.clear();
  for (int n = first; n <= last; ++n) {
    compare::PlanRow row;
    row.cameras = n;
    row.cost = compare::cameras_cost(compare::scene_with_cameras(scene, n));
    row.runs_planned = args.runs;
    std::vector<double> errs, evaluations, seconds;
    std::optional<optimize::RunFile> best;
    std::string best_file;
    for (int r = 0; r < args.runs; ++r) {
      const unsigned seed = args.seed + static_cast<unsigned>(r);
      const std::string file =
          (out / "runs" / std::to_string(n) / ("run-" + std::to_string(seed) + ".json")).string();
      std::optional<optimize::RunFile> run = finished_run(file);
      if (!run) {
        missing.push_back(std::to_string(n) + " cameras seed " + std::to_string(seed));
        continue;
      }
      ++row.runs_done;
      errs.push_back(run->run.err);
      evaluations.push_back(static_cast<double>(run->run.evaluations));
      seconds.push_back(run->run.seconds);
      row.tolerance = run->run.tolerance;
      row.err_lower_bound = run->run.err_lower_bound;
      if (!best || run->run.err < best->run.err) {
        best = std::move(run);
        best_file = file;
      }
    }
    if (best) {
      row.best_seed = best->run.seed;
      row.best_run_file = best_file;
      row.voxel_err = best->run.err;
      row.median_voxel_err = core::median(errs);
      row.median_evaluations = core::median(evaluations);
      row.median_seconds = core::median(seconds);
      // After a Ctrl-C the checks wait for the rerun (they are cached per run file).
      if (!interrupted && !stop.load()) {
        std::cerr << "plan: exact check of the best run with " << n << " cameras\n";
        const compare::RunValidation check = checker.check(best_file);
        if (check.error.empty()) {
          row.exact_err = check.exact_err;
          row.voxel_err_pyramid = check.voxel_err_same_fov;
          row.max_overestimate = check.max_overestimate;
        } else {
          row.check_error = check.error;
        }
      }
    } else {
      row.tolerance = core::default_tolerance(scene.area, resolution);
    }
    rows.push_back(std::move(row));
  }
  interrupted = interrupted || stop.load();

  compare::PlanReport report;
  report.command = "camplace plan " + args.scene + " --counts " + args.counts + " --runs " +
                   std::to_string(args.runs) + " --seed " + std::to_string(args.seed) +
                   " --algorithm " + args.algorithm + " --mode " + args.mode + " --max-evals " +
                   std::to_string(args.max_evals) + " --time-limit " +
                   number_text(args.time_limit) + " --threads " + std::to_string(args.threads) +
                   (args.resolution.empty() ? "" : " --resolution " + args.resolution) +
                   (args.refine > 0 ? " --refine " + std::to_string(args.refine) : "") + " --out " +
                   args.out;
  report.provenance = core::make_provenance(scene);
  report.settings = "Per count " + std::to_string(args.runs) + " runs of " + args.algorithm +
                    " (seeds " + std::to_string(args.seed) + ".." +
                    std::to_string(args.seed + static_cast<unsigned>(args.runs) - 1) + "), " +
                    args.mode + " mode" +
                    (args.refine > 0 ? ", refine " + std::to_string(args.refine) : "") +
                    ", at most " + std::to_string(args.max_evals) + " evaluations and " +
                    number_text(args.time_limit) + " s per run.";
  report.interrupted = interrupted;
  report.missing = missing;
  compare::write_plan_report(args.out, rows, report);

  std::printf("%7s %6s %9s %11s %11s %11s %10s\n", "cameras", "runs", "best", "voxel Err",
              "exact Err", "lower bnd", "tolerance");
  const auto value = [](bool known, double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.5f", v);
    return known ? std::string(text) : std::string("-");
  };
  for (const compare::PlanRow& r : rows) {
    const bool ran = r.best_seed.has_value();
    std::printf("%7d %3d/%-2d %9s %11s %11s %11s %10.5f%s\n", r.cameras, r.runs_done,
                r.runs_planned, ran ? ("seed " + std::to_string(*r.best_seed)).c_str() : "-",
                value(ran, r.voxel_err).c_str(),
                value(r.exact_err.has_value(), r.exact_err.value_or(0.0)).c_str(),
                value(ran, r.err_lower_bound).c_str(), r.tolerance,
                r.reached_exact() ? "  reached (exact)" : "");
  }
  const std::optional<int> recommended = compare::recommended_count(rows);
  if (recommended) {
    std::cout << "recommendation: " << *recommended
              << " cameras (the smallest count whose best configuration reaches the tolerance by "
                 "its exact Err)"
              << (compare::recommendation_is_final(rows) ? "" : "; provisional: runs are missing")
              << "\n";
  } else {
    std::cout << "no count up to " << last
              << " cameras reaches the tolerance by its exact Err (best configuration of each "
                 "count)\n";
  }
  if (!missing.empty()) std::cout << missing.size() << " runs missing\n";
  std::cout << "report: " << args.out << "/plan.md\n";
  if (interrupted) throw jobs::Interrupted("plan interrupted; rerun the same command to resume");
}

}  // namespace

void register_plan_command(CLI::App& app) {
  auto args = std::make_shared<PlanArgs>();
  CLI::App* cmd = app.add_subcommand(
      "plan", "how many cameras: optimise each count, exact-check, recommend, report in DIR");
  cmd->footer(
      "For each camera count of --counts (the scene's cameras cycled: camera i takes the model\n"
      "and domain of the scene's camera i mod n), --runs `camplace optimize` runs; the best of\n"
      "each count is checked by the exact pipeline, and DIR/plan.md recommends the smallest count\n"
      "whose best configuration reaches the tolerance by its exact Err. Rerun the same command to\n"
      "resume (Ctrl-C keeps the finished runs); under `mpirun -n N` the runs are spread over the\n"
      "ranks; --shard I/N runs a fixed part of them, then --report-only writes the report.");
  cmd->add_option("scene", args->scene, "scene JSON file")->required();
  cmd->add_option("--counts", args->counts, "camera counts A..B (or one count N)")->required();
  cmd->add_option("--runs", args->runs, "optimisation runs per count")->check(in_range(1, 100000));
  cmd->add_option("--seed", args->seed, "seed of the first run of each count; run i uses seed+i");
  cmd->add_option("--max-evals", args->max_evals, "objective evaluations per run, 0 = none")
      ->check(in_range(0LL, 1000000000000LL, "must lie in [0, 1e12] (0 = no limit)"));
  cmd->add_option("--time-limit", args->time_limit, "seconds per run, 0 = none")
      ->check(in_range(0.0, 1e7, "must be a number of seconds in [0, 1e7] (0 = no limit)"));
  cmd->add_option("--algorithm", args->algorithm, "solver (see camplace optimize --help)")
      ->check(CLI::IsMember(optimize::algorithm_names()));
  cmd->add_option("--mode", args->mode, "voxel labelling mode")->check(one_of<core::LabelMode>());
  cmd->add_option("--resolution", args->resolution,
                  "voxel resolution NXxNYxNZ (default: the scene's)");
  cmd->add_option("--refine", args->refine, "conservative mode: refinement levels L")
      ->check(in_range(0, voxel::kMaxRefine));
  cmd->add_option("--threads", args->threads, "threads of each run's batch evaluation")
      ->check(in_range(1, core::kMaxThreads));
  cmd->add_option("--out", args->out, "output directory; rerun to resume");
  cmd->add_flag("--restart", args->restart,
                "discard the runs, scenes, exact checks and report already in --out");
  cmd->add_option("--shard", args->shard,
                  "I/N: run only the I-th of N fixed parts of the runs (the k-th run goes to part "
                  "k mod N + 1), no report");
  cmd->add_flag("--report-only", args->report_only,
                "run nothing: write the report from the runs in --out (exact-checking each "
                "count's best) and list the missing ones");
  cmd->add_option("--max-seconds", args->max_seconds,
                  "stop with exit status 1 when the command takes longer than S seconds (the "
                  "run under way is stopped and repeated by a rerun; the finished runs are kept; "
                  "default 0: no limit)")
      ->check(in_range(0.0, 1e9, "must be a number of seconds in [0, 1e9] (0 = no limit)"));
  cmd->callback([args] { run_plan(*args); });
}

}  // namespace camplace::app
