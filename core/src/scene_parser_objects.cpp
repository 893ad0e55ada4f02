// Scene loading (SPEC §2): the scene parser's objects, events, robots and time steps, and the
// check that no target meets an obstacle of its own state.
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>

#include "camplace/core/json_reader.hpp"
#include "camplace/core/names.hpp"
#include "mesh_checks.hpp"
#include "mesh_repair.hpp"
#include "people.hpp"
#include "robot.hpp"
#include "scene_format.hpp"
#include "scene_limits.hpp"
#include "scene_parser.hpp"

namespace camplace::core {

namespace {

void apply_transform(TriangleMesh& mesh, const JsonNode& node) {
  node.only_keys({"scale", "rotate_deg", "translate"});
  Vec3 scale = Vec3::Ones();
  if (node.has("scale")) {
    const JsonNode s = node.at("scale");
    scale = s.value().is_array() ? s.vec3() : Vec3::Constant(s.number());
    if ((scale.array() == 0.0).any()) s.fail("scale must not be 0");
  }
  const Eigen::Matrix3d rotation = node.has("rotate_deg")
                                       ? detail::rotation_deg(node.at("rotate_deg").vec3())
                                       : Eigen::Matrix3d::Identity();
  const Vec3 translation = node.has("translate") ? node.at("translate").vec3() : Vec3::Zero();
  for (Vec3& v : mesh.vertices) v = rotation * scale.cwiseProduct(v) + translation;
}

}  // namespace

namespace detail {

const char* SceneParser::role_name(Role role) {
  switch (role) {
    case Role::static_obstacle:
      return "static obstacle";
    case Role::dynamic_obstacle:
      return "dynamic obstacle";
    case Role::critical:
      return "critical object";
    case Role::target:
      return "target";
  }
  return "object";
}

SceneObject SceneParser::parse_object(const JsonNode& node, Role role) const {
  node.only_keys(
      {"name", "box", "tetrahedron", "mesh", "file", "transform", "units", "up_axis", "repair"});
  const detail::MeshFileOptions file_options = detail::parse_mesh_file_options(node);
  const detail::RepairOptions repair =
      node.has("repair") ? detail::parse_repair(node.at("repair")) : default_repair_;
  SceneObject object;
  object.entry = node.pointer();
  object.name = node.has("name") ? node.at("name").string() : node.pointer();
  int kinds = 0;
  for (const char* k : {"box", "tetrahedron", "mesh", "file"}) kinds += node.has(k);
  if (kinds != 1) node.fail("an object needs exactly one of box, tetrahedron, mesh or file");
  if (node.has("box")) {
    const JsonNode b = node.at("box");
    b.only_keys({"min", "max"});
    const Vec3 lo = b.at("min").vec3(), hi = b.at("max").vec3();
    if (!((lo.array() < hi.array()).all()))
      b.fail("box is degenerate: min must be below max on every axis");
    object.mesh = detail::box_mesh(lo, hi);
  } else if (node.has("tetrahedron")) {
    const JsonNode t = node.at("tetrahedron");
    if (t.array_size() != 4) t.fail("a tetrahedron needs exactly 4 points");
    std::vector<Vec3> points;
    for (std::size_t i = 0; i < 4; ++i) points.push_back(t.at(i).vec3());
    object.mesh = detail::tetrahedron_mesh(points);
  } else if (node.has("mesh")) {
    const JsonNode m = node.at("mesh");
    m.only_keys({"vertices", "triangles"});
    const JsonNode verts = m.at("vertices"), tris = m.at("triangles");
    const std::size_t n_verts = limited_size(verts, kMaxInlineMesh, "vertices of a mesh");
    const std::size_t n_tris = limited_size(tris, kMaxInlineMesh, "triangles of a mesh");
    for (std::size_t i = 0; i < n_verts; ++i) object.mesh.vertices.push_back(verts.at(i).vec3());
    for (std::size_t i = 0; i < n_tris; ++i) {
      const JsonNode t = tris.at(i);
      if (t.array_size() != 3) t.fail("a triangle needs exactly 3 vertex indices");
      std::array<int, 3> tri{};
      for (std::size_t k = 0; k < 3; ++k) {
        tri[k] = t.at(k).integer_in(0, static_cast<int>(verts.array_size()) - 1);
      }
      object.mesh.triangles.push_back(tri);
    }
  } else {
    const JsonNode f = node.at("file");
    const std::filesystem::path rel = f.string();
    const std::string full = (rel.is_absolute() ? rel : dir_ / rel).string();
    object.mesh = detail::read_mesh_file(full, path_, f.pointer(), file_options);
    note_file(full);
  }
  if (node.has("transform")) apply_transform(object.mesh, node.at("transform"));
  finish_object_mesh(object.mesh, repair, node.pointer(), object.name, role_name(role));
  object.bounds = bounding_box(object.mesh);
  const Box3& s = scene_.area;
  if (role == Role::target && ((object.bounds.min.array() < s.min.array() - kAreaSlack).any() ||
                               (object.bounds.max.array() > s.max.array() + kAreaSlack).any())) {
    node.fail("target \"" + object.name + "\" leaves the area S: its bounds " +
              format_vec(object.bounds.min) + "–" + format_vec(object.bounds.max) +
              " are not inside " + format_vec(s.min) + "–" + format_vec(s.max));
  }
  return object;
}

std::vector<SceneObject> SceneParser::parse_objects(const JsonNode& list, Role role) const {
  std::vector<SceneObject> objects;
  const std::size_t n = limited_size(list, kMaxObjects, "objects in one list");
  for (std::size_t i = 0; i < n; ++i) objects.push_back(parse_object(list.at(i), role));
  return objects;
}

std::vector<SceneParser::ParsedEvent> SceneParser::parse_events(const JsonNode& events) const {
  std::vector<ParsedEvent> out;
  const std::size_t n = limited_size(events, kMaxEvents, "events");
  for (std::size_t l = 0; l < n; ++l) {
    const JsonNode e = events.at(l);
    e.only_keys({"weight", "targets", "name"});
    ParsedEvent parsed;
    const JsonNode w = e.at("weight");
    parsed.event.weight = w.number();
    parsed.weight_entry = w.pointer();
    if (parsed.event.weight < 0.0) w.fail("weight must not be negative");
    const JsonNode targets = e.at("targets");
    if (targets.array_size() == 0) targets.fail("an event needs at least one target");
    parsed.event.targets = parse_objects(targets, Role::target);
    out.push_back(std::move(parsed));
  }
  return out;
}

std::vector<detail::RobotSteps> SceneParser::parse_robots(const JsonNode& list) {
  std::vector<detail::RobotSteps> robots;
  const detail::LinkMeshFinisher finish = [this](TriangleMesh& mesh, const std::string& entry,
                                                 const std::string& name) {
    finish_object_mesh(mesh, default_repair_, entry, name, role_name(Role::dynamic_obstacle));
  };
  const std::size_t n = limited_size(list, kMaxRobots, "robots");
  for (std::size_t i = 0; i < n; ++i) {
    const JsonNode node = list.at(i);
    detail::RobotSteps robot = detail::expand_robot(node, dir_, path_, finish);
    for (const std::string& f : robot.files) note_file(f);
    if (robot.times.empty() || robot.links.empty()) node.fail("the robot gives no time step");
    for (const detail::RobotSteps& other : robots) {
      if (other.name == robot.name) {
        node.fail("robot \"" + robot.name +
                  "\" is named twice (its links' objects would share "
                  "their names); give each robot its own \"name\"");
      }
    }
    if (!robots.empty() && robot.times.size() == robots.front().times.size()) {
      for (std::size_t h = 0; h < robot.times.size(); ++h) {
        const double t = robots.front().times[h];
        if (!(std::abs(robot.times[h] - t) <= 1e-9 * std::max(1.0, std::abs(t)))) {
          node.fail("robot \"" + robot.name + "\" samples t = " + format_number(robot.times[h]) +
                    " s where robot \"" + robots.front().name +
                    "\" (/robots/0) samples t = " + format_number(t) + " s (sample " +
                    std::to_string(h) + "): every robot must be sampled at the same times");
        }
      }
    }
    if (!robots.empty() && robot.times.size() != robots.front().times.size()) {
      node.fail("robot \"" + robot.name + "\" gives " + std::to_string(robot.times.size()) +
                " time steps, robot \"" + robots.front().name + "\" (/robots/0) gives " +
                std::to_string(robots.front().times.size()) +
                ": every robot must give the same number of samples");
    }
    robots.push_back(std::move(robot));
  }
  if (robots.empty()) list.fail("expected at least one robot");
  return robots;
}

void SceneParser::parse_time_steps(const JsonNode& root) {
  std::vector<detail::RobotSteps> robots;
  if (root.has("robots")) robots = parse_robots(root.at("robots"));
  const bool given = root.has("time_steps");
  if (!given && robots.empty()) {
    throw InputError(path_, "/",
                     "missing required field \"time_steps\" (or give \"robots\", whose "
                     "trajectory makes the time steps)");
  }
  std::vector<std::vector<ParsedEvent>> events;  // per step
  std::vector<bool> own_critical;                // per step: "critical" given
  std::vector<std::string> step_entry;
  if (given) {
    const JsonNode list = root.at("time_steps");
    if (limited_size(list, kMaxTimeSteps, "time steps") == 0)
      list.fail("a scene needs at least one time step");
    if (!robots.empty() && list.array_size() != robots.front().times.size()) {
      list.fail("expected one time step per sample of the robots' trajectory (" +
                std::to_string(robots.front().times.size()) + "), found " +
                std::to_string(list.array_size()));
    }
    for (std::size_t h = 0; h < list.array_size(); ++h) {
      const JsonNode node = list.at(h);
      node.only_keys({"t", "dynamic_obstacles", "critical", "events"});
      TimeStep step;
      step.t = node.has("t") ? node.at("t").number() : static_cast<double>(h);
      if (!robots.empty()) {
        const double t = robots.front().times[h];
        if (node.has("t") && !(std::abs(step.t - t) <= 1e-9 * std::max(1.0, std::abs(t)))) {
          node.at("t").fail("t " + format_number(step.t) + " differs from the robots' sample " +
                            std::to_string(h) + " at t = " + format_number(t) +
                            " (leave \"t\" out: the trajectory gives it)");
        }
        step.t = t;
      }
      if (node.has("dynamic_obstacles")) {
        step.dynamic_obstacles =
            parse_objects(node.at("dynamic_obstacles"), Role::dynamic_obstacle);
      }
      own_critical.push_back(node.has("critical"));
      if (node.has("critical")) step.critical = parse_objects(node.at("critical"), Role::critical);
      events.push_back(node.has("events") ? parse_events(node.at("events"))
                                          : std::vector<ParsedEvent>{});
      step_entry.push_back(node.pointer());
      scene_.time_steps.push_back(std::move(step));
    }
  } else {
    for (std::size_t h = 0; h < robots.front().times.size(); ++h) {
      TimeStep step;
      step.t = robots.front().times[h];
      scene_.time_steps.push_back(std::move(step));
      events.emplace_back();
      own_critical.push_back(false);
      step_entry.push_back("/robots (sample " + std::to_string(h) + ")");
    }
  }
  const std::size_t steps = scene_.time_steps.size();
  for (std::size_t h = 0; h < steps; ++h) {
    TimeStep& step = scene_.time_steps[h];
    for (const detail::RobotSteps& robot : robots) {
      step.dynamic_obstacles.insert(step.dynamic_obstacles.end(), robot.links[h].begin(),
                                    robot.links[h].end());
    }
    if (!own_critical[h]) step.critical = step.dynamic_obstacles;
    if (step.critical.empty()) {
      throw InputError(path_, step_entry[h],
                       "time step has no critical objects: give \"critical\", "
                       "\"dynamic_obstacles\" or \"robots\"");
    }
  }
  if (root.has("events")) {
    const std::vector<ParsedEvent> shared = parse_events(root.at("events"));
    for (auto& e : events) e.insert(e.end(), shared.begin(), shared.end());
  }
  if (root.has("people")) {
    const JsonNode list = root.at("people");
    std::vector<std::string> names;  // the zones' names prefix their objects': unique
    // Generated people over all steps (each a dozen meshes checked against the obstacles).
    constexpr double kMaxPeople = 100000;
    double total_people = 0;
    const std::size_t zones = limited_size(list, kMaxPeopleZones, "people zones");
    for (std::size_t i = 0; i < zones; ++i) {
      const detail::PeopleZone zone =
          detail::parse_people_zone(list.at(i), scene_.area, static_cast<int>(i));
      if (std::find(names.begin(), names.end(), zone.name) != names.end()) {
        list.at(i).fail("people zone \"" + zone.name +
                        "\" is named twice (its people's objects would share their names)");
      }
      names.push_back(zone.name);
      total_people += static_cast<double>(zone.count) * static_cast<double>(steps);
      if (total_people > kMaxPeople) {
        list.at(i).fail("the people zones give " + format_number(total_people) + " people over " +
                        std::to_string(steps) + " time steps, more than " +
                        format_number(kMaxPeople) + ": lower \"count\" or sample fewer steps");
      }
      const std::string weight_entry =
          list.at(i).has("weight") ? list.at(i).at("weight").pointer() : list.at(i).pointer();
      for (std::size_t h = 0; h < steps; ++h) {
        std::vector<const SceneObject*> obstacles;
        for (const SceneObject& o : scene_.static_obstacles) obstacles.push_back(&o);
        for (const SceneObject& o : scene_.time_steps[h].dynamic_obstacles) obstacles.push_back(&o);
        for (Event& e :
             detail::people_events(zone, obstacles, scene_.area, path_, static_cast<int>(h))) {
          events[h].push_back({std::move(e), weight_entry});
        }
      }
    }
  }
  double weight_sum = 0.0;
  // Err ≤ Σ ω · diag(S)² (kMaxErr): the largest sum of weights whose Err stays finite with a
  // wide margin. (S is parsed before the time steps.)
  const double diagonal_sq = scene_.area.diagonal() * scene_.area.diagonal();
  const double max_weight_sum = kMaxErr / diagonal_sq;
  for (std::size_t h = 0; h < steps; ++h) {
    if (events[h].empty()) {
      throw InputError(path_, given ? step_entry[h] + "/events" : step_entry[h],
                       "a time step needs at least one event (give its \"events\", the "
                       "scene's shared \"events\" or \"people\")");
    }
    for (ParsedEvent& parsed : events[h]) {
      // Checked on the sum itself, before any product with diag(S)² can overflow; a sum that
      // overflows (or a diagonal whose square underflows to 0) is caught as not finite.
      weight_sum += parsed.event.weight;
      if (!(weight_sum <= max_weight_sum) || !std::isfinite(weight_sum)) {
        throw InputError(
            path_, parsed.weight_entry,
            "weight " + format_number(parsed.event.weight) +
                " is too large: the weights up to here sum to " +
                (std::isfinite(weight_sum) ? format_number(weight_sum) : "more than any double") +
                ", and Err can reach that sum times diag(S)² = " + format_number(diagonal_sq) +
                " m², which must not exceed " + format_number(kMaxErr) +
                " m² (so that Err stays finite)");
      }
      scene_.time_steps[h].events.push_back(std::move(parsed.event));
    }
  }
  if (!(weight_sum > 0.0)) {
    throw InputError(path_, given ? "/time_steps" : "",
                     "all event weights are 0: Err would be identically 0");
  }
}

void SceneParser::check_targets_clear_of_obstacles(const JsonNode& root) const {
  // Obstacles are rigid: a target may not meet an obstacle of its own state (SPEC §2).
  for (std::size_t h = 0; h < scene_.time_steps.size(); ++h) {
    const TimeStep& step = scene_.time_steps[h];
    for (const Event& event : step.events) {
      for (const SceneObject& target : event.targets) {
        auto check = [&](const SceneObject& obstacle) {
          if (!boxes_meet(target.bounds, obstacle.bounds)) return;
          if (detail::solids_intersect(target.mesh, obstacle.mesh)) {
            throw InputError(path_, target.entry,
                             "target \"" + target.name + "\" intersects obstacle \"" +
                                 obstacle.name + "\" (" + obstacle.entry +
                                 ") of its own state (time step " + std::to_string(h) +
                                 ", t = " + format_number(step.t) + " s)");
          }
        };
        for (const SceneObject& o : scene_.static_obstacles) check(o);
        for (const SceneObject& o : step.dynamic_obstacles) check(o);
      }
    }
  }
  (void)root;
}

void SceneParser::note_file(const std::string& full) const {
  if (std::find(mesh_files_.begin(), mesh_files_.end(), full) == mesh_files_.end())
    mesh_files_.push_back(full);
}

void SceneParser::finish_object_mesh(TriangleMesh& mesh, const detail::RepairOptions& repair,
                                     const std::string& entry, const std::string& name,
                                     const char* role) const {
  if (std::optional<MeshRepair> r = detail::finish_mesh(mesh, repair, path_, entry, name)) {
    r->role = role;
    repairs_.push_back(std::move(*r));
  }
}

bool SceneParser::boxes_meet(const Box3& a, const Box3& b) {
  return (a.min.array() <= b.max.array()).all() && (b.min.array() <= a.max.array()).all();
}

}  // namespace detail
}  // namespace camplace::core
