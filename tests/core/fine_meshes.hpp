#pragma once
// Finely triangulated closed solids built in code (tests and benchmarks): boxes with every face
// cut into a k×k grid and latitude–longitude ellipsoids, outward oriented, vertices shared.
#include <Eigen/Geometry>
#include <array>
#include <map>
#include <random>
#include <tuple>

#include "camplace/core/geometry.hpp"

namespace camplace::testing {

/// A random rotation: about z, then y, then x by angles uniform in (−3.14, 3.14).
inline Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::uniform_real_distribution<double> angle(-3.14, 3.14);
  return (Eigen::AngleAxisd(angle(rng), core::Vec3::UnitZ()) *
          Eigen::AngleAxisd(angle(rng), core::Vec3::UnitY()) *
          Eigen::AngleAxisd(angle(rng), core::Vec3::UnitX()))
      .toRotationMatrix();
}

/// Turns every triangle so that its normal points away from `inside` (a point of the solid's
/// interior that sees every face, as the centre of a box or an ellipsoid).
inline void orient_outward(core::TriangleMesh& m, const core::Vec3& inside) {
  for (auto& t : m.triangles) {
    const core::Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    if ((b - a).cross(c - a).dot((a + b + c) / 3 - inside) < 0) std::swap(t[1], t[2]);
  }
}

/// The box [lo, hi] with each face cut into k×k squares, each square into 2 triangles
/// (12·k² triangles).
inline core::TriangleMesh subdivided_box(const core::Vec3& lo, const core::Vec3& hi, int k) {
  core::TriangleMesh m;
  std::map<std::tuple<int, int, int>, int> index;
  auto vertex = [&](int i, int j, int l) {
    const auto key = std::make_tuple(i, j, l);
    const auto it = index.find(key);
    if (it != index.end()) return it->second;
    const core::Vec3 f(double(i) / k, double(j) / k, double(l) / k);
    m.vertices.push_back(lo + f.cwiseProduct(hi - lo));
    return index[key] = static_cast<int>(m.vertices.size()) - 1;
  };
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side <= k; side += k) {
      for (int u = 0; u < k; ++u) {
        for (int v = 0; v < k; ++v) {
          auto at = [&](int du, int dv) {
            std::array<int, 3> c{};
            c[axis] = side;
            c[(axis + 1) % 3] = u + du;
            c[(axis + 2) % 3] = v + dv;
            return vertex(c[0], c[1], c[2]);
          };
          m.triangles.push_back({at(0, 0), at(1, 0), at(1, 1)});
          m.triangles.push_back({at(0, 0), at(1, 1), at(0, 1)});
        }
      }
    }
  }
  orient_outward(m, 0.5 * (lo + hi));
  return m;
}

/// Ellipsoid with semi-axes `radii` (before `rotation`), centred at `center`: `slices`
/// meridians and `stacks` latitude bands, 2·slices·(stacks − 1) triangles.
inline core::TriangleMesh ellipsoid(const core::Vec3& center, const core::Vec3& radii, int slices,
                                    int stacks,
                                    const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity()) {
  const double pi = 3.14159265358979323846;
  core::TriangleMesh m;
  m.vertices.push_back(center + rotation * core::Vec3(0, 0, radii.z()));  // north pole
  for (int s = 1; s < stacks; ++s) {
    const double theta = pi * s / stacks;
    for (int l = 0; l < slices; ++l) {
      const double phi = 2 * pi * l / slices;
      const core::Vec3 unit(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                            std::cos(theta));
      m.vertices.push_back(center + rotation * unit.cwiseProduct(radii));
    }
  }
  m.vertices.push_back(center + rotation * core::Vec3(0, 0, -radii.z()));  // south pole
  const int south = static_cast<int>(m.vertices.size()) - 1;
  auto ring = [&](int s, int l) { return 1 + (s - 1) * slices + (l % slices); };
  for (int l = 0; l < slices; ++l) {
    m.triangles.push_back({0, ring(1, l), ring(1, l + 1)});
    m.triangles.push_back({south, ring(stacks - 1, l + 1), ring(stacks - 1, l)});
    for (int s = 1; s + 1 < stacks; ++s) {
      m.triangles.push_back({ring(s, l), ring(s + 1, l), ring(s + 1, l + 1)});
      m.triangles.push_back({ring(s, l), ring(s + 1, l + 1), ring(s, l + 1)});
    }
  }
  orient_outward(m, center);
  return m;
}

/// The mesh moved rigidly: v ↦ rotation·v + shift.
inline core::TriangleMesh moved(core::TriangleMesh m, const Eigen::Matrix3d& rotation,
                                const core::Vec3& shift) {
  for (core::Vec3& v : m.vertices) v = rotation * v + shift;
  return m;
}

}  // namespace camplace::testing
