// Mounts and keep-out boxes in the optimizer: the decision vector holds (s, t)
// and the mount-relative angles, decoded cameras lie on their mounts, no run ends in a keep-out
// box, start files off their mounts are refused.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "camplace/core/camera.hpp"
#include "camplace/core/error.hpp"
#include "camplace/optimize/encoding.hpp"
#include "camplace/optimize/optimizer.hpp"
#include "camplace/optimize/voxel_objective.hpp"
#include "test_scene.hpp"

namespace camplace::optimize {
namespace {

using nlohmann::json;
constexpr double kDeg = M_PI / 180.0;

using testing::temp_path;

json two_mounts() {
  return json::parse(R"({
    "mounts": [
      {"name": "ceiling", "corner": [0, 0, 2.5], "edges": [[0, 3, 0], [3, 0, 0]],
       "pitch_deg": [-20, 20], "yaw_deg": [-30, 30]},
      {"name": "wall", "corner": [0, 3, 1], "edges": [[3, 0, 0], [0, 0, 1.5]]}
    ],
    "camera_domains": [{"mount": "ceiling"}, {"mount": "wall"}, null]
  })");
}

TEST(MountEncoding, DecisionVectorHoldsSurfaceCoordinatesAndRelativeAngles) {
  const core::Scene scene = testing::small_scene_with(two_mounts());
  const Encoding encoding(scene);
  // Cones: s, t, yaw', pitch' on each mount, 5 variables for the room camera.
  ASSERT_EQ(encoding.dimension(), 4u + 4u + 5u);
  EXPECT_EQ(encoding.variables()[0].component, Component::s);
  EXPECT_EQ(encoding.variables()[1].component, Component::t);
  EXPECT_EQ(encoding.variables()[2].component, Component::yaw);
  EXPECT_NEAR(encoding.variables()[2].hi, 30 * kDeg, 1e-12);
  EXPECT_NEAR(encoding.variables()[3].lo, -20 * kDeg, 1e-12);
  const auto [lo, hi] = encoding.bounds();
  std::mt19937 rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<double> x(lo.size());
    for (std::size_t k = 0; k < x.size(); ++k)
      x[k] = std::uniform_real_distribution<double>(lo[k], hi[k])(rng);
    const core::CameraConfig config = encoding.decode(x);
    // Camera 0 on the ceiling at (x, y) = (t·3, s·3), looking down within 20°/30° of vertical.
    EXPECT_DOUBLE_EQ(config[0].position.z(), 2.5);
    EXPECT_NEAR(config[0].position.y(), 3 * x[0], 1e-12);
    EXPECT_NEAR(config[0].position.x(), 3 * x[1], 1e-12);
    const core::Vec3 d0 = core::view_direction(config[0]);
    EXPECT_NEAR(d0.z(), -std::cos(x[2]) * std::cos(x[3]), 1e-9);
    // Camera 1 on the wall y = 3, z ∈ [1, 2.5], looking into the room (−y).
    EXPECT_DOUBLE_EQ(config[1].position.y(), 3.0);
    EXPECT_GE(config[1].position.z(), 1.0);
    EXPECT_LE(config[1].position.z(), 2.5);
    EXPECT_LE(core::view_direction(config[1]).y(), 1e-12);
    // encode ∘ decode is the identity on the vector.
    const std::vector<double> back = encoding.encode(config);
    for (std::size_t k = 0; k < x.size(); ++k) EXPECT_NEAR(back[k], x[k], 1e-9) << k;
  }
}

TEST(MountEncoding, CornerStartLiesOnTheMounts) {
  const core::Scene scene = testing::small_scene_with(two_mounts());
  const core::CameraConfig c = corner_start(scene);
  EXPECT_DOUBLE_EQ(c[0].position.z(), 2.5);
  EXPECT_DOUBLE_EQ(c[1].position.y(), 3.0);
  const auto [yaw, pitch] =
      scene.cameras.domains[0].mount->relative_angles(core::view_direction(c[0]));
  EXPECT_LE(std::abs(yaw), 30 * kDeg + 1e-9);
  EXPECT_LE(std::abs(pitch), 20 * kDeg + 1e-9);
}

TEST(MountEncoding, StartFilesOffTheirMountsOrInKeepOutAreRefused) {
  json cams = two_mounts();
  cams["keep_out"] = json::parse(R"([{"name": "reach", "min": [0, 0, 0], "max": [1, 1, 2]}])");
  const core::Scene scene = testing::small_scene_with(cams);
  VoxelObjective objective(scene, {});
  const auto run_from = [&](const core::CameraConfig& config, const std::string& name) {
    const std::string path = temp_path(name + ".json");
    std::ofstream(path) << core::camera_config_json(config);
    return path;
  };
  const core::CameraConfig good = corner_start(scene);
  const auto expect_refused = [&](core::CameraConfig config, const std::string& name,
                                  const std::string& entry, const std::string& reason) {
    const std::string path = run_from(config, name);
    OptimizeOptions o;
    o.max_evaluations = 20;
    o.threads = 1;
    o.start.kind = StartKind::file;
    o.start.file = path;
    try {
      optimize(scene, objective, o);
      ADD_FAILURE() << "accepted " << name;
    } catch (const core::InputError& e) {
      EXPECT_EQ(e.file(), path);
      EXPECT_EQ(e.entry(), entry) << e.what();
      EXPECT_NE(e.reason().find(reason), std::string::npos) << e.what();
    }
    std::filesystem::remove(path);
  };
  core::CameraConfig below = good;
  below[0].position.z() = 2.4;  // 10 cm below the ceiling mount
  expect_refused(below, "below", "/cameras/0/position", "off mount \"ceiling\"");
  core::CameraConfig up = good;
  up[1].pitch = 0.0;
  up[1].yaw = M_PI / 2;  // looks out of the wall (+y)
  expect_refused(up, "out", "/cameras/1", "outside the ranges of mount \"wall\"");
  core::CameraConfig inside = good;
  inside[2].position = core::Vec3(0.5, 0.5, 1.0);
  expect_refused(inside, "keep-out", "/cameras/2/position", "keep-out box \"reach\"");
  // The corner start itself is accepted.
  const std::string path = run_from(good, "good");
  OptimizeOptions o;
  o.max_evaluations = 20;
  o.threads = 1;
  o.start.kind = StartKind::file;
  o.start.file = path;
  EXPECT_NO_THROW(optimize(scene, objective, o));
  std::filesystem::remove(path);
}

// Most of the room is keep-out: every decoded configuration and the run's result stay out.
TEST(KeepOutRun, NoCameraEndsInAKeepOutBox) {
  const json cams = json::parse(R"({
    "keep_out": [{"name": "big", "min": [-1, -1, -1], "max": [2.7, 4, 2.2]},
                 {"name": "top", "min": [0.5, 0.5, 2.0], "max": [2.9, 2.9, 3]}]
  })");
  const core::Scene scene = testing::small_scene_with(cams);
  const Encoding encoding(scene);
  const auto [lo, hi] = encoding.bounds();
  std::mt19937 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> x(lo.size());
    for (std::size_t k = 0; k < x.size(); ++k)
      x[k] = std::uniform_real_distribution<double>(lo[k], hi[k])(rng);
    for (const core::CameraSetting& c : encoding.decode(x)) {
      for (const core::KeepOut& k : scene.cameras.keep_out) {
        EXPECT_FALSE(k.contains(c.position)) << c.position.transpose();
      }
    }
  }
  VoxelObjective objective(scene, {});
  for (unsigned seed : {1u, 2u}) {
    OptimizeOptions o;
    o.algorithm = "pso";
    o.max_evaluations = 300;
    o.seed = seed;
    o.threads = 2;
    o.tolerance = 0.0;
    const RunResult r = optimize(scene, objective, o);
    for (const core::CameraSetting& c : r.best) {
      for (const core::KeepOut& k : scene.cameras.keep_out) {
        EXPECT_FALSE(k.contains(c.position)) << c.position.transpose();
      }
    }
  }
}

}  // namespace
}  // namespace camplace::optimize
