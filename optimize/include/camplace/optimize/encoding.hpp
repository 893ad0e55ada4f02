#pragma once
/// The decision vector of SPEC §7: the camera settings (x, y, z, yaw, pitch, roll) within the
/// scene's domain, with every variable that the domain fixes removed from the vector. Roll is a
/// variable only where the domain frees it (`roll_deg`) and the camera's model is not a cone
/// (roll leaves a cone unchanged: a cone camera's roll is 0, whatever its domain says).
#include <array>
#include <utility>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::optimize {

/// Which component of a camera setting a decision variable holds. A camera on a mount has the
/// surface coordinates s and t (position = corner + s·u + t·v, (s, t) ∈ [0, 1]²) instead of x,
/// y, z, and its yaw and pitch are relative to the mount's frame (core::Mount).
enum class Component { x = 0, y = 1, z = 2, yaw = 3, pitch = 4, roll = 5, s = 6, t = 7 };

/// One free decision variable: camera index and component, with its bounds (m or rad).
struct Variable {
  int camera = 0;
  Component component = Component::x;
  double lo = 0.0;
  double hi = 0.0;
};

/// Maps decision vectors to camera configurations and back for one scene's camera domains.
class Encoding {
 public:
  /// Builds the encoding from scene.cameras.domains (one domain per camera).
  explicit Encoding(const core::Scene& scene);

  /// Number of free variables (6n minus the fixed ones).
  std::size_t dimension() const { return variables_.size(); }
  const std::vector<Variable>& variables() const { return variables_; }
  /// Lower and upper bounds of the decision vector (m, rad), each of size dimension().
  std::pair<std::vector<double>, std::vector<double>> bounds() const;

  /// The configuration for decision vector x (size dimension()); fixed variables take their
  /// domain value, free ones are clamped into their bounds. A position in a keep-out box is
  /// repaired: moved to the nearest free point of the camera's domain (core::keep_out_repair),
  /// so that no decoded configuration has a camera in a keep-out box.
  core::CameraConfig decode(const std::vector<double>& x) const { return decode(x, true); }
  /// decode(), with the keep-out repair only when `repair` is true.
  core::CameraConfig decode(const std::vector<double>& x, bool repair) const;
  /// True when no camera of decode(x, false) (only camera `camera` when it is ≥ 0) lies in a
  /// keep-out box.
  bool keeps_out(const std::vector<double>& x, int camera = -1) const;
  /// The grid step of each variable for `optimize --snap`: position_m (m) for x, y, z,
  /// position_m/|u| for s and position_m/|v| for t (metres along the mount's edges), `angle`
  /// (radians) for yaw, pitch (mount-relative on a mount) and roll.
  std::vector<double> steps(double position_m, double angle) const;
  /// The decision vector of a configuration (size n), clamped into the bounds; the
  /// configuration's values of fixed variables are ignored. A camera on a mount is projected
  /// onto the mount's plane for (s, t); its direction gives the relative yaw and pitch.
  std::vector<double> encode(const core::CameraConfig& config) const;
  /// The configuration clamped into the domain (decode(encode(config))).
  core::CameraConfig clamp(const core::CameraConfig& config) const;

 private:
  /// Per camera, its 6 parameters: x, y, z, yaw, pitch, roll (box domain) or s, t, unused,
  /// relative yaw, relative pitch, roll (mount).
  using Parameters = std::array<double, 6>;
  core::CameraSetting setting(int camera, const Parameters& p, bool repair) const;
  Parameters parameters(int camera, const core::CameraSetting& setting) const;

  std::vector<Variable> variables_;
  std::vector<core::CameraDomain> domains_;
  std::vector<bool> has_roll_;
  std::vector<core::KeepOut> keep_out_;
  /// Every camera with each parameter at its lower bound (a cone's roll at 0).
  std::vector<Parameters> fixed_;
};

/// The paper's heuristic start (SPEC §7): cameras high in the corners of S looking at S's
/// centre, clamped into each camera's domain. Cameras 0..3 take the top corners (diagonal
/// pairs first), 4..7 the midpoints of the top edges, further ones repeat the pattern a quarter
/// of S's height lower. Roll: 0 clamped into the domain (0 for a cone). A camera on a mount
/// takes the mount's point nearest to that spot, looking as near to S's centre as its ranges
/// allow; positions in keep-out boxes are repaired as decode() does.
core::CameraConfig corner_start(const core::Scene& scene);

}  // namespace camplace::optimize
