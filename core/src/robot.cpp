// Robots from URDF on a joint trajectory: each link's geometry read once, then posed at every
// sample by forward kinematics (Eigen), and swept volumes. The URDF, the trajectory and the meshes
// are read by robot_urdf.cpp, robot_trajectory.cpp and robot_meshes.cpp. docs/robots.md is the
// user's description of everything here.
#include "robot.hpp"

#include <urdf_model/model.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "camplace/core/error.hpp"
#include "mesh_checks.hpp"
#include "robot_parts.hpp"
#include "scene_format.hpp"

namespace camplace::core::detail {

namespace {

using robot_parts::convex_hull_with_cube;
using robot_parts::in_quotes;
using robot_parts::interpolate;
using robot_parts::JointMotion;
using robot_parts::read_csv_trajectory;
using robot_parts::read_json_trajectory;
using robot_parts::read_urdf;
using robot_parts::resolve_mesh_path;
using robot_parts::RobotModel;
using robot_parts::sample_times;
using robot_parts::Trajectory;

// Posed link vertices over all samples: beyond this the expansion would take gigabytes.
constexpr double kMaxPosedVertices = 3e7;
/// Sub-steps (at most, per piece between knots) and the margin (m) they aim for.
constexpr int kSweptSteps = 64;
constexpr double kSweptMargin = 0.005;

Eigen::Isometry3d to_isometry(const urdf::Pose& pose) {
  // urdfdom stores the origin's rpy as the quaternion of Rz(yaw)·Ry(pitch)·Rx(roll).
  double x = 0, y = 0, z = 0, w = 1;
  pose.rotation.getQuaternion(x, y, z, w);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond(w, x, y, z).normalized().toRotationMatrix();
  t.translation() = Vec3(pose.position.x, pose.position.y, pose.position.z);
  return t;
}

/// The pose of joint motion for value v: rotation about the axis (rad) or translation along it
/// (m).
Eigen::Isometry3d joint_motion(const JointMotion& m, double v) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  if (m.joint->type == urdf::Joint::PRISMATIC) {
    t.translation() = v * m.axis;
  } else if (m.joint->type == urdf::Joint::REVOLUTE || m.joint->type == urdf::Joint::CONTINUOUS) {
    t.linear() = Eigen::AngleAxisd(v, m.axis).toRotationMatrix();
  }
  return t;
}

/// One link geometry element, read and finished once in its link frame.
struct LinkPart {
  std::string link;
  SceneObject object;  ///< mesh in the link frame
};

}  // namespace

RobotSteps expand_robot(const JsonNode& node, const std::filesystem::path& scene_dir,
                        const std::string& scene_file, const LinkMeshFinisher& finish) {
  node.only_keys(
      {"name", "urdf", "links", "package_paths", "base", "trajectory", "sample", "swept"});
  RobotSteps out;
  out.name = node.has("name") ? node.at("name").string() : "robot";
  if (out.name.empty()) node.at("name").fail("a robot's name must not be empty");
  const auto resolve = [&](const JsonNode& n) {
    const std::filesystem::path rel = n.string();
    if (rel.empty()) n.fail("the path is empty");
    return (rel.is_absolute() ? rel : scene_dir / rel).string();
  };
  const auto add_file = [&](const std::string& f) {
    if (std::find(out.files.begin(), out.files.end(), f) == out.files.end()) out.files.push_back(f);
  };

  bool visual = false;
  if (node.has("links")) {
    const JsonNode l = node.at("links");
    const std::string kind = l.string();
    if (kind != "collision" && kind != "visual")
      l.fail("unknown links " + in_quotes(kind) + " (expected \"collision\" or \"visual\")");
    visual = kind == "visual";
  }
  if (node.has("package_paths")) {
    const JsonNode p = node.at("package_paths");
    if (!p.is_object()) p.fail("expected an object {\"package\": \"folder\", ...}");
    for (const auto& item : p.value().items()) p.at(item.key()).string();
  }
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  if (node.has("base")) {
    const JsonNode b = node.at("base");
    b.only_keys({"rotate_deg", "translate"});
    if (b.has("rotate_deg")) base.linear() = rotation_deg(b.at("rotate_deg").vec3());
    if (b.has("translate")) base.translation() = b.at("translate").vec3();
  }
  bool swept = false;
  if (node.has("swept")) {
    const JsonNode s = node.at("swept");
    if (!s.value().is_boolean())
      s.fail(std::string("expected a boolean, found ") + s.value().type_name());
    swept = s.value().get<bool>();
  }

  const JsonNode urdf_node = node.at("urdf");
  const std::string urdf_path = resolve(urdf_node);
  add_file(urdf_path);
  const RobotModel model = read_urdf(urdf_node, urdf_path, scene_file);

  const JsonNode traj_node = node.at("trajectory");
  Trajectory traj;
  if (traj_node.is_string()) {
    const std::string csv = resolve(traj_node);
    add_file(csv);
    traj = read_csv_trajectory(traj_node, csv, model);
  } else if (traj_node.value().is_array()) {
    traj = read_json_trajectory(traj_node, model);
  } else {
    traj_node.fail("expected a CSV file path or an array of {\"t\", \"joints\"} rows");
  }
  std::optional<JsonNode> sample;
  if (node.has("sample")) sample = node.at("sample");
  out.times = sample_times(traj, sample ? &*sample : nullptr);

  // Link geometry, depth first from the root link; each element read and finished once.
  const std::filesystem::path urdf_dir = std::filesystem::path(urdf_path).parent_path();
  std::vector<LinkPart> parts;
  std::vector<const urdf::Link*> order;
  std::vector<const urdf::Link*> stack{model.urdf->getRoot().get()};
  while (!stack.empty()) {
    const urdf::Link* link = stack.back();
    stack.pop_back();
    order.push_back(link);
    for (auto it = link->child_links.rbegin(); it != link->child_links.rend(); ++it)
      stack.push_back(it->get());
  }
  for (const urdf::Link* link : order) {
    std::vector<std::pair<urdf::Pose, urdf::GeometrySharedPtr>> elements;
    if (visual) {
      for (const auto& v : link->visual_array)
        if (v) elements.emplace_back(v->origin, v->geometry);
    } else {
      for (const auto& c : link->collision_array)
        if (c) elements.emplace_back(c->origin, c->geometry);
    }
    for (std::size_t e = 0; e < elements.size(); ++e) {
      LinkPart part;
      part.link = link->name;
      part.object.name = out.name + "/" + link->name + (e ? "/" + std::to_string(e) : "");
      part.object.entry = node.pointer() + " (link " + in_quotes(link->name) + ", " +
                          (visual ? "visual " : "collision ") + std::to_string(e) + ")";
      const std::string& entry = part.object.entry;
      const urdf::Geometry* g = elements[e].second.get();
      if (!g) throw InputError(scene_file, entry, "the element has no geometry");
      TriangleMesh mesh;
      if (g->type == urdf::Geometry::BOX) {
        const auto& d = static_cast<const urdf::Box*>(g)->dim;
        const Vec3 size(d.x, d.y, d.z);
        if (!((size.array() > 0).all()) || !size.allFinite())
          throw InputError(scene_file, entry, "box size must be positive on every axis");
        mesh = box_mesh(-0.5 * size, 0.5 * size);
      } else if (g->type == urdf::Geometry::CYLINDER) {
        const auto* c = static_cast<const urdf::Cylinder*>(g);
        if (!(c->radius > 0) || !(c->length > 0) || !std::isfinite(c->radius) ||
            !std::isfinite(c->length))
          throw InputError(scene_file, entry, "cylinder radius and length must be positive");
        mesh = cylinder_mesh(c->radius, c->length);
      } else if (g->type == urdf::Geometry::SPHERE) {
        const auto* s = static_cast<const urdf::Sphere*>(g);
        if (!(s->radius > 0) || !std::isfinite(s->radius))
          throw InputError(scene_file, entry, "sphere radius must be positive");
        mesh = sphere_mesh(s->radius);
      } else {
        const auto* m = static_cast<const urdf::Mesh*>(g);
        const std::string path =
            resolve_mesh_path(m->filename, node, scene_dir, urdf_dir, scene_file, entry);
        mesh = read_mesh_file(path, scene_file, entry);
        add_file(path);
        const Vec3 scale(m->scale.x, m->scale.y, m->scale.z);
        if ((scale.array() == 0).any() || !scale.allFinite())
          throw InputError(scene_file, entry, "mesh scale must be finite and non-zero");
        for (Vec3& v : mesh.vertices) v = scale.cwiseProduct(v);
        if (scale.prod() < 0) {
          // A mirroring scale turns the faces inside out; keep them outward.
          for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
        }
      }
      const Eigen::Isometry3d origin = to_isometry(elements[e].first);
      for (Vec3& v : mesh.vertices) v = origin * v;
      finish(mesh, entry, part.object.name);
      part.object.mesh = std::move(mesh);
      parts.push_back(std::move(part));
    }
  }

  // Forward kinematics: T(child) = T(parent) · origin(joint) · motion(joint value).
  const auto value_of = [&](const JointMotion& m, const std::vector<double>& q) {
    return m.column < 0 ? 0.0 : m.multiplier * q[m.column] + m.offset;
  };
  const auto link_poses = [&](const std::vector<double>& q) {
    std::map<std::string, Eigen::Isometry3d> pose;
    for (const urdf::Link* link : order) {
      if (!link->parent_joint) {
        pose[link->name] = base;
        continue;
      }
      const urdf::Joint& j = *link->parent_joint;
      const JointMotion& m = model.joints.at(j.name);
      pose[link->name] = pose.at(j.parent_link_name) *
                         to_isometry(j.parent_to_joint_origin_transform) *
                         joint_motion(m, value_of(m, q));
    }
    return pose;
  };
  const auto placed = [&](const LinkPart& part, const Eigen::Isometry3d& tf, double t) {
    SceneObject o = part.object;
    for (Vec3& v : o.mesh.vertices) v = tf * v;
    o.bounds = bounding_box(o.mesh);
    // A huge joint value or mimic multiplier can throw a link far away or to inf/NaN.
    if (!(o.bounds.min.array().abs().maxCoeff() <= kMaxCoordinate) ||
        !(o.bounds.max.array().abs().maxCoeff() <= kMaxCoordinate)) {
      throw InputError(scene_file, o.entry,
                       "at t = " + format_number(t) + " s the link lies beyond ±" +
                           format_number(kMaxCoordinate) +
                           " m (or at a non-finite position): check the joint values and mimic "
                           "multipliers");
    }
    return o;
  };
  double vertices = 0;
  for (const LinkPart& part : parts)
    vertices += static_cast<double>(part.object.mesh.vertices.size());
  if (vertices * static_cast<double>(out.times.size()) > kMaxPosedVertices) {
    node.fail("the robot's " + format_number(vertices) + " link vertices at " +
              std::to_string(out.times.size()) + " samples exceed " +
              format_number(kMaxPosedVertices) +
              " posed vertices: sample fewer time steps or use coarser link meshes");
  }
  if (parts.empty()) {
    node.fail(std::string("the URDF has no ") + (visual ? "visual" : "collision") +
              " geometry: the robot would have no object" +
              (visual ? "" : " (its visual meshes: \"links\": \"visual\")"));
  }
  out.links.reserve(out.times.size());
  for (const double t : out.times) {
    const auto pose = link_poses(interpolate(traj, t));
    std::vector<SceneObject> objects;
    objects.reserve(parts.size());
    for (const LinkPart& part : parts) objects.push_back(placed(part, pose.at(part.link), t));
    out.links.push_back(std::move(objects));
  }
  if (!swept) return out;

  // Swept volumes (docs/robots.md, "Swept volumes"): sample k's object of a link encloses the
  // link's motion over [t_k, t_k+1]; the last sample keeps its pose. Between trajectory rows the
  // joint values are linear in t, so each piece [a, b] between consecutive knots (samples and
  // rows) has constant joint speeds, and a point of the link moves at most
  //   D = Σ_j |Δv_j| · R_j  (revolute, continuous)  + Σ_j |Δv_j|  (prismatic)
  // over it, with R_j ≥ the point's distance from joint j's axis throughout [a, b]. Poses at m
  // equal steps of [a, b] leave every instant within (b − a)/2m of one of them, so every point
  // stays within D/2m of its position there: the convex hull of the link's vertices at those
  // poses, Minkowski-added a cube of half-side D/2m (which contains that ball), encloses it.
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const LinkPart& part = parts[p];
    // The joints from the link up to the root, nearest first.
    std::vector<const urdf::Joint*> chain;
    for (const urdf::Link* l = model.urdf->getLink(part.link).get(); l && l->parent_joint;
         l = l->getParent().get())
      chain.push_back(l->parent_joint.get());
    double reach = 0.0;  // max |p| over the solid: its vertices bound it (it lies in their hull)
    for (const Vec3& v : part.object.mesh.vertices) reach = std::max(reach, v.norm());
    for (std::size_t k = 0; k + 1 < out.times.size(); ++k) {
      std::vector<double> knots{out.times[k]};
      for (const double tr : traj.times)
        if (tr > out.times[k] && tr < out.times[k + 1]) knots.push_back(tr);
      knots.push_back(out.times[k + 1]);
      std::vector<Vec3> points;
      double margin = 0.0;
      bool moves = false;
      for (std::size_t i = 0; i + 1 < knots.size(); ++i) {
        const std::vector<double> qa = interpolate(traj, knots[i]),
                                  qb = interpolate(traj, knots[i + 1]);
        double travel = 0.0;     // D above
        double outward = reach;  // R_j: |p| plus every joint origin and prismatic travel below j
        for (const urdf::Joint* j : chain) {
          const JointMotion& m = model.joints.at(j->name);
          const double va = value_of(m, qa), vb = value_of(m, qb);
          if (j->type == urdf::Joint::PRISMATIC) {
            travel += std::abs(vb - va);
          } else if (j->type == urdf::Joint::REVOLUTE || j->type == urdf::Joint::CONTINUOUS) {
            travel += std::abs(vb - va) * outward;
          }
          const auto& o = j->parent_to_joint_origin_transform.position;
          outward +=
              Vec3(o.x, o.y, o.z).norm() +
              (j->type == urdf::Joint::PRISMATIC ? std::max(std::abs(va), std::abs(vb)) : 0.0);
        }
        if (travel > 0) moves = true;
        const int steps = static_cast<int>(std::clamp(std::ceil(travel / (2 * kSweptMargin)), 1.0,
                                                      static_cast<double>(kSweptSteps)));
        margin = std::max(margin, travel / (2 * steps));
        for (int s = 0; s <= steps; ++s) {
          const double t =
              s == steps ? knots[i + 1] : knots[i] + (knots[i + 1] - knots[i]) * s / steps;
          const Eigen::Isometry3d tf = link_poses(interpolate(traj, t)).at(part.link);
          for (const Vec3& v : part.object.mesh.vertices) points.push_back(tf * v);
        }
      }
      if (!moves) continue;  // at rest over the interval: the link itself is its sweep
      SceneObject& o = out.links[k][p];
      o.mesh = convex_hull_with_cube(points, margin);
      o.bounds = bounding_box(o.mesh);
    }
  }
  return out;
}

}  // namespace camplace::core::detail
