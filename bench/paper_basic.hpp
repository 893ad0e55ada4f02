#pragma once
// The benchmarks' scene: data/paper_basic.json and its corners configuration
// (data/paper_basic_corners.json), loaded once per program.
#include <string>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::bench {

inline const core::Scene& paper_scene() {
  static const core::Scene scene =
      core::load_scene(std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic.json");
  return scene;
}

inline const core::CameraConfig& corners() {
  static const core::CameraConfig config = core::load_camera_config(
      std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic_corners.json", paper_scene());
  return config;
}

}  // namespace camplace::bench
