#include "camplace/optimize/encoding.hpp"

#include <algorithm>
#include <cmath>

#include "camplace/core/error.hpp"

namespace camplace::optimize {
namespace {

/// The slot of a component in Encoding::Parameters.
int slot(Component c) {
  switch (c) {
    case Component::s:
      return 0;
    case Component::t:
      return 1;
    default:
      return static_cast<int>(c);
  }
}

/// The bounds of component c of a camera with this domain.
core::Interval interval(const core::CameraDomain& domain, Component c) {
  if (domain.mount) {
    switch (c) {
      case Component::s:
      case Component::t:
        return {0.0, 1.0};
      case Component::yaw:
        return domain.mount->yaw;
      case Component::pitch:
        return domain.mount->pitch;
      case Component::roll:
        return domain.mount->roll;
      default:
        break;
    }
    CAMPLACE_ASSERT(false && "no x, y, z on a mount");
  }
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
    default:
      break;
  }
  CAMPLACE_ASSERT(false && "no s, t in a box domain");
  return domain.x;
}

constexpr Component kBoxComponents[] = {Component::x,   Component::y,     Component::z,
                                        Component::yaw, Component::pitch, Component::roll};
constexpr Component kMountComponents[] = {Component::s, Component::t, Component::yaw,
                                          Component::pitch, Component::roll};

}  // namespace

Encoding::Encoding(const core::Scene& scene)
    : domains_(scene.cameras.domains), keep_out_(scene.cameras.keep_out) {
  CAMPLACE_ASSERT(static_cast<int>(domains_.size()) == scene.cameras.count);
  fixed_.assign(domains_.size(), Parameters{});
  for (std::size_t i = 0; i < domains_.size(); ++i) {
    const bool has_roll = scene.cameras.models.at(i).has_roll();
    has_roll_.push_back(has_roll);
    const bool on_mount = domains_[i].mount.has_value();
    const auto add = [&](Component c) {
      if (c == Component::roll && !has_roll) return;  // a cone's roll stays 0
      const core::Interval range = interval(domains_[i], c);
      CAMPLACE_ASSERT(range.lo <= range.hi);
      fixed_[i][slot(c)] = range.lo;
      // SPEC §7: variables fixed by the domain leave the decision vector (no zero-width bounds).
      if (!range.fixed()) variables_.push_back({static_cast<int>(i), c, range.lo, range.hi});
    };
    if (on_mount) {
      for (Component c : kMountComponents) add(c);
    } else {
      for (Component c : kBoxComponents) add(c);
    }
  }
}

core::CameraSetting Encoding::setting(int camera, const Parameters& p, bool repair) const {
  const core::CameraDomain& d = domains_[camera];
  core::CameraSetting out;
  if (d.mount) {
    out.position = d.mount->point(p[0], p[1]);
    const core::Vec3 dir = d.mount->direction(p[3], p[4]);
    const double horizontal = std::hypot(dir.x(), dir.y());
    out.yaw = horizontal > 0.0 ? std::atan2(dir.y(), dir.x()) : 0.0;
    out.pitch = std::atan2(dir.z(), horizontal);
  } else {
    out.position = core::Vec3(p[0], p[1], p[2]);
    out.yaw = p[3];
    out.pitch = p[4];
  }
  out.roll = has_roll_[camera] ? p[5] : 0.0;
  const auto blocked = [&](const core::KeepOut& k) { return k.contains(out.position); };
  if (repair && std::any_of(keep_out_.begin(), keep_out_.end(), blocked)) {
    // Keep-out (docs/scene-format.md): a position in a keep-out box is moved to the nearest free
    // point of the domain. A repair rather than a penalty: every decoded configuration is
    // feasible, the objective stays the plain Err (no penalty weight to choose, no infeasible
    // best), and points inside a box evaluate like the nearest point on its faces.
    if (auto free = core::keep_out_repair(d, keep_out_, out.position)) out.position = *free;
  }
  return out;
}

Encoding::Parameters Encoding::parameters(int camera, const core::CameraSetting& c) const {
  const core::CameraDomain& d = domains_[camera];
  Parameters p{};
  if (d.mount) {
    const auto [s, t] = d.mount->coordinates(c.position);
    const auto [yaw, pitch] = d.mount->relative_angles(core::view_direction(c));
    p = {s, t, 0.0, yaw, pitch, c.roll};
  } else {
    p = {c.position.x(), c.position.y(), c.position.z(), c.yaw, c.pitch, c.roll};
  }
  return p;
}

std::pair<std::vector<double>, std::vector<double>> Encoding::bounds() const {
  std::vector<double> lo, hi;
  for (const Variable& v : variables_) {
    lo.push_back(v.lo);
    hi.push_back(v.hi);
  }
  return {lo, hi};
}

core::CameraConfig Encoding::decode(const std::vector<double>& x, bool repair) const {
  CAMPLACE_ASSERT(x.size() == variables_.size());
  std::vector<Parameters> params = fixed_;
  for (std::size_t k = 0; k < variables_.size(); ++k) {
    const Variable& v = variables_[k];
    params[v.camera][slot(v.component)] = std::clamp(x[k], v.lo, v.hi);
  }
  core::CameraConfig config(params.size());
  for (std::size_t i = 0; i < params.size(); ++i)
    config[i] = setting(static_cast<int>(i), params[i], repair);
  return config;
}

std::vector<double> Encoding::encode(const core::CameraConfig& config) const {
  CAMPLACE_ASSERT(config.size() == fixed_.size());
  std::vector<Parameters> params(config.size());
  for (std::size_t i = 0; i < config.size(); ++i)
    params[i] = parameters(static_cast<int>(i), config[i]);
  std::vector<double> x(variables_.size());
  for (std::size_t k = 0; k < variables_.size(); ++k) {
    const Variable& v = variables_[k];
    const double value = params[v.camera][slot(v.component)];
    x[k] = std::isfinite(value) ? std::clamp(value, v.lo, v.hi) : v.lo;
  }
  return x;
}

bool Encoding::keeps_out(const std::vector<double>& x, int camera) const {
  if (keep_out_.empty()) return true;
  const core::CameraConfig config = decode(x, false);
  for (int i = 0; i < static_cast<int>(config.size()); ++i) {
    if (camera >= 0 && i != camera) continue;
    for (const core::KeepOut& k : keep_out_) {
      if (k.contains(config[i].position)) return false;
    }
  }
  return true;
}

std::vector<double> Encoding::steps(double position_m, double angle) const {
  std::vector<double> out;
  for (const Variable& v : variables_) {
    const core::CameraDomain& d = domains_[v.camera];
    switch (v.component) {
      case Component::s:
        out.push_back(position_m / d.mount->u.norm());
        break;
      case Component::t:
        out.push_back(position_m / d.mount->v.norm());
        break;
      case Component::x:
      case Component::y:
      case Component::z:
        out.push_back(position_m);
        break;
      default:
        out.push_back(angle);
    }
  }
  return out;
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
    if (d.mount) {
      // The mount's point nearest to the spot, looking toward S's centre within its ranges.
      const auto [s_coord, t_coord] = d.mount->coordinates(p);
      const core::Vec3 q =
          d.mount->point(std::clamp(s_coord, 0.0, 1.0), std::clamp(t_coord, 0.0, 1.0));
      core::Vec3 dir = centre - q;
      if (dir.norm() == 0.0) dir = d.mount->normal();
      const auto [rel_yaw, rel_pitch] = d.mount->relative_angles(dir.normalized());
      const core::Vec3 look =
          d.mount->direction(std::clamp(rel_yaw, d.mount->yaw.lo, d.mount->yaw.hi),
                             std::clamp(rel_pitch, d.mount->pitch.lo, d.mount->pitch.hi));
      config[i].position = q;
      const double h = std::hypot(look.x(), look.y());
      config[i].yaw = h > 0.0 ? std::atan2(look.y(), look.x()) : 0.0;
      config[i].pitch = std::atan2(look.z(), h);
    }
  }
  // Clamped and repaired as the optimizer will decode it.
  return Encoding(scene).clamp(config);
}

}  // namespace camplace::optimize
