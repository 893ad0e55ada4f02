// `camplace compare`: the voxel pipeline against the exact one for one configuration (SPEC §8).
#include <algorithm>
#include <array>
#include <iostream>
#include <mutex>
#include <string>
#include <vector>

#include "camplace/compare/optimizer_validation.hpp"
#include "camplace/compare/voxel_vs_exact.hpp"
#include "camplace/core/camera.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/jobs/interrupt.hpp"
#include "camplace/jobs/progress.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "cli_checks.hpp"
#include "commands.hpp"
#include "memory_estimate.hpp"
#include "scene_input.hpp"

namespace camplace::app {

namespace {

struct CompareArgs {
  std::string scene, cameras, resolutions, refine, out;
  bool resolutions_given = false, progress = false;
  double max_seconds = 0.0;  // the whole command's bound; 0 = none
};

/// "16x12x12".
std::string resolution_name(const std::array<int, 3>& n) {
  return std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" + std::to_string(n[2]);
}

/// The memory estimate of each resolution's voxel pipeline (the finest refinement level, the
/// largest need) and of the exact pipeline against what is available; `option` sized the grids.
void check_compare_memory(const core::Scene& scene, std::vector<std::array<int, 3>> resolutions,
                          const std::vector<int>& levels, const std::string& option,
                          const std::string& command) {
  if (resolutions.empty()) resolutions.push_back(scene.voxels);
  const int level = levels.empty() ? 0 : *std::max_element(levels.begin(), levels.end());
  std::string sizes;
  for (const auto& n : resolutions) sizes += (sizes.empty() ? "" : ",") + resolution_name(n);
  jobs::set_work_description(command + " " + option + " " + sizes + " with " +
                             std::to_string(scene.cameras.domains.size()) + " cameras" +
                             (level > 0 ? ", --refine up to " + std::to_string(level) : ""));
  for (const auto& n : resolutions) check_memory(voxel_work(scene, n, level, 1, false), option);
  check_exact_memory(exact_work(scene, 0));  // the exact pipeline with one thread per core
}

/// "0,1,3" → refinement levels, each 0..voxel::kMaxRefine; an empty list or item is an error.
std::vector<int> parse_level_list(const std::string& text) {
  std::vector<int> out;
  std::size_t begin = 0;
  while (true) {
    const std::size_t end = std::min(text.find(',', begin), text.size());
    const std::string item = text.substr(begin, end - begin);
    int level = -1;
    std::size_t used = 0;
    try {
      level = std::stoi(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (item.empty() || used != item.size() || level < 0 || level > voxel::kMaxRefine) {
      throw core::InputError("command line", "--refine",
                             "bad entry \"" + item + "\" in \"" + text + "\" (expected levels 0.." +
                                 std::to_string(voxel::kMaxRefine) +
                                 " separated by commas, e.g. 0,1,2,3)");
    }
    out.push_back(level);
    if (end == text.size()) return out;
    begin = end + 1;
  }
}

/// "16x12x12,24x18x18" → the resolutions; an empty list or item is an error.
std::vector<std::array<int, 3>> parse_resolution_list(const std::string& text) {
  std::vector<std::array<int, 3>> out;
  std::size_t begin = 0;
  while (true) {
    const std::size_t end = std::min(text.find(',', begin), text.size());
    const std::string item = text.substr(begin, end - begin);
    if (item.empty()) {
      throw core::InputError("command line", "--resolutions",
                             "empty entry in \"" + text + "\" (expected e.g. 16x12x12,24x18x18)");
    }
    out.push_back(core::parse_resolution(item, "--resolutions"));
    if (end == text.size()) return out;
    begin = end + 1;
  }
}

void run_compare(const CompareArgs& args, const std::string& command) {
  const jobs::InterruptSignals
      signals;  // a signal before the work starts: jobs::StopAtOnce ends it there
  jobs::set_deadline(args.max_seconds, "compare stopped: --max-seconds " +
                                           core::format_number(args.max_seconds) + " exceeded");
  const core::Scene scene = load_scene_and_report(args.scene);
  const core::CameraConfig config = core::load_camera_config(args.cameras, scene);
  compare::CompareOptions options;
  if (args.resolutions_given) options.resolutions = parse_resolution_list(args.resolutions);
  if (!args.refine.empty()) options.refine_levels = parse_level_list(args.refine);
  options.command = command;
  check_compare_memory(scene, options.resolutions, options.refine_levels,
                       args.resolutions_given ? "--resolutions" : "the scene's voxels", "compare");
  core::create_output_directory(args.out, "--out");
  jobs::ProgressLine progress("compare", args.progress);
  if (progress.enabled()) {
    // The exact pipeline first, counted in (state, camera) steps; then the voxel pipelines,
    // counted in evaluations.
    options.on_exact_progress = [&progress](long done, long total) {
      progress.update("exact pipeline, (state, camera) steps", done, total);
    };
    options.on_progress = [&progress](int done, int total) {
      if (done > 0) progress.update("voxel pipelines, evaluations", done, total);
    };
  }
  compare::CompareResult result;
  {
    // Neither pipeline can stop inside an evaluation: a signal ends the process within a second,
    // keeping the report of the evaluations done (rewritten after each, marked incomplete).
    jobs::StopAtOnce::Options stop;
    stop.kept = "nothing was written (the exact pipeline had not finished)";
    stop.temp_dirs.push_back(args.out);
    const jobs::StopAtOnce at_once(stop);
    result = compare::compare_voxel_exact(
        scene, config, options, [&](const compare::CompareResult& partial) {
          if (partial.evaluations_done == partial.evaluations_total) return;  // written below
          const std::lock_guard<std::mutex> lock(jobs::StopAtOnce::writing());
          compare::write_compare_report(scene, partial, options, args.out);
          jobs::StopAtOnce::set_kept(args.out + "/report.md and its files hold " +
                                     std::to_string(partial.evaluations_done) + " of " +
                                     std::to_string(partial.evaluations_total) +
                                     " evaluations (marked incomplete); rerun the command for all");
        });
  }
  progress.finish();
  compare::write_compare_report(scene, result, options, args.out);
  std::cout << "conservative-mode violations: " << result.conservative_violations
            << "\ncenter-mode violations: " << result.center_violations << "\nErr [m²]:";
  // Each number with the resolution it belongs to (and its refinement levels).
  for (const auto& e : result.errs) {
    std::cout << "\n  " << e.pipeline;
    if (e.pipeline != "exact") std::cout << " at " << resolution_name(e.resolution);
    std::cout << ": " << e.err;
  }
  std::cout << "\nreport: " << args.out << "/report.md\n";
  if (jobs::InterruptSignals::flag().load()) {
    throw jobs::Interrupted("compare: a signal came while the report was written; it is complete");
  }
}

}  // namespace

void register_compare_command(CLI::App& app) {
  auto args = std::make_shared<CompareArgs>();
  CLI::App* cmd =
      app.add_subcommand("compare", "voxel pipeline against the exact pipeline, report in DIR");
  cmd->add_option("scene", args->scene, "scene JSON file")->required();
  cmd->add_option("--cameras", args->cameras, "camera configuration JSON file")->required();
  CLI::Option* resolutions = cmd->add_option(
      "--resolutions", args->resolutions,
      "comma-separated voxel resolutions, e.g. 16x12x12,24x18x18 (default: the scene's)");
  CLI::Option* refine = cmd->add_option(
      "--refine", args->refine,
      "comma-separated refinement levels of conservative mode at every resolution, e.g. "
      "0,1,2,3 (default: 0)");
  cmd->add_option("--out", args->out, "output directory")->required();
  cmd->add_option("--max-seconds", args->max_seconds,
                  "stop with exit status 1 when the command takes longer than S seconds (the "
                  "report of the evaluations done is kept; default 0: no limit)")
      ->check(in_range(0.0, 1e9, "must be a number of seconds in [0, 1e9] (0 = no limit)"));
  cmd->add_flag("--progress", args->progress,
                "progress on stderr also when it is not a terminal (on a terminal: always)");
  cmd->footer(
      "Ctrl-C (or SIGTERM, SIGHUP) stops within a second; the report then holds the evaluations\n"
      "done, marked incomplete, and the exit status is 128 + the signal.");
  cmd->callback([args, resolutions, refine] {
    args->resolutions_given = resolutions->count() > 0;
    if (refine->count() > 0 && args->refine.empty()) args->refine = ",";  // an empty list: refused
    std::string command = "camplace compare " + args->scene + " --cameras " + args->cameras;
    if (!args->resolutions.empty()) command += " --resolutions " + args->resolutions;
    if (!args->refine.empty()) command += " --refine " + args->refine;
    run_compare(*args, command + " --out " + args->out);
  });
}

void register_compare_optimizer_command(CLI::App& app) {
  struct Args {
    std::string scene, runs, resolutions, out;
    int samples = 12;
    unsigned seed = 1;
    bool progress = false;
    double max_seconds = 0.0;  // the whole command's bound; 0 = none
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "compare-optimizer",
      "exact Err of optimizer results and voxel/exact rank agreement, report in DIR");
  cmd->add_option("scene", args->scene, "scene JSON file")->required();
  cmd->add_option("--runs", args->runs, "directory with run-<seed>.json files of camplace optimize")
      ->required();
  cmd->add_option("--samples", args->samples, "random configurations for the rank agreement")
      ->check(in_range(2, 100000));
  cmd->add_option("--seed", args->seed, "seed of the random configurations");
  CLI::Option* resolutions =
      cmd->add_option("--resolutions", args->resolutions,
                      "comma-separated voxel resolutions (default: the scene's)");
  cmd->add_option("--out", args->out, "output directory")->required();
  cmd->add_flag("--progress", args->progress,
                "progress on stderr also when it is not a terminal (on a terminal: always)");
  cmd->add_option("--max-seconds", args->max_seconds,
                  "stop with exit status 1 when the command takes longer than S seconds (what "
                  "was written by then is kept; default 0: no limit)")
      ->check(in_range(0.0, 1e9, "must be a number of seconds in [0, 1e9] (0 = no limit)"));
  cmd->footer(
      "Ctrl-C (or SIGTERM, SIGHUP) stops within a second, keeping runs.csv once every run's\n"
      "exact Err is known; the exit status is then 128 + the signal.");
  cmd->callback([args, resolutions] {
    const jobs::InterruptSignals signals;
    jobs::set_deadline(args->max_seconds, "compare-optimizer stopped: --max-seconds " +
                                              core::format_number(args->max_seconds) + " exceeded");
    const core::Scene scene = load_scene_and_report(args->scene);
    compare::OptimizerValidationOptions options;
    options.runs_dir = args->runs;
    options.samples = args->samples;
    options.seed = args->seed;
    if (resolutions->count() > 0) options.resolutions = parse_resolution_list(args->resolutions);
    check_compare_memory(scene, options.resolutions, {},
                         resolutions->count() > 0 ? "--resolutions" : "the scene's voxels",
                         "compare-optimizer");
    core::create_output_directory(args->out, "--out");
    options.command = "camplace compare-optimizer " + args->scene + " --runs " + args->runs +
                      " --samples " + std::to_string(args->samples) + " --seed " +
                      std::to_string(args->seed) +
                      (args->resolutions.empty() ? "" : " --resolutions " + args->resolutions) +
                      " --out " + args->out;
    jobs::ProgressLine progress("compare-optimizer", args->progress);
    if (progress.enabled()) {
      options.on_progress = [&progress](int done, int total) {
        progress.update("evaluations", done, total);
      };
    }
    options.writing = &jobs::StopAtOnce::writing();
    options.on_written = [](const std::string& kept) { jobs::StopAtOnce::set_kept(kept); };
    {
      // No evaluation can stop half-way: a signal ends the process within a second, keeping
      // what was written (jobs::StopAtOnce).
      jobs::StopAtOnce::Options stop;
      stop.temp_dirs.push_back(args->out);
      const jobs::StopAtOnce at_once(stop);
      compare::validate_optimizer(scene, options, args->out);
    }
    progress.finish();
    std::cout << "report: " << args->out << "/report.md\n";
    if (jobs::InterruptSignals::flag().load()) {
      throw jobs::Interrupted(
          "compare-optimizer: a signal came while the report was written; it is complete");
    }
  });
}

}  // namespace camplace::app
