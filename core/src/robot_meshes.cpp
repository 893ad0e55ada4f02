// Robots' link meshes: the polyhedra of URDF <cylinder> and <sphere>, mesh file URIs, and the
// convex hulls of swept volumes (detail::convex_hull, CGAL).

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "camplace/core/error.hpp"
#include "mesh_repair.hpp"
#include "robot.hpp"
#include "robot_parts.hpp"

namespace camplace::core::detail {

namespace robot_parts {

TriangleMesh convex_hull_with_cube(const std::vector<Vec3>& points, double h) {
  CAMPLACE_ASSERT(h > 0.0);
  TriangleMesh cloud;
  cloud.vertices.reserve(points.size() * 8);
  for (const Vec3& p : points) {
    for (int c = 0; c < 8; ++c)
      cloud.vertices.emplace_back(p.x() + (c & 1 ? h : -h), p.y() + (c & 2 ? h : -h),
                                  p.z() + (c & 4 ? h : -h));
  }
  // The corners of a cube of edge 2h > 0 span a volume: there is a hull.
  std::optional<TriangleMesh> hull = convex_hull(cloud);
  CAMPLACE_ASSERT(hull.has_value());
  return *std::move(hull);
}

std::string resolve_mesh_path(const std::string& uri, const JsonNode& node,
                              const std::filesystem::path& scene_dir,
                              const std::filesystem::path& urdf_dir, const std::string& scene_file,
                              const std::string& entry) {
  const std::string package = "package://", file = "file://";
  if (uri.rfind(package, 0) == 0) {
    const std::string rest = uri.substr(package.size());
    const auto slash = rest.find('/');
    const std::string pkg = rest.substr(0, slash);
    const std::string inside = slash == std::string::npos ? "" : rest.substr(slash + 1);
    if (!node.has("package_paths") || !node.at("package_paths").has(pkg)) {
      throw InputError(scene_file, entry,
                       "mesh " + in_quotes(uri) + " is in package " + in_quotes(pkg) +
                           ", which \"package_paths\" does not list: add \"package_paths\": {" +
                           in_quotes(pkg) +
                           ": \"DIR\"} with DIR the package's folder (relative to "
                           "the scene file)");
    }
    const std::filesystem::path dir = node.at("package_paths").at(pkg).string();
    return ((dir.is_absolute() ? dir : scene_dir / dir) / inside).string();
  }
  std::filesystem::path p = uri;
  if (uri.rfind(file, 0) == 0) {
    p = uri.substr(file.size());
  } else if (uri.find("://") != std::string::npos) {
    throw InputError(scene_file, entry,
                     "mesh " + in_quotes(uri) +
                         ": unsupported URI scheme (expected a path, file:// or package://)");
  }
  return (p.is_absolute() ? p : urdf_dir / p).string();
}

}  // namespace robot_parts

TriangleMesh cylinder_mesh(double radius, double length) {
  const int k = kCylinderSides;
  // The polygon's edges touch the circle: vertices at r / cos(π/k).
  const double rv = radius / std::cos(kPi / k);
  TriangleMesh m;
  for (const double z : {-0.5 * length, 0.5 * length}) {
    for (int j = 0; j < k; ++j) {
      const double phi = 2 * kPi * j / k;
      m.vertices.emplace_back(rv * std::cos(phi), rv * std::sin(phi), z);
    }
  }
  const int bottom = 2 * k, top = 2 * k + 1;
  m.vertices.emplace_back(0, 0, -0.5 * length);
  m.vertices.emplace_back(0, 0, 0.5 * length);
  for (int j = 0; j < k; ++j) {
    const int a = j, b = (j + 1) % k;
    m.triangles.push_back({a, b, k + b});  // side, outward (counter-clockwise seen from outside)
    m.triangles.push_back({a, k + b, k + a});
    m.triangles.push_back({bottom, b, a});  // bottom cap, facing −z
    m.triangles.push_back({top, k + a, k + b});
  }
  return m;
}

TriangleMesh sphere_mesh(double radius) {
  const int bands = kSphereBands, sectors = kSphereSectors;
  // Vertices on the unit sphere: rings at polar angles iπ/bands, i = 1..bands−1, and the poles.
  // The mesh is their convex hull (each band's quads are planar trapezoids), so scaling it until
  // its nearest face plane is at distance `radius` makes it contain the sphere.
  TriangleMesh m;
  for (int i = 1; i < bands; ++i) {
    const double theta = kPi * i / bands;
    for (int j = 0; j < sectors; ++j) {
      const double phi = 2 * kPi * j / sectors;
      m.vertices.emplace_back(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                              std::cos(theta));
    }
  }
  const int north = static_cast<int>(m.vertices.size()), south = north + 1;
  m.vertices.emplace_back(0, 0, 1);
  m.vertices.emplace_back(0, 0, -1);
  const auto ring = [&](int i, int j) { return (i - 1) * sectors + (j % sectors); };
  for (int j = 0; j < sectors; ++j) {
    m.triangles.push_back({north, ring(1, j), ring(1, j + 1)});
    m.triangles.push_back({south, ring(bands - 1, j + 1), ring(bands - 1, j)});
    for (int i = 1; i + 1 < bands; ++i) {
      m.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  }
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& t : m.triangles) {
    const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    nearest = std::min(nearest, std::abs((b - a).cross(c - a).normalized().dot(a)));
  }
  // Round the scale up a little so that rounding cannot bring a face inside the sphere.
  const double scale = radius / nearest * (1 + 1e-12);
  for (Vec3& v : m.vertices) v *= scale;
  return m;
}

}  // namespace camplace::core::detail
