#pragma once
/// The decision vector of SPEC §7: the camera settings (x, y, z, yaw, pitch, roll) within the
/// scene's domain, with every variable that the domain fixes removed from the vector. Roll is a
/// variable only where the domain frees it (`roll_deg`) and the camera's model is not a cone
/// (roll leaves a cone unchanged: a cone camera's roll is 0, whatever its domain says).
#include <utility>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::optimize {

/// Which component of a camera setting a decision variable holds.
enum class Component { x = 0, y = 1, z = 2, yaw = 3, pitch = 4, roll = 5 };

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
  /// domain value, free ones are clamped into their bounds.
  core::CameraConfig decode(const std::vector<double>& x) const;
  /// The decision vector of a configuration (size n), clamped into the bounds; the
  /// configuration's values of fixed variables are ignored.
  std::vector<double> encode(const core::CameraConfig& config) const;
  /// The configuration clamped into the domain (decode(encode(config))).
  core::CameraConfig clamp(const core::CameraConfig& config) const;

 private:
  std::vector<Variable> variables_;
  /// Every camera with each component at its domain's lower bound (a cone's roll at 0).
  core::CameraConfig fixed_;
};

/// The paper's heuristic start (SPEC §7): cameras high in the corners of S looking at S's
/// centre, clamped into each camera's domain. Cameras 0..3 take the top corners (diagonal
/// pairs first), 4..7 the midpoints of the top edges, further ones repeat the pattern a quarter
/// of S's height lower. Roll: 0 clamped into the domain (0 for a cone).
core::CameraConfig corner_start(const core::Scene& scene);

}  // namespace camplace::optimize
