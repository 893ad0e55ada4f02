// `camplace generate`: writes a scene of the paper's examinations (SPEC §9 table).
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "camplace/scenes/generator.hpp"
#include "commands.hpp"

namespace camplace::app {

namespace {

struct GenerateArgs {
  std::string family, out, base;
  int param = 0;
  unsigned seed = 1;
};

std::string families_help() {
  std::string text = "scene families (i = --param):";
  for (const scenes::SceneFamily& f : scenes::scene_families()) {
    text += "\n  " + f.name;
    if (f.has_param) {
      text += " (i = " + std::to_string(f.min_param) + ".." + std::to_string(f.max_param) + ")";
    }
    text += ": " + f.what + (f.random ? ", seeded" : "");
    if (!f.on_base.empty()) text += "\n      with --base: " + f.on_base;
  }
  return text;
}

}  // namespace

void register_generate_command(CLI::App& app) {
  auto args = std::make_shared<GenerateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "generate",
      "write a scene of the paper's examinations (SPEC §9), derived from the basic setup or from "
      "another scene (--base)");
  cmd->footer(families_help());
  cmd->add_option("family", args->family, "scene family (listed below)")->required();
  CLI::Option* param = cmd->add_option("--param", args->param, "the family's parameter i");
  cmd->add_option("--seed", args->seed, "seed of the random placements (default 1)");
  cmd->add_option("--base", args->base,
                  "scene file the family is applied to (default: the paper's basic setup, "
                  "data/paper_basic.json)");
  cmd->add_option("--out", args->out, "scene JSON file to write")->required();
  cmd->callback([args, param] {
    const std::optional<int> i =
        param->count() > 0 ? std::optional<int>(args->param) : std::nullopt;
    std::optional<scenes::BaseScene> base;
    if (!args->base.empty()) base = scenes::load_base_scene(args->base, args->base);
    const std::string description = scenes::write_generated_scene(
        args->family, i, args->seed, args->out, base ? &*base : nullptr);
    std::cout << "wrote " << args->out << ": " << description << "\n";
  });
}

}  // namespace camplace::app
