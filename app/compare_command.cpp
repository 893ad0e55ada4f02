// `camplace compare`: the voxel pipeline against the exact one for one configuration (SPEC §8).
#include <algorithm>
#include <iostream>

#include "camplace/compare/optimizer_validation.hpp"
#include "camplace/compare/voxel_vs_exact.hpp"
#include "camplace/core/camera.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "cli_checks.hpp"
#include "commands.hpp"

namespace camplace::app {

namespace {

struct CompareArgs {
  std::string scene, cameras, resolutions, refine, out;
  bool resolutions_given = false;
};

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
  const core::Scene scene = core::load_scene(args.scene);
  const core::CameraConfig config = core::load_camera_config(args.cameras, scene);
  compare::CompareOptions options;
  if (args.resolutions_given) options.resolutions = parse_resolution_list(args.resolutions);
  if (!args.refine.empty()) options.refine_levels = parse_level_list(args.refine);
  options.command = command;
  core::create_output_directory(args.out, "--out");
  const compare::CompareResult result = compare::compare_voxel_exact(scene, config, options);
  compare::write_compare_report(scene, result, options, args.out);
  std::cout << "conservative-mode violations: " << result.conservative_violations
            << "\ncenter-mode violations: " << result.center_violations << "\nErr:";
  for (const auto& e : result.errs) std::cout << "  " << e.pipeline << " " << e.err;
  std::cout << "\nreport: " << args.out << "/report.md\n";
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
  cmd->callback([args, resolutions] {
    const core::Scene scene = core::load_scene(args->scene);
    compare::OptimizerValidationOptions options;
    options.runs_dir = args->runs;
    options.samples = args->samples;
    options.seed = args->seed;
    if (resolutions->count() > 0) options.resolutions = parse_resolution_list(args->resolutions);
    core::create_output_directory(args->out, "--out");
    options.command = "camplace compare-optimizer " + args->scene + " --runs " + args->runs +
                      " --samples " + std::to_string(args->samples) + " --seed " +
                      std::to_string(args->seed) +
                      (args->resolutions.empty() ? "" : " --resolutions " + args->resolutions) +
                      " --out " + args->out;
    compare::validate_optimizer(scene, options, args->out);
    std::cout << "report: " << args->out << "/report.md\n";
  });
}

}  // namespace camplace::app
