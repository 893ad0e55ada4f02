#pragma once
/// Camera poses in the conventions of other tools (docs/export.md): ROS frames, OpenCV
/// extrinsics, glTF nodes. The world frame is camplace's (right-handed, z up, metres).
#include <Eigen/Geometry>
#include <string>

#include "camplace/core/camera.hpp"

namespace camplace::view {

/// One camera's pose. Rotations map frame axes to world axes (columns = the frame's x, y, z in
/// world coordinates); quaternions are the same rotations.
struct CameraPose {
  core::Vec3 position = core::Vec3::Zero();  ///< optical centre c, m
  /// ROS optical frame (REP 103 `*_optical_frame`, OpenCV's camera frame): z forward (the
  /// viewing direction d), x right (d × u), y down (−u); u = core::up_vector.
  Eigen::Matrix3d optical = Eigen::Matrix3d::Identity();
  /// ROS body frame (REP 103 `camera_link`): x forward (d), y left (u × d), z up (u).
  Eigen::Matrix3d body = Eigen::Matrix3d::Identity();
  /// OpenCV extrinsics, world → camera: p_cam = R · p_world + t (R = optical^T, t = −R·c).
  Eigen::Matrix3d opencv_r = Eigen::Matrix3d::Identity();
  core::Vec3 opencv_t = core::Vec3::Zero();
};

/// The pose of a camera setting (roll 0: SPEC §1).
CameraPose camera_pose(const core::CameraSetting& camera);

/// Quaternion of a rotation matrix as [x, y, z, w] with w ≥ 0.
Eigen::Vector4d quaternion_xyzw(const Eigen::Matrix3d& rotation);

/// poses.json: {"conventions": {...}, "cameras": [{"index", "position", "yaw_deg", "pitch_deg",
/// "optical_frame": {"quaternion_xyzw", "rotation"}, "body_frame": {...}, "opencv": {"R",
/// "t"}}]} (docs/export.md).
std::string poses_json(const core::CameraConfig& config);
/// poses.yaml: the same poses as ROS transforms (frame `world` → `camera_<i>_link` and
/// `camera_<i>_optical_frame`), quaternions x, y, z, w.
std::string poses_yaml(const core::CameraConfig& config);

}  // namespace camplace::view
