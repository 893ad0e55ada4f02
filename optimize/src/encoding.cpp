#include "camplace/optimize/encoding.hpp"

#include <algorithm>
#include <cmath>

#include "camplace/core/error.hpp"

namespace camplace::optimize {
namespace {

const core::Interval& interval(const core::CameraDomain& domain, Component c) {
  switch (c) {
    case Component::x:
      return domain.x;
    case Component::y:
      return domain.y;
    case Component::z:
      return domain.z;
    case Component::yaw:
      return domain.yaw;
    case Component::pitch:
      return domain.pitch;
    case Component::roll:
      return domain.roll;
  }
  return domain.x;
}

double& component(core::CameraSetting& camera, Component c) {
  switch (c) {
    case Component::x:
      return camera.position.x();
    case Component::y:
      return camera.position.y();
    case Component::z:
      return camera.position.z();
    case Component::yaw:
      return camera.yaw;
    case Component::pitch:
      return camera.pitch;
    case Component::roll:
      return camera.roll;
  }
  return camera.position.x();
}

double component(const core::CameraSetting& camera, Component c) {
  return component(const_cast<core::CameraSetting&>(camera), c);
}

constexpr Component kComponents[] = {Component::x,   Component::y,     Component::z,
                                     Component::yaw, Component::pitch, Component::roll};

}  // namespace

Encoding::Encoding(const core::Scene& scene) {
  const auto& domains = scene.cameras.domains;
  CAMPLACE_ASSERT(static_cast<int>(domains.size()) == scene.cameras.count);
  fixed_.resize(domains.size());
  for (std::size_t i = 0; i < domains.size(); ++i) {
    const bool has_roll = scene.cameras.models.at(i).has_roll();
    for (Component c : kComponents) {
      if (c == Component::roll && !has_roll) continue;  // a cone's roll stays 0
      const core::Interval& range = interval(domains[i], c);
      CAMPLACE_ASSERT(range.lo <= range.hi);
      component(fixed_[i], c) = range.lo;
      // SPEC §7: variables fixed by the domain leave the decision vector (no zero-width bounds).
      if (!range.fixed()) variables_.push_back({static_cast<int>(i), c, range.lo, range.hi});
    }
  }
}

std::pair<std::vector<double>, std::vector<double>> Encoding::bounds() const {
  std::vector<double> lo, hi;
  for (const Variable& v : variables_) {
    lo.push_back(v.lo);
    hi.push_back(v.hi);
  }
  return {lo, hi};
}

core::CameraConfig Encoding::decode(const std::vector<double>& x) const {
  CAMPLACE_ASSERT(x.size() == variables_.size());
  core::CameraConfig config = fixed_;
  for (std::size_t k = 0; k < variables_.size(); ++k) {
    const Variable& v = variables_[k];
    component(config[v.camera], v.component) = std::clamp(x[k], v.lo, v.hi);
  }
  return config;
}

std::vector<double> Encoding::encode(const core::CameraConfig& config) const {
  CAMPLACE_ASSERT(config.size() == fixed_.size());
  std::vector<double> x(variables_.size());
  for (std::size_t k = 0; k < variables_.size(); ++k) {
    const Variable& v = variables_[k];
    const double value = component(config[v.camera], v.component);
    x[k] = std::isfinite(value) ? std::clamp(value, v.lo, v.hi) : v.lo;
  }
  return x;
}

core::CameraConfig Encoding::clamp(const core::CameraConfig& config) const {
  return decode(encode(config));
}

core::CameraConfig corner_start(const core::Scene& scene) {
  const core::Box3& s = scene.area;
  const core::Vec3 centre = s.center();
  const double height = s.size().z();
  // (u, v) in {0, ½, 1}² on the top face: diagonal corner pairs first, then edge midpoints.
  static constexpr double kSpots[8][2] = {{0, 0},   {1, 1},   {0, 1},   {1, 0},
                                          {0.5, 0}, {0.5, 1}, {0, 0.5}, {1, 0.5}};
  const auto& domains = scene.cameras.domains;
  core::CameraConfig config(domains.size());
  for (std::size_t i = 0; i < domains.size(); ++i) {
    const auto& spot = kSpots[i % 8];
    const double level = static_cast<double>(i / 8) * 0.25 * height;
    const core::CameraDomain& d = domains[i];
    core::Vec3 p(s.min.x() + spot[0] * s.size().x(), s.min.y() + spot[1] * s.size().y(),
                 s.max.z() - std::min(level, height));
    p = core::Vec3(std::clamp(p.x(), d.x.lo, d.x.hi), std::clamp(p.y(), d.y.lo, d.y.hi),
                   std::clamp(p.z(), d.z.lo, d.z.hi));
    const core::Vec3 to_centre = centre - p;
    const double horizontal = std::hypot(to_centre.x(), to_centre.y());
    double yaw = horizontal > 0.0 ? std::atan2(to_centre.y(), to_centre.x()) : 0.0;
    double pitch = (horizontal > 0.0 || to_centre.z() != 0.0)
                       ? std::atan2(to_centre.z(), horizontal)
                       : -core::kPi / 2;
    config[i].position = p;
    config[i].yaw = std::clamp(yaw, d.yaw.lo, d.yaw.hi);
    config[i].pitch = std::clamp(pitch, d.pitch.lo, d.pitch.hi);
    if (scene.cameras.models.at(i).has_roll())
      config[i].roll = std::clamp(0.0, d.roll.lo, d.roll.hi);
  }
  return config;
}

}  // namespace camplace::optimize
