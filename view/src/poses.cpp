// Camera poses in ROS, OpenCV and glTF conventions (docs/export.md).
#include "camplace/view/poses.hpp"

#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

namespace camplace::view {

CameraPose camera_pose(const core::CameraSetting& camera) {
  const core::Vec3 d = core::view_direction(camera);
  const core::Vec3 u = core::up_vector(camera);
  const core::Vec3 right = d.cross(u);
  CameraPose pose;
  pose.position = camera.position;
  pose.optical.col(0) = right;
  pose.optical.col(1) = -u;
  pose.optical.col(2) = d;
  pose.body.col(0) = d;
  pose.body.col(1) = -right;  // u × d: left
  pose.body.col(2) = u;
  pose.opencv_r = pose.optical.transpose();
  pose.opencv_t = -pose.opencv_r * camera.position;
  return pose;
}

Eigen::Vector4d quaternion_xyzw(const Eigen::Matrix3d& rotation) {
  Eigen::Quaterniond q(rotation);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  return q.coeffs();  // Eigen stores x, y, z, w
}

namespace {

nlohmann::json rows(const Eigen::Matrix3d& m) {
  nlohmann::json out = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) out.push_back({m(r, 0), m(r, 1), m(r, 2)});
  return out;
}

nlohmann::json vec(const Eigen::VectorXd& v) {
  nlohmann::json out = nlohmann::json::array();
  for (int i = 0; i < v.size(); ++i) out.push_back(v[i]);
  return out;
}

}  // namespace

std::string poses_json(const core::CameraConfig& config) {
  nlohmann::ordered_json cameras = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < config.size(); ++i) {
    const CameraPose pose = camera_pose(config[i]);
    nlohmann::ordered_json c;
    c["index"] = i;
    c["position"] = vec(pose.position);
    c["yaw_deg"] = config[i].yaw / core::kDegree;
    c["pitch_deg"] = config[i].pitch / core::kDegree;
    c["roll_deg"] = config[i].roll / core::kDegree;
    c["view_direction"] = vec(core::view_direction(config[i]));
    c["up_vector"] = vec(core::up_vector(config[i]));
    c["optical_frame"] = {{"quaternion_xyzw", vec(quaternion_xyzw(pose.optical))},
                          {"rotation", rows(pose.optical)}};
    c["body_frame"] = {{"quaternion_xyzw", vec(quaternion_xyzw(pose.body))},
                       {"rotation", rows(pose.body)}};
    c["opencv"] = {{"R", rows(pose.opencv_r)}, {"t", vec(pose.opencv_t)}};
    cameras.push_back(c);
  }
  nlohmann::ordered_json doc;
  doc["conventions"] = {
      {"world", "camplace world frame: right-handed, z up, metres (docs/scene-format.md)"},
      {"quaternion_order", "x, y, z, w (Hamilton, unit, w >= 0)"},
      {"rotation", "frame -> world: columns are the frame's x, y, z axes in world coordinates"},
      {"optical_frame",
       "ROS REP 103 optical frame = OpenCV camera frame: z forward (view "
       "direction), x right, y down"},
      {"body_frame", "ROS REP 103 camera_link: x forward, y left, z up"},
      {"opencv",
       "extrinsics world -> camera: p_cam = R p_world + t; R = optical rotation "
       "transposed, t = -R position"}};
  doc["cameras"] = cameras;
  return doc.dump(2) + "\n";
}

std::string poses_yaml(const core::CameraConfig& config) {
  std::ostringstream out;
  out << std::setprecision(17);
  out << "# Camera poses written by camplace export (docs/export.md).\n"
         "# Parent frame: world (camplace's: right-handed, z up, metres).\n"
         "# rotation: quaternion x, y, z, w of the child frame in the world frame.\n"
         "# camera_<i>_link: x forward, y left, z up (REP 103);\n"
         "# camera_<i>_optical_frame: z forward, x right, y down (OpenCV).\n"
         "transforms:\n";
  for (std::size_t i = 0; i < config.size(); ++i) {
    const CameraPose pose = camera_pose(config[i]);
    const std::string name = "camera_" + std::to_string(i);
    for (const auto& [child, rotation] :
         {std::pair<std::string, Eigen::Matrix3d>{name + "_link", pose.body},
          std::pair<std::string, Eigen::Matrix3d>{name + "_optical_frame", pose.optical}}) {
      const Eigen::Vector4d q = quaternion_xyzw(rotation);
      out << "  - header: {frame_id: world}\n"
          << "    child_frame_id: " << child << "\n"
          << "    transform:\n"
          << "      translation: {x: " << pose.position.x() << ", y: " << pose.position.y()
          << ", z: " << pose.position.z() << "}\n"
          << "      rotation: {x: " << q[0] << ", y: " << q[1] << ", z: " << q[2] << ", w: " << q[3]
          << "}\n";
    }
  }
  return out.str();
}

}  // namespace camplace::view
