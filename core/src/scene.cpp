// Scene loading and validation (SPEC §2).
#include "camplace/core/scene.hpp"

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

namespace camplace::core {

namespace {

constexpr double kDeg = kDegree;
// Vertices may leave S by this much (metres) to absorb rounding of transformed meshes.
constexpr double kAreaSlack = 1e-9;

std::string format_vec(const Vec3& v) {
  return "[" + format_number(v.x()) + ", " + format_number(v.y()) + ", " + format_number(v.z()) +
         "]";
}

Eigen::Matrix3d rotation_deg(const Vec3& deg) {
  // Rz · Ry · Rx: rotate about x first, then y, then z (extrinsic, world axes).
  return (Eigen::AngleAxisd(deg.z() * kDeg, Vec3::UnitZ()) *
          Eigen::AngleAxisd(deg.y() * kDeg, Vec3::UnitY()) *
          Eigen::AngleAxisd(deg.x() * kDeg, Vec3::UnitX()))
      .toRotationMatrix();
}

void apply_transform(TriangleMesh& mesh, const JsonNode& node) {
  node.only_keys({"scale", "rotate_deg", "translate"});
  Vec3 scale = Vec3::Ones();
  if (node.has("scale")) {
    const JsonNode s = node.at("scale");
    scale = s.value().is_array() ? s.vec3() : Vec3::Constant(s.number());
    if ((scale.array() == 0.0).any()) s.fail("scale must not be 0");
  }
  const Eigen::Matrix3d rotation = node.has("rotate_deg")
                                       ? rotation_deg(node.at("rotate_deg").vec3())
                                       : Eigen::Matrix3d::Identity();
  const Vec3 translation = node.has("translate") ? node.at("translate").vec3() : Vec3::Zero();
  for (Vec3& v : mesh.vertices) v = rotation * scale.cwiseProduct(v) + translation;
}

class SceneParser {
 public:
  explicit SceneParser(std::string path) : path_(std::move(path)) {
    dir_ = std::filesystem::path(path_).parent_path();
  }

  Scene parse() {
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
      if (p.has("min_volume"))
        scene_.plausibility.min_volume = p.at("min_volume").number_in(0, 1e9);
      if (p.has("min_height"))
        scene_.plausibility.min_height = p.at("min_height").number_in(0, 1e9);
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

 private:
  void parse_area(const JsonNode& node) {
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

  std::array<int, 3> parse_voxels(const JsonNode& node) const {
    if (node.array_size() != 3) node.fail("expected [nx, ny, nz]");
    std::array<int, 3> n{};
    for (std::size_t i = 0; i < 3; ++i) n[i] = node.at(i).integer_in(1, kMaxVoxelsPerAxis);
    const std::string problem = resolution_problem(n);
    if (!problem.empty()) node.fail(problem);
    return n;
  }

  Interval parse_interval(const JsonNode& node, double lo, double hi, double unit) const {
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
                "] leaves the allowed range " + limits.str() +
                (unit == 1.0 ? " of the area S" : ""));
    }
    return iv;
  }

  CameraDomain parse_domain(const JsonNode& node) const {
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
          .fail("unknown domain preset \"" + preset +
                "\" (expected room, ceiling or upper_fourth)");
    }
    CameraDomain d = *base;
    if (node.is_object()) {
      if (node.has("x")) d.x = parse_interval(node.at("x"), s.min.x(), s.max.x(), 1.0);
      if (node.has("y")) d.y = parse_interval(node.at("y"), s.min.y(), s.max.y(), 1.0);
      if (node.has("z")) d.z = parse_interval(node.at("z"), s.min.z(), s.max.z(), 1.0);
      if (node.has("yaw_deg")) d.yaw = parse_interval(node.at("yaw_deg"), -kPi, kPi, kDeg);
      if (node.has("pitch_deg")) {
        d.pitch = parse_interval(node.at("pitch_deg"), -kPi / 2, kPi / 2, kDeg);
        d.ceiling_pitch = false;
      }
      if (node.has("roll_deg")) d.roll = parse_interval(node.at("roll_deg"), -kPi, kPi, kDeg);
    }
    return d;
  }

  /// A range: a far plane `far` (> 0) or [near, far] with 0 ≤ near < far (m).
  static void parse_range(const JsonNode& r, CameraModel& m) {
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

  /// The model keys of `node` (a model of "models", or the cameras block itself in the
  /// single-model form).
  static CameraModel parse_model(const JsonNode& node) {
    CameraModel m;
    if (node.has("fov")) {
      const JsonNode f = node.at("fov");
      const std::string fov = f.string();
      const auto parsed = from_name<FovShape>(fov);
      if (!parsed)
        f.fail("unknown fov \"" + fov + "\" (expected " + names_listed<FovShape>() + ")");
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
        return deg * kDeg;
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
      m.half_angle = half_deg * kDeg;
      if (node.has("sides")) m.sides = node.at("sides").integer_in(3, 1024);
    }
    if (node.has("range")) parse_range(node.at("range"), m);
    return m;
  }

  void parse_cameras(const JsonNode& node) {
    node.only_keys({"count", "half_angle_deg", "fov", "sides", "range", "horizontal_deg",
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
           {"half_angle_deg", "fov", "sides", "range", "horizontal_deg", "vertical_deg"}) {
        if (node.has(key)) {
          node.at(key).fail(std::string(key) +
                            " belongs in a model of \"models\" when \"models\" is given");
        }
      }
      const JsonNode list = node.at("models");
      if (list.array_size() == 0) list.fail("expected at least one model");
      std::vector<CameraModel> models;
      std::vector<std::optional<int>> counts;
      for (std::size_t i = 0; i < list.array_size(); ++i) {
        const JsonNode m = list.at(i);
        m.only_keys({"name", "fov", "half_angle_deg", "sides", "horizontal_deg", "vertical_deg",
                     "range", "count"});
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
            list.at(i).fail("model \"" + models[i].name +
                            "\" needs a \"count\" (or give \"list\")");
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
    // keep-out boxes.
    for (int i = 0; i < c.count; ++i) {
      if (c.keep_out.empty()) break;
      const CameraDomain& d = c.domains[i];
      const Vec3 middle =
          d.mount ? d.mount->point(0.5, 0.5)
                  : Vec3(0.5 * (d.x.lo + d.x.hi), 0.5 * (d.y.lo + d.y.hi), 0.5 * (d.z.lo + d.z.hi));
      if (!keep_out_repair(d, c.keep_out, middle)) {
        const std::string what =
            d.mount ? "mount \"" + d.mount->name + "\"" : std::string("placement domain");
        throw InputError(path_, origin[i],
                         "the keep-out boxes cover the whole " + what + " of camera " +
                             std::to_string(i) + ": it has nowhere to go");
      }
    }
  }

  void parse_mounts(const JsonNode& list) {
    const Box3& s = scene_.area;
    for (std::size_t i = 0; i < list.array_size(); ++i) {
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
      if (node.has("yaw_deg")) m.yaw = parse_interval(node.at("yaw_deg"), -kPi / 2, kPi / 2, kDeg);
      if (node.has("pitch_deg")) {
        m.pitch = parse_interval(node.at("pitch_deg"), -kPi / 2, kPi / 2, kDeg);
      }
      if (node.has("roll_deg")) m.roll = parse_interval(node.at("roll_deg"), -kPi, kPi, kDeg);
      scene_.cameras.mounts.push_back(std::move(m));
    }
  }

  void parse_keep_out(const JsonNode& list) {
    for (std::size_t i = 0; i < list.array_size(); ++i) {
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

  /// The domain of a camera on the mount `node` names.
  CameraDomain mount_domain(const JsonNode& node) const {
    const std::string wanted = node.string();
    const auto& mounts = scene_.cameras.mounts;
    auto it = std::find_if(mounts.begin(), mounts.end(),
                           [&](const Mount& m) { return m.name == wanted; });
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

  /// What an object is in its state: obstacles and critical objects may reach beyond S (they
  /// occlude and, masked, change pixels wherever they are); targets must lie in S (SPEC §2).
  enum class Role { static_obstacle, dynamic_obstacle, critical, target };

  static const char* role_name(Role role) {
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

  SceneObject parse_object(const JsonNode& node, Role role) const {
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
      for (std::size_t i = 0; i < verts.array_size(); ++i)
        object.mesh.vertices.push_back(verts.at(i).vec3());
      for (std::size_t i = 0; i < tris.array_size(); ++i) {
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

  std::vector<SceneObject> parse_objects(const JsonNode& list, Role role) const {
    std::vector<SceneObject> objects;
    for (std::size_t i = 0; i < list.array_size(); ++i)
      objects.push_back(parse_object(list.at(i), role));
    return objects;
  }

  /// An event as parsed, with the JSON pointer of its weight (for the weight checks).
  struct ParsedEvent {
    Event event;
    std::string weight_entry;
  };

  std::vector<ParsedEvent> parse_events(const JsonNode& events) const {
    std::vector<ParsedEvent> out;
    for (std::size_t l = 0; l < events.array_size(); ++l) {
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

  /// The robots of "robots", each expanded into its links at every sample of its trajectory.
  std::vector<detail::RobotSteps> parse_robots(const JsonNode& list) {
    std::vector<detail::RobotSteps> robots;
    const detail::LinkMeshFinisher finish = [this](TriangleMesh& mesh, const std::string& entry,
                                                   const std::string& name) {
      finish_object_mesh(mesh, default_repair_, entry, name, role_name(Role::dynamic_obstacle));
    };
    for (std::size_t i = 0; i < list.array_size(); ++i) {
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

  // The time steps (SPEC §2): those of "time_steps" and, with "robots", one per sample of the
  // robots' trajectories (the robots' links join each step's dynamic obstacles); each step's
  // events are its own, then the scene's shared "events", then the people generated for it.
  void parse_time_steps(const JsonNode& root) {
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
      if (list.array_size() == 0) list.fail("a scene needs at least one time step");
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
        if (node.has("critical"))
          step.critical = parse_objects(node.at("critical"), Role::critical);
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
      for (std::size_t i = 0; i < list.array_size(); ++i) {
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
          for (const SceneObject& o : scene_.time_steps[h].dynamic_obstacles)
            obstacles.push_back(&o);
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

  void check_targets_clear_of_obstacles(const JsonNode& root) const {
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

  /// Records a file the scene reads (for provenance), once.
  void note_file(const std::string& full) const {
    if (std::find(mesh_files_.begin(), mesh_files_.end(), full) == mesh_files_.end())
      mesh_files_.push_back(full);
  }

  /// Validates and orients an object's mesh, repairing it as `repair` asks; records the repair.
  void finish_object_mesh(TriangleMesh& mesh, const detail::RepairOptions& repair,
                          const std::string& entry, const std::string& name,
                          const char* role) const {
    if (std::optional<MeshRepair> r = detail::finish_mesh(mesh, repair, path_, entry, name)) {
      r->role = role;
      repairs_.push_back(std::move(*r));
    }
  }

  static bool boxes_meet(const Box3& a, const Box3& b) {
    return (a.min.array() <= b.max.array()).all() && (b.min.array() <= a.max.array()).all();
  }

  static inline const nlohmann::json kRoom = "room";
  std::string path_;
  std::filesystem::path dir_;
  Scene scene_;
  mutable std::vector<std::string> mesh_files_;  ///< filled while objects are parsed
  mutable std::vector<MeshRepair> repairs_;      ///< filled while objects are parsed
  detail::RepairOptions default_repair_;         ///< the root "repair" (default: none)
};
}  // namespace

Vec3 Mount::normal() const { return u.cross(v).normalized(); }
Vec3 Mount::e1() const { return u.normalized(); }
Vec3 Mount::e2() const { return normal().cross(e1()); }
Vec3 Mount::point(double s, double t) const { return corner + s * u + t * v; }

std::pair<double, double> Mount::coordinates(const Vec3& p) const {
  Eigen::Matrix<double, 3, 2> a;
  a << u, v;
  const Eigen::Vector2d st = (a.transpose() * a).ldlt().solve(a.transpose() * (p - corner));
  return {st.x(), st.y()};
}

Vec3 Mount::direction(double rel_yaw, double rel_pitch) const {
  const double c = std::cos(rel_pitch);
  return (c * std::cos(rel_yaw) * normal() + c * std::sin(rel_yaw) * e1() +
          std::sin(rel_pitch) * e2())
      .normalized();
}

std::pair<double, double> Mount::relative_angles(const Vec3& d) const {
  const double along_n = d.dot(normal()), along_e1 = d.dot(e1());
  const double yaw = (along_n == 0.0 && along_e1 == 0.0) ? 0.0 : std::atan2(along_e1, along_n);
  return {yaw, std::asin(std::clamp(d.dot(e2()), -1.0, 1.0))};
}

bool KeepOut::contains(const Vec3& p) const {
  return (p.array() > box.min.array() + kKeepOutSlack).all() &&
         (p.array() < box.max.array() - kKeepOutSlack).all();
}

std::optional<Vec3> keep_out_repair(const CameraDomain& domain,
                                    const std::vector<KeepOut>& keep_out, const Vec3& p) {
  const auto blocked = [&](const Vec3& q) {
    return std::any_of(keep_out.begin(), keep_out.end(),
                       [&](const KeepOut& k) { return k.contains(q); });
  };
  // The domain as origin + A·w with w in the box [lo, hi] (k = 3 for a box domain, k = 2 for
  // a mount's (s, t)).
  const bool on_mount = domain.mount.has_value();
  const int k = on_mount ? 2 : 3;
  Eigen::MatrixXd a(3, k);
  Eigen::VectorXd lo(k), hi(k), w0(k);
  Vec3 origin = Vec3::Zero();
  if (on_mount) {
    const Mount& m = *domain.mount;
    a << m.u, m.v;
    origin = m.corner;
    lo << 0.0, 0.0;
    hi << 1.0, 1.0;
    const auto [s, t] = m.coordinates(p);
    w0 << s, t;
  } else {
    a.setIdentity();
    lo << domain.x.lo, domain.y.lo, domain.z.lo;
    hi << domain.x.hi, domain.y.hi, domain.z.hi;
    w0 = p;
  }
  w0 = w0.cwiseMax(lo).cwiseMin(hi);
  const auto world = [&](const Eigen::VectorXd& w) -> Vec3 { return origin + a * w; };
  if (!blocked(world(w0))) return world(w0);
  // The free part of the domain is closed; its point nearest to w0 (in the world metric
  // G = AᵀA) is w0 projected onto the intersection of at most k of the planes that bound the
  // keep-out boxes and the domain. Try every such intersection and keep the nearest free one.
  std::vector<std::pair<Eigen::VectorXd, double>> planes;  // row·w = value
  for (int j = 0; j < k; ++j) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(k);
    e[j] = 1.0;
    planes.push_back({e, lo[j]});
    planes.push_back({e, hi[j]});
  }
  for (const KeepOut& box : keep_out) {
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::VectorXd row = a.row(axis).transpose();
      if (row.norm() == 0.0) continue;
      planes.push_back({row, box.box.min[axis] - origin[axis]});
      planes.push_back({row, box.box.max[axis] - origin[axis]});
    }
  }
  const Eigen::MatrixXd g = a.transpose() * a;
  const Eigen::MatrixXd g_inv = g.inverse();
  std::optional<Vec3> best;
  double best_distance = std::numeric_limits<double>::infinity();
  const auto consider = [&](const std::vector<int>& chosen) {
    const int m = static_cast<int>(chosen.size());
    Eigen::MatrixXd c(m, k);
    Eigen::VectorXd b(m);
    for (int r = 0; r < m; ++r) {
      c.row(r) = planes[chosen[r]].first.transpose();
      b[r] = planes[chosen[r]].second;
    }
    const Eigen::MatrixXd s = c * g_inv * c.transpose();
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(s);
    if (!lu.isInvertible()) return;
    Eigen::VectorXd w = w0 + g_inv * c.transpose() * lu.solve(b - c * w0);
    if (((w - lo).array() < -1e-9).any() || ((w - hi).array() > 1e-9).any()) return;
    w = w.cwiseMax(lo).cwiseMin(hi);
    const Vec3 q = world(w);
    if (blocked(q)) return;
    const double distance = (q - world(w0)).norm();
    if (distance < best_distance) {
      best_distance = distance;
      best = q;
    }
  };
  const int n = static_cast<int>(planes.size());
  for (int i = 0; i < n; ++i) {
    consider({i});
    for (int j = i + 1; j < n; ++j) {
      consider({i, j});
      if (k == 3) {
        for (int l = j + 1; l < n; ++l) consider({i, j, l});
      }
    }
  }
  return best;
}

double CameraModel::bounding_half_angle() const {
  if (fov != FovShape::frustum) return half_angle;
  const double tx = std::tan(0.5 * horizontal), ty = std::tan(0.5 * vertical);
  return std::atan(std::hypot(tx, ty));
}

void CameraSpec::resize(int n) {
  CAMPLACE_ASSERT(n >= 1 && !models.empty() && !domains.empty());
  models.resize(n, models.back());
  domains.resize(n, domains.back());
  count = n;
}

bool CameraSpec::one_model() const {
  for (const CameraModel& m : models) {
    if (m.name != models.front().name || m.fov != models.front().fov ||
        m.half_angle != models.front().half_angle || m.sides != models.front().sides ||
        m.horizontal != models.front().horizontal || m.vertical != models.front().vertical ||
        m.near != models.front().near || m.range != models.front().range) {
      return false;
    }
  }
  return true;
}

CameraModel exact_model(const CameraModel& model) {
  CameraModel out = model;
  if (out.fov == FovShape::cone) out.fov = FovShape::pyramid;
  return out;
}

void use_exact_models(CameraSpec& cameras) {
  for (CameraModel& m : cameras.models) m = exact_model(m);
}

std::string fov_description(const CameraSpec& cameras) {
  std::ostringstream out;
  const CameraModel& first = cameras.models.front();
  if (cameras.one_model() && first.fov == FovShape::cone) {
    out << "the " << first.sides << "-sided pyramid inscribed in each camera's "
        << first.half_angle / kDeg << "° cone";
    return out.str();
  }
  std::vector<std::string> seen;
  for (const CameraModel& m : cameras.models) {
    const std::string key = m.name;
    if (std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
    seen.push_back(key);
    const auto uses = std::count_if(cameras.models.begin(), cameras.models.end(),
                                    [&](const CameraModel& k) { return k.name == key; });
    if (seen.size() > 1) out << "; ";
    if (!m.name.empty()) out << "model \"" << m.name << "\" (" << uses << " cameras): ";
    if (m.fov == FovShape::frustum) {
      out << "a " << m.horizontal / kDeg << "° × " << m.vertical / kDeg << "° frustum";
    } else if (m.fov == FovShape::pyramid) {
      out << "a " << m.sides << "-sided pyramid of half angle " << m.half_angle / kDeg << "°";
    } else {
      out << "the " << m.sides << "-sided pyramid inscribed in a " << m.half_angle / kDeg
          << "° cone";
    }
    if (m.near > 0.0) out << ", near " << m.near << " m";
    if (m.range) out << ", far " << *m.range << " m";
  }
  return out.str();
}

std::vector<StateIndex> states(const Scene& scene) {
  std::vector<StateIndex> out;
  for (int h = 0; h < static_cast<int>(scene.time_steps.size()); ++h) {
    for (int l = 0; l < static_cast<int>(scene.time_steps[h].events.size()); ++l)
      out.push_back({h, l});
  }
  return out;
}

std::optional<CameraDomain> domain_preset(const Box3& area, const std::string& name) {
  CameraDomain d;
  d.x = {area.min.x(), area.max.x()};
  d.y = {area.min.y(), area.max.y()};
  d.z = {area.min.z(), area.max.z()};
  if (name == "ceiling") {
    d.z = {area.max.z(), area.max.z()};
    // Only looking down or level (issue 14): nothing of S lies above its top. A cone FOV tilted
    // up by θ > 0 (no far plane) holds no point of S that the same cone tilted down by θ lacks:
    // for p below c, (p − c)·d(−θ) − (p − c)·d(θ) = −2 (p − c)_z sin θ ≥ 0, and the rays
    // (hence the labels) do not depend on the tilt. Looking up only wastes the optimizer's time.
    d.pitch = {-kPi / 2, 0.0};
    d.ceiling_pitch = true;
  } else if (name == "upper_fourth") {
    d.z = {area.max.z() - 0.25 * (area.max.z() - area.min.z()), area.max.z()};
  } else if (name != "room") {
    return std::nullopt;
  }
  return d;
}

Scene load_scene(const std::string& path) { return SceneParser(path).parse(); }

bool has_ceiling_pitch(const CameraSpec& cameras) {
  return std::any_of(cameras.domains.begin(), cameras.domains.end(),
                     [](const CameraDomain& d) { return d.ceiling_pitch; });
}

std::array<int, 3> parse_resolution(const std::string& text, const std::string& what) {
  std::array<int, 3> n{};
  std::istringstream in(text);
  char x1 = 0, x2 = 0;
  std::string rest;
  if (!(in >> n[0] >> x1 >> n[1] >> x2 >> n[2]) || (x1 != 'x' && x1 != 'X') ||
      (x2 != 'x' && x2 != 'X') || (in >> rest)) {
    throw InputError("command line", what,
                     "expected NXxNYxNZ (e.g. 16x12x12), got \"" + text + "\"");
  }
  const std::string problem = resolution_problem(n);
  if (!problem.empty()) throw InputError("command line", what, problem + " in \"" + text + "\"");
  return n;
}

std::string resolution_problem(const std::array<int, 3>& n) {
  for (int v : n) {
    if (v < 1 || v > kMaxVoxelsPerAxis) {
      return "every voxel count must lie in [1, " + std::to_string(kMaxVoxelsPerAxis) + "]";
    }
  }
  const long long total = static_cast<long long>(n[0]) * n[1] * n[2];
  if (total > kMaxVoxels) {
    return "too many voxels (" + std::to_string(total) + "; at most " + std::to_string(kMaxVoxels) +
           ")";
  }
  return "";
}

}  // namespace camplace::core
