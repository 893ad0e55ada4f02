#pragma once
/// Camera settings e = (x, y, z, yaw ψ, pitch θ, roll ρ) and the FOV geometry of SPEC §1.
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "camplace/core/geometry.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::core {

/// One camera's setting: position (m, world frame), yaw, pitch and roll (radians). Roll turns
/// the image about the viewing direction d by the right-hand rule (positive: the image's up
/// vector turns toward its right vector); it changes nothing for a cone.
struct CameraSetting {
  Vec3 position = Vec3::Zero();
  double yaw = 0.0;
  double pitch = 0.0;
  double roll = 0.0;
};
using CameraConfig = std::vector<CameraSetting>;

/// Unit viewing direction d = (cos θ cos ψ, cos θ sin ψ, sin θ).
Vec3 view_direction(const CameraSetting& camera);
/// Unit up vector of the image: world z made orthogonal to d, or world y when d is vertical
/// (SPEC §1), then turned by the roll about d (right-hand rule).
Vec3 up_vector(const CameraSetting& camera);

/// The camera's field of view as a convex test: the cone of half angle α, the inscribed regular
/// k-sided pyramid (first edge toward the up vector), or the frustum over the image rectangle
/// (half-widths tan(H/2) along the right vector and tan(V/2) along the up vector at unit depth),
/// each cut by the near plane (p − c)·d ≥ near and the far plane (p − c)·d ≤ range.
class Fov {
 public:
  Fov(const CameraSetting& camera, const CameraModel& model);
  Fov(const CameraSetting& camera, FovShape shape, double half_angle, int sides,
      std::optional<double> range);
  /// True when p is inside the (closed) FOV.
  bool contains(const Vec3& p) const;
  /// Unit edge directions of the pyramid (k of them, first along the up vector side; for a
  /// frustum the 4 corners, up-right, down-right, down-left, up-left). A cone's are those of its
  /// inscribed k-sided pyramid.
  const std::vector<Vec3>& pyramid_edges() const { return edges_; }
  /// Inward unit normals of the pyramid's (frustum's) side planes through the apex.
  const std::vector<Vec3>& pyramid_normals() const { return normals_; }
  const Vec3& apex() const { return apex_; }
  const Vec3& axis() const { return axis_; }
  /// The near plane's axial depth (m, 0 = none) and the far plane's (none = unlimited).
  double near() const { return near_; }
  const std::optional<double>& range() const { return range_; }
  /// True for the cone; false for the pyramid and the frustum (side planes).
  bool is_cone() const { return shape_ == FovShape::cone; }

 private:
  Vec3 apex_, axis_;
  FovShape shape_;
  double half_angle_, cos_half_, sin_half_;
  double near_ = 0.0;
  std::optional<double> range_;
  std::vector<Vec3> edges_, normals_;
};

/// Reads a camera configuration file {"cameras": [{"position": [x,y,z], "yaw_deg": a,
/// "pitch_deg": b, "roll_deg": r}, ...]} (roll_deg optional, default 0; an optional "model"
/// must name the scene's model of that camera); the count must equal the scene's camera count.
/// Throws InputError.
CameraConfig load_camera_config(const std::string& path, const Scene& scene);
/// The configuration in `doc`, a camera file's parsed content, checked as load_camera_config
/// checks a file; `file` names the source in messages. With a `scene` the count must equal its
/// camera count; nullptr accepts any count. Throws InputError.
CameraConfig camera_config_from_json(const nlohmann::json& doc, const std::string& file,
                                     const Scene* scene);
/// The configuration as the JSON text load_camera_config reads (angles in degrees; roll_deg
/// only for a camera whose roll is not 0). With a `scene` each camera also names its model
/// ("model"; only when the scene's models are named).
std::string camera_config_json(const CameraConfig& config, int indent = 2,
                               const Scene* scene = nullptr);

}  // namespace camplace::core
