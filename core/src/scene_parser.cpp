// Scene loading (SPEC §2): the scene parser's entry and its area, voxels, cameras, mounts and
// keep-out boxes.
#include "scene_parser.hpp"

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

namespace camplace::core {

namespace detail {

Scene SceneParser::parse() {
  const nlohmann::json doc = read_json_file(path_);
  const JsonNode root(doc, path_, "");
  root.only_keys({"area", "voxels", "cameras", "static_obstacles", "time_steps", "dynamic_mode",
                  "plausibility", "description", "name", "repair", "robots", "events", "people"});
  scene_.file = path_;
  // The scene-wide repair is every object's default (an object's own "repair" overrides it).
  if (root.has("repair")) default_repair_ = detail::parse_repair(root.at("repair"));
  parse_area(root.at("area"));
  scene_.voxels = parse_voxels(root.at("voxels"));
  parse_cameras(root.at("cameras"));
  if (root.has("dynamic_mode")) {
    const JsonNode m = root.at("dynamic_mode");
    const std::string mode = m.string();
    const auto parsed = from_name<DynamicMode>(mode);
    if (!parsed) {
      m.fail("unknown dynamic_mode \"" + mode + "\" (expected " + names_listed<DynamicMode>() +
             ")");
    }
    scene_.dynamic_mode = *parsed;
  }
  if (root.has("plausibility")) {
    const JsonNode p = root.at("plausibility");
    p.only_keys({"min_volume", "min_height"});
    if (p.has("min_volume")) scene_.plausibility.min_volume = p.at("min_volume").number_in(0, 1e9);
    if (p.has("min_height")) scene_.plausibility.min_height = p.at("min_height").number_in(0, 1e9);
  }
  if (root.has("static_obstacles")) {
    scene_.static_obstacles = parse_objects(root.at("static_obstacles"), Role::static_obstacle);
  }
  parse_time_steps(root);
  check_targets_clear_of_obstacles(root);
  scene_.mesh_files = std::move(mesh_files_);
  scene_.repairs = std::move(repairs_);
  return std::move(scene_);
}

void SceneParser::parse_area(const JsonNode& node) {
  node.only_keys({"min", "max"});
  scene_.area.min = node.at("min").vec3();
  scene_.area.max = node.at("max").vec3();
  for (const char* key : {"min", "max"}) {
    const Vec3 corner = node.at(key).vec3();
    if (corner.cwiseAbs().maxCoeff() > kMaxCoordinate) {
      node.at(key).fail("coordinates must lie within ±" + format_number(kMaxCoordinate) + " m");
    }
  }
  for (int i = 0; i < 3; ++i) {
    if (!(scene_.area.min[i] < scene_.area.max[i])) {
      node.fail("area is empty: min " + format_vec(scene_.area.min) + " must be below max " +
                format_vec(scene_.area.max) + " on every axis");
    }
  }
}

std::array<int, 3> SceneParser::parse_voxels(const JsonNode& node) const {
  if (node.array_size() != 3) node.fail("expected [nx, ny, nz]");
  std::array<int, 3> n{};
  for (std::size_t i = 0; i < 3; ++i) n[i] = node.at(i).integer_in(1, kMaxVoxelsPerAxis);
  const std::string problem = resolution_problem(n);
  if (!problem.empty()) node.fail(problem);
  return n;
}

Interval SceneParser::parse_interval(const JsonNode& node, double lo, double hi,
                                     double unit) const {
  if (node.array_size() != 2) node.fail("expected [lo, hi]");
  const double given_lo = node.at(std::size_t{0}).number();
  const double given_hi = node.at(std::size_t{1}).number();
  Interval iv{given_lo * unit, given_hi * unit};
  if (iv.lo > iv.hi) node.fail("domain is empty: lo > hi");
  if (iv.lo < lo - kAreaSlack || iv.hi > hi + kAreaSlack) {
    // The limits in the given unit, without the rounding of the unit conversion.
    std::ostringstream limits;
    limits << std::setprecision(12) << "[" << lo / unit << ", " << hi / unit << "]";
    node.fail("domain [" + format_number(given_lo) + ", " + format_number(given_hi) +
              "] leaves the allowed range " + limits.str() + (unit == 1.0 ? " of the area S" : ""));
  }
  return iv;
}

CameraDomain SceneParser::parse_domain(const JsonNode& node) const {
  const Box3& s = scene_.area;
  std::string preset = "room";
  if (node.is_string()) {
    preset = node.string();
  } else if (node.has("mount")) {
    // {"mount": name}: the camera sits on that mount.
    node.only_keys({"mount"});
    return mount_domain(node.at("mount"));
  } else {
    node.only_keys({"preset", "x", "y", "z", "yaw_deg", "pitch_deg", "roll_deg"});
    if (node.has("preset")) preset = node.at("preset").string();
  }
  const std::optional<CameraDomain> base = domain_preset(s, preset);
  if (!base) {
    (node.is_string() ? node : node.at("preset"))
        .fail("unknown domain preset \"" + preset + "\" (expected room, ceiling or upper_fourth)");
  }
  CameraDomain d = *base;
  if (node.is_object()) {
    if (node.has("x")) d.x = parse_interval(node.at("x"), s.min.x(), s.max.x(), 1.0);
    if (node.has("y")) d.y = parse_interval(node.at("y"), s.min.y(), s.max.y(), 1.0);
    if (node.has("z")) d.z = parse_interval(node.at("z"), s.min.z(), s.max.z(), 1.0);
    if (node.has("yaw_deg")) d.yaw = parse_interval(node.at("yaw_deg"), -kPi, kPi, kDegree);
    if (node.has("pitch_deg")) {
      d.pitch = parse_interval(node.at("pitch_deg"), -kPi / 2, kPi / 2, kDegree);
      d.ceiling_pitch = false;
    }
    if (node.has("roll_deg")) d.roll = parse_interval(node.at("roll_deg"), -kPi, kPi, kDegree);
  }
  return d;
}

void SceneParser::parse_range(const JsonNode& r, CameraModel& m) {
  if (r.value().is_array()) {
    if (r.array_size() != 2) r.fail("expected a far depth or [near, far] (m)");
    const double near = r.at(std::size_t{0}).number(), far = r.at(std::size_t{1}).number();
    if (!(near >= 0.0)) r.at(std::size_t{0}).fail("near must not be negative");
    if (!(far > 0.0)) r.at(std::size_t{1}).fail("range must be positive");
    if (!(near < far)) {
      r.fail("near " + format_number(near) + " must lie below far " + format_number(far));
    }
    if (far > kMaxCoordinate)
      r.at(std::size_t{1}).fail("far exceeds " + format_number(kMaxCoordinate) + " m");
    m.near = near;
    m.range = far;
    return;
  }
  const double range = r.number();
  if (!(range > 0.0)) r.fail("range must be positive");
  m.range = range;
}

CameraModel SceneParser::parse_model(const JsonNode& node) {
  CameraModel m;
  if (node.has("fov")) {
    const JsonNode f = node.at("fov");
    const std::string fov = f.string();
    const auto parsed = from_name<FovShape>(fov);
    if (!parsed) f.fail("unknown fov \"" + fov + "\" (expected " + names_listed<FovShape>() + ")");
    m.fov = *parsed;
  }
  if (m.fov == FovShape::frustum) {
    for (const char* key : {"half_angle_deg", "sides"}) {
      if (node.has(key)) node.at(key).fail(std::string(key) + " is not used by a frustum");
    }
    auto full_angle = [&](const char* key) {
      const JsonNode a = node.at(key);
      const double deg = a.number();
      if (!(deg > 0.0 && deg < 180.0)) {
        a.fail(std::string(key) + " (a full opening angle) must lie in (0, 180)");
      }
      return deg * kDegree;
    };
    m.horizontal = full_angle("horizontal_deg");
    m.vertical = full_angle("vertical_deg");
  } else {
    for (const char* key : {"horizontal_deg", "vertical_deg"}) {
      if (node.has(key)) node.at(key).fail(std::string(key) + " is used only by a frustum");
    }
    const JsonNode half = node.at("half_angle_deg");
    const double half_deg = half.number();
    if (!(half_deg > 0.0 && half_deg < 90.0)) half.fail("half_angle_deg must lie in (0, 90)");
    m.half_angle = half_deg * kDegree;
    if (node.has("sides")) m.sides = node.at("sides").integer_in(3, 1024);
  }
  if (node.has("range")) parse_range(node.at("range"), m);
  if (node.has("cost")) {
    const JsonNode cost = node.at("cost");
    m.cost = cost.number();
    if (!(*m.cost >= 0.0) || !std::isfinite(*m.cost))
      cost.fail("cost must be a finite number >= 0");
  }
  return m;
}

void SceneParser::parse_cameras(const JsonNode& node) {
  node.only_keys({"count", "half_angle_deg", "fov", "sides", "range", "cost", "horizontal_deg",
                  "vertical_deg", "models", "list", "domain", "camera_domains", "mounts", "mount",
                  "keep_out"});
  CameraSpec& c = scene_.cameras;
  if (node.has("mounts")) parse_mounts(node.at("mounts"));
  if (node.has("keep_out")) parse_keep_out(node.at("keep_out"));
  // 0: not given.
  const int count = node.has("count") ? node.at("count").integer_in(1, 256) : 0;
  if (node.has("mount") && node.has("domain")) {
    node.at("mount").fail("give either \"mount\" or \"domain\", not both");
  }
  const CameraDomain shared = node.has("mount")    ? mount_domain(node.at("mount"))
                              : node.has("domain") ? parse_domain(node.at("domain"))
                                                   : parse_domain(JsonNode(kRoom, path_, ""));
  // Where each camera's domain came from, for keep-out messages.
  std::vector<std::string> origin;
  const std::string shared_origin = node.has("mount")    ? node.at("mount").pointer()
                                    : node.has("domain") ? node.at("domain").pointer()
                                                         : node.pointer() + " (domain room)";
  std::vector<std::optional<CameraDomain>> own;  // per-camera domains of "list"
  std::vector<std::string> own_origin;
  if (!node.has("models")) {
    // The single-model form: the model's keys in the cameras block.
    for (const char* key : {"list"}) {
      if (node.has(key)) node.at(key).fail("\"list\" needs \"models\" to name");
    }
    if (count == 0) node.fail("\"count\" is required (or give \"models\")");
    c.count = count;
    c.models.assign(c.count, parse_model(node));
  } else {
    for (const char* key :
         {"half_angle_deg", "fov", "sides", "range", "cost", "horizontal_deg", "vertical_deg"}) {
      if (node.has(key)) {
        node.at(key).fail(std::string(key) +
                          " belongs in a model of \"models\" when \"models\" is given");
      }
    }
    const JsonNode list = node.at("models");
    if (limited_size(list, kMaxCameraModels, "camera models") == 0) {
      list.fail("expected at least one model");
    }
    std::vector<CameraModel> models;
    std::vector<std::optional<int>> counts;
    for (std::size_t i = 0; i < list.array_size(); ++i) {
      const JsonNode m = list.at(i);
      m.only_keys({"name", "fov", "half_angle_deg", "sides", "horizontal_deg", "vertical_deg",
                   "range", "cost", "count"});
      CameraModel model = parse_model(m);
      const JsonNode name = m.at("name");
      model.name = name.string();
      if (model.name.empty()) name.fail("a model's name must not be empty");
      for (const CameraModel& other : models) {
        if (other.name == model.name) name.fail("model \"" + model.name + "\" is named twice");
      }
      counts.push_back(m.has("count") ? std::optional<int>(m.at("count").integer_in(0, 256))
                                      : std::nullopt);
      models.push_back(std::move(model));
    }
    if (node.has("list")) {
      if (node.has("camera_domains")) {
        node.at("camera_domains")
            .fail("give per-camera domains in \"list\" when \"list\" is given");
      }
      for (std::size_t i = 0; i < counts.size(); ++i) {
        if (counts[i]) list.at(i).at("count").fail("a model's count is not used with \"list\"");
      }
      const JsonNode cams = node.at("list");
      if (cams.array_size() == 0) cams.fail("expected at least one camera");
      if (cams.array_size() > 256) cams.fail("at most 256 cameras");
      for (std::size_t i = 0; i < cams.array_size(); ++i) {
        const JsonNode cam = cams.at(i);
        cam.only_keys({"model", "domain", "mount"});
        if (cam.has("mount") && cam.has("domain")) {
          cam.at("mount").fail("give either \"mount\" or \"domain\", not both");
        }
        const JsonNode name = cam.at("model");
        const std::string wanted = name.string();
        auto it = std::find_if(models.begin(), models.end(),
                               [&](const CameraModel& m) { return m.name == wanted; });
        if (it == models.end()) {
          std::string known;
          for (const CameraModel& m : models)
            known += (known.empty() ? "\"" : ", \"") + m.name + "\"";
          name.fail("unknown model \"" + wanted + "\" (the models are " + known + ")");
        }
        c.models.push_back(*it);
        own.push_back(cam.has("mount")    ? std::optional(mount_domain(cam.at("mount")))
                      : cam.has("domain") ? std::optional(parse_domain(cam.at("domain")))
                                          : std::nullopt);
        own_origin.push_back(cam.has("mount")    ? cam.at("mount").pointer()
                             : cam.has("domain") ? cam.at("domain").pointer()
                                                 : shared_origin);
      }
    } else if (models.size() == 1 && !counts[0]) {
      if (count == 0) node.fail("\"count\" is required (or give the model a \"count\")");
      c.models.assign(count, models[0]);
    } else {
      for (std::size_t i = 0; i < counts.size(); ++i) {
        if (!counts[i]) {
          list.at(i).fail("model \"" + models[i].name + "\" needs a \"count\" (or give \"list\")");
        }
        c.models.insert(c.models.end(), *counts[i], models[i]);
      }
      if (c.models.empty()) list.fail("the models' counts sum to 0: a scene needs a camera");
      if (c.models.size() > 256) list.fail("the models' counts sum to more than 256 cameras");
    }
    c.count = static_cast<int>(c.models.size());
    if (count != 0 && count != c.count) {
      node.at("count").fail("count " + std::to_string(count) + " does not match the " +
                            std::to_string(c.count) + " cameras the models give");
    }
  }
  c.domains.assign(c.count, shared);
  origin.assign(c.count, shared_origin);
  for (std::size_t i = 0; i < own.size(); ++i) {
    if (own[i]) c.domains[i] = *own[i];
    origin[i] = own_origin[i];
  }
  if (node.has("camera_domains")) {
    const JsonNode list = node.at("camera_domains");
    if (list.array_size() != static_cast<std::size_t>(c.count)) {
      list.fail("expected one domain per camera (" + std::to_string(c.count) + "), found " +
                std::to_string(list.array_size()));
    }
    for (int i = 0; i < c.count; ++i) {
      const JsonNode item = list.at(std::size_t(i));
      if (!item.value().is_null()) {
        c.domains[i] = parse_domain(item);
        origin[i] = item.pointer();
      }
    }
  }
  // A camera needs somewhere to go: its domain (box or mount) must not lie wholly in the
  // keep-out boxes. Checked once per distinct domain (cameras mostly share one), against the
  // boxes whose interior meets the domain's bounds (the others block none of its points).
  std::vector<int> checked;  // cameras whose domain passed
  for (int i = 0; i < c.count; ++i) {
    if (c.keep_out.empty()) break;
    const CameraDomain& d = c.domains[i];
    const auto same_position_domain = [&](int j) {
      const CameraDomain& e = c.domains[j];
      if (d.mount.has_value() != e.mount.has_value()) return false;
      if (d.mount) return d.mount->name == e.mount->name;
      return d.x.lo == e.x.lo && d.x.hi == e.x.hi && d.y.lo == e.y.lo && d.y.hi == e.y.hi &&
             d.z.lo == e.z.lo && d.z.hi == e.z.hi;
    };
    if (std::any_of(checked.begin(), checked.end(), same_position_domain)) continue;
    Vec3 lo(d.x.lo, d.y.lo, d.z.lo), hi(d.x.hi, d.y.hi, d.z.hi);
    if (d.mount) {
      lo = hi = d.mount->corner;
      for (double a : {0.0, 1.0}) {
        for (double b : {0.0, 1.0}) {
          lo = lo.cwiseMin(d.mount->point(a, b));
          hi = hi.cwiseMax(d.mount->point(a, b));
        }
      }
    }
    std::vector<KeepOut> meeting;
    for (const KeepOut& k : c.keep_out) {
      if ((k.box.min.array() + kKeepOutSlack < hi.array()).all() &&
          (k.box.max.array() - kKeepOutSlack > lo.array()).all()) {
        meeting.push_back(k);
      }
    }
    const Vec3 middle =
        d.mount ? d.mount->point(0.5, 0.5)
                : Vec3(0.5 * (d.x.lo + d.x.hi), 0.5 * (d.y.lo + d.y.hi), 0.5 * (d.z.lo + d.z.hi));
    checked.push_back(i);
    if (meeting.empty()) continue;
    if (!keep_out_repair(d, meeting, middle)) {
      const std::string what =
          d.mount ? "mount \"" + d.mount->name + "\"" : std::string("placement domain");
      throw InputError(path_, origin[i],
                       "the keep-out boxes cover the whole " + what + " of camera " +
                           std::to_string(i) + ": it has nowhere to go");
    }
  }
}

void SceneParser::parse_mounts(const JsonNode& list) {
  const Box3& s = scene_.area;
  const std::size_t n = limited_size(list, kMaxMounts, "mounts");
  for (std::size_t i = 0; i < n; ++i) {
    const JsonNode node = list.at(i);
    node.only_keys({"name", "corner", "edges", "yaw_deg", "pitch_deg", "roll_deg"});
    Mount m;
    m.entry = node.pointer();
    const JsonNode name = node.at("name");
    m.name = name.string();
    if (m.name.empty()) name.fail("a mount's name must not be empty");
    for (const Mount& other : scene_.cameras.mounts) {
      if (other.name == m.name) name.fail("mount \"" + m.name + "\" is named twice");
    }
    m.corner = node.at("corner").vec3();
    const JsonNode edges = node.at("edges");
    if (edges.array_size() != 2) edges.fail("expected two edge vectors [[ux,uy,uz],[vx,vy,vz]]");
    m.u = edges.at(std::size_t{0}).vec3();
    m.v = edges.at(std::size_t{1}).vec3();
    const double area = m.u.cross(m.v).norm();
    if (!(area > 1e-12 * std::max(m.u.squaredNorm(), m.v.squaredNorm())) || !(area > 0.0)) {
      edges.fail("mount \"" + m.name +
                 "\" is degenerate: its edges are zero or parallel (zero area)");
    }
    for (double a : {0.0, 1.0}) {
      for (double b : {0.0, 1.0}) {
        const Vec3 p = m.point(a, b);
        if ((p.array() < s.min.array() - kAreaSlack).any() ||
            (p.array() > s.max.array() + kAreaSlack).any()) {
          node.fail("mount \"" + m.name + "\" leaves the area S: its corner " + format_vec(p) +
                    " is not inside " + format_vec(s.min) + "–" + format_vec(s.max));
        }
      }
    }
    if (node.has("yaw_deg")) m.yaw = parse_interval(node.at("yaw_deg"), -kPi / 2, kPi / 2, kDegree);
    if (node.has("pitch_deg")) {
      m.pitch = parse_interval(node.at("pitch_deg"), -kPi / 2, kPi / 2, kDegree);
    }
    if (node.has("roll_deg")) m.roll = parse_interval(node.at("roll_deg"), -kPi, kPi, kDegree);
    scene_.cameras.mounts.push_back(std::move(m));
  }
}

void SceneParser::parse_keep_out(const JsonNode& list) {
  const std::size_t n = limited_size(list, kMaxKeepOut, "keep-out boxes");
  for (std::size_t i = 0; i < n; ++i) {
    const JsonNode node = list.at(i);
    node.only_keys({"name", "min", "max"});
    KeepOut k;
    k.entry = node.pointer();
    k.name = node.has("name") ? node.at("name").string() : node.pointer();
    k.box.min = node.at("min").vec3();
    k.box.max = node.at("max").vec3();
    if (!((k.box.min.array() < k.box.max.array()).all())) {
      node.fail("keep-out box is degenerate: min must be below max on every axis");
    }
    scene_.cameras.keep_out.push_back(std::move(k));
  }
}

CameraDomain SceneParser::mount_domain(const JsonNode& node) const {
  const std::string wanted = node.string();
  const auto& mounts = scene_.cameras.mounts;
  auto it =
      std::find_if(mounts.begin(), mounts.end(), [&](const Mount& m) { return m.name == wanted; });
  if (it == mounts.end()) {
    std::string known;
    for (const Mount& m : mounts) known += (known.empty() ? "\"" : ", \"") + m.name + "\"";
    node.fail("unknown mount \"" + wanted + "\" (" +
              (known.empty() ? std::string("\"mounts\" names none") : "the mounts are " + known) +
              ")");
  }
  CameraDomain d;
  Vec3 lo = it->corner, hi = it->corner;
  for (double a : {0.0, 1.0}) {
    for (double b : {0.0, 1.0}) {
      lo = lo.cwiseMin(it->point(a, b));
      hi = hi.cwiseMax(it->point(a, b));
    }
  }
  d.x = {lo.x(), hi.x()};
  d.y = {lo.y(), hi.y()};
  d.z = {lo.z(), hi.z()};
  d.roll = it->roll;
  d.mount = *it;
  return d;
}

}  // namespace detail

Scene load_scene(const std::string& path) { return detail::SceneParser(path).parse(); }

}  // namespace camplace::core
