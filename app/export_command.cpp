// `camplace export`: glTF files, a viewer page and camera poses of one camera configuration
// (docs/export.md).
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <string>
#include <thread>

#include "camplace/core/camera.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/core/threads.hpp"
#include "camplace/jobs/interrupt.hpp"
#include "camplace/jobs/progress.hpp"
#include "camplace/view/export.hpp"
#include "cli_checks.hpp"
#include "commands.hpp"
#include "memory_estimate.hpp"
#include "scene_input.hpp"

namespace camplace::app {

namespace {

struct ExportArgs {
  std::string scene, cameras, out, mode = "conservative", resolution, pipeline = "voxel";
  std::vector<std::string> states;
  std::string three_dir = view::kDefaultThreeDir;
  int threads = 0;           // 0 = one per core
  int refine = 0;            // voxel::VoxelOptions::refine
  double max_seconds = 0.0;  // the whole command's bound; 0 = none
  bool progress = false;     // --progress
};

/// "H,L" → the state; InputError naming --state otherwise.
core::StateIndex parse_state(const std::string& text) {
  const std::size_t comma = text.find(',');
  auto number = [&](const std::string& part, int* value) {
    if (part.empty() || part.size() > 9 ||
        !std::all_of(part.begin(), part.end(), [](char c) { return c >= '0' && c <= '9'; }))
      return false;
    *value = std::stoi(part);
    return true;
  };
  core::StateIndex state;
  if (comma == std::string::npos || !number(text.substr(0, comma), &state.time_step) ||
      !number(text.substr(comma + 1), &state.event)) {
    throw core::InputError("command line", "--state",
                           "expected H,L (time step and event, e.g. 0,1), got \"" + text + "\"");
  }
  return state;
}

void run_export(const ExportArgs& args) {
  const jobs::InterruptSignals signals;
  // --max-seconds bounds the whole command: loading, the evaluation and the writing.
  jobs::set_deadline(args.max_seconds, "export stopped: --max-seconds " +
                                           core::format_number(args.max_seconds) + " exceeded");
  const core::Scene scene = load_scene_and_report(args.scene);
  const core::CameraConfig config = core::load_camera_config(args.cameras, scene);
  view::ExportOptions options;
  options.pipeline = parse_enum<core::Pipeline>(args.pipeline);
  options.voxel.mode = parse_enum<core::LabelMode>(args.mode);
  options.voxel.refine = args.refine;
  if (!args.resolution.empty()) {
    options.voxel.resolution = core::parse_resolution(args.resolution, "--resolution");
  }
  options.voxel.threads = args.threads > 0 ? args.threads : core::machine_cores();
  options.threads = args.threads;
  for (const std::string& s : args.states) options.states.push_back(parse_state(s));
  options.three_dir = args.three_dir;
  options.scene_file = args.scene;
  options.cameras_file = args.cameras;
  // Every check before the output folder is created or anything is computed.
  view::check_export_options(scene, options);
  const std::string resolution_option =
      args.resolution.empty() ? "the scene's voxels" : "--resolution";
  const VoxelWork work =
      voxel_work(scene, options.voxel.resolution, args.refine, options.voxel.threads, false);
  jobs::set_work_description("export " + resolution_option + " " + std::to_string(work.n[0]) + "x" +
                             std::to_string(work.n[1]) + "x" + std::to_string(work.n[2]) +
                             " with " + std::to_string(config.size()) + " cameras" +
                             (args.refine > 0 ? ", --refine " + std::to_string(args.refine) : ""));
  if (options.pipeline == core::Pipeline::voxel) {
    check_memory(work, resolution_option);
  } else {
    check_exact_memory(exact_work(scene, args.threads));
  }
  core::create_output_directory(args.out, "--out");
  jobs::ProgressLine progress("export", args.progress);
  if (progress.enabled()) {
    options.on_exact_progress = [&progress](long done, long total) {
      progress.update("exact evaluation, (state, camera) steps", done, total);
    };
  }
  view::ExportResult result;
  {
    // A signal ends the export within a second, removing unfinished temporary files.
    jobs::StopAtOnce::Options stop;
    stop.kept = "the files written so far are in " + args.out + " (the export is incomplete)";
    stop.temp_dirs.push_back(args.out);
    const jobs::StopAtOnce at_once(stop);
    result = view::export_scene(scene, config, options, args.out);
  }
  progress.finish();
  std::printf("%4s %5s %7s %9s %10s  %s\n", "step", "event", "weight", "d_true[m]", "d_model[m]",
              "file");
  for (const view::ExportedState& s : result.states) {
    std::printf("%4d %5d %7.3f %9.4f %10.4f  %s\n", s.state.time_step, s.state.event,
                s.result.weight, s.result.d_true, s.result.d_model, s.glb.c_str());
  }
  const std::size_t states_total = core::states(scene).size();
  const std::string over = std::size_t(result.err_states) == states_total
                               ? "all " + std::to_string(states_total) + " states"
                               : "the " + std::to_string(result.err_states) + " exported of " +
                                     std::to_string(states_total) + " states";
  std::printf("Err = %.6f m² (%s pipeline, %s)\n%zu files in %s; open %s/index.html in a browser\n",
              result.err, args.pipeline.c_str(), over.c_str(), result.files.size(),
              args.out.c_str(), args.out.c_str());
}

}  // namespace

void register_export_command(CLI::App& app) {
  auto args = std::make_shared<ExportArgs>();
  CLI::App* cmd = app.add_subcommand(
      "export", "glTF scene per state, a 3D viewer page and camera poses, written to DIR");
  cmd->add_option("scene", args->scene, "scene JSON file")->required();
  cmd->add_option("--cameras", args->cameras,
                  "camera configuration JSON file (or an optimize run file)")
      ->required();
  cmd->add_option("--out", args->out, "output directory")->required();
  cmd->add_option("--pipeline", args->pipeline, "voxel or exact")
      ->check(CLI::IsMember(
          {core::name_of(core::Pipeline::voxel), core::name_of(core::Pipeline::exact)}));
  cmd->add_option("--mode", args->mode, "voxel labelling mode")->check(one_of<core::LabelMode>());
  cmd->add_option("--resolution", args->resolution,
                  "voxel resolution NXxNYxNZ (default: the scene's)");
  cmd->add_option("--refine", args->refine,
                  "conservative mode: refine the model L levels, as evaluate --refine (the model "
                  "is drawn as its finest cells)")
      ->check(in_range(0, voxel::kMaxRefine));
  cmd->add_option("--state", args->states,
                  "export only state H,L (time step, event); repeatable (default: every state)");
  cmd->add_option("--max-seconds", args->max_seconds,
                  "stop with exit status 1 when the command takes longer than S seconds (the "
                  "files written so far are kept; default 0: no limit)")
      ->check(in_range(0.0, 1e9, "must be a number of seconds in [0, 1e9] (0 = no limit)"));
  cmd->add_option("--threads", args->threads, "threads (default: one per core)")
      ->check(in_range(1, core::kMaxThreads));
  cmd->add_option("--three-dir", args->three_dir,
                  "directory of three.js (Debian's libjs-three) copied beside index.html");
  cmd->add_flag("--progress", args->progress,
                "progress of the exact pipeline on stderr also when it is not a terminal (on a "
                "terminal: always)");
  cmd->callback([args] { run_export(*args); });
}

}  // namespace camplace::app
