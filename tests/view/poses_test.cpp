// Camera poses against hand-computed frames: the ROS optical/body frames, the quaternion order
// and the OpenCV projection of known points.
#include "camplace/view/poses.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <random>

#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using core::Vec3;

void expect_near(const Eigen::Vector4d& a, const Eigen::Vector4d& b) {
  EXPECT_NEAR((a - b).norm(), 0.0, 1e-12) << a.transpose() << " vs " << b.transpose();
}

TEST(CameraPose, HorizontalCameraAlongX) {
  // Looking along +x, up = +z: right = −y. The optical frame is REP 103's standard rotation of
  // the body frame, quaternion (−0.5, 0.5, −0.5, 0.5); the body frame is the world frame.
  const view::CameraPose pose = view::camera_pose(camera_at({0, 0, 3}, 0, 0));
  expect_near(view::quaternion_xyzw(pose.optical), Eigen::Vector4d(-0.5, 0.5, -0.5, 0.5));
  expect_near(view::quaternion_xyzw(pose.body), Eigen::Vector4d(0, 0, 0, 1));
  // OpenCV: a point 5 m ahead is on the optical axis; 1 m to the right (−y) and 1 m up map to
  // x = +1 (right) and y = −1 (y points down).
  auto project = [&](const Vec3& p) -> Vec3 { return pose.opencv_r * p + pose.opencv_t; };
  EXPECT_NEAR((project({5, 0, 3}) - Vec3(0, 0, 5)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((project({5, -1, 4}) - Vec3(1, -1, 5)).norm(), 0.0, 1e-12);
}

TEST(CameraPose, DownwardCameraUsesWorldYAsUp) {
  // d = −z, u = +y (SPEC §1: world y when d is vertical), right = d × u = +x: the optical frame
  // is diag(1, −1, −1), a half turn about x.
  const view::CameraPose pose = view::camera_pose(camera_at({1, 1, 3}, 0, -90));
  expect_near(view::quaternion_xyzw(pose.optical), Eigen::Vector4d(1, 0, 0, 0));
  EXPECT_NEAR((pose.opencv_r * Vec3(1, 1, 0) + pose.opencv_t - Vec3(0, 0, 3)).norm(), 0.0, 1e-12);
}

TEST(CameraPose, QuaternionRotatesTheOpticalAxisOntoTheViewDirection) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> yaw(-180, 180), pitch(-90, 90);
  for (int n = 0; n < 200; ++n) {
    const core::CameraSetting camera = camera_at({1, 2, 3}, yaw(rng), pitch(rng));
    const view::CameraPose pose = view::camera_pose(camera);
    const Eigen::Vector4d q = view::quaternion_xyzw(pose.optical);
    const Eigen::Quaterniond quaternion(q[3], q[0], q[1], q[2]);  // Eigen's constructor: w first
    EXPECT_NEAR((quaternion * Vec3::UnitZ() - core::view_direction(camera)).norm(), 0, 1e-12);
    EXPECT_NEAR((quaternion * Vec3::UnitY() + core::up_vector(camera)).norm(), 0, 1e-12);
    EXPECT_NEAR(pose.optical.determinant(), 1.0, 1e-12);
    EXPECT_NEAR((pose.opencv_r * camera.position + pose.opencv_t).norm(), 0.0, 1e-12);
    EXPECT_GE(q[3], 0.0);
  }
}

TEST(CameraPose, PoseFilesNameTheConventionsAndHoldEveryCamera) {
  const core::CameraConfig config{camera_at({0, 0, 3}, 0, 0), camera_at({4, 3, 3}, -143.13, -35)};
  const auto j = nlohmann::json::parse(view::poses_json(config));
  EXPECT_EQ(j["conventions"]["quaternion_order"], "x, y, z, w (Hamilton, unit, w >= 0)");
  ASSERT_EQ(j["cameras"].size(), 2u);
  EXPECT_EQ(j["cameras"][0]["optical_frame"]["quaternion_xyzw"],
            nlohmann::json({-0.5, 0.5, -0.5, 0.5}));
  EXPECT_EQ(j["cameras"][1]["position"], nlohmann::json({4.0, 3.0, 3.0}));
  const std::string yaml = view::poses_yaml(config);
  EXPECT_NE(yaml.find("child_frame_id: camera_1_optical_frame"), std::string::npos);
  EXPECT_NE(yaml.find("rotation: {x: -0.5, y: 0.5, z: -0.5, w: 0.5}"), std::string::npos);
}

}  // namespace
}  // namespace camplace::testing
