#include "scene_input.hpp"

#include <cstdio>
#include <optional>

#include "camplace/jobs/interrupt.hpp"

namespace camplace::app {

core::Scene load_scene_and_report(const std::string& path) {
  std::optional<core::Scene> scene;
  {
    // Loading cannot stop half-way (mesh files, repairs, the keep-out check): a signal, or the
    // command's --max-seconds, ends the process within a second; nothing is written yet.
    std::optional<jobs::StopAtOnce> at_once;
    if (!jobs::StopAtOnce::active()) at_once.emplace(jobs::StopAtOnce::Options{});
    scene.emplace(core::load_scene(path));
  }
  for (const std::string& line : core::repair_warnings(*scene))
    std::fprintf(stderr, "warning: %s\n", line.c_str());
  return std::move(*scene);
}

}  // namespace camplace::app
