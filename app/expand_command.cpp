// `camplace expand`: the scene with its robots (URDF and trajectory) and its people model written
// out as plain objects and events, so that what the other commands compute on can be read,
// diffed and reused (loading the written file gives the same scene).
#include <iostream>
#include <memory>
#include <string>

#include "camplace/core/provenance.hpp"
#include "camplace/core/scene_writer.hpp"
#include "commands.hpp"
#include "scene_input.hpp"

namespace camplace::app {

namespace {

struct ExpandArgs {
  std::string scene, out;
};

void run_expand(const ExpandArgs& args) {
  const core::Scene scene = load_scene_and_report(args.scene);
  const core::Provenance provenance = core::make_provenance(scene);
  std::size_t states = 0, objects = scene.static_obstacles.size();
  for (const core::TimeStep& step : scene.time_steps) {
    states += step.events.size();
    objects += step.dynamic_obstacles.size();
    for (const core::Event& e : step.events) objects += e.targets.size();
  }
  const std::string description =
      "Expanded by camplace " + provenance.build.version + " (commit " + provenance.build.commit +
      ") from " + args.scene + " (content sha256 " + provenance.scene.combined + ", " +
      std::to_string(scene.mesh_files.size()) +
      " files read): robots, people and mesh files written out as inline objects and events.";
  core::write_scene(scene, args.out, description);
  std::cout << "wrote " << args.out << ": " << scene.time_steps.size() << " time steps, " << states
            << " states, " << objects << " objects";
  if (!scene.repairs.empty()) std::cout << ", " << scene.repairs.size() << " meshes repaired";
  std::cout << "\n";
}

}  // namespace

void register_expand_command(CLI::App& app) {
  auto args = std::make_shared<ExpandArgs>();
  CLI::App* cmd = app.add_subcommand(
      "expand",
      "write the scene with its robots (URDF, trajectory), people model, mesh files and repairs "
      "expanded into plain inline objects and events (loading it gives the same scene)");
  cmd->add_option("scene", args->scene, "scene JSON file (docs/scene-format.md)")->required();
  cmd->add_option("--out", args->out, "scene JSON file to write")->required();
  cmd->callback([args] { run_expand(*args); });
}

}  // namespace camplace::app
