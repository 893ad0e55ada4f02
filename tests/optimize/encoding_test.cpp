#include "camplace/optimize/encoding.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test_scene.hpp"

namespace camplace::optimize {
namespace {

using testing::small_scene;

TEST(Encoding, RoomDomainHasAllFiveVariablesPerCamera) {
  const core::Scene scene = small_scene();
  const Encoding encoding(scene);
  EXPECT_EQ(encoding.dimension(), 15u);
  const auto [lo, hi] = encoding.bounds();
  EXPECT_DOUBLE_EQ(lo[2], 0.0);  // camera 0 z
  EXPECT_DOUBLE_EQ(hi[2], 2.5);
  EXPECT_NEAR(hi[3], M_PI, 1e-12);  // camera 0 yaw
}

TEST(Encoding, CeilingRemovesZFromTheDecisionVector) {
  const core::Scene scene = small_scene("\"ceiling\"");
  const Encoding encoding(scene);
  ASSERT_EQ(encoding.dimension(), 12u);  // 4 free variables per camera, no zero-width bounds
  for (const Variable& v : encoding.variables()) {
    EXPECT_NE(v.component, Component::z);
    EXPECT_LT(v.lo, v.hi);
  }
  // Every decoded configuration sits at S's top, whatever the vector.
  const auto [lo, hi] = encoding.bounds();
  for (const auto& x : {lo, hi}) {
    for (const core::CameraSetting& c : encoding.decode(x)) EXPECT_EQ(c.position.z(), 2.5);
  }
}

TEST(Encoding, ExplicitFixedYawIsRemovedAndKept) {
  const core::Scene scene = small_scene(R"({"preset": "room", "yaw_deg": [45, 45]})");
  const Encoding encoding(scene);
  ASSERT_EQ(encoding.dimension(), 12u);
  const auto [lo, hi] = encoding.bounds();
  for (const core::CameraSetting& c : encoding.decode(hi)) {
    EXPECT_NEAR(c.yaw, M_PI / 4, 1e-12);
  }
}

// Roll is a variable only where the domain frees it and the model is not a cone.
TEST(Encoding, RollIsFreeOnlyForFreedNonConeCameras) {
  const std::string roll = R"({"preset": "room", "roll_deg": [-30, 60]})";
  // The small scene's cameras are cones: the roll domain changes nothing, roll stays 0.
  const core::Scene cones = small_scene(roll);
  const Encoding cone_encoding(cones);
  EXPECT_EQ(cone_encoding.dimension(), 15u);
  for (const core::CameraSetting& c : cone_encoding.decode(cone_encoding.bounds().second)) {
    EXPECT_EQ(c.roll, 0.0);
  }
  // Frusta: 6 variables per camera, roll within [−30°, 60°].
  core::Scene frusta = cones;
  for (core::CameraModel& m : frusta.cameras.models) {
    m.fov = core::FovShape::frustum;
    m.horizontal = M_PI / 2;
    m.vertical = M_PI / 3;
  }
  const Encoding encoding(frusta);
  ASSERT_EQ(encoding.dimension(), 18u);
  EXPECT_EQ(encoding.variables()[5].component, Component::roll);
  EXPECT_NEAR(encoding.variables()[5].lo, -M_PI / 6, 1e-12);
  EXPECT_NEAR(encoding.variables()[5].hi, M_PI / 3, 1e-12);
  core::CameraConfig config(3);
  config[1].roll = 0.5;
  config[2].roll = 2.0;  // beyond 60°: clamped
  const core::CameraConfig back = encoding.decode(encoding.encode(config));
  EXPECT_EQ(back[0].roll, 0.0);
  EXPECT_EQ(back[1].roll, 0.5);
  EXPECT_NEAR(back[2].roll, M_PI / 3, 1e-12);
  // Without roll_deg a frustum's roll is fixed at 0 and leaves the vector.
  core::Scene fixed = frusta;
  for (core::CameraDomain& d : fixed.cameras.domains) d.roll = {0.0, 0.0};
  EXPECT_EQ(Encoding(fixed).dimension(), 15u);
}

TEST(Encoding, EncodeClampsIntoTheDomainAndDecodeInverts) {
  const core::Scene scene = small_scene();
  const Encoding encoding(scene);
  core::CameraConfig config(3);
  config[0].position = core::Vec3(1.0, 2.0, 0.5);
  config[0].yaw = 0.3;
  config[0].pitch = -0.2;
  config[1].position = core::Vec3(-5.0, 9.0, 1.0);  // outside S: clamped to its faces
  config[2].position = core::Vec3(1.5, 1.5, 1.5);
  const core::CameraConfig back = encoding.decode(encoding.encode(config));
  EXPECT_EQ(back[0].position, config[0].position);
  EXPECT_EQ(back[0].yaw, 0.3);
  EXPECT_EQ(back[0].pitch, -0.2);
  EXPECT_EQ(back[1].position, core::Vec3(0.0, 3.0, 1.0));
}

TEST(CornerStart, CamerasSitHighInTheCornersAndLookAtTheCentre) {
  const core::Scene scene = small_scene();
  const core::CameraConfig config = corner_start(scene);
  ASSERT_EQ(config.size(), 3u);
  EXPECT_EQ(config[0].position, core::Vec3(0, 0, 2.5));
  EXPECT_EQ(config[1].position, core::Vec3(3, 3, 2.5));  // diagonal opposite first
  EXPECT_EQ(config[2].position, core::Vec3(0, 3, 2.5));
  const core::Vec3 centre(1.5, 1.5, 1.25);
  for (const core::CameraSetting& c : config) {
    const core::Vec3 to_centre = (centre - c.position).normalized();
    EXPECT_NEAR(core::view_direction(c).dot(to_centre), 1.0, 1e-12);
  }
}

TEST(CornerStart, ClampsIntoACeilingDomain) {
  // Ceiling: z is fixed at the top anyway; an explicit lower region forces clamping.
  const core::Scene scene = small_scene(R"({"preset": "room", "z": [0.5, 1.0]})");
  for (const core::CameraSetting& c : corner_start(scene)) {
    EXPECT_EQ(c.position.z(), 1.0);
    EXPECT_GT(c.pitch, -M_PI / 2);
  }
}

}  // namespace
}  // namespace camplace::optimize
