#include "camplace/core/camera.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "camplace/core/json_reader.hpp"

namespace camplace::core {

namespace {
constexpr double kDeg = kDegree;
}  // namespace

Vec3 view_direction(const CameraSetting& camera) {
  const double cp = std::cos(camera.pitch);
  return Vec3(cp * std::cos(camera.yaw), cp * std::sin(camera.yaw), std::sin(camera.pitch));
}

Vec3 up_vector(const CameraSetting& camera) {
  const Vec3 d = view_direction(camera);
  Vec3 up = Vec3::UnitZ() - d.z() * d;  // component of world z orthogonal to d (SPEC §1)
  if (up.norm() < 1e-9) up = Vec3::UnitY() - d.y() * d;  // d vertical: world y
  return up.normalized();
}

Fov::Fov(const CameraSetting& camera, const CameraSpec& spec)
    : Fov(camera, spec.fov, spec.half_angle, spec.sides, spec.range) {}

Fov::Fov(const CameraSetting& camera, FovShape shape, double half_angle, int sides,
         std::optional<double> range)
    : apex_(camera.position),
      axis_(view_direction(camera)),
      shape_(shape),
      half_angle_(half_angle),
      cos_half_(std::cos(half_angle)),
      sin_half_(std::sin(half_angle)),
      range_(range) {
  // The regular k-sided pyramid inscribed in the cone: edges on the cone, the first one toward
  // the up vector (SPEC §1). Always built, so both pipelines share the same edges.
  const Vec3 up = up_vector(camera);
  const Vec3 right = axis_.cross(up);
  edges_.reserve(sides);
  for (int j = 0; j < sides; ++j) {
    const double phi = 2.0 * kPi * j / sides;
    edges_.push_back((cos_half_ * axis_ + sin_half_ * (std::cos(phi) * up + std::sin(phi) * right))
                         .normalized());
  }
  normals_.reserve(sides);
  for (int j = 0; j < sides; ++j) {
    Vec3 n = edges_[j].cross(edges_[(j + 1) % sides]).normalized();
    if (n.dot(axis_) < 0) n = -n;
    normals_.push_back(n);
  }
}

bool Fov::contains(const Vec3& p) const {
  const Vec3 v = p - apex_;
  const double axial = v.dot(axis_);
  if (range_ && axial > *range_) return false;
  if (shape_ == FovShape::cone) return axial >= v.norm() * cos_half_;
  for (const Vec3& n : normals_) {
    if (n.dot(v) < 0.0) return false;
  }
  return true;
}

bool Fov::contains_ball(const Vec3& center, double radius) const {
  const Vec3 v = center - apex_;
  const double axial = v.dot(axis_);
  if (range_ && axial + radius > *range_) return false;
  if (shape_ == FovShape::pyramid) {
    for (const Vec3& n : normals_) {
      if (n.dot(v) < radius) return false;
    }
    return true;
  }
  // Cone: the ball's angular radius asin(r/|v|) plus its angle to the axis must fit in α.
  const double dist = v.norm();
  if (dist <= radius) return false;
  const double axis_angle = std::acos(std::clamp(axial / dist, -1.0, 1.0));
  return axis_angle + std::asin(radius / dist) <= half_angle_;
}

CameraConfig load_camera_config(const std::string& path, const Scene& scene) {
  return camera_config_from_json(read_json_file(path), path, &scene);
}

CameraConfig camera_config_from_json(const nlohmann::json& doc, const std::string& file,
                                     const Scene* scene) {
  const JsonNode root(doc, file, "");
  const JsonNode cameras = root.at("cameras");
  const std::size_t count = cameras.array_size();
  if (scene != nullptr && count != static_cast<std::size_t>(scene->cameras.count)) {
    cameras.fail("holds " + std::to_string(count) + " cameras but the scene " + scene->file +
                 " has " + std::to_string(scene->cameras.count));
  }
  CameraConfig config;
  for (std::size_t i = 0; i < count; ++i) {
    const JsonNode entry = cameras.at(i);
    entry.only_keys({"position", "yaw_deg", "pitch_deg", "name"});
    CameraSetting camera;
    camera.position = entry.at("position").vec3();
    // Outside S is allowed (a camera on the cell's fence looking in); far beyond any cell is not.
    if (camera.position.cwiseAbs().maxCoeff() > kMaxCoordinate) {
      entry.at("position")
          .fail("coordinates must lie within ±" + format_number(kMaxCoordinate) + " m");
    }
    camera.yaw = entry.at("yaw_deg").number_in(-180.0, 180.0) * kDeg;
    camera.pitch = entry.at("pitch_deg").number_in(-90.0, 90.0) * kDeg;
    config.push_back(camera);
  }
  return config;
}

std::string camera_config_json(const CameraConfig& config, int indent) {
  nlohmann::json cameras = nlohmann::json::array();
  for (const CameraSetting& c : config) {
    cameras.push_back({{"position", {c.position.x(), c.position.y(), c.position.z()}},
                       {"yaw_deg", std::clamp(c.yaw / kDeg, -180.0, 180.0)},
                       {"pitch_deg", std::clamp(c.pitch / kDeg, -90.0, 90.0)}});
  }
  return nlohmann::json{{"cameras", cameras}}.dump(indent);
}

}  // namespace camplace::core
