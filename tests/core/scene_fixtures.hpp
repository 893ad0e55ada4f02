#pragma once
// Shared by the scene-loading tests: a small valid scene and the rejection check.
#include <gtest/gtest.h>

#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "camplace/core/error.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::testing {

/// A small valid scene: 4×3×3 m, 2 cameras, a static box, one robot link, one person box.
inline nlohmann::json base_scene() {
  return nlohmann::json::parse(R"({
    "area": {"min": [0, 0, 0], "max": [4, 3, 3]},
    "voxels": [8, 6, 6],
    "cameras": {"count": 2, "half_angle_deg": 30},
    "static_obstacles": [{"name": "table", "box": {"min": [0.2, 0.2, 0], "max": [1, 1, 0.8]}}],
    "time_steps": [{
      "dynamic_obstacles": [{"name": "link", "tetrahedron": [[3, 2, 0], [3.5, 2, 0], [3, 2.5, 0], [3.2, 2.2, 1]]}],
      "events": [{"weight": 1, "targets": [{"name": "person", "box": {"min": [2, 0.5, 0], "max": [2.4, 0.9, 1.8]}}]}]
    }]
  })");
}

/// Loads the scene at `path` and expects an InputError naming the file, this entry and a
/// reason containing `reason`.
inline void expect_rejected(const std::string& path, const std::string& entry,
                            const std::string& reason) {
  try {
    core::load_scene(path);
    ADD_FAILURE() << "accepted " << path << " (expected: " << entry << ": " << reason << ")";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.entry(), entry) << e.what();
    EXPECT_NE(e.reason().find(reason), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
  }
}

/// An inline mesh object {"mesh": {"vertices": v, "triangles": t}}.
inline nlohmann::json inline_mesh(const std::vector<std::array<double, 3>>& v,
                                  const std::vector<std::array<int, 3>>& t) {
  return {{"mesh", {{"vertices", v}, {"triangles", t}}}};
}

}  // namespace camplace::testing
