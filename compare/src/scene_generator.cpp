// Scene families of the paper's examinations (SPEC §9 table), derived from the basic setup of
// data/paper_basic.json (data/README.md says where its numbers come from).
//
// Properties every generated scene keeps (they make the plausibility filter of SPEC §4 valid,
// see data/README.md "Why the person is made of two tall parts"):
// - every dynamic obstacle's top is below 1 m, every target is at least 1.45 m tall;
// - min_volume / min_height are the smallest target's volume and z-extent, rounded down to
//   6 decimals, so no component holding a whole target part is ever discarded;
// - no target meets an obstacle of its own state, nothing leaves S, every time step has
//   critical objects and its event weights sum to 1.
#include "camplace/compare/scene_generator.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/core/scene_writer.hpp"

namespace camplace::compare {

namespace {

using core::Box3;
using core::SceneObject;
using core::TriangleMesh;
using core::Vec3;

using core::kPi;
// Generated (non-basic) vertices are rounded to micrometres: readable files, same text.
constexpr double kRound = 1e6;
// Random placements keep bounding boxes this far apart (m) and this far inside S's walls.
constexpr double kClearance = 0.1;
constexpr double kWallMargin = 0.05;
// The plausibility rule's bounds (data/README.md): robot below 1 m, person parts ≥ 1.45 m.
constexpr double kDynamicTopLimit = 1.0;
constexpr double kTargetMinHeight = 1.45;

// ---------------------------------------------------------------------------------------------
// Objects

using Tetra = std::array<Vec3, 4>;  ///< base triangle (points 0, 1, 2) and apex (point 3)

struct NamedTetra {
  std::string name;
  Tetra points;
};

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

/// The tetrahedron as the scene loader makes it of a "tetrahedron" entry (the 4 points in the
/// given order, turned outward), so the scene writer writes it as one.
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

/// The basic tetrahedron made finer with the same volume (and the same z-range when the base is
/// horizontal, as for every basic object but the robot's forearm): the pyramid with the same
/// apex over a regular n-gon (F = 2n − 2 facets) in the base triangle's plane, inscribed in the
/// base triangle's Steiner circumellipse shrunk about the centroid so the polygon's area equals
/// the triangle's. For n = 3 that polygon is the triangle itself, so F = 4 gives the basic
/// tetrahedron back (written as given); for the n ≥ 8 the facet families use, the polygon
/// bulges beyond each edge by at most 36 % of the centroid–edge distance (a few cm here; every
/// generated scene is checked against S and the other objects by the scene loader).
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

/// Splits `total` facets over `parts` objects: even counts ≥ 4, as equal as possible, the
/// larger ones first.
std::vector<int> split_facets(int total, int parts) {
  CAMPLACE_ASSERT(total % 2 == 0 && total >= 4 * parts);
  const int pairs = total / 2;
  std::vector<int> out;
  for (int j = 0; j < parts; ++j) out.push_back(2 * (pairs / parts + (j < pairs % parts ? 1 : 0)));
  return out;
}

// ---------------------------------------------------------------------------------------------
// The basic setup (data/paper_basic.json), and the few additions some families need.

const Box3 kArea{Vec3(0, 0, 0), Vec3(4, 3, 3)};
constexpr std::array<int, 3> kBasicVoxels{16, 12, 12};
constexpr int kBasicCameras = 6;

std::vector<NamedTetra> basic_static() {
  return {{"cabinet",
           {Vec3(0.1, 0.1, 0.0), Vec3(1.0, 0.1, 0.0), Vec3(0.1, 0.8, 0.0), Vec3(0.3, 0.3, 1.1)}},
          {"workbench",
           {Vec3(3.0, 2.2, 0.0), Vec3(3.9, 2.3, 0.0), Vec3(3.9, 2.9, 0.0), Vec3(3.6, 2.6, 0.9)}}};
}

/// More furniture for the static_objects family, along the walls, clear of the robot and of
/// the persons of the basic setup.
std::vector<NamedTetra> extra_static() {
  return {
      {"shelf",
       {Vec3(0.1, 2.3, 0.0), Vec3(0.7, 2.9, 0.0), Vec3(0.1, 2.9, 0.0), Vec3(0.25, 2.75, 1.6)}},
      {"crate",
       {Vec3(3.45, 0.1, 0.0), Vec3(3.9, 0.1, 0.0), Vec3(3.9, 0.45, 0.0), Vec3(3.8, 0.2, 0.6)}},
      {"cupboard",
       {Vec3(3.55, 1.25, 0.0), Vec3(3.9, 1.25, 0.0), Vec3(3.9, 1.95, 0.0), Vec3(3.8, 1.6, 1.3)}}};
}

NamedTetra robot_pedestal() {
  return {"robot pedestal",
          {Vec3(2.6, 0.5, 0.0), Vec3(3.1, 0.5, 0.0), Vec3(2.85, 1.0, 0.0), Vec3(2.85, 0.7, 0.7)}};
}

/// The basic robot of 3 tetrahedra: poses 0 (reaching toward the persons, −x) and 1 (turned
/// toward +y) are the basic ones; pose 2 (turned toward +x) is added for 3 time steps.
std::vector<NamedTetra> robot_pose(int pose) {
  const Vec3 b0(2.75, 0.62, 0.66), b1(2.95, 0.62, 0.66), b2(2.85, 0.8, 0.66);
  switch (pose) {
    case 0:
      return {robot_pedestal(),
              {"robot upper arm", {b0, b1, b2, Vec3(2.7, 0.95, 0.98)}},
              {"robot forearm",
               {Vec3(2.66, 0.92, 0.92), Vec3(2.76, 1.02, 0.97), Vec3(2.68, 1.04, 0.88),
                Vec3(2.15, 1.3, 0.9)}}};
    case 1:
      return {robot_pedestal(),
              {"robot upper arm", {b0, b1, b2, Vec3(3.05, 0.95, 0.98)}},
              {"robot forearm",
               {Vec3(3.0, 0.92, 0.92), Vec3(3.1, 1.02, 0.97), Vec3(3.02, 1.04, 0.88),
                Vec3(3.3, 1.55, 0.9)}}};
    default:
      CAMPLACE_ASSERT(pose == 2);
      return {robot_pedestal(),
              {"robot upper arm", {b0, b1, b2, Vec3(3.1, 0.6, 0.98)}},
              {"robot forearm",
               {Vec3(3.05, 0.57, 0.92), Vec3(3.15, 0.67, 0.97), Vec3(3.07, 0.69, 0.88),
                Vec3(3.65, 0.45, 0.9)}}};
  }
}

/// A robot of 2 tetrahedra (pedestal and one arm) for the dynamic_steps family; at step h the
/// arm points at 180° − 30°·h (from −x toward the persons over +y), its tip at 0.95 m.
std::vector<NamedTetra> two_link_robot(int step) {
  const double phi = (180.0 - 30.0 * step) * kPi / 180.0;
  const Vec3 tip(2.85 + 0.65 * std::cos(phi), 0.7 + 0.65 * std::sin(phi), 0.95);
  return {robot_pedestal(),
          {"robot arm",
           {Vec3(2.75, 0.62, 0.66), Vec3(2.95, 0.62, 0.66), Vec3(2.85, 0.8, 0.66), rounded(tip)}}};
}

/// Where a person stands: the basic setup's 3 places, then 2 more for unmodelled_events.
const std::array<std::array<double, 2>, 5> kPlaces{
    {{1.2, 1.6}, {1.7, 2.3}, {1.5, 0.7}, {0.6, 1.6}, {2.3, 2.0}}};

/// The basic person of 2 tetrahedra standing at place `place` (computed as the basic file's
/// numbers were, so the 3 basic places reproduce them bit for bit).
std::vector<NamedTetra> person(int place) {
  const double x = kPlaces[place][0], y = kPlaces[place][1];
  return {{"person legs-head",
           {Vec3(x - 0.22, y - 0.12, 0.0), Vec3(x + 0.22, y - 0.12, 0.0), Vec3(x, y + 0.2, 0.0),
            Vec3(x, y, 1.75)}},
          {"person shoulders-feet",
           {Vec3(x - 0.25, y - 0.05, 1.45), Vec3(x + 0.25, y - 0.05, 1.45), Vec3(x, y + 0.15, 1.45),
            Vec3(x, y + 0.02, 0.0)}}};
}

/// Event weights for L events, summing to 1 (L = 3: the basic setup's 0.5, 0.3, 0.2).
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

std::vector<SceneObject> finer_all(const std::vector<NamedTetra>& tetras, int facets) {
  std::vector<SceneObject> out;
  for (const NamedTetra& t : tetras) out.push_back(finer(t, facets));
  return out;
}

/// The basic persons at places 0..events−1, each part with `facets` facets.
std::vector<core::Event> person_events(int events, int facets) {
  const std::vector<double> weights = event_weights(events);
  std::vector<core::Event> out;
  for (int l = 0; l < events; ++l) out.push_back({weights[l], finer_all(person(l), facets)});
  return out;
}

/// A time step with these robot links and events; its time and critical objects are set when
/// the scene is finished.
core::TimeStep time_step(std::vector<SceneObject> dynamic, std::vector<core::Event> events) {
  core::TimeStep step;
  step.dynamic_obstacles = std::move(dynamic);
  step.events = std::move(events);
  return step;
}

// ---------------------------------------------------------------------------------------------
// Random placement (dynamic_objects, unmodelled_objects)

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

struct PyramidShape {
  double radius_lo, radius_hi;  ///< circumradius of the regular base polygon (m)
  double height_lo, height_hi;  ///< z-extent (m)
  double lean;                  ///< apex offset from the axis, fraction of the radius
  bool upright;                 ///< base on the floor (else base on top, apex on the floor)
};

/// Draws pyramids with the given facet counts at random places in S until each has its
/// bounding box kClearance away from every box in `avoid` (and from the ones drawn before).
std::vector<SceneObject> place_randomly(std::mt19937& rng, const std::vector<int>& facets,
                                        const PyramidShape& shape, const std::string& name,
                                        std::vector<Box3> avoid, const Box3& area = kArea) {
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

// ---------------------------------------------------------------------------------------------
// Families

const std::vector<SceneFamily> kFamilies = {
    {"resolution", true, 0, 5, false, "voxels (16+4i)x(12+3i)x(12+3i)",
     "the base's voxels times (4+i)/4 along each axis, rounded"},
    {"static_facets", true, 0, 5, false, "8+60i static facets at 2 objects (4+30i each)",
     "each static tetrahedron of the base with 4+30i facets (same volume)"},
    {"static_objects", true, 0, 3, false,
     "2+i static tetrahedra, 8+4i facets (the paper's \"6+4i facets at 2+i objects\" is "
     "impossible for closed polyhedra)",
     "the base's static obstacles and i of the paper's 3 extra pieces of furniture, their floor "
     "plan stretched from the paper's 4x3 m to the base's area"},
    {"dynamic_facets", true, 0, 5, false,
     "24+60i dynamic facets at 3 objects per time step, 2 time steps (4+10i each)",
     "each dynamic tetrahedron of the base with 4+10i facets (same volume)"},
    {"dynamic_objects", true, 0, 3, true,
     "2+i dynamic objects with 24+4i facets in total, 1 time step, placed randomly",
     "the base's first time step, its dynamic obstacles replaced by 2+i random ones (24+4i "
     "facets, 0.5-0.95 m tall)"},
    {"dynamic_steps", true, 1, 5, false,
     "i time steps with 2i dynamic tetrahedra (8i facets), 3 events per step",
     "not on another base: it moves the paper's robot arm"},
    {"unmodelled_facets", true, 0, 5, false,
     "24+60i target facets at 2 objects per event, 3 events (4+10i each)",
     "each target tetrahedron of the base with 4+10i facets (same volume)"},
    {"unmodelled_objects", true, 0, 3, true,
     "2+i target objects with 24+4i facets in total, 1 event, placed randomly",
     "one event of 2+i random targets (24+4i facets, 1.5-1.9 m tall) in every time step of "
     "the base"},
    {"unmodelled_events", true, 1, 5, false,
     "i events with 2i target tetrahedra (8i facets), 3 time steps",
     "the base's first i events of every time step (i up to the base's fewest), weights scaled "
     "to the step's sum"},
    {"cameras", true, 3, 9, false, "i cameras", "i cameras, with the base's shared domain"},
    {"domain_ceiling", false, 0, 0, false, "cameras on the ceiling only (domain preset ceiling)",
     ""},
    {"domain_upper_fourth", false, 0, 0, false,
     "cameras in the upper fourth of S's height only (domain preset upper_fourth)", ""},
};

/// A generated scene and what its description says beyond the scene itself.
struct GeneratedScene {
  core::Scene scene;
  std::string domain = "room";  ///< the cameras' domain preset
  std::string note;             ///< appended to the description
};

GeneratedScene basic_scene() {
  GeneratedScene g;
  core::Scene& s = g.scene;
  s.area = kArea;
  s.voxels = kBasicVoxels;
  s.cameras.count = kBasicCameras;
  core::CameraModel model;
  model.half_angle = 30.0 * core::kDegree;  // "half_angle_deg": 30, as the loader reads it
  model.fov = core::FovShape::cone;
  model.sides = 16;
  s.cameras.models.assign(s.cameras.count, model);
  s.static_obstacles = finer_all(basic_static(), 4);
  for (int h = 0; h < 2; ++h) {
    s.time_steps.push_back(time_step(finer_all(robot_pose(h), 4), person_events(3, 4)));
  }
  s.dynamic_mode = core::DynamicMode::masked;
  return g;
}

/// x rounded down to 6 decimals, never above x.
double floor6(double x) {
  double k = std::floor(x * 1e6);
  while (k / 1e6 > x) k -= 1.0;
  return k / 1e6;
}

/// What every family shares once its objects are placed: the domains of the preset, the times
/// h and the critical objects of the time steps (SPEC §2 defaults), the plausibility thresholds.
void finish(GeneratedScene& g) {
  core::Scene& s = g.scene;
  const std::optional<core::CameraDomain> domain = core::domain_preset(s.area, g.domain);
  CAMPLACE_ASSERT(domain.has_value());
  s.cameras.domains.assign(s.cameras.count, *domain);
  s.cameras.models.resize(s.cameras.count, s.cameras.models.front());
  for (std::size_t h = 0; h < s.time_steps.size(); ++h) {
    s.time_steps[h].t = static_cast<double>(h);
    s.time_steps[h].critical = s.time_steps[h].dynamic_obstacles;
  }
  // The smallest target part, rounded down: a component holding a whole part is never smaller,
  // so no true target part is discarded (data/README.md, "plausibility").
  double min_volume = INFINITY, min_height = INFINITY;
  for (const core::TimeStep& step : s.time_steps) {
    for (const core::Event& e : step.events) {
      for (const SceneObject& o : e.targets) {
        min_volume = std::min(min_volume, std::abs(core::signed_volume(o.mesh)));
        min_height = std::min(min_height, o.bounds.size().z());
      }
    }
  }
  s.plausibility = {floor6(min_volume), floor6(min_height)};
}

GeneratedScene build(const SceneFamily& family, int i, unsigned seed) {
  GeneratedScene g = basic_scene();
  core::Scene& s = g.scene;
  const std::string& f = family.name;
  std::mt19937 rng(seed);
  if (f == "resolution") {
    s.voxels = {16 + 4 * i, 12 + 3 * i, 12 + 3 * i};
  } else if (f == "static_facets") {
    s.static_obstacles = finer_all(basic_static(), 4 + 30 * i);
  } else if (f == "static_objects") {
    std::vector<NamedTetra> tetras = basic_static();
    const std::vector<NamedTetra> extra = extra_static();
    tetras.insert(tetras.end(), extra.begin(), extra.begin() + i);
    s.static_obstacles = finer_all(tetras, 4);
    g.note =
        " Note: SPEC §9 lists \"6+4i facets at 2+i objects\", impossible for closed "
        "polyhedra (each has at least 4 facets); this scene has 2+i tetrahedra, 8+4i facets.";
  } else if (f == "dynamic_facets") {
    for (int h = 0; h < 2; ++h) {
      s.time_steps[h].dynamic_obstacles = finer_all(robot_pose(h), 4 + 10 * i);
    }
  } else if (f == "dynamic_objects") {
    s.time_steps.resize(1);
    std::vector<Box3> avoid = boxes_of(s.static_obstacles);
    for (const core::Event& e : s.time_steps[0].events) {
      const std::vector<Box3> b = boxes_of(e.targets);
      avoid.insert(avoid.end(), b.begin(), b.end());
    }
    // Robot-like links on the floor, tops in [0.5, 0.95] m (< 1 m, see the file comment).
    const PyramidShape shape{0.15, 0.3, 0.5, 0.95, 0.5, true};
    s.time_steps[0].dynamic_obstacles =
        place_randomly(rng, split_facets(24 + 4 * i, 2 + i), shape, "robot part", avoid);
    CAMPLACE_ASSERT(s.time_steps[0].dynamic_obstacles.size() == static_cast<std::size_t>(2 + i));
  } else if (f == "dynamic_steps") {
    s.time_steps.clear();
    for (int h = 0; h < i; ++h) {
      s.time_steps.push_back(time_step(finer_all(two_link_robot(h), 4), person_events(3, 4)));
    }
  } else if (f == "unmodelled_facets") {
    for (core::TimeStep& step : s.time_steps) step.events = person_events(3, 4 + 10 * i);
  } else if (f == "unmodelled_objects") {
    std::vector<Box3> avoid = boxes_of(s.static_obstacles);
    for (const core::TimeStep& step : s.time_steps) {
      const std::vector<Box3> b = boxes_of(step.dynamic_obstacles);
      avoid.insert(avoid.end(), b.begin(), b.end());
    }
    // Person-part-like pyramids 1.5–1.9 m tall (≥ 1.45 m, see the file comment), alternately
    // upright (like legs-head) and inverted (like shoulders-feet).
    const PyramidShape shape{0.15, 0.3, 1.5, 1.9, 0.3, false};
    const core::Event event{
        1.0, place_randomly(rng, split_facets(24 + 4 * i, 2 + i), shape, "target", avoid)};
    CAMPLACE_ASSERT(event.targets.size() == static_cast<std::size_t>(2 + i));
    for (core::TimeStep& step : s.time_steps) step.events = {event};
  } else if (f == "unmodelled_events") {
    s.time_steps.clear();
    for (int h = 0; h < 3; ++h) {
      s.time_steps.push_back(time_step(finer_all(robot_pose(h), 4), person_events(i, 4)));
    }
  } else if (f == "cameras") {
    s.cameras.count = i;
  } else if (f == "domain_ceiling") {
    g.domain = "ceiling";
  } else if (f == "domain_upper_fourth") {
    g.domain = "upper_fourth";
  }
  finish(g);
  return g;
}

// ---------------------------------------------------------------------------------------------
// Families on another base scene

/// Thrown when `family` cannot be applied to the base: names the family, the base and why.
[[noreturn]] void not_applicable(const SceneFamily& family, const BaseScene& base,
                                 const std::string& reason) {
  throw core::OptionError("base", "family " + family.name +
                                      " cannot be applied to the base scene " + base.label + ": " +
                                      reason);
}

/// `objects` with `facets` facets each (finer()); every one must be a tetrahedron (4 vertices,
/// 4 facets, as the loader makes of a "tetrahedron" entry: base triangle, then apex).
std::vector<SceneObject> finer_objects(const SceneFamily& family, const BaseScene& base,
                                       const std::vector<SceneObject>& objects, int facets,
                                       const std::string& what) {
  std::vector<SceneObject> out;
  for (const SceneObject& o : objects) {
    if (o.mesh.vertices.size() != 4 || o.mesh.triangles.size() != 4) {
      not_applicable(family, base,
                     what + " \"" + o.name + "\" has " + std::to_string(o.mesh.triangles.size()) +
                         " facets; only tetrahedra are made finer");
    }
    NamedTetra t{o.name,
                 {o.mesh.vertices[0], o.mesh.vertices[1], o.mesh.vertices[2], o.mesh.vertices[3]}};
    out.push_back(finer(t, facets));
  }
  return out;
}

/// Same names and vertices (a step's critical objects left at their default, SPEC §2).
bool same_objects(const std::vector<SceneObject>& a, const std::vector<SceneObject>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].name != b[i].name || a[i].mesh.vertices != b[i].mesh.vertices) return false;
  }
  return true;
}

/// The smallest target part's volume and z-extent rounded down (as finish() sets them).
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

GeneratedScene build_on_base(const SceneFamily& family, int i, unsigned seed,
                             const BaseScene& base) {
  GeneratedScene g;
  g.scene = base.scene;
  g.domain.clear();  // the base's domains stay unless the family sets a preset
  core::Scene& s = g.scene;
  const Box3& area = s.area;
  const std::string& f = family.name;
  std::mt19937 rng(seed);
  // Critical objects left at their default follow the dynamic obstacles they copy.
  std::vector<bool> default_critical;
  for (const core::TimeStep& step : s.time_steps) {
    default_critical.push_back(same_objects(step.critical, step.dynamic_obstacles));
  }
  bool new_targets = false;
  if (f == "resolution") {
    for (int a = 0; a < 3; ++a) {
      s.voxels[a] = static_cast<int>(std::lround(base.scene.voxels[a] * (4.0 + i) / 4.0));
    }
    const std::string problem = core::resolution_problem(s.voxels);
    if (!problem.empty()) not_applicable(family, base, problem);
  } else if (f == "static_facets") {
    if (s.static_obstacles.empty()) not_applicable(family, base, "it has no static obstacles");
    s.static_obstacles =
        finer_objects(family, base, s.static_obstacles, 4 + 30 * i, "static obstacle");
  } else if (f == "static_objects") {
    // The paper's extra furniture at the same place relative to the floor (x, y stretched from
    // the paper's S to the base's), at its own height above the base's floor.
    std::vector<NamedTetra> extra = extra_static();
    extra.resize(i);
    for (NamedTetra& t : extra) {
      for (Vec3& p : t.points) {
        p = rounded(
            Vec3(area.min.x() + (p.x() - kArea.min.x()) * area.size().x() / kArea.size().x(),
                 area.min.y() + (p.y() - kArea.min.y()) * area.size().y() / kArea.size().y(),
                 area.min.z() + p.z()));
      }
      s.static_obstacles.push_back(tetra_object(t));
    }
  } else if (f == "dynamic_facets") {
    bool any = false;
    for (core::TimeStep& step : s.time_steps) {
      any = any || !step.dynamic_obstacles.empty();
      step.dynamic_obstacles =
          finer_objects(family, base, step.dynamic_obstacles, 4 + 10 * i, "dynamic obstacle");
    }
    if (!any) not_applicable(family, base, "it has no dynamic obstacles");
  } else if (f == "dynamic_objects") {
    s.time_steps.resize(1);
    default_critical.resize(1);
    // A base with explicit critical objects keeps them (they are what must be observed).
    std::vector<Box3> avoid = boxes_of(s.static_obstacles);
    for (const core::Event& e : s.time_steps[0].events) {
      const std::vector<Box3> b = boxes_of(e.targets);
      avoid.insert(avoid.end(), b.begin(), b.end());
    }
    const PyramidShape shape{0.15, 0.3, 0.5, 0.95, 0.5, true};
    s.time_steps[0].dynamic_obstacles =
        place_randomly(rng, split_facets(24 + 4 * i, 2 + i), shape, "robot part", avoid, area);
    if (s.time_steps[0].dynamic_obstacles.empty()) {
      not_applicable(family, base,
                     "no room for " + std::to_string(2 + i) +
                         " objects 0.5-0.95 m tall and up to 0.6 m wide, 0.1 m clear of the "
                         "other objects and the walls (seed " +
                         std::to_string(seed) + ")");
    }
  } else if (f == "dynamic_steps") {
    not_applicable(family, base,
                   "the family moves the paper's robot arm over i time steps; it applies to the "
                   "paper's basic setup only (no base)");
  } else if (f == "unmodelled_facets") {
    for (core::TimeStep& step : s.time_steps) {
      for (core::Event& e : step.events) {
        e.targets = finer_objects(family, base, e.targets, 4 + 10 * i, "target");
      }
    }
  } else if (f == "unmodelled_objects") {
    std::vector<Box3> avoid = boxes_of(s.static_obstacles);
    for (const core::TimeStep& step : s.time_steps) {
      const std::vector<Box3> b = boxes_of(step.dynamic_obstacles);
      avoid.insert(avoid.end(), b.begin(), b.end());
    }
    const PyramidShape shape{0.15, 0.3, 1.5, 1.9, 0.3, false};
    const core::Event event{
        1.0, place_randomly(rng, split_facets(24 + 4 * i, 2 + i), shape, "target", avoid, area)};
    if (event.targets.empty()) {
      not_applicable(family, base,
                     "no room for " + std::to_string(2 + i) +
                         " targets 1.5-1.9 m tall and up to 0.6 m wide, 0.1 m clear of the "
                         "obstacles and the walls (seed " +
                         std::to_string(seed) + ")");
    }
    for (core::TimeStep& step : s.time_steps) step.events = {event};
    new_targets = true;
  } else if (f == "unmodelled_events") {
    for (std::size_t h = 0; h < s.time_steps.size(); ++h) {
      std::vector<core::Event>& events = s.time_steps[h].events;
      if (static_cast<int>(events.size()) < i) {
        not_applicable(family, base,
                       "i = " + std::to_string(i) + " needs " + std::to_string(i) +
                           " events in every time step, and its time step " + std::to_string(h) +
                           " has " + std::to_string(events.size()));
      }
      double all = 0.0, kept = 0.0;
      for (std::size_t l = 0; l < events.size(); ++l) {
        all += events[l].weight;
        if (static_cast<int>(l) < i) kept += events[l].weight;
      }
      if (!(kept > 0.0)) {
        not_applicable(family, base,
                       "the first " + std::to_string(i) + " events of time step " +
                           std::to_string(h) + " all have weight 0");
      }
      events.resize(i);
      for (core::Event& e : events) e.weight *= all / kept;
    }
  } else if (f == "cameras") {
    for (const core::CameraDomain& d : s.cameras.domains) {
      const core::CameraDomain& d0 = s.cameras.domains.front();
      const bool same = d.x.lo == d0.x.lo && d.x.hi == d0.x.hi && d.y.lo == d0.y.lo &&
                        d.y.hi == d0.y.hi && d.z.lo == d0.z.lo && d.z.hi == d0.z.hi &&
                        d.yaw.lo == d0.yaw.lo && d.yaw.hi == d0.yaw.hi &&
                        d.pitch.lo == d0.pitch.lo && d.pitch.hi == d0.pitch.hi &&
                        d.roll.lo == d0.roll.lo && d.roll.hi == d0.roll.hi;
      if (!same) {
        not_applicable(family, base,
                       "its cameras have different domains (\"camera_domains\"); the family "
                       "needs one domain shared by every camera");
      }
    }
    if (!s.cameras.one_model()) {
      not_applicable(family, base,
                     "its cameras have different models (\"cameras.models\"); the family needs "
                     "one model shared by every camera");
    }
    s.cameras.resize(1);
    s.cameras.resize(i);
  } else if (f == "domain_ceiling") {
    g.domain = "ceiling";
  } else if (f == "domain_upper_fourth") {
    g.domain = "upper_fourth";
  }
  if (!g.domain.empty()) {
    s.cameras.domains.assign(s.cameras.count, *core::domain_preset(area, g.domain));
  }
  for (std::size_t h = 0; h < s.time_steps.size(); ++h) {
    if (default_critical[h]) s.time_steps[h].critical = s.time_steps[h].dynamic_obstacles;
  }
  // New targets: thresholds from the smallest target part, as for the paper's scenes; finer
  // targets keep their volume and height, so the base's thresholds stay.
  if (new_targets) s.plausibility = smallest_target(s);
  s.file.clear();
  s.mesh_files.clear();
  return g;
}

/// Throws not_applicable with the loader's reason when the generated scene `text` does not load
/// (an object leaving S, a target meeting an obstacle, ...).
void check_loads(const SceneFamily& family, const BaseScene& base, const std::string& text) {
  namespace fs = std::filesystem;
  static std::atomic<unsigned> counter{0};
  const fs::path file =
      fs::temp_directory_path() / ("camplace-generated-" + std::to_string(::getpid()) + "-" +
                                   std::to_string(counter++) + ".json");
  core::write_file_atomically(file.string(), text);
  std::string problem;
  try {
    (void)core::load_scene(file.string());
  } catch (const core::InputError& e) {
    problem = "the scene it makes is not valid: " + e.reason() +
              (e.entry().empty() ? "" : " (at " + e.entry() + ")");
  }
  std::error_code ec;
  fs::remove(file, ec);
  if (!problem.empty()) not_applicable(family, base, problem);
}

// ---------------------------------------------------------------------------------------------
// Output

std::size_t facets_of(const std::vector<SceneObject>& objects) {
  std::size_t n = 0;
  for (const SceneObject& o : objects) n += o.mesh.triangles.size();
  return n;
}

/// Internal invariants of every generated scene (the scene loader checks the rest).
void check_invariants(const core::Scene& s) {
  CAMPLACE_ASSERT(!s.time_steps.empty());
  for (const core::TimeStep& step : s.time_steps) {
    CAMPLACE_ASSERT(!step.critical.empty());
    for (const SceneObject& o : step.dynamic_obstacles) {
      CAMPLACE_ASSERT(o.bounds.max.z() < kDynamicTopLimit);
    }
    double sum = 0.0;
    for (const core::Event& e : step.events) {
      sum += e.weight;
      for (const SceneObject& o : e.targets) {
        CAMPLACE_ASSERT(o.bounds.size().z() >= kTargetMinHeight);
      }
    }
    CAMPLACE_ASSERT(std::abs(sum - 1.0) < 1e-12);
  }
}

std::string describe(const SceneFamily& family, std::optional<int> param, unsigned seed,
                     const GeneratedScene& g, const BaseScene* base) {
  const core::Scene& s = g.scene;
  std::size_t dyn_facets = 0, dyn_objects = 0;
  for (const core::TimeStep& step : s.time_steps) {
    dyn_facets += facets_of(step.dynamic_obstacles);
    dyn_objects += step.dynamic_obstacles.size();
  }
  const std::vector<core::Event>& events = s.time_steps[0].events;
  std::size_t target_facets = 0, target_objects = 0;
  for (const core::Event& e : events) {
    target_facets += facets_of(e.targets);
    target_objects += e.targets.size();
  }
  std::ostringstream d;
  d << "Generated by `camplace generate " << family.name;
  if (param) d << " --param " << *param;
  d << " --seed " << seed;
  if (base) {
    // The base's content hash: a changed base (or mesh file) changes every scene made from it.
    d << " --base " << base->label << "` from the base scene " << base->label
      << " (SHA-256 of it and its mesh files " << base->hashes.combined << "): family "
      << family.name;
  } else {
    d << "` from the paper's basic setup (data/paper_basic.json): family " << family.name;
  }
  if (param) d << ", param i = " << *param;
  d << " (" << (base && !family.on_base.empty() ? family.on_base : family.what) << "), seed "
    << seed << (family.random ? "" : " (the placement does not depend on the seed)") << ". Static "
    << facets_of(s.static_obstacles) << " facets at " << s.static_obstacles.size()
    << " objects; dynamic " << dyn_facets << " facets at " << dyn_objects << " objects in "
    << s.time_steps.size() << " time step" << (s.time_steps.size() == 1 ? "" : "s")
    << "; unmodelled " << target_facets << " facets at " << target_objects << " objects in "
    << events.size() << " event" << (events.size() == 1 ? "" : "s")
    << (base ? " (in the first time step); " : " (the same targets in every time step); ")
    << s.cameras.count << " cameras, domain " << (g.domain.empty() ? "of the base" : g.domain)
    << "; voxels " << s.voxels[0] << "x" << s.voxels[1] << "x" << s.voxels[2] << "." << g.note;
  return d.str();
}

const SceneFamily& find_family(const std::string& name) {
  for (const SceneFamily& f : kFamilies) {
    if (f.name == name) return f;
  }
  std::string names;
  for (const SceneFamily& f : kFamilies) names += (names.empty() ? "" : ", ") + f.name;
  throw core::OptionError("family",
                          "unknown scene family \"" + name + "\" (expected one of: " + names + ")");
}

void check_param(const SceneFamily& f, std::optional<int> param) {
  const std::string range =
      "[" + std::to_string(f.min_param) + ", " + std::to_string(f.max_param) + "]";
  if (f.has_param && !param) {
    throw core::OptionError(
        "param", "family " + f.name + " needs a parameter i in " + range + " (" + f.what + ")");
  }
  if (!f.has_param && param) {
    throw core::OptionError("param", "family " + f.name + " takes no parameter");
  }
  if (param && (*param < f.min_param || *param > f.max_param)) {
    throw core::OptionError("param", "family " + f.name + " takes i in " + range + " (" + f.what +
                                         "), got " + std::to_string(*param));
  }
}

}  // namespace

const std::vector<SceneFamily>& scene_families() { return kFamilies; }

BaseScene load_base_scene(const std::string& path, const std::string& label) {
  BaseScene base;
  base.scene = core::load_scene(path);
  base.label = label;
  base.hashes = core::hash_scene(base.scene);
  return base;
}

std::string generate_scene_json(const std::string& family, std::optional<int> param, unsigned seed,
                                const BaseScene* base) {
  const SceneFamily& f = find_family(family);
  check_param(f, param);
  if (!base) {
    const GeneratedScene g = build(f, param.value_or(0), seed);
    check_invariants(g.scene);
    // The scene file as the scene writer writes it; the description names family, param, seed.
    return core::scene_text(g.scene, describe(f, param, seed, g, nullptr));
  }
  const GeneratedScene g = build_on_base(f, param.value_or(0), seed, *base);
  const std::string text = core::scene_text(g.scene, describe(f, param, seed, g, base));
  check_loads(f, *base, text);
  return text;
}

std::string write_generated_scene(const std::string& family, std::optional<int> param,
                                  unsigned seed, const std::string& path, const BaseScene* base) {
  namespace fs = std::filesystem;
  const std::string text = generate_scene_json(family, param, seed, base);
  // Written beside the target and validated there (the loader checks everything SPEC §2 lists),
  // then renamed: a scene that does not load is never published.
  std::error_code ec;
  if (path.empty() || fs::is_directory(path, ec)) {
    throw core::OptionError("out", "\"" + path + "\" is not a file name");
  }
  const std::string check = path + ".check" + std::to_string(::getpid());
  try {
    core::write_file_atomically(check, text);
  } catch (const std::exception& e) {
    throw core::OptionError("out", e.what());
  }
  try {
    (void)core::load_scene(check);
  } catch (const std::exception& e) {
    std::error_code ec;
    fs::remove(check, ec);
    throw std::logic_error("internal error: the generated scene does not load: " +
                           std::string(e.what()));
  }
  fs::rename(check, path, ec);
  if (ec) {
    const std::string reason = ec.message();
    fs::remove(check, ec);
    throw core::OptionError("out", path + ": cannot write: " + reason);
  }
  return nlohmann::json::parse(text)["description"].get<std::string>();
}

}  // namespace camplace::compare
