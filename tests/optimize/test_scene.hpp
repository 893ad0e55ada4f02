#pragma once
// A small scene for the optimizer tests: S = 3 × 3 × 2.5 m at 9 × 9 × 8 voxels, 3 cameras, one
// robot box and a person box in two events; the plausibility filter (min height 1.4 m) drops
// model parts around the robot that could not be a person, as in data/paper_basic.json. Written to
// a temporary file and loaded through core::load_scene, so the tests see exactly what the command
// line sees.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "camplace/core/scene.hpp"

namespace camplace::optimize::testing {

inline std::string small_scene_json(const std::string& domain) {
  return R"({
  "area": {"min": [0, 0, 0], "max": [3, 3, 2.5]},
  "voxels": [9, 9, 8],
  "cameras": {"count": 3, "half_angle_deg": 30, "fov": "cone", "domain": )" +
         domain + R"(},
  "plausibility": {"min_volume": 0.01, "min_height": 1.4},
  "static_obstacles": [{"name": "table", "box": {"min": [2.2, 0.3, 0], "max": [2.8, 0.9, 0.8]}}],
  "time_steps": [{
    "t": 0,
    "dynamic_obstacles": [{"name": "robot", "box": {"min": [0.3, 0.3, 0], "max": [0.9, 0.9, 1.2]}}],
    "events": [
      {"weight": 1.0, "targets": [{"name": "person A", "box": {"min": [1.8, 1.8, 0], "max": [2.3, 2.3, 1.7]}}]},
      {"weight": 0.5, "targets": [{"name": "person B", "box": {"min": [0.4, 1.9, 0], "max": [0.9, 2.4, 1.7]}}]}
    ]
  }]
})";
}

/// A path in the temporary directory named after this process and `name`.
inline std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("camplace-optimize-test-" + std::to_string(::getpid()) + "-" + name))
      .string();
}

/// Writes the scene text to a temporary file and loads it.
inline core::Scene load_scene_text(const std::string& text) {
  static int counter = 0;
  const std::string path = temp_path("scene-" + std::to_string(counter++) + ".json");
  std::ofstream(path) << text;
  core::Scene scene = core::load_scene(path);
  std::filesystem::remove(path);
  return scene;
}

/// Writes the small scene with the given domain (a JSON value, e.g. "\"room\"") and loads it.
inline core::Scene small_scene(const std::string& domain = "\"room\"") {
  return load_scene_text(small_scene_json(domain));
}

/// The small scene (domain "room") with `cameras` merged into its cameras block, loaded.
inline core::Scene small_scene_with(const nlohmann::json& cameras) {
  nlohmann::json s = nlohmann::json::parse(small_scene_json("\"room\""));
  s["cameras"].update(cameras);
  return load_scene_text(s.dump(1));
}

}  // namespace camplace::optimize::testing
