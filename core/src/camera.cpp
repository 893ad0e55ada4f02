#include "camplace/core/camera.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "camplace/core/json_reader.hpp"

namespace camplace::core {

Vec3 view_direction(const CameraSetting& camera) {
  const double cp = std::cos(camera.pitch);
  return Vec3(cp * std::cos(camera.yaw), cp * std::sin(camera.yaw), std::sin(camera.pitch));
}

namespace {

/// The unrolled up vector: world z made orthogonal to d, or world y when d is vertical.
Vec3 level_up(const Vec3& d) {
  Vec3 up = Vec3::UnitZ() - d.z() * d;  // component of world z orthogonal to d (SPEC §1)
  if (up.norm() < 1e-9) up = Vec3::UnitY() - d.y() * d;  // d vertical: world y
  return up.normalized();
}

CameraModel model_of(FovShape shape, double half_angle, int sides, std::optional<double> range) {
  CameraModel m;
  m.fov = shape;
  m.half_angle = half_angle;
  m.sides = sides;
  m.range = range;
  return m;
}

}  // namespace

Vec3 up_vector(const CameraSetting& camera) {
  const Vec3 d = view_direction(camera);
  const Vec3 up = level_up(d);
  if (camera.roll == 0.0) return up;
  // Rodrigues about d (right-hand rule): up·cos ρ + (d × up)·sin ρ, d × up the unrolled right.
  return (std::cos(camera.roll) * up + std::sin(camera.roll) * d.cross(up)).normalized();
}

Fov::Fov(const CameraSetting& camera, FovShape shape, double half_angle, int sides,
         std::optional<double> range)
    : Fov(camera, model_of(shape, half_angle, sides, range)) {}

Fov::Fov(const CameraSetting& camera, const CameraModel& model)
    : apex_(camera.position),
      axis_(view_direction(camera)),
      shape_(model.fov),
      half_angle_(model.bounding_half_angle()),
      cos_half_(std::cos(half_angle_)),
      sin_half_(std::sin(half_angle_)),
      near_(model.near),
      range_(model.range) {
  const Vec3 up = up_vector(camera);
  const Vec3 right = axis_.cross(up);
  if (shape_ == FovShape::frustum) {
    // The image rectangle at unit depth: corners d ± tan(H/2)·right ± tan(V/2)·up, in the order
    // up-right, down-right, down-left, up-left (as the pyramid's, clockwise seen from behind).
    const double tx = std::tan(0.5 * model.horizontal), ty = std::tan(0.5 * model.vertical);
    for (const auto& [sx, sy] : {std::pair{1, 1}, {1, -1}, {-1, -1}, {-1, 1}}) {
      edges_.push_back((axis_ + sx * tx * right + sy * ty * up).normalized());
    }
  } else {
    // The regular k-sided pyramid inscribed in the cone: edges on the cone, the first one toward
    // the up vector (SPEC §1). Always built, so both pipelines share the same edges.
    const int sides = model.sides;
    edges_.reserve(sides);
    for (int j = 0; j < sides; ++j) {
      const double phi = 2.0 * kPi * j / sides;
      edges_.push_back(
          (cos_half_ * axis_ + sin_half_ * (std::cos(phi) * up + std::sin(phi) * right))
              .normalized());
    }
  }
  const int sides = static_cast<int>(edges_.size());
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
  if (axial < near_) return false;
  if (shape_ == FovShape::cone) return axial >= v.norm() * cos_half_;
  for (const Vec3& n : normals_) {
    if (n.dot(v) < 0.0) return false;
  }
  return true;
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
    entry.only_keys({"position", "yaw_deg", "pitch_deg", "roll_deg", "name", "model"});
    CameraSetting camera;
    camera.position = entry.at("position").vec3();
    // Outside S is allowed (a camera on the cell's fence looking in); far beyond any cell is not.
    if (camera.position.cwiseAbs().maxCoeff() > kMaxCoordinate) {
      entry.at("position")
          .fail("coordinates must lie within ±" + format_number(kMaxCoordinate) + " m");
    }
    camera.yaw = entry.at("yaw_deg").number_in(-180.0, 180.0) * kDegree;
    camera.pitch = entry.at("pitch_deg").number_in(-90.0, 90.0) * kDegree;
    if (entry.has("roll_deg"))
      camera.roll = entry.at("roll_deg").number_in(-180.0, 180.0) * kDegree;
    if (entry.has("model") && scene != nullptr) {
      const JsonNode model = entry.at("model");
      const std::string& expected = scene->cameras.models.at(i).name;
      if (model.string() != expected) {
        model.fail("camera " + std::to_string(i) + " is a \"" + expected + "\" camera in " +
                   scene->file + ", not \"" + model.string() + "\"");
      }
    }
    config.push_back(camera);
  }
  return config;
}

std::string camera_config_json(const CameraConfig& config, int indent, const Scene* scene) {
  nlohmann::json cameras = nlohmann::json::array();  // keys in alphabetical order
  for (std::size_t i = 0; i < config.size(); ++i) {
    const CameraSetting& c = config[i];
    nlohmann::json entry;
    if (scene != nullptr && i < scene->cameras.models.size() &&
        !scene->cameras.models[i].name.empty()) {
      entry["model"] = scene->cameras.models[i].name;
    }
    entry["position"] = {c.position.x(), c.position.y(), c.position.z()};
    entry["yaw_deg"] = std::clamp(c.yaw / kDegree, -180.0, 180.0);
    entry["pitch_deg"] = std::clamp(c.pitch / kDegree, -90.0, 90.0);
    // Only a rolled camera carries roll_deg: files without it read as roll 0, and those written
    // before roll existed are written back byte for byte.
    if (c.roll != 0.0) entry["roll_deg"] = std::clamp(c.roll / kDegree, -180.0, 180.0);
    cameras.push_back(entry);
  }
  return nlohmann::json{{"cameras", cameras}}.dump(indent);
}

}  // namespace camplace::core
