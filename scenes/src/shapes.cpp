// Objects of the scene families (SPEC §9 table).
#include "shapes.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "camplace/core/error.hpp"

namespace camplace::scenes::detail {

namespace {

using core::Box3;
using core::kPi;
using core::SceneObject;
using core::TriangleMesh;
using core::Vec3;

// Generated (non-basic) vertices are rounded to micrometres: readable files, same text.
constexpr double kRound = 1e6;
// Random placements keep bounding boxes this far apart (m) and this far inside S's walls.
constexpr double kClearance = 0.1;
constexpr double kWallMargin = 0.05;

void orient_outward(TriangleMesh& mesh) {
  if (core::signed_volume(mesh) < 0) {
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  }
}

SceneObject scene_object(std::string name, TriangleMesh mesh) {
  SceneObject o;
  o.name = std::move(name);
  o.mesh = std::move(mesh);
  o.bounds = core::bounding_box(o.mesh);
  return o;
}

/// The pyramid over the closed polygon `ring` (n ≥ 3 points, convex, planar) with apex `apex`:
/// n − 2 base triangles (a fan from ring[0]) and n side triangles, 2n − 2 facets, outward.
TriangleMesh pyramid(const std::vector<Vec3>& ring, const Vec3& apex) {
  const int n = static_cast<int>(ring.size());
  CAMPLACE_ASSERT(n >= 3);
  TriangleMesh m;
  for (const Vec3& v : ring) m.vertices.push_back(rounded(v));
  m.vertices.push_back(rounded(apex));
  for (int k = 1; k + 1 < n; ++k) m.triangles.push_back({0, k + 1, k});
  for (int k = 0; k < n; ++k) m.triangles.push_back({k, (k + 1) % n, n});
  orient_outward(m);
  return m;
}

/// Facets → base polygon corners of a pyramid: F = 2n − 2.
int corners_for(int facets) {
  CAMPLACE_ASSERT(facets >= 4 && facets % 2 == 0);
  return (facets + 2) / 2;
}

/// Uniform in [0, 1) from the raw 32-bit output, which the standard fixes for std::mt19937
/// (std::uniform_real_distribution is not portable across standard libraries).
double unit(std::mt19937& rng) { return static_cast<double>(rng()) / 4294967296.0; }

bool boxes_apart(const Box3& a, const Box3& b, double margin) {
  for (int i = 0; i < 3; ++i) {
    if (a.max[i] + margin < b.min[i] || b.max[i] + margin < a.min[i]) return true;
  }
  return false;
}

bool inside_area(const Box3& b, const Box3& area) {
  return b.min.x() >= area.min.x() + kWallMargin && b.max.x() <= area.max.x() - kWallMargin &&
         b.min.y() >= area.min.y() + kWallMargin && b.max.y() <= area.max.y() - kWallMargin &&
         b.min.z() >= area.min.z() && b.max.z() <= area.max.z();
}

/// x rounded down to 6 decimals, never above x.
double floor6(double x) {
  double k = std::floor(x * 1e6);
  while (k / 1e6 > x) k -= 1.0;
  return k / 1e6;
}

/// The 4 points of a tetrahedron the loader made (base triangle, then apex).
Tetra points_of(const SceneObject& o) {
  CAMPLACE_ASSERT(o.mesh.vertices.size() == 4);
  return {o.mesh.vertices[0], o.mesh.vertices[1], o.mesh.vertices[2], o.mesh.vertices[3]};
}

}  // namespace

SceneObject tetra_object(const NamedTetra& t) {
  TriangleMesh mesh;
  mesh.vertices.assign(t.points.begin(), t.points.end());
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  orient_outward(mesh);
  return scene_object(t.name, std::move(mesh));
}

Vec3 rounded(const Vec3& v) {
  return Vec3(std::round(v.x() * kRound) / kRound, std::round(v.y() * kRound) / kRound,
              std::round(v.z() * kRound) / kRound);
}

/// The same volume (and the same z-range when the base is horizontal, as for every basic object
/// but the robot's forearm): the pyramid with the same apex over a regular n-gon (F = 2n − 2
/// facets) in the base triangle's plane, inscribed in the base triangle's Steiner circumellipse
/// shrunk about the centroid so the polygon's area equals the triangle's. For n = 3 that polygon
/// is the triangle itself, so F = 4 gives the tetrahedron back (written as given); for the n ≥ 8
/// the facet families use, the polygon bulges beyond each edge by at most 36 % of the
/// centroid–edge distance (a few cm here; every generated scene is checked against S and the
/// other objects by the scene loader).
SceneObject finer(const NamedTetra& t, int facets) {
  if (facets == 4) return tetra_object(t);
  const int n = corners_for(facets);
  const Vec3& a = t.points[0];
  const Vec3& b = t.points[1];
  const Vec3& c = t.points[2];
  const Vec3 g = (a + b + c) / 3.0;
  // Circumellipse g + u cos τ + w sin τ passes through a (τ = 0), b (2π/3), c (4π/3).
  const Vec3 u = a - g;
  const Vec3 w = (b - c) / std::sqrt(3.0);
  // Area of a regular n-gon inscribed in that ellipse: |u × w| · (n/2) sin(2π/n); the
  // triangle's: |u × w| · (3/2) sin(2π/3).
  const double scale =
      std::sqrt((1.5 * std::sin(2.0 * kPi / 3.0)) / (0.5 * n * std::sin(2.0 * kPi / n)));
  std::vector<Vec3> ring;
  for (int j = 0; j < n; ++j) {
    const double tau = 2.0 * kPi * j / n;
    ring.push_back(g + scale * (u * std::cos(tau) + w * std::sin(tau)));
  }
  return scene_object(t.name, pyramid(ring, t.points[3]));
}

std::vector<int> split_facets(int total, int parts) {
  CAMPLACE_ASSERT(total % 2 == 0 && total >= 4 * parts);
  const int pairs = total / 2;
  std::vector<int> out;
  for (int j = 0; j < parts; ++j) out.push_back(2 * (pairs / parts + (j < pairs % parts ? 1 : 0)));
  return out;
}

std::vector<SceneObject> place_randomly(std::mt19937& rng, const std::vector<int>& facets,
                                        const PyramidShape& shape, const std::string& name,
                                        std::vector<Box3> avoid, const Box3& area) {
  std::vector<SceneObject> out;
  for (std::size_t j = 0; j < facets.size(); ++j) {
    const int n = corners_for(facets[j]);
    const bool upright = shape.upright || j % 2 == 0;
    bool placed = false;
    for (int attempt = 0; attempt < 100000 && !placed; ++attempt) {
      const double r = shape.radius_lo + (shape.radius_hi - shape.radius_lo) * unit(rng);
      const double h = shape.height_lo + (shape.height_hi - shape.height_lo) * unit(rng);
      const double turn = 2.0 * kPi * unit(rng);
      const Vec3 center(area.min.x() + area.size().x() * unit(rng),
                        area.min.y() + area.size().y() * unit(rng), area.min.z());
      const Vec3 lean(shape.lean * r * (2.0 * unit(rng) - 1.0),
                      shape.lean * r * (2.0 * unit(rng) - 1.0), 0.0);
      const double base_z = upright ? 0.0 : h, apex_z = upright ? h : 0.0;
      std::vector<Vec3> ring;
      for (int k = 0; k < n; ++k) {
        const double a = turn + 2.0 * kPi * k / n;
        ring.push_back(center + Vec3(r * std::cos(a), r * std::sin(a), base_z));
      }
      TriangleMesh mesh = pyramid(ring, center + lean + Vec3(0, 0, apex_z));
      const Box3 box = core::bounding_box(mesh);
      if (!inside_area(box, area)) continue;
      if (!std::all_of(avoid.begin(), avoid.end(),
                       [&](const Box3& o) { return boxes_apart(box, o, kClearance); })) {
        continue;
      }
      avoid.push_back(box);
      out.push_back(scene_object(name + " " + std::to_string(j + 1) + " (" +
                                     (upright ? "upright" : "inverted") + " pyramid over a " +
                                     std::to_string(n) + "-gon)",
                                 std::move(mesh)));
      placed = true;
    }
    // On the paper's S the free floor is far larger than what these objects need: not finding
    // a place is a bug in the shapes above. On another base it says the base has no room.
    if (!placed) return {};
  }
  return out;
}

std::vector<Box3> boxes_of(const std::vector<SceneObject>& objects) {
  std::vector<Box3> out;
  for (const SceneObject& o : objects) out.push_back(o.bounds);
  return out;
}

core::Plausibility smallest_target(const core::Scene& s) {
  double min_volume = INFINITY, min_height = INFINITY;
  for (const core::TimeStep& step : s.time_steps) {
    for (const core::Event& e : step.events) {
      for (const SceneObject& o : e.targets) {
        min_volume = std::min(min_volume, std::abs(core::signed_volume(o.mesh)));
        min_height = std::min(min_height, o.bounds.size().z());
      }
    }
  }
  return {floor6(min_volume), floor6(min_height)};
}

// ---------------------------------------------------------------------------------------------
// Additions to the paper's basic setup

const Box3& paper_area() {
  static const Box3 area{Vec3(0, 0, 0), Vec3(4, 3, 3)};
  return area;
}

std::vector<NamedTetra> extra_static() {
  return {
      {"shelf",
       {Vec3(0.1, 2.3, 0.0), Vec3(0.7, 2.9, 0.0), Vec3(0.1, 2.9, 0.0), Vec3(0.25, 2.75, 1.6)}},
      {"crate",
       {Vec3(3.45, 0.1, 0.0), Vec3(3.9, 0.1, 0.0), Vec3(3.9, 0.45, 0.0), Vec3(3.8, 0.2, 0.6)}},
      {"cupboard",
       {Vec3(3.55, 1.25, 0.0), Vec3(3.9, 1.25, 0.0), Vec3(3.9, 1.95, 0.0), Vec3(3.8, 1.6, 1.3)}}};
}

std::vector<SceneObject> robot_toward_x(const std::vector<SceneObject>& pose0) {
  CAMPLACE_ASSERT(pose0.size() == 3);
  const Tetra arm = points_of(pose0[1]);
  return {pose0[0],
          tetra_object({"robot upper arm", {arm[0], arm[1], arm[2], Vec3(3.1, 0.6, 0.98)}}),
          tetra_object({"robot forearm",
                        {Vec3(3.05, 0.57, 0.92), Vec3(3.15, 0.67, 0.97), Vec3(3.07, 0.69, 0.88),
                         Vec3(3.65, 0.45, 0.9)}})};
}

std::vector<SceneObject> two_link_robot(const std::vector<SceneObject>& pose0, int step) {
  CAMPLACE_ASSERT(pose0.size() == 3);
  const Tetra arm = points_of(pose0[1]);
  const double phi = (180.0 - 30.0 * step) * kPi / 180.0;
  const Vec3 tip(2.85 + 0.65 * std::cos(phi), 0.7 + 0.65 * std::sin(phi), 0.95);
  return {pose0[0], tetra_object({"robot arm", {arm[0], arm[1], arm[2], rounded(tip)}})};
}

std::vector<SceneObject> extra_person(int place) {
  // Where the extra persons stand (the basic setup's are at (1.2, 1.6), (1.7, 2.3), (1.5, 0.7)).
  static const std::array<std::array<double, 2>, 2> kPlaces{{{0.6, 1.6}, {2.3, 2.0}}};
  CAMPLACE_ASSERT(place == 3 || place == 4);
  const double x = kPlaces[place - 3][0], y = kPlaces[place - 3][1];
  return {tetra_object({"person legs-head",
                        {Vec3(x - 0.22, y - 0.12, 0.0), Vec3(x + 0.22, y - 0.12, 0.0),
                         Vec3(x, y + 0.2, 0.0), Vec3(x, y, 1.75)}}),
          tetra_object({"person shoulders-feet",
                        {Vec3(x - 0.25, y - 0.05, 1.45), Vec3(x + 0.25, y - 0.05, 1.45),
                         Vec3(x, y + 0.15, 1.45), Vec3(x, y + 0.02, 0.0)}})};
}

std::vector<double> event_weights(int events) {
  switch (events) {
    case 1:
      return {1.0};
    case 2:
      return {0.6, 0.4};
    case 3:
      return {0.5, 0.3, 0.2};
    case 4:
      return {0.4, 0.3, 0.2, 0.1};
    default:
      CAMPLACE_ASSERT(events == 5);
      return {0.3, 0.25, 0.2, 0.15, 0.1};
  }
}

}  // namespace camplace::scenes::detail
