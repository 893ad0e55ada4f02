// The voxel model's boundary (greedy meshing) and the FOV clipped to S (a convex polyhedron cut
// by S's six planes).
#include "camplace/view/meshing.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "camplace/core/error.hpp"

namespace camplace::view {

using core::Box3;
using core::TriangleMesh;
using core::Vec3;

core::TriangleMesh voxel_boundary_mesh(const voxel::Grid& grid,
                                       const std::vector<std::uint8_t>& model) {
  CAMPLACE_ASSERT(static_cast<int>(model.size()) == grid.count());
  const auto& n = grid.n;
  auto in_model = [&](const std::array<int, 3>& c) {
    for (int a = 0; a < 3; ++a) {
      if (c[a] < 0 || c[a] >= n[a]) return false;
    }
    return model[c[0] + n[0] * (c[1] + n[1] * c[2])] != 0;
  };
  // Grid plane `index` along `axis`; the last plane is S's boundary itself.
  auto coordinate = [&](int axis, int index) {
    return index == n[axis] ? grid.area.max[axis] : grid.area.min[axis] + index * grid.step[axis];
  };
  TriangleMesh mesh;
  std::vector<std::uint8_t> mask;
  for (int d = 0; d < 3; ++d) {
    // (d, u, v) cyclic, so e_u × e_v = e_d.
    const int u = (d + 1) % 3, v = (d + 2) % 3;
    for (int s = 0; s <= n[d]; ++s) {
      for (const int sign : {+1, -1}) {
        // Faces on plane s between the voxel below (index s − 1 along d) and above (s); sign +1:
        // the model is below, the face looks along +d.
        mask.assign(static_cast<std::size_t>(n[u]) * n[v], 0);
        bool any = false;
        for (int b = 0; b < n[v]; ++b) {
          for (int a = 0; a < n[u]; ++a) {
            std::array<int, 3> below{}, above{};
            below[d] = s - 1;
            above[d] = s;
            below[u] = above[u] = a;
            below[v] = above[v] = b;
            const bool face = sign > 0 ? in_model(below) && !in_model(above)
                                       : in_model(above) && !in_model(below);
            mask[a + static_cast<std::size_t>(n[u]) * b] = face;
            any = any || face;
          }
        }
        if (!any) continue;
        auto at = [&](int a, int b) -> std::uint8_t& {
          return mask[a + static_cast<std::size_t>(n[u]) * b];
        };
        // Greedy: the widest run along u, then as many rows along v as hold the whole run.
        for (int b = 0; b < n[v]; ++b) {
          for (int a = 0; a < n[u];) {
            if (!at(a, b)) {
              ++a;
              continue;
            }
            int w = 1;
            while (a + w < n[u] && at(a + w, b)) ++w;
            int h = 1;
            while (b + h < n[v] &&
                   std::all_of(&at(a, b + h), &at(a, b + h) + w, [](std::uint8_t m) { return m; }))
              ++h;
            for (int y = b; y < b + h; ++y) std::fill(&at(a, y), &at(a, y) + w, 0);
            auto corner = [&](int ua, int vb) {
              Vec3 p;
              p[d] = coordinate(d, s);
              p[u] = coordinate(u, ua);
              p[v] = coordinate(v, vb);
              return p;
            };
            const int first = static_cast<int>(mesh.vertices.size());
            mesh.vertices.push_back(corner(a, b));
            mesh.vertices.push_back(corner(a + w, b));
            mesh.vertices.push_back(corner(a + w, b + h));
            mesh.vertices.push_back(corner(a, b + h));
            if (sign > 0) {
              mesh.triangles.push_back({first, first + 1, first + 2});
              mesh.triangles.push_back({first, first + 2, first + 3});
            } else {
              mesh.triangles.push_back({first, first + 2, first + 1});
              mesh.triangles.push_back({first, first + 3, first + 2});
            }
            a += w;
          }
        }
      }
    }
  }
  return mesh;
}

namespace {

using Polygon = std::vector<Vec3>;
using Polyhedron = std::vector<Polygon>;

/// The convex polyhedron cut by the half-space n·x ≤ h (Sutherland–Hodgman on every face, the
/// cut closed by a cap polygon). `eps`: distance (m) within which a vertex counts as on the
/// plane.
Polyhedron clip(const Polyhedron& poly, const Vec3& n, double h, double eps) {
  Polyhedron out;
  Polygon cut;
  bool face_on_plane = false;
  for (const Polygon& face : poly) {
    Polygon kept;
    bool all_on = true;
    for (std::size_t i = 0; i < face.size(); ++i) {
      const Vec3& p = face[i];
      const Vec3& q = face[(i + 1) % face.size()];
      const double dp = n.dot(p) - h, dq = n.dot(q) - h;
      all_on = all_on && std::abs(dp) <= eps;
      if (dp <= eps) kept.push_back(p);
      if (std::abs(dp) <= eps) cut.push_back(p);
      if ((dp < -eps && dq > eps) || (dp > eps && dq < -eps)) {
        const Vec3 x = p + (q - p) * (dp / (dp - dq));
        kept.push_back(x);
        cut.push_back(x);
      }
    }
    if (kept.size() >= 3) out.push_back(kept);
    face_on_plane = face_on_plane || (all_on && kept.size() >= 3);
  }
  if (face_on_plane || cut.size() < 3) return out;
  // The cap: the cut points without repeats, in angular order around their centroid.
  Polygon cap;
  for (const Vec3& p : cut) {
    if (std::none_of(cap.begin(), cap.end(), [&](const Vec3& q) { return (p - q).norm() <= eps; }))
      cap.push_back(p);
  }
  if (cap.size() < 3) return out;
  Vec3 center = Vec3::Zero();
  for (const Vec3& p : cap) center += p;
  center /= static_cast<double>(cap.size());
  const Vec3 e1 = n.unitOrthogonal(), e2 = n.normalized().cross(e1);
  std::sort(cap.begin(), cap.end(), [&](const Vec3& a, const Vec3& b) {
    return std::atan2((a - center).dot(e2), (a - center).dot(e1)) <
           std::atan2((b - center).dot(e2), (b - center).dot(e1));
  });
  out.push_back(cap);
  return out;
}

/// Fan triangulation of every face, oriented outward (away from the vertices' centroid, which
/// lies inside a convex polyhedron); slivers below `min_area` (m²) are dropped.
TriangleMesh triangulate(const Polyhedron& poly, double min_area) {
  TriangleMesh mesh;
  Vec3 inside = Vec3::Zero();
  int count = 0;
  for (const Polygon& face : poly) {
    for (const Vec3& p : face) {
      inside += p;
      ++count;
    }
  }
  if (count == 0) return mesh;
  inside /= count;
  for (const Polygon& face : poly) {
    Vec3 normal = Vec3::Zero(), center = Vec3::Zero();
    for (std::size_t i = 0; i < face.size(); ++i) {
      normal += face[i].cross(face[(i + 1) % face.size()]);  // Newell
      center += face[i];
    }
    center /= static_cast<double>(face.size());
    const bool flip = normal.dot(center - inside) < 0;
    for (std::size_t i = 1; i + 1 < face.size(); ++i) {
      const Vec3 &a = face[0], &b = face[i], &c = face[i + 1];
      if (0.5 * (b - a).cross(c - a).norm() < min_area) continue;
      const int first = static_cast<int>(mesh.vertices.size());
      mesh.vertices.push_back(a);
      mesh.vertices.push_back(flip ? c : b);
      mesh.vertices.push_back(flip ? b : c);
      mesh.triangles.push_back({first, first + 1, first + 2});
    }
  }
  return mesh;
}

}  // namespace

core::TriangleMesh fov_mesh(const core::CameraSetting& camera, const core::CameraModel& model,
                            const core::Box3& area) {
  core::CameraModel drawn = model;
  if (drawn.fov == core::FovShape::cone) {
    drawn.fov = core::FovShape::pyramid;
    drawn.sides = kConeDrawSides;
  }
  const core::CameraModel& spec = drawn;
  const core::Fov fov(camera, drawn);
  const Vec3& apex = fov.apex();
  const Vec3& axis = fov.axis();
  // The pyramid is cut at the far plane (range), or just beyond S's farthest corner so that
  // only S's planes bound it.
  double depth = -1.0;
  for (const Vec3& corner : area.corners()) depth = std::max(depth, (corner - apex).dot(axis));
  const double scale = area.diagonal() + area.max.cwiseAbs().maxCoeff() +
                       area.min.cwiseAbs().maxCoeff() + apex.cwiseAbs().maxCoeff();
  const double eps = 1e-9 * scale;
  if (depth <= eps) return {};
  depth = spec.range ? std::min(*spec.range, depth + 1.0) : depth + 1.0;
  Polyhedron poly;
  Polygon base;
  const auto& edges = fov.pyramid_edges();
  for (const Vec3& e : edges) base.push_back(apex + e * (depth / e.dot(axis)));
  for (std::size_t j = 0; j < base.size(); ++j) {
    poly.push_back({apex, base[j], base[(j + 1) % base.size()]});
  }
  poly.push_back(base);
  if (spec.near > 0.0) {  // keep (p − apex)·axis ≥ near
    poly = clip(poly, -axis, -(spec.near + apex.dot(axis)), eps);
    if (poly.empty()) return {};
  }
  for (int a = 0; a < 3; ++a) {
    poly = clip(poly, Vec3::Unit(a), area.max[a], eps);
    poly = clip(poly, -Vec3::Unit(a), -area.min[a], eps);
    if (poly.empty()) return {};
  }
  return triangulate(poly, eps * eps);
}

}  // namespace camplace::view
