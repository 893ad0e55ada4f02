#include "reference.hpp"

#include <algorithm>
#include <array>
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

// Whether p lies in the camera's FOV, computed from the angles directly; `ambiguous` when p
// lies within `margin` of the FOV's boundary.
struct FovTest {
  bool inside = false;
  bool ambiguous = false;
};

FovTest fov_test(const core::CameraModel& model, const core::CameraSetting& camera, const Vec3& p,
                 double margin) {
  FovTest out;
  const double yaw = camera.yaw, pitch = camera.pitch;
  const Vec3 d(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
  const Vec3 v = p - camera.position;
  const double dist = v.norm();
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
  out.inside = true;
  return out;
}

struct Object {
  const core::TriangleMesh* mesh;
  bool occupying;
};

// The objects of state (h, l) with their role (SPEC §3: targets, and dynamic obstacles in
// masked mode, occupy).
std::vector<Object> state_objects(const core::Scene& scene, int time_step, int event) {
  const bool masked = scene.dynamic_mode == core::DynamicMode::masked;
  std::vector<Object> objects;
  for (const auto& o : scene.static_obstacles) objects.push_back({&o.mesh, false});
  const auto& step = scene.time_steps[time_step];
  for (const auto& o : step.dynamic_obstacles) objects.push_back({&o.mesh, masked});
  for (const auto& o : step.events[event].targets) objects.push_back({&o.mesh, true});
  return objects;
}

// A camera inside an object of the state sees nothing (SPEC §3.3).
bool blind(const std::vector<Object>& objects, const Vec3& c) {
  for (const Object& o : objects) {
    if (reference_inside(*o.mesh, c)) return true;
  }
  return false;
}

// Distance from p to the segment [a, b].
double point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

// Distance from p to the triangle (a, b, e): the plane's when p projects inside, else the
// nearest edge's.
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& e) {
  const Vec3 n = (b - a).cross(e - a);
  const double area = n.squaredNorm();
  const Vec3 q = p - n * (n.dot(p - a) / area);  // p projected onto the plane
  const double w0 = n.dot((b - q).cross(e - q)) / area;
  const double w1 = n.dot((e - q).cross(a - q)) / area;
  if (w0 >= 0 && w1 >= 0 && w0 + w1 <= 1) return (p - q).norm();
  return std::min({point_segment_distance(p, a, b), point_segment_distance(p, b, e),
                   point_segment_distance(p, e, a)});
}

// How deep the box (centre at `w` from the apex, half extents h) reaches into the cone
// {Σ λ_i n-planes ≥ 0}: t* = max over x in the box of min_i n_i·x (n_i the cone's unit inward
// plane normals, x relative to the apex); the cone meets the box iff t* ≥ 0. Computed by LP
// duality, not by separating axes: t* = min over μ in the simplex of
// F(μ) = Σ_i μ_i n_i·w + Σ_k |m_k(μ)| h_k with m(μ) = Σ_i μ_i n_i, a convex function that is
// linear between the lines m_k(μ) = 0; so its minimum lies at a vertex of the simplex cut by
// those lines, and every such vertex is tried.
double cone_box_depth(const std::array<Vec3, 3>& n, const Vec3& w, const Vec3& h) {
  // μ = (1 − a − b, a, b).
  auto value = [&](double a, double b) {
    const double mu[3] = {1.0 - a - b, a, b};
    const Vec3 m = mu[0] * n[0] + mu[1] * n[1] + mu[2] * n[2];
    return mu[0] * n[0].dot(w) + mu[1] * n[1].dot(w) + mu[2] * n[2].dot(w) + m.cwiseAbs().dot(h);
  };
  auto in_simplex = [](double a, double b) {
    constexpr double eps = 1e-12;
    return a >= -eps && b >= -eps && a + b <= 1.0 + eps;
  };
  double best = std::min({value(0, 0), value(1, 0), value(0, 1)});
  // Line k: p_k + q_k a + r_k b = 0.
  double p[3], q[3], r[3];
  for (int k = 0; k < 3; ++k) {
    p[k] = n[0][k];
    q[k] = n[1][k] - n[0][k];
    r[k] = n[2][k] - n[0][k];
  }
  auto consider = [&](double a, double b) {
    if (in_simplex(a, b)) {
      a = std::clamp(a, 0.0, 1.0);
      b = std::clamp(b, 0.0, 1.0 - a);
      best = std::min(best, value(a, b));
    }
  };
  for (int k = 0; k < 3; ++k) {
    if (q[k] != 0) consider(-p[k] / q[k], 0.0);  // edge b = 0
    if (r[k] != 0) consider(0.0, -p[k] / r[k]);  // edge a = 0
    if (q[k] != r[k]) {                          // edge a + b = 1
      const double a = -(p[k] + r[k]) / (q[k] - r[k]);
      consider(a, 1.0 - a);
    }
    for (int j = k + 1; j < 3; ++j) {  // two lines
      const double det = q[k] * r[j] - q[j] * r[k];
      if (det == 0) continue;
      consider((-p[k] * r[j] + p[j] * r[k]) / det, (-q[k] * p[j] + q[j] * p[k]) / det);
    }
  }
  return best;
}
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
  const std::vector<Object> objects = state_objects(scene, time_step, event);
  const Vec3 c = camera.position;
  if (blind(objects, c)) return out;
  const Vec3 v = p - c;
  const double dist = v.norm();
  if (dist < margin) {
    out.ambiguous = true;
    return out;
  }
  const FovTest fov = fov_test(model, camera, p, margin);
  out.ambiguous = fov.ambiguous;
  if (!fov.inside) return out;
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

ReferenceLabel reference_box_label(const core::Scene& scene, int time_step, int event,
                                   const core::CameraSetting& camera, const core::Box3& box,
                                   double margin, int camera_index) {
  const core::CameraModel& model = scene.cameras.models.at(camera_index);
  ReferenceLabel out;
  const std::vector<Object> objects = state_objects(scene, time_step, event);
  const Vec3 c = camera.position;
  if (blind(objects, c)) return out;
  const Vec3 half = 0.5 * box.size();
  const Vec3 w = box.center() - c;
  // The camera in or at the box's bounding ball: never free.
  const double r = half.norm(), dist = w.norm();
  if (std::abs(dist - r) < margin) out.ambiguous = true;
  if (dist <= r) return out;
  // Every corner in the FOV (then the whole box: the FOV is convex); `far`: the farthest one.
  double far = 0.0;
  for (int q = 0; q < 8; ++q) {
    const Vec3 corner((q & 1) ? box.max.x() : box.min.x(), (q & 2) ? box.max.y() : box.min.y(),
                      (q & 4) ? box.max.z() : box.min.z());
    const FovTest fov = fov_test(model, camera, corner, margin);
    out.ambiguous = out.ambiguous || fov.ambiguous;
    if (!fov.inside) return out;
    far = std::max(far, (corner - c).norm());
  }
  // Back faces (SPEC §3 by the first meeting point: a segment from a camera outside a closed,
  // outward solid first meets it on a triangle that faces the camera), computed here from the
  // mesh: an object is culled when its signed volume is positive, the camera lies outside it and
  // clear of its surface by 1e-6 of the scale, and no triangle is near edge-on (|det| above 1e-6
  // of |a||b||e|); then its triangles with the camera behind their plane are not tested, as the
  // pipeline defines the conservative label (a back face's cone can meet the box nearer than its
  // farthest corner while the front faces over the same rays lie beyond it). Objects near those
  // thresholds may be culled or not: where that changes the label, a tie.
  enum class Cull { no, yes, maybe };
  std::vector<Cull> cull(objects.size(), Cull::no);
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const core::TriangleMesh& mesh = *objects[i].mesh;
    double volume = 0.0, clearance = std::numeric_limits<double>::infinity(), scale = 0.0;
    bool clear_tilts = true;
    for (const auto& t : mesh.triangles) {
      const Vec3 a = mesh.vertices[t[0]] - c, b = mesh.vertices[t[1]] - c,
                 e = mesh.vertices[t[2]] - c;
      const double det = a.dot(b.cross(e));
      volume += det;  // 6 × the signed volume, from the camera (the sum does not depend on it)
      clearance = std::min(clearance, point_triangle_distance(Vec3::Zero(), a, b, e));
      scale = std::max({scale, a.norm(), b.norm(), e.norm()});
      clear_tilts = clear_tilts && std::abs(det) > 1e-6 * a.norm() * b.norm() * e.norm();
    }
    if (!(volume > 0.0)) continue;  // inward or flat: the pipeline keeps every triangle
    cull[i] = clear_tilts && clearance > 1e-6 * scale ? Cull::yes : Cull::maybe;
  }
  // Every triangle's cone against the box. Sure / within the margin: occupying triangles whose
  // cone meets the box, occluding ones whose cone meets it and that come nearer to the camera
  // than its farthest point. Twice: with the back faces of the `maybe` objects (`kept`) and
  // without them (`culled`).
  struct Flags {
    bool occupied = false, occupied_tie = false, blocked = false, blocked_tie = false;
  };
  Flags kept, culled;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const Object& o = objects[i];
    for (const auto& t : o.mesh->triangles) {
      const Vec3 a = o.mesh->vertices[t[0]] - c, b = o.mesh->vertices[t[1]] - c,
                 e = o.mesh->vertices[t[2]] - c;
      const double det = a.dot(b.cross(e));
      if (det > 0 && cull[i] == Cull::yes) continue;  // a back face (the camera behind it)
      const bool maybe_culled = det > 0 && cull[i] == Cull::maybe;
      if (std::abs(det) <= 1e-9 * a.norm() * b.norm() * e.norm()) {
        // The camera in the triangle's plane: a cone without volume, whose rays also meet the
        // neighbouring triangles of the closed mesh; only touching boxes can tell. A tie.
        out.ambiguous = true;
        continue;
      }
      const double sign = det > 0 ? 1.0 : -1.0;
      const std::array<Vec3, 3> n{(sign * a.cross(b)).normalized(),
                                  (sign * b.cross(e)).normalized(),
                                  (sign * e.cross(a)).normalized()};
      const double depth = cone_box_depth(n, w, half);
      if (depth < -margin) continue;
      const bool sure = depth > margin;
      for (Flags* f : {&kept, &culled}) {
        if (f == &culled && maybe_culled) continue;
        if (o.occupying) {
          (sure ? f->occupied : f->occupied_tie) = true;
          continue;
        }
        const double near = point_triangle_distance(Vec3::Zero(), a, b, e);
        if (near < far - margin) {
          (sure ? f->blocked : f->blocked_tie) = true;
        } else if (near < far + margin) {
          f->blocked_tie = true;
        }
      }
    }
  }
  // The label of one set of flags; `tie` when the margin decides.
  auto decide = [](const Flags& f, bool& tie) {
    tie = false;
    if (f.occupied) return voxel::Label::occupied;
    if (f.occupied_tie) {
      tie = true;
      return voxel::Label::undetectable;
    }
    if (f.blocked) return voxel::Label::undetectable;
    if (f.blocked_tie) tie = true;
    return f.blocked_tie ? voxel::Label::undetectable : voxel::Label::free;
  };
  bool tie_kept = false, tie_culled = false;
  out.label = decide(kept, tie_kept);
  const voxel::Label other = decide(culled, tie_culled);
  if (tie_kept || tie_culled || other != out.label) out.ambiguous = true;
  return out;
}

}  // namespace camplace::testing
