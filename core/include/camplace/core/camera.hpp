#pragma once
/// Camera settings e = (x, y, z, yaw ψ, pitch θ) and the FOV geometry of SPEC §1.
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "camplace/core/geometry.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::core {

/// One camera's setting: position (m, world frame), yaw and pitch (radians), roll 0.
struct CameraSetting {
  Vec3 position = Vec3::Zero();
  double yaw = 0.0;
  double pitch = 0.0;
};
using CameraConfig = std::vector<CameraSetting>;

/// Unit viewing direction d = (cos θ cos ψ, cos θ sin ψ, sin θ).
Vec3 view_direction(const CameraSetting& camera);
/// Unit up vector: world z made orthogonal to d, or world y when d is vertical (SPEC §1).
Vec3 up_vector(const CameraSetting& camera);

/// The camera's field of view as a convex test: the cone of half angle α, or the inscribed
/// regular k-sided pyramid, optionally cut by the far plane (p - c)·d ≤ range.
class Fov {
 public:
  Fov(const CameraSetting& camera, const CameraSpec& spec);
  Fov(const CameraSetting& camera, FovShape shape, double half_angle, int sides,
      std::optional<double> range);
  /// True when p is inside the (closed) FOV.
  bool contains(const Vec3& p) const;
  /// True when the whole ball (center, radius) is inside the FOV (a sufficient test).
  bool contains_ball(const Vec3& center, double radius) const;
  /// Unit edge directions of the pyramid (k of them, first along the up vector side).
  const std::vector<Vec3>& pyramid_edges() const { return edges_; }
  /// Inward unit normals of the pyramid's side planes through the apex.
  const std::vector<Vec3>& pyramid_normals() const { return normals_; }
  const Vec3& apex() const { return apex_; }
  const Vec3& axis() const { return axis_; }

 private:
  Vec3 apex_, axis_;
  FovShape shape_;
  double half_angle_, cos_half_, sin_half_;
  std::optional<double> range_;
  std::vector<Vec3> edges_, normals_;
};

/// Reads a camera configuration file {"cameras": [{"position": [x,y,z], "yaw_deg": a,
/// "pitch_deg": b}, ...]}; the count must equal the scene's camera count. Throws InputError.
CameraConfig load_camera_config(const std::string& path, const Scene& scene);
/// The configuration in `doc`, a camera file's parsed content, checked as load_camera_config
/// checks a file; `file` names the source in messages. With a `scene` the count must equal its
/// camera count; nullptr accepts any count. Throws InputError.
CameraConfig camera_config_from_json(const nlohmann::json& doc, const std::string& file,
                                     const Scene* scene);
/// The configuration as the JSON text load_camera_config reads (angles in degrees).
std::string camera_config_json(const CameraConfig& config, int indent = 2);

}  // namespace camplace::core
