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

// The image's right vector, d × up (so d = up × right).
Vec3 right_of(const core::CameraSetting& c) {
  return core::view_direction(c).cross(core::up_vector(c)).normalized();
}

core::CameraModel frustum_model(double h_deg, double v_deg, double near,
                                std::optional<double> far) {
  core::CameraModel m;
  m.name = "rgb";
  m.fov = core::FovShape::frustum;
  m.horizontal = h_deg * kPi / 180;
  m.vertical = v_deg * kPi / 180;
  m.near = near;
  m.range = far;
  return m;
}

// A 90° × 60° frustum, near 0.5, far 5, at the origin looking along +x (yaw 0, pitch 0): up is
// +z, right is d × up = x × z = −y. At depth 2 the image rectangle has half-widths
// 2·tan 45° = 2 (along right) and 2·tan 30° = 1.1547 (along up).
TEST(Camera, FrustumEdgesAndDepthPlanesWithoutRoll) {
  const auto c = camera_at({0, 0, 0}, 0, 0);
  EXPECT_TRUE(right_of(c).isApprox(Vec3(0, -1, 0), 1e-12));
  const core::Fov fov(c, frustum_model(90, 60, 0.5, 5.0));
  EXPECT_FALSE(fov.is_cone());
  ASSERT_EQ(fov.pyramid_edges().size(), 4u);
  // Right edge (y = −2 at depth 2), left (y = +2), up (z = +1.1547), down (z = −1.1547).
  EXPECT_TRUE(fov.contains({2, -1.99, 0}));
  EXPECT_FALSE(fov.contains({2, -2.01, 0}));
  EXPECT_TRUE(fov.contains({2, 1.99, 0}));
  EXPECT_FALSE(fov.contains({2, 2.01, 0}));
  EXPECT_TRUE(fov.contains({2, 0, 1.15}));
  EXPECT_FALSE(fov.contains({2, 0, 1.16}));
  EXPECT_TRUE(fov.contains({2, 0, -1.15}));
  EXPECT_FALSE(fov.contains({2, 0, -1.16}));
  // A corner: (2, −1.99, 1.15) in, the same beyond either edge out.
  EXPECT_TRUE(fov.contains({2, -1.99, 1.15}));
  EXPECT_FALSE(fov.contains({2, -2.01, 1.15}));
  EXPECT_FALSE(fov.contains({2, -1.99, 1.16}));
  // Near plane x = 0.5, far plane x = 5.
  EXPECT_TRUE(fov.contains({0.51, 0, 0}));
  EXPECT_FALSE(fov.contains({0.49, 0, 0}));
  EXPECT_TRUE(fov.contains({4.99, 0, 0}));
  EXPECT_FALSE(fov.contains({5.01, 0, 0}));
  EXPECT_FALSE(fov.contains({-2, 0, 0}));  // behind
  // The corner edges point at (1, ∓1, ±tan 30°)/|…| (up-right first: right is −y).
  const double n = std::sqrt(2.0 + 1.0 / 3.0);
  EXPECT_TRUE(fov.pyramid_edges()[0].isApprox(Vec3(1, -1, std::sqrt(1.0 / 3.0)) / n, 1e-12));
  EXPECT_TRUE(fov.pyramid_edges()[2].isApprox(Vec3(1, 1, -std::sqrt(1.0 / 3.0)) / n, 1e-12));
}

// The same frustum rolled by 30°. Roll turns the image about d = +x by the right-hand rule:
// up = cos 30°·z + sin 30°·(−y) = (0, −0.5, 0.866025), right = cos 30°·(−y) − sin 30°·z =
// (0, −0.866025, −0.5). A point at depth 2 with image coordinates (s along right, t along up)
// is (2, 0, 0) + s·right + t·up, inside when |s| ≤ 2 and |t| ≤ 1.1547.
TEST(Camera, FrustumEdgesWithRoll30) {
  auto c = camera_at({0, 0, 0}, 0, 0);
  c.roll = 30 * kPi / 180;
  const Vec3 up(0, -0.5, std::sqrt(3.0) / 2), right(0, -std::sqrt(3.0) / 2, -0.5);
  EXPECT_TRUE(core::up_vector(c).isApprox(up, 1e-12));
  EXPECT_TRUE(right_of(c).isApprox(right, 1e-12));
  const core::Fov fov(c, frustum_model(90, 60, 0.5, 5.0));
  // s = ±1.99 in, ±2.01 out: (2, −1.723390, −0.995), (2, −1.740711, −1.005) and mirrored.
  EXPECT_TRUE(fov.contains({2, -1.723390, -0.995}));
  EXPECT_FALSE(fov.contains({2, -1.740711, -1.005}));
  EXPECT_TRUE(fov.contains({2, 1.723390, 0.995}));
  EXPECT_FALSE(fov.contains({2, 1.740711, 1.005}));
  // t = ±1.15 in, ±1.16 out: (2, −0.575, 0.995929), (2, −0.58, 1.004589) and mirrored.
  EXPECT_TRUE(fov.contains({2, -0.575, 0.995929}));
  EXPECT_FALSE(fov.contains({2, -0.58, 1.004589}));
  EXPECT_TRUE(fov.contains({2, 0.575, -0.995929}));
  EXPECT_FALSE(fov.contains({2, 0.58, -1.004589}));
  // (2, 0, 1.3): outside without roll (1.3 > 1.1547), inside rolled: s = −0.65, t = 1.125833.
  EXPECT_TRUE(fov.contains({2, 0, 1.3}));
  EXPECT_FALSE(
      core::Fov(camera_at({0, 0, 0}, 0, 0), frustum_model(90, 60, 0.5, 5.0)).contains({2, 0, 1.3}));
  // Near and far planes do not turn with the roll.
  EXPECT_TRUE(fov.contains({0.51, 0, 0}));
  EXPECT_FALSE(fov.contains({0.49, 0, 0}));
  EXPECT_TRUE(fov.contains({4.99, 0, 0}));
  EXPECT_FALSE(fov.contains({5.01, 0, 0}));
}

// A wide frustum (179° × 120°) still has finite edges in front of the camera, and its bounding
// cone holds it.
TEST(Camera, WideFrustumAndItsBoundingCone) {
  const core::CameraModel m = frustum_model(179, 120, 0, std::nullopt);
  const auto c = camera_at({0, 0, 0}, 20, -10);
  const core::Fov fov(c, m);
  const core::Fov cone(c, core::FovShape::cone, m.bounding_half_angle(), 16, std::nullopt);
  for (const Vec3& e : fov.pyramid_edges()) EXPECT_GT(e.dot(fov.axis()), 0.0);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-3, 3);
  int inside = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    if (fov.contains(p)) {
      ++inside;
      EXPECT_TRUE(cone.contains(p));
    }
  }
  EXPECT_GT(inside, 1000);
}

TEST(Camera, ConfigFileRoundTripsAndCountIsChecked) {
  core::Scene scene = simple_scene({Vec3(0, 0, 0), Vec3(4, 3, 3)}, {4, 3, 3}, 2, 30, {}, {});
  scene.file = "scene.json";
  core::CameraConfig config = {camera_at({1, 1, 2.5}, 180, -90),
                               camera_at({3, 2, 1}, -45.5, 12.25)};
  config[1].roll = -33.5 * kPi / 180;
  const std::string dir = temp_dir("camera");
  const std::string path = write_file(dir + "/cams.json", core::camera_config_json(config));
  const core::CameraConfig back = core::load_camera_config(path, scene);
  ASSERT_EQ(back.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(back[i].position, config[i].position);
    EXPECT_NEAR(back[i].yaw, config[i].yaw, 1e-15);
    EXPECT_NEAR(back[i].pitch, config[i].pitch, 1e-15);
    EXPECT_NEAR(back[i].roll, config[i].roll, 1e-15);
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
  // roll_deg in [−180, 180]; a "model" must name the scene's model of that camera.
  const std::string roll = write_file(
      dir + "/roll.json",
      R"({"cameras": [{"position": [1,1,1], "yaw_deg": 0, "pitch_deg": 0, "roll_deg": 181}, {"position": [1,1,1], "yaw_deg": 0, "pitch_deg": 0}]})");
  try {
    core::load_camera_config(roll, scene);
    FAIL() << "roll 181 accepted";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.entry(), "/cameras/0/roll_deg");
  }
  for (auto& m : scene.cameras.models) m.name = "rgb";
  EXPECT_NE(core::camera_config_json(config, 2, &scene).find("\"model\": \"rgb\""),
            std::string::npos);
  const std::string named = write_file(
      dir + "/named.json",
      R"({"cameras": [{"model": "rgb", "position": [1,1,1], "yaw_deg": 0, "pitch_deg": 0}, {"model": "depth", "position": [1,1,1], "yaw_deg": 0, "pitch_deg": 0}]})");
  try {
    core::load_camera_config(named, scene);
    FAIL() << "wrong model accepted";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.entry(), "/cameras/1/model");
    EXPECT_NE(e.reason().find("\"rgb\" camera"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace camplace::testing
