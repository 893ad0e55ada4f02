// The camera placement domain presets (room, ceiling, upper_fourth) over the area S.
#include <optional>
#include <string>

#include "camplace/core/scene.hpp"

namespace camplace::core {

std::optional<CameraDomain> domain_preset(const Box3& area, const std::string& name) {
  CameraDomain d;
  d.x = {area.min.x(), area.max.x()};
  d.y = {area.min.y(), area.max.y()};
  d.z = {area.min.z(), area.max.z()};
  if (name == "ceiling") {
    d.z = {area.max.z(), area.max.z()};
    // Only looking down or level: nothing of S lies above its top. A cone FOV tilted
    // up by θ > 0 (no far plane) holds no point of S that the same cone tilted down by θ lacks:
    // for p below c, (p − c)·d(−θ) − (p − c)·d(θ) = −2 (p − c)_z sin θ ≥ 0, and the rays
    // (hence the labels) do not depend on the tilt. Looking up only wastes the optimizer's time.
    d.pitch = {-kPi / 2, 0.0};
    d.ceiling_pitch = true;
  } else if (name == "upper_fourth") {
    d.z = {area.max.z() - 0.25 * (area.max.z() - area.min.z()), area.max.z()};
  } else if (name != "room") {
    return std::nullopt;
  }
  return d;
}

}  // namespace camplace::core
