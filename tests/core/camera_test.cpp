// Camera geometry of SPEC §1 and the camera-configuration file format.
#include "camplace/core/camera.hpp"

#include <gtest/gtest.h>

#include <random>

#include "camplace/core/error.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using core::Vec3;
constexpr double kPi = 3.14159265358979323846;

TEST(Camera, ViewDirectionAndUpVectorFollowTheConventions) {
  const auto c = camera_at({0, 0, 0}, 90, 0);
  EXPECT_TRUE(core::view_direction(c).isApprox(Vec3(0, 1, 0), 1e-12));
  EXPECT_TRUE(core::up_vector(c).isApprox(Vec3(0, 0, 1), 1e-12));
  const auto down = camera_at({0, 0, 0}, 0, -90);
  EXPECT_TRUE(core::view_direction(down).isApprox(Vec3(0, 0, -1), 1e-12));
  EXPECT_TRUE(core::up_vector(down).isApprox(Vec3(0, 1, 0), 1e-12));  // world y when vertical
  const auto tilted = camera_at({0, 0, 0}, 0, -45);
  EXPECT_TRUE(core::up_vector(tilted).isApprox(Vec3(std::sqrt(0.5), 0, std::sqrt(0.5)), 1e-12));
}

TEST(Camera, PyramidEdgesLieOnTheConeAndFirstPointsUp) {
  const auto c = camera_at({1, 2, 3}, 30, -20);
  const core::Fov fov(c, core::FovShape::pyramid, 25 * kPi / 180, 6, std::nullopt);
  ASSERT_EQ(fov.pyramid_edges().size(), 6u);
  for (const Vec3& e : fov.pyramid_edges()) {
    EXPECT_NEAR(std::acos(e.dot(core::view_direction(c))), 25 * kPi / 180, 1e-12);
  }
  const Vec3 first = fov.pyramid_edges()[0] - core::view_direction(c) * std::cos(25 * kPi / 180);
  EXPECT_NEAR(first.normalized().dot(core::up_vector(c)), 1.0, 1e-12);
}

TEST(Camera, PyramidNeverSeesMoreThanTheCone) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-3, 3);
  const auto c = camera_at({0, 0, 0}, 10, 5);
  const core::Fov cone(c, core::FovShape::cone, 0.5, 5, std::nullopt);
  const core::Fov pyramid(c, core::FovShape::pyramid, 0.5, 5, std::nullopt);
  int inside = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    if (pyramid.contains(p)) {
      ++inside;
      EXPECT_TRUE(cone.contains(p));
    }
  }
  EXPECT_GT(inside, 100);
}

TEST(Camera, BallTestIsSufficientForContainment) {
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(-3, 3), unit(0, 1);
  for (auto shape : {core::FovShape::cone, core::FovShape::pyramid}) {
    const core::Fov fov(camera_at({0, 0, 0}, 0, 0), shape, 0.6, 7, 2.0);
    int balls = 0;
    for (int i = 0; i < 5000; ++i) {
      const Vec3 center(u(rng), u(rng), u(rng));
      const double r = 0.3 * unit(rng);
      if (!fov.contains_ball(center, r)) continue;
      ++balls;
      for (int k = 0; k < 20; ++k) {
        const Vec3 dir = Vec3(u(rng), u(rng), u(rng)).normalized();
        EXPECT_TRUE(fov.contains(center + r * dir));
      }
    }
    EXPECT_GT(balls, 10);
  }
}

TEST(Camera, ConfigFileRoundTripsAndCountIsChecked) {
  core::Scene scene = simple_scene({Vec3(0, 0, 0), Vec3(4, 3, 3)}, {4, 3, 3}, 2, 30, {}, {});
  scene.file = "scene.json";
  const core::CameraConfig config = {camera_at({1, 1, 2.5}, 180, -90),
                                     camera_at({3, 2, 1}, -45.5, 12.25)};
  const std::string dir = temp_dir("camera");
  const std::string path = write_file(dir + "/cams.json", core::camera_config_json(config));
  const core::CameraConfig back = core::load_camera_config(path, scene);
  ASSERT_EQ(back.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(back[i].position, config[i].position);
    EXPECT_NEAR(back[i].yaw, config[i].yaw, 1e-15);
    EXPECT_NEAR(back[i].pitch, config[i].pitch, 1e-15);
  }
  scene.cameras.count = 3;
  try {
    core::load_camera_config(path, scene);
    FAIL() << "count mismatch accepted";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.entry(), "/cameras");
    EXPECT_NE(e.reason().find("holds 2 cameras"), std::string::npos);
  }
  const std::string bad = write_file(
      dir + "/bad.json",
      R"({"cameras": [{"position": [1,1,1], "yaw_deg": 0, "pitch_deg": 95}, {"position": [1,1,1], "yaw_deg": 0, "pitch_deg": 0}]})");
  scene.cameras.count = 2;
  try {
    core::load_camera_config(bad, scene);
    FAIL() << "pitch 95 accepted";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.entry(), "/cameras/0/pitch_deg");
  }
}

}  // namespace
}  // namespace camplace::testing
