// `camplace serve`: a local web planner (docs/serve.md). Thin: parse, set up the planner and the
// server, print the URL, serve until a signal.
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "camplace/core/camera.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/threads.hpp"
#include "camplace/jobs/interrupt.hpp"
#include "camplace/optimize/encoding.hpp"
#include "camplace/serve/planner.hpp"
#include "camplace/serve/server.hpp"
#include "cli_checks.hpp"
#include "commands.hpp"
#include "memory_estimate.hpp"
#include "scene_input.hpp"

namespace camplace::app {

namespace {

struct ServeArgs {
  std::string scene, cameras, mode = "conservative", resolution, host = "127.0.0.1",
                              out = "camplace-serve", three_dir = serve::kThreeDir;
  int port = 8765, refine = 0, threads = 0;
};

void run_serve(const ServeArgs& args) {
  const jobs::InterruptSignals signals;
  const core::Scene scene = load_scene_and_report(args.scene);
  const core::CameraConfig start = args.cameras.empty()
                                       ? optimize::corner_start(scene)
                                       : core::load_camera_config(args.cameras, scene);
  serve::PlannerOptions options;
  options.voxel.mode = parse_enum<core::LabelMode>(args.mode);
  if (!args.resolution.empty()) {
    options.voxel.resolution = core::parse_resolution(args.resolution, "--resolution");
  }
  options.voxel.refine = args.refine;
  options.voxel.threads = args.threads > 0 ? args.threads : core::machine_cores();
  options.scene_file = args.scene;
  options.cameras_file = args.cameras;
  options.out_dir = args.out;
  const std::string resolution_option =
      args.resolution.empty() ? "the scene's voxels" : "--resolution";
  const VoxelWork work =
      voxel_work(scene, options.voxel.resolution, args.refine, options.voxel.threads, true);
  jobs::set_work_description("serve " + resolution_option + " " + std::to_string(work.n[0]) + "x" +
                             std::to_string(work.n[1]) + "x" + std::to_string(work.n[2]) +
                             " with " + std::to_string(work.cameras) + " cameras");
  check_memory(work, resolution_option);
  core::create_output_directory(args.out, "--out");
  serve::Planner planner(scene, start, options);

  serve::ServerOptions server_options;
  server_options.host = args.host;
  server_options.port = args.port;
  server_options.three_dir = args.three_dir;
  serve::Server server(planner, server_options);
  if (args.host != "127.0.0.1" && args.host != "localhost" && args.host != "::1") {
    std::fprintf(stderr,
                 "warning: --host %s: the planner is reachable from other machines; anyone who "
                 "has the URL (it holds the token) can move the cameras and write into %s\n",
                 args.host.c_str(), args.out.c_str());
  }
  std::printf("camplace serve: %s, %zu cameras, %s mode, %dx%dx%d voxels\n", args.scene.c_str(),
              start.size(), args.mode.c_str(), work.n[0], work.n[1], work.n[2]);
  std::printf("open %s\n", server.url().c_str());
  std::printf("saves go to %s/; Ctrl-C stops the server\n", args.out.c_str());
  std::fflush(stdout);
  server.run(jobs::InterruptSignals::flag());
  const std::string unsaved = planner.save_unsaved();
  if (unsaved.empty()) {
    std::printf("camplace serve stopped; no unsaved changes\n");
  } else {
    std::printf("camplace serve stopped; the unsaved configuration is in %s\n", unsaved.c_str());
  }
}

}  // namespace

void register_serve_command(CLI::App& app) {
  auto args = std::make_shared<ServeArgs>();
  CLI::App* cmd = app.add_subcommand("serve", "a local web planner: move cameras, see Err live");
  cmd->footer(
      "Prints the URL to open (with a random token every request must carry). Listens on\n"
      "127.0.0.1 unless --host says otherwise. Ctrl-C or SIGTERM stop it; a configuration\n"
      "changed since it was loaded or saved is then written to --out as unsaved-<time>.json.\n"
      "docs/serve.md describes the page and its API.");
  cmd->add_option("scene", args->scene, "scene JSON file")->required();
  cmd->add_option("--cameras", args->cameras,
                  "start configuration: a camera file or run file (default: cameras high in the "
                  "corners)");
  cmd->add_option("--port", args->port, "TCP port (0 = any free port)")->check(in_range(0, 65535));
  cmd->add_option("--host", args->host,
                  "address to listen on (anything but 127.0.0.1 reaches other machines)");
  cmd->add_option("--mode", args->mode, "voxel labelling mode")->check(one_of<core::LabelMode>());
  cmd->add_option("--resolution", args->resolution,
                  "voxel resolution NXxNYxNZ (default: the scene's)");
  cmd->add_option("--refine", args->refine,
                  "conservative mode: refine the model's voxels L levels (default 0 = none)")
      ->check(in_range(0, voxel::kMaxRefine));
  cmd->add_option("--threads", args->threads, "threads of one evaluation (default: one per core)")
      ->check(in_range(1, core::kMaxThreads));
  cmd->add_option("--out", args->out, "folder for saved and unsaved configurations");
  cmd->add_option("--three-dir", args->three_dir, "directory of three.js (Debian's libjs-three)");
  cmd->callback([args] { run_serve(*args); });
}

}  // namespace camplace::app
