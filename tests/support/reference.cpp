#include "reference.hpp"

#include <cmath>
#include <limits>

namespace camplace::testing {

namespace {
using core::Vec3;
constexpr double kPi = 3.14159265358979323846;

struct Hit {
  double t = -1.0;        // ray parameter (unit direction: metres)
  double edge_gap = 1.0;  // smallest barycentric coordinate times edge scale
};

// Ray–plane intersection followed by a barycentric inside test.
Hit ray_hits(const Vec3& o, const Vec3& u, const Vec3& a, const Vec3& b, const Vec3& c) {
  Hit hit;
  const Vec3 n = (b - a).cross(c - a);
  const double denom = n.dot(u);
  if (std::abs(denom) < 1e-14 * n.norm()) return hit;
  const double t = n.dot(a - o) / denom;
  if (t <= 0) return hit;
  const Vec3 q = o + t * u;
  const double area = n.squaredNorm();
  const double w0 = n.dot((b - q).cross(c - q)) / area;
  const double w1 = n.dot((c - q).cross(a - q)) / area;
  const double w2 = 1.0 - w0 - w1;
  const double smallest = std::min({w0, w1, w2});
  const double scale = std::sqrt(std::sqrt(area));
  hit.edge_gap = std::abs(smallest) * scale;
  if (smallest < 0) {
    hit.t = -1.0;
    return hit;
  }
  hit.t = t;
  return hit;
}

struct Object {
  const core::TriangleMesh* mesh;
  bool occupying;
};
}  // namespace

bool reference_inside(const core::TriangleMesh& mesh, const Vec3& p) {
  const Vec3 dir = Vec3(0.5773, 0.5774, 0.5775).normalized();
  int crossings = 0;
  for (const auto& t : mesh.triangles) {
    if (ray_hits(p, dir, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]).t > 0)
      ++crossings;
  }
  return crossings % 2 == 1;
}

ReferenceLabel reference_label(const core::Scene& scene, int time_step, int event,
                               const core::CameraSetting& camera, const Vec3& p, double margin,
                               int camera_index) {
  const core::CameraModel& model = scene.cameras.models.at(camera_index);
  ReferenceLabel out;
  const bool masked = scene.dynamic_mode == core::DynamicMode::masked;
  std::vector<Object> objects;
  for (const auto& o : scene.static_obstacles) objects.push_back({&o.mesh, false});
  const auto& step = scene.time_steps[time_step];
  for (const auto& o : step.dynamic_obstacles) objects.push_back({&o.mesh, masked});
  for (const auto& o : step.events[event].targets) objects.push_back({&o.mesh, true});
  const Vec3 c = camera.position;
  for (const Object& o : objects) {
    if (reference_inside(*o.mesh, c)) return out;  // blind camera
  }
  // FOV, computed from the angles directly.
  const double yaw = camera.yaw, pitch = camera.pitch;
  const Vec3 d(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
  const Vec3 v = p - c;
  const double dist = v.norm();
  if (dist < margin) {
    out.ambiguous = true;
    return out;
  }
  const double alpha = model.half_angle;
  const double axial = v.dot(d);
  if (model.range) {
    if (std::abs(axial - *model.range) < margin) out.ambiguous = true;
    if (axial > *model.range) return out;
  }
  if (model.near > 0.0) {
    if (std::abs(axial - model.near) < margin) out.ambiguous = true;
    if (axial < model.near) return out;
  }
  // The image axes: world z (or y) made orthogonal to d, then turned by the roll ρ about d
  // (right-hand rule: the up axis turns toward the right axis).
  Vec3 up0 = Vec3::UnitZ() - d.z() * d;
  if (up0.norm() < 1e-9) up0 = Vec3::UnitY() - d.y() * d;
  up0.normalize();
  const Vec3 right0 = d.cross(up0);
  const Vec3 up = std::cos(camera.roll) * up0 + std::sin(camera.roll) * right0;
  const Vec3 right = std::cos(camera.roll) * right0 - std::sin(camera.roll) * up0;
  if (model.fov == core::FovShape::frustum) {
    // |right·v| ≤ tan(H/2)·axial and |up·v| ≤ tan(V/2)·axial; the side plane's distance is
    // (t·axial − |s|)/√(1 + t²).
    if (axial <= 0) return out;
    const double tx = std::tan(0.5 * model.horizontal), ty = std::tan(0.5 * model.vertical);
    const double sx = std::abs(v.dot(right)), sy = std::abs(v.dot(up));
    const double gap_x = (tx * axial - sx) / std::sqrt(1 + tx * tx);
    const double gap_y = (ty * axial - sy) / std::sqrt(1 + ty * ty);
    if (std::abs(gap_x) < margin || std::abs(gap_y) < margin) out.ambiguous = true;
    if (gap_x < 0 || gap_y < 0) return out;
  } else if (model.fov == core::FovShape::cone) {
    const double angle = std::acos(std::clamp(axial / dist, -1.0, 1.0));
    if (std::abs(angle - alpha) * dist < margin) out.ambiguous = true;
    if (angle > alpha) return out;
  } else {
    // Project onto the image plane at depth 1 and test against the regular k-gon whose
    // vertices lie on the circle of radius tan α, the first one on the up axis.
    if (axial <= 0) return out;
    const double x = v.dot(up) / axial, y = v.dot(right) / axial;
    const int k = model.sides;
    const double r = std::tan(alpha);
    for (int j = 0; j < k; ++j) {
      const double a0 = 2 * kPi * j / k, a1 = 2 * kPi * (j + 1) / k;
      const double x0 = r * std::cos(a0), y0 = r * std::sin(a0);
      const double x1 = r * std::cos(a1), y1 = r * std::sin(a1);
      const double side =
          ((x1 - x0) * (y - y0) - (y1 - y0) * (x - x0)) / std::hypot(x1 - x0, y1 - y0);
      if (std::abs(side) * axial < margin) out.ambiguous = true;
      if (side < 0) return out;
    }
  }
  // First hit along the whole ray from c through p.
  const Vec3 u = v / dist;
  double first = std::numeric_limits<double>::infinity();
  bool occupying = false;
  for (const Object& o : objects) {
    for (const auto& t : o.mesh->triangles) {
      const Hit h =
          ray_hits(c, u, o.mesh->vertices[t[0]], o.mesh->vertices[t[1]], o.mesh->vertices[t[2]]);
      if (h.edge_gap < margin) out.ambiguous = true;
      if (h.t > 0 && h.t < first) {
        if (std::abs(h.t - first) < margin && occupying != o.occupying) out.ambiguous = true;
        first = h.t;
        occupying = o.occupying;
      } else if (h.t > 0 && std::abs(h.t - first) < margin && occupying != o.occupying) {
        out.ambiguous = true;
      }
    }
  }
  if (occupying) {
    out.label = voxel::Label::occupied;
    return out;
  }
  if (std::isfinite(first) && std::abs(first - dist) < margin) out.ambiguous = true;
  out.label = dist < first ? voxel::Label::free : voxel::Label::undetectable;
  return out;
}

}  // namespace camplace::testing
