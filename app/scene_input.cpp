#include "scene_input.hpp"

#include <cstdio>

namespace camplace::app {

core::Scene load_scene_and_report(const std::string& path) {
  core::Scene scene = core::load_scene(path);
  for (const std::string& line : core::repair_warnings(scene))
    std::fprintf(stderr, "warning: %s\n", line.c_str());
  return scene;
}

}  // namespace camplace::app
