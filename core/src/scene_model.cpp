// The scene model's methods (SPEC §2): mounts, keep-out boxes, camera models and specs, the
// field-of-view description and the states of a scene.
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "camplace/core/error.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::core {

Vec3 Mount::normal() const { return u.cross(v).normalized(); }
Vec3 Mount::e1() const { return u.normalized(); }
Vec3 Mount::e2() const { return normal().cross(e1()); }
Vec3 Mount::point(double s, double t) const { return corner + s * u + t * v; }

std::pair<double, double> Mount::coordinates(const Vec3& p) const {
  Eigen::Matrix<double, 3, 2> a;
  a << u, v;
  const Eigen::Vector2d st = (a.transpose() * a).ldlt().solve(a.transpose() * (p - corner));
  return {st.x(), st.y()};
}

Vec3 Mount::direction(double rel_yaw, double rel_pitch) const {
  const double c = std::cos(rel_pitch);
  return (c * std::cos(rel_yaw) * normal() + c * std::sin(rel_yaw) * e1() +
          std::sin(rel_pitch) * e2())
      .normalized();
}

std::pair<double, double> Mount::relative_angles(const Vec3& d) const {
  const double along_n = d.dot(normal()), along_e1 = d.dot(e1());
  const double yaw = (along_n == 0.0 && along_e1 == 0.0) ? 0.0 : std::atan2(along_e1, along_n);
  return {yaw, std::asin(std::clamp(d.dot(e2()), -1.0, 1.0))};
}

bool KeepOut::contains(const Vec3& p) const {
  return (p.array() > box.min.array() + kKeepOutSlack).all() &&
         (p.array() < box.max.array() - kKeepOutSlack).all();
}

double CameraModel::bounding_half_angle() const {
  if (fov != FovShape::frustum) return half_angle;
  const double tx = std::tan(0.5 * horizontal), ty = std::tan(0.5 * vertical);
  return std::atan(std::hypot(tx, ty));
}

void CameraSpec::resize(int n) {
  CAMPLACE_ASSERT(n >= 1 && !models.empty() && !domains.empty());
  models.resize(n, models.back());
  domains.resize(n, domains.back());
  count = n;
}

bool CameraSpec::one_model() const {
  for (const CameraModel& m : models) {
    if (m.name != models.front().name || m.fov != models.front().fov ||
        m.half_angle != models.front().half_angle || m.sides != models.front().sides ||
        m.horizontal != models.front().horizontal || m.vertical != models.front().vertical ||
        m.near != models.front().near || m.range != models.front().range ||
        m.cost != models.front().cost) {
      return false;
    }
  }
  return true;
}

CameraModel exact_model(const CameraModel& model) {
  CameraModel out = model;
  if (out.fov == FovShape::cone) out.fov = FovShape::pyramid;
  return out;
}

void use_exact_models(CameraSpec& cameras) {
  for (CameraModel& m : cameras.models) m = exact_model(m);
}

std::string fov_description(const CameraSpec& cameras) {
  std::ostringstream out;
  const CameraModel& first = cameras.models.front();
  if (cameras.one_model() && first.fov == FovShape::cone) {
    out << "the " << first.sides << "-sided pyramid inscribed in each camera's "
        << first.half_angle / kDegree << "° cone";
    return out.str();
  }
  std::vector<std::string> seen;
  for (const CameraModel& m : cameras.models) {
    const std::string key = m.name;
    if (std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
    seen.push_back(key);
    const auto uses = std::count_if(cameras.models.begin(), cameras.models.end(),
                                    [&](const CameraModel& k) { return k.name == key; });
    if (seen.size() > 1) out << "; ";
    if (!m.name.empty()) out << "model \"" << m.name << "\" (" << uses << " cameras): ";
    if (m.fov == FovShape::frustum) {
      out << "a " << m.horizontal / kDegree << "° × " << m.vertical / kDegree << "° frustum";
    } else if (m.fov == FovShape::pyramid) {
      out << "a " << m.sides << "-sided pyramid of half angle " << m.half_angle / kDegree << "°";
    } else {
      out << "the " << m.sides << "-sided pyramid inscribed in a " << m.half_angle / kDegree
          << "° cone";
    }
    if (m.near > 0.0) out << ", near " << m.near << " m";
    if (m.range) out << ", far " << *m.range << " m";
  }
  return out.str();
}

std::vector<StateIndex> states(const Scene& scene) {
  std::vector<StateIndex> out;
  for (int h = 0; h < static_cast<int>(scene.time_steps.size()); ++h) {
    for (int l = 0; l < static_cast<int>(scene.time_steps[h].events.size()); ++l)
      out.push_back({h, l});
  }
  return out;
}

bool has_ceiling_pitch(const CameraSpec& cameras) {
  return std::any_of(cameras.domains.begin(), cameras.domains.end(),
                     [](const CameraDomain& d) { return d.ceiling_pitch; });
}

}  // namespace camplace::core
