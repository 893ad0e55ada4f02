#include "scene_builder.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace camplace::testing {

using core::Vec3;
constexpr double kDeg = 3.14159265358979323846 / 180.0;

core::SceneObject box_object(const std::string& name, const Vec3& lo, const Vec3& hi) {
  core::SceneObject o;
  o.name = o.entry = name;
  for (int i = 0; i < 8; ++i) {
    o.mesh.vertices.emplace_back((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(),
                                 (i & 4) ? hi.z() : lo.z());
  }
  o.mesh.triangles = {{0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}, {0, 1, 5}, {0, 5, 4},
                      {2, 6, 7}, {2, 7, 3}, {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}};
  o.bounds = core::bounding_box(o.mesh);
  return o;
}

core::TriangleMesh ellipsoid_mesh(const core::Box3& box, int triangles) {
  if (triangles < 6 || triangles % 2 != 0) {
    throw std::invalid_argument("ellipsoid_mesh: the triangle count must be even and at least 6");
  }
  const Vec3 radii = 0.5 * box.size();
  if (!(radii.minCoeff() > 0.0)) throw std::invalid_argument("ellipsoid_mesh: empty box");
  // 2·m·(b − 1) = triangles: pick d = b − 1 among the divisors of triangles/2 with m ≥ 3.
  const int half = triangles / 2;
  const double ideal = std::sqrt(triangles / 4.0);
  int d = 1;
  for (int k = 1; k <= half / 3; ++k) {
    if (half % k == 0 && std::abs(k - ideal) < std::abs(d - ideal)) d = k;
  }
  const int m = half / d, bands = d + 1;
  const Vec3 c = box.center();
  core::TriangleMesh mesh;
  // Vertex 0 the top pole, then rings 1..b−1 from the top (m vertices each), then the bottom.
  mesh.vertices.push_back(c + Vec3(0, 0, radii.z()));
  for (int i = 1; i < bands; ++i) {
    const double phi = core::kPi * i / bands;
    for (int j = 0; j < m; ++j) {
      const double theta = 2.0 * core::kPi * j / m;
      mesh.vertices.push_back(c + Vec3(radii.x() * std::sin(phi) * std::cos(theta),
                                       radii.y() * std::sin(phi) * std::sin(theta),
                                       radii.z() * std::cos(phi)));
    }
  }
  const int bottom = static_cast<int>(mesh.vertices.size());
  mesh.vertices.push_back(c - Vec3(0, 0, radii.z()));
  auto ring = [&](int i, int j) { return 1 + (i - 1) * m + (j % m); };
  // Counter-clockwise seen from outside: (upper, lower j, lower j + 1) around +z.
  for (int j = 0; j < m; ++j) mesh.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int i = 1; i + 1 < bands; ++i) {
    for (int j = 0; j < m; ++j) {
      mesh.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      mesh.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  }
  for (int j = 0; j < m; ++j) {
    mesh.triangles.push_back({bottom, ring(bands - 1, j + 1), ring(bands - 1, j)});
  }
  return mesh;
}

core::SceneObject mesh_object(const std::string& name, core::TriangleMesh mesh) {
  core::SceneObject o;
  o.name = o.entry = name;
  o.mesh = std::move(mesh);
  o.bounds = core::bounding_box(o.mesh);
  return o;
}

core::SceneObject ellipsoid_object(const std::string& name, const core::Box3& box, int triangles) {
  return mesh_object(name, ellipsoid_mesh(box, triangles));
}

core::SceneObject tetra_object(const std::string& name, const Vec3& a, const Vec3& b, const Vec3& c,
                               const Vec3& d) {
  core::SceneObject o;
  o.name = o.entry = name;
  o.mesh.vertices = {a, b, c, d};
  o.mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  if ((b - a).cross(c - a).dot(d - a) < 0) {
    for (auto& t : o.mesh.triangles) std::swap(t[1], t[2]);
  }
  o.bounds = core::bounding_box(o.mesh);
  return o;
}

core::Scene simple_scene(const core::Box3& area, std::array<int, 3> voxels, int count,
                         double half_angle_deg, std::vector<core::SceneObject> critical,
                         std::vector<core::SceneObject> targets) {
  core::Scene s;
  s.file = "<test scene>";
  s.area = area;
  s.voxels = voxels;
  s.cameras.count = count;
  core::CameraModel model;
  model.half_angle = half_angle_deg * kDeg;
  s.cameras.models.assign(count, model);
  core::CameraDomain domain;
  domain.x = {area.min.x(), area.max.x()};
  domain.y = {area.min.y(), area.max.y()};
  domain.z = {area.min.z(), area.max.z()};
  s.cameras.domains.assign(count, domain);
  core::TimeStep step;
  step.critical = std::move(critical);
  core::Event event;
  event.weight = 1.0;
  event.targets = std::move(targets);
  step.events.push_back(std::move(event));
  s.time_steps.push_back(std::move(step));
  return s;
}

core::CameraSetting camera_at(const Vec3& position, double yaw_deg, double pitch_deg) {
  return {position, yaw_deg * kDeg, pitch_deg * kDeg};
}

namespace {
core::SceneObject random_object(std::mt19937& rng, const std::string& name, const Vec3& cell_lo,
                                const Vec3& cell_hi) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto point = [&] {
    return Vec3(cell_lo.x() + unit(rng) * (cell_hi.x() - cell_lo.x()),
                cell_lo.y() + unit(rng) * (cell_hi.y() - cell_lo.y()),
                cell_lo.z() + unit(rng) * (cell_hi.z() - cell_lo.z()));
  };
  if (unit(rng) < 0.5) {
    const Vec3 a = point(), b = point();
    Vec3 lo = a.cwiseMin(b), hi = a.cwiseMax(b);
    hi = hi.cwiseMax(lo + Vec3::Constant(0.05)).cwiseMin(cell_hi);
    lo = lo.cwiseMin(hi - Vec3::Constant(0.05));
    return box_object(name, lo, hi);
  }
  for (;;) {
    const Vec3 a = point(), b = point(), c = point(), d = point();
    if (std::abs((b - a).cross(c - a).dot(d - a)) > 1e-3) return tetra_object(name, a, b, c, d);
  }
}

}  // namespace

core::Scene random_scene(std::mt19937& rng, std::array<int, 3> voxels) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const core::Box3 area{Vec3(0, 0, 0), Vec3(4, 3, 3)};
  // 4×3×2 cells of 1×1×1.5 m; each object gets its own cell shrunk by 0.1 m.
  std::vector<int> cells(24);
  for (int i = 0; i < 24; ++i) cells[i] = i;
  std::shuffle(cells.begin(), cells.end(), rng);
  int next = 0;
  auto object_in_next_cell = [&](const std::string& name) {
    const int c = cells[next++];
    const Vec3 lo(c % 4, (c / 4) % 3, 1.5 * (c / 12));
    return random_object(rng, name, lo + Vec3::Constant(0.1), lo + Vec3(0.9, 0.9, 1.4));
  };
  core::Scene s = simple_scene(area, voxels, 3, 20.0 + 40.0 * unit(rng), {}, {});
  s.time_steps.clear();
  s.static_obstacles.push_back(object_in_next_cell("static 0"));
  s.static_obstacles.push_back(object_in_next_cell("static 1"));
  for (int h = 0; h < 2; ++h) {
    core::TimeStep step;
    step.dynamic_obstacles.push_back(object_in_next_cell("dynamic"));
    step.critical = step.dynamic_obstacles;
    for (int l = 0; l < 2; ++l) {
      core::Event e;
      e.weight = 0.5;
      e.targets.push_back(object_in_next_cell("target a"));
      e.targets.push_back(object_in_next_cell("target b"));
      step.events.push_back(e);
    }
    s.time_steps.push_back(step);
  }
  const core::FovShape shape = unit(rng) < 0.5 ? core::FovShape::cone : core::FovShape::pyramid;
  const int sides = 3 + static_cast<int>(unit(rng) * 14);
  const bool ranged = unit(rng) < 0.3;
  const double range = 2.0 + 3.0 * unit(rng);
  for (core::CameraModel& m : s.cameras.models) {
    m.fov = shape;
    m.sides = sides;
    if (ranged) m.range = range;
  }
  s.dynamic_mode = unit(rng) < 0.5 ? core::DynamicMode::masked : core::DynamicMode::modelled;
  return s;
}

core::Scene with_fine_meshes(core::Scene scene, int triangles) {
  auto refine = [&](std::vector<core::SceneObject>& objects) {
    for (core::SceneObject& o : objects) {
      const std::string entry = o.entry;
      o = ellipsoid_object(o.name, o.bounds, triangles);
      o.entry = entry;
    }
  };
  refine(scene.static_obstacles);
  for (core::TimeStep& step : scene.time_steps) {
    refine(step.dynamic_obstacles);
    refine(step.critical);
    for (core::Event& event : step.events) refine(event.targets);
  }
  return scene;
}

void put_on_walls(std::mt19937& rng, const core::Scene& scene, core::CameraConfig& config) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::size_t i = 0; i < config.size(); i += 2) {
    core::Vec3& p = config[i].position;
    const int axis = int(unit(rng) * 2.0);  // x or y wall
    p[axis] = unit(rng) < 0.5 ? scene.area.min[axis] : scene.area.max[axis];
    const core::Vec3 at = scene.area.min + scene.area.size().cwiseProduct(
                                               core::Vec3(unit(rng), unit(rng), 0.5 * unit(rng)));
    const core::Vec3 d = (at - p).normalized();
    config[i].yaw = std::atan2(d.y(), d.x());
    config[i].pitch = std::asin(d.z());
  }
}

core::CameraConfig random_config(std::mt19937& rng, const core::Scene& scene) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  core::CameraConfig config;
  for (int i = 0; i < scene.cameras.count; ++i) {
    const Vec3 p = scene.area.min + unit(rng) * Vec3::UnitX() * scene.area.size().x() +
                   unit(rng) * Vec3::UnitY() * scene.area.size().y() +
                   unit(rng) * Vec3::UnitZ() * scene.area.size().z();
    config.push_back(camera_at(p, -180 + 360 * unit(rng), -90 + 180 * unit(rng)));
  }
  return config;
}

std::string write_file(const std::string& path, const std::string& text) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

namespace {

/// Removes the test's scratch directories when the test program ends (set
/// CAMPLACE_KEEP_TEST_FILES to keep them for inspection).
struct ScratchDirectories {
  std::vector<std::filesystem::path> dirs;
  ~ScratchDirectories() {
    if (std::getenv("CAMPLACE_KEEP_TEST_FILES") != nullptr) return;
    std::error_code ec;
    for (const auto& dir : dirs) std::filesystem::remove_all(dir, ec);
  }
};

ScratchDirectories& scratch_directories() {
  static ScratchDirectories registry;
  return registry;
}

}  // namespace

std::string temp_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("camplace-test-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  scratch_directories().dirs.push_back(dir);
  return dir.string();
}

std::vector<core::CameraConfig> configs_around(const core::CameraConfig& base,
                                               const core::Scene& scene, unsigned seed,
                                               int jittered, int random) {
  std::vector<core::CameraConfig> out{base};
  std::mt19937 rng(seed);
  std::normal_distribution<double> jitter(0.0, 1.0);
  for (int n = 0; n < jittered; ++n) {
    core::CameraConfig c = base;
    for (core::CameraSetting& s : c) {
      s.position += 0.1 * core::Vec3(jitter(rng), jitter(rng), jitter(rng));
      s.position = s.position.cwiseMax(scene.area.min).cwiseMin(scene.area.max);
      s.yaw += 0.05 * jitter(rng);
      s.pitch = std::clamp(s.pitch + 0.05 * jitter(rng), -1.5, 1.5);
    }
    out.push_back(c);
  }
  for (int n = 0; n < random; ++n) out.push_back(random_config(rng, scene));
  return out;
}

CellRoom cell_room(std::mt19937& rng) {
  std::vector<int> cells(24);
  for (int i = 0; i < 24; ++i) cells[i] = i;
  std::shuffle(cells.begin(), cells.end(), rng);
  CellRoom room;
  for (int c : cells)
    room.cells.emplace_back(c % 4 + 0.5, (c / 4) % 3 + 0.5, 1.5 * (c / 12) + 0.75);
  const core::Box3 area{core::Vec3(0, 0, 0), core::Vec3(4, 3, 3)};
  room.scene = simple_scene(area, {8, 6, 6}, 2 + int(rng() % 2), 30.0, {}, {});
  randomize_camera_models(rng, room.scene);
  core::use_exact_models(room.scene.cameras);
  return room;
}

void randomize_camera_models(std::mt19937& rng, core::Scene& scene) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < scene.cameras.count; ++i) {
    core::CameraModel& m = scene.cameras.models[i];
    m = core::CameraModel{};
    m.name = "m" + std::to_string(i);
    if (i % 3 < 2) {
      m.fov = core::FovShape::frustum;
      m.horizontal = (20.0 + 150.0 * unit(rng)) * kDeg;
      m.vertical = (20.0 + 130.0 * unit(rng)) * kDeg;
    } else {
      m.fov = unit(rng) < 0.5 ? core::FovShape::pyramid : core::FovShape::cone;
      m.half_angle = (15.0 + 50.0 * unit(rng)) * kDeg;
      m.sides = 3 + static_cast<int>(unit(rng) * 14);
    }
    if (unit(rng) < 0.5) m.near = 0.05 + 0.75 * unit(rng);
    if (unit(rng) < 0.33) m.range = 2.0 + 3.0 * unit(rng);
  }
}

void randomize_rolls(std::mt19937& rng, core::CameraConfig& config) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (core::CameraSetting& c : config) c.roll = (-180.0 + 360.0 * unit(rng)) * kDeg;
}

}  // namespace camplace::testing
