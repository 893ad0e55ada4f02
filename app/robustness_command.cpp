// `camplace robustness`: the Err of a camera configuration when every camera is mounted within
// a position and an angle tolerance (compare/robustness.hpp). Thin: parse, check, call, print.
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "camplace/compare/robustness.hpp"
#include "camplace/core/camera.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/provenance.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/jobs/interrupt.hpp"
#include "camplace/jobs/progress.hpp"
#include "camplace/optimize/optimizer.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "cli_checks.hpp"
#include "commands.hpp"
#include "memory_estimate.hpp"
#include "scene_input.hpp"

namespace camplace::app {
namespace {

struct RobustnessArgs {
  std::string scene, cameras, out = "robustness", pipeline = "voxel", mode = "conservative",
                              resolution;
  double position_tol = 0.0, angle_tol = 0.0;
  double max_seconds = 0.0;  // the whole command's bound; 0 = none
  int samples = 200, refine = 0, threads = 1, search_evals = 2000, exact_checks = 3;
  unsigned seed = 1;
  bool progress = false;
};

std::string command_line(const RobustnessArgs& a) {
  char tolerances[128];
  std::snprintf(tolerances, sizeof tolerances, " --position-tol %g --angle-tol %g", a.position_tol,
                a.angle_tol);
  std::string c = "camplace robustness " + a.scene + " --cameras " + a.cameras + tolerances +
                  " --samples " + std::to_string(a.samples) + " --seed " + std::to_string(a.seed) +
                  " --pipeline " + a.pipeline + " --mode " + a.mode;
  if (!a.resolution.empty()) c += " --resolution " + a.resolution;
  if (a.refine > 0) c += " --refine " + std::to_string(a.refine);
  c += " --search-evals " + std::to_string(a.search_evals) + " --exact-checks " +
       std::to_string(a.exact_checks) + " --out " + a.out;
  return c;
}

void run_robustness(const RobustnessArgs& args) {
  const jobs::InterruptSignals signals;
  std::atomic<bool>& stop = jobs::InterruptSignals::flag();
  jobs::set_deadline(args.max_seconds, "robustness stopped: --max-seconds " +
                                           core::format_number(args.max_seconds) + " exceeded");
  const core::Scene scene = load_scene_and_report(args.scene);
  // The planned configuration must fit the scene: its count and models (load_camera_config),
  // its domains, mounts and keep-out boxes (what the optimizer asks of a start file).
  const core::CameraConfig planned = core::load_camera_config(args.cameras, scene);
  optimize::check_inside_domains(planned, scene, args.cameras);
  // A run file records the scene it was made for: another scene's run is refused (as validate
  // refuses it), even with the same camera count.
  const core::Provenance provenance = core::make_provenance(scene);
  {
    const nlohmann::json doc = core::read_json_file(args.cameras);
    const core::JsonNode root(doc, args.cameras, "");
    if (root.has("provenance")) {
      core::check_same_scene(core::provenance_from_json(root.at("provenance")).scene,
                             provenance.scene, args.scene, args.cameras);
    }
  }

  compare::RobustnessOptions options;
  options.position_tol = args.position_tol;
  options.angle_tol = args.angle_tol * core::kDegree;
  options.samples = args.samples;
  options.seed = args.seed;
  options.pipeline = parse_enum<core::Pipeline>(args.pipeline);
  options.mode = parse_enum<core::LabelMode>(args.mode);
  if (!args.resolution.empty()) {
    options.resolution = core::parse_resolution(args.resolution, "--resolution");
  }
  options.refine = args.refine;
  options.threads = args.threads;
  options.search_evaluations = args.search_evals;
  options.exact_checks = args.exact_checks;
  options.interrupt = &stop;

  const std::string resolution_option =
      args.resolution.empty() ? "the scene's voxels" : "--resolution";
  const VoxelWork work = voxel_work(scene, options.resolution, args.refine, args.threads, false);
  jobs::set_work_description("robustness " + resolution_option + " " + std::to_string(work.n[0]) +
                             "x" + std::to_string(work.n[1]) + "x" + std::to_string(work.n[2]) +
                             " with " + std::to_string(work.cameras) + " cameras");
  check_memory(work, resolution_option);
  core::create_output_directory(args.out, "--out");

  jobs::ProgressLine progress("robustness", args.progress);
  if (progress.enabled()) {
    options.on_progress = [&progress](const std::string& stage, int done, int total) {
      progress.update(stage, done, total);
    };
  }
  // --max-seconds ends the process at its deadline, within a second, even in the middle of an
  // exact check; the report is written only at the end. A signal still stops after the
  // evaluation under way and writes the report of the samples done.
  jobs::StopAtOnce::Options at_deadline;
  at_deadline.end_on_signal = false;
  at_deadline.temp_dirs = {args.out};
  const jobs::StopAtOnce at_once(at_deadline);
  compare::RobustnessReport report;
  report.command = command_line(args);
  report.cameras_file = args.cameras;
  report.provenance = provenance;
  const compare::RobustnessResult result = compare::analyse_robustness(scene, planned, options);
  progress.finish();
  if (result.samples.empty()) {
    throw jobs::Interrupted("robustness stopped before its first sample; nothing was written");
  }
  compare::write_robustness_report(args.out, options, result, report);
  std::cout << compare::robustness_summary(options, result);
  std::cout << "report: " << args.out << "/robustness.md; worst configuration: " << args.out
            << "/worst-cameras.json\n";
  if (result.interrupted) {
    throw jobs::Interrupted("the work done so far is in " + args.out + "; rerun to redo it all");
  }
}

}  // namespace

void register_robustness_command(CLI::App& app) {
  auto args = std::make_shared<RobustnessArgs>();
  CLI::App* cmd = app.add_subcommand(
      "robustness", "Err of a camera configuration under mounting errors, report in DIR");
  cmd->footer(
      "Every camera is moved by at most --position-tol metres and its viewing direction turned by\n"
      "at most --angle-tol degrees (its roll, where the model has one, by at most as much), then\n"
      "made valid as the optimizer makes its configurations. Random samples, a worst-case search\n"
      "(coordinate ascent on the voxel Err), each camera alone, and the worst configurations\n"
      "checked by the exact pipeline. DIR/worst-cameras.json is the worst configuration found:\n"
      "`camplace evaluate SCENE --cameras DIR/worst-cameras.json` with the same --mode,\n"
      "--resolution and --refine gives its Err. Ctrl-C writes the report of the work done.");
  cmd->add_option("scene", args->scene, "scene JSON file")->required();
  cmd->add_option("--cameras", args->cameras, "camera file or run file of the planned cameras")
      ->required();
  cmd->add_option("--position-tol", args->position_tol, "position tolerance M (metres)")
      ->required()
      ->check(in_range(0.0, 1e6, "must be a finite number of metres in [0, 1e6]"));
  cmd->add_option("--angle-tol", args->angle_tol, "angle tolerance DEG (degrees)")
      ->required()
      ->check(in_range(0.0, 180.0, "must be a finite number of degrees in [0, 180]"));
  cmd->add_option("--samples", args->samples, "random perturbations of all cameras")
      ->check(in_range(1, 10000000));
  cmd->add_option("--seed", args->seed, "seed of the random perturbations");
  cmd->add_option("--pipeline", args->pipeline,
                  "Err of the samples by the voxel pipeline, or by the exact one (slow; the "
                  "worst-case search still climbs the voxel Err)")
      ->check(CLI::IsMember({"voxel", "exact"}));
  cmd->add_option("--mode", args->mode, "voxel labelling mode")->check(one_of<core::LabelMode>());
  cmd->add_option("--resolution", args->resolution,
                  "voxel resolution NXxNYxNZ (default: the scene's)");
  cmd->add_option("--refine", args->refine, "conservative mode: refinement levels L")
      ->check(in_range(0, voxel::kMaxRefine));
  cmd->add_option("--search-evals", args->search_evals,
                  "voxel evaluations of the worst-case search (as many again for the cameras one "
                  "at a time); 0 = no search")
      ->check(in_range(0, 100000000));
  cmd->add_option("--exact-checks", args->exact_checks,
                  "worst distinct configurations checked by the exact pipeline (0 = none)")
      ->check(in_range(0, 10000));
  cmd->add_option("--threads", args->threads, "threads of one evaluation")
      ->check(in_range(1, core::kMaxThreads));
  cmd->add_option("--out", args->out, "output directory");
  cmd->add_flag("--progress", args->progress,
                "progress on stderr also when it is not a terminal (on a terminal: always)");
  cmd->add_option("--max-seconds", args->max_seconds,
                  "stop with exit status 1 when the command takes longer than S seconds (nothing "
                  "is written then; default 0: no limit)")
      ->check(in_range(0.0, 1e9, "must be a number of seconds in [0, 1e9] (0 = no limit)"));
  cmd->callback([args] { run_robustness(*args); });
}

}  // namespace camplace::app
