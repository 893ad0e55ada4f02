#pragma once
// The scene as every command loads it: validated by core::load_scene, and every mesh the loader
// repaired named on stderr (an enclosing repair is conservative for targets and critical
// objects but changes what an obstacle occludes; the user must see it).
#include <string>

#include "camplace/core/scene.hpp"

namespace camplace::app {

/// core::load_scene(path), then one "warning: ..." line on stderr per repaired mesh
/// (core::repair_warnings).
core::Scene load_scene_and_report(const std::string& path);

}  // namespace camplace::app
