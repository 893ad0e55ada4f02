// Robots from URDF on a joint trajectory: URDF parsing (urdfdom), the trajectory (CSV or
// inline JSON), its sampling, and forward kinematics (Eigen). docs/robots.md is the user's
// description of everything here.
#include "robot.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include "camplace/core/error.hpp"
#include "mesh_checks.hpp"
#include "scene_format.hpp"

namespace camplace::core::detail {

namespace {

/// Slack (rad or m) of the joint limit check: values computed elsewhere may round past a limit.
constexpr double kLimitSlack = 1e-9;
/// At most this many samples per robot (an "every_s" far below the trajectory's length would
/// otherwise make millions of time steps).
constexpr int kMaxSamples = 100000;
// Trajectory times (s) beyond this are refused: differences and interpolation stay finite.
constexpr double kMaxTime = 1e9;
// Posed link vertices over all samples: beyond this the expansion would take gigabytes.
constexpr double kMaxPosedVertices = 3e7;

std::string in_quotes(const std::string& s) { return "\"" + s + "\""; }

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "(none)" : out;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

/// Collects what urdfdom reports through console_bridge while it parses (it prints to stderr
/// otherwise) and restores the previous handler and level afterwards.
class ConsoleCapture : public console_bridge::OutputHandler {
 public:
  ConsoleCapture()
      : previous_(console_bridge::getOutputHandler()), level_(console_bridge::getLogLevel()) {
    console_bridge::useOutputHandler(this);
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_WARN);
  }
  ~ConsoleCapture() override {
    console_bridge::useOutputHandler(previous_);
    console_bridge::setLogLevel(level_);
  }
  ConsoleCapture(const ConsoleCapture&) = delete;
  ConsoleCapture& operator=(const ConsoleCapture&) = delete;

  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors_.push_back(trim(text));
  }
  /// The errors, joined by "; ".
  std::string errors() const {
    std::string out;
    for (const auto& e : errors_) out += (out.empty() ? "" : "; ") + e;
    return out;
  }

 private:
  console_bridge::OutputHandler* previous_;
  console_bridge::LogLevel level_;
  std::vector<std::string> errors_;
};

Eigen::Isometry3d to_isometry(const urdf::Pose& pose) {
  // urdfdom stores the origin's rpy as the quaternion of Rz(yaw)·Ry(pitch)·Rx(roll).
  double x = 0, y = 0, z = 0, w = 1;
  pose.rotation.getQuaternion(x, y, z, w);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond(w, x, y, z).normalized().toRotationMatrix();
  t.translation() = Vec3(pose.position.x, pose.position.y, pose.position.z);
  return t;
}

Eigen::Matrix3d rotation_deg(const Vec3& deg) {
  // Rz · Ry · Rx, as an object's transform (docs/scene-format.md).
  return (Eigen::AngleAxisd(deg.z() * kDegree, Vec3::UnitZ()) *
          Eigen::AngleAxisd(deg.y() * kDegree, Vec3::UnitY()) *
          Eigen::AngleAxisd(deg.x() * kDegree, Vec3::UnitX()))
      .toRotationMatrix();
}

/// A joint of the robot and how its value is found: from a trajectory column (`column` ≥ 0),
/// from another joint (mimic: multiplier · value(column) + offset), or none (fixed).
struct JointMotion {
  const urdf::Joint* joint = nullptr;
  int column = -1;  ///< index into the trajectory's joint values; -1 for a fixed joint
  double multiplier = 1.0;
  double offset = 0.0;
  Vec3 axis = Vec3::UnitX();  ///< unit axis in the joint frame
};

/// The robot's URDF, its joints, and which of them the trajectory gives.
struct RobotModel {
  urdf::ModelInterfaceSharedPtr urdf;
  std::vector<std::string> movable;  ///< movable non-mimic joints: the trajectory's columns
  std::map<std::string, JointMotion> joints;
  std::string entry;  ///< JSON pointer of the "urdf" entry
};

bool is_movable(const urdf::Joint& j) {
  return j.type == urdf::Joint::REVOLUTE || j.type == urdf::Joint::CONTINUOUS ||
         j.type == urdf::Joint::PRISMATIC;
}

bool has_limits(const urdf::Joint& j) {
  return j.type == urdf::Joint::REVOLUTE || j.type == urdf::Joint::PRISMATIC;
}

RobotModel read_urdf(const JsonNode& urdf_node, const std::string& path,
                     const std::string& scene_file) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) urdf_node.fail("URDF file " + path + " does not exist");
  if (!std::filesystem::is_regular_file(path, ec))
    urdf_node.fail("URDF file " + path + " is not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) urdf_node.fail("URDF file " + path + " cannot be opened");
  std::stringstream buffer;
  buffer << in.rdbuf();
  RobotModel model;
  model.entry = urdf_node.pointer();
  // urdfdom ignores elements it does not know: a xacro file would parse into a robot without
  // the links its macros make.
  if (buffer.str().find("<xacro:") != std::string::npos) {
    urdf_node.fail("URDF file " + path +
                   " contains xacro macros (<xacro:...>): expand it first, e.g. xacro "
                   "robot.urdf.xacro > robot.urdf (ROS 2: ros2 run xacro xacro "
                   "robot.urdf.xacro > robot.urdf)");
  }
  {
    ConsoleCapture capture;
    try {
      model.urdf = urdf::parseURDF(buffer.str());
    } catch (const std::exception& e) {
      urdf_node.fail("URDF file " + path + " cannot be parsed: " + e.what());
    }
    if (!model.urdf) {
      const std::string why = capture.errors();
      urdf_node.fail("URDF file " + path + " cannot be parsed" +
                     (why.empty() ? std::string(" (urdfdom gave no reason)") : ": " + why));
    }
  }
  const auto joint_fail = [&](const std::string& name, const std::string& reason) {
    throw InputError(scene_file, model.entry + " (joint " + in_quotes(name) + ")", reason);
  };
  for (const auto& [name, joint] : model.urdf->joints_) {
    JointMotion m;
    m.joint = joint.get();
    if (joint->type == urdf::Joint::FLOATING || joint->type == urdf::Joint::PLANAR) {
      joint_fail(name, std::string("joint type \"") +
                           (joint->type == urdf::Joint::FLOATING ? "floating" : "planar") +
                           "\" is not supported (only revolute, continuous, prismatic and "
                           "fixed joints): a robot's base is placed with \"base\"");
    }
    if (joint->type == urdf::Joint::UNKNOWN) joint_fail(name, "joint type is unknown");
    if (is_movable(*joint)) {
      const Vec3 axis(joint->axis.x, joint->axis.y, joint->axis.z);
      if (!(axis.norm() > 1e-12) || !axis.allFinite()) joint_fail(name, "joint axis is zero");
      m.axis = axis.normalized();
      if (has_limits(*joint) && !joint->limits) joint_fail(name, "joint has no <limit>");
      if (has_limits(*joint) && !(joint->limits->lower <= joint->limits->upper)) {
        joint_fail(name, "joint limits are empty: lower " + format_number(joint->limits->lower) +
                             " > upper " + format_number(joint->limits->upper));
      }
      if (!joint->mimic) model.movable.push_back(name);
    }
    model.joints[name] = m;
  }
  // Columns in the order of `movable` (joint names sorted); then mimic joints resolved through
  // chains of mimics to the column they follow.
  for (std::size_t c = 0; c < model.movable.size(); ++c)
    model.joints[model.movable[c]].column = static_cast<int>(c);
  for (auto& [name, m] : model.joints) {
    if (!is_movable(*m.joint) || !m.joint->mimic) continue;
    double multiplier = 1.0, offset = 0.0;
    std::string current = name;
    std::set<std::string> seen{name};
    while (true) {
      const urdf::JointMimic& mimic = *model.joints.at(current).joint->mimic;
      const auto target = model.joints.find(mimic.joint_name);
      if (target == model.joints.end() || !is_movable(*target->second.joint)) {
        joint_fail(name, "joint mimics " + in_quotes(mimic.joint_name) +
                             ", which is not a movable joint of the robot");
      }
      // value(current) = mimic.multiplier · value(target) + mimic.offset
      offset += multiplier * mimic.offset;
      multiplier *= mimic.multiplier;
      if (!target->second.joint->mimic) {
        m.column = target->second.column;
        break;
      }
      current = target->first;
      if (!seen.insert(current).second) joint_fail(name, "mimic joints form a cycle");
    }
    m.multiplier = multiplier;
    m.offset = offset;
  }
  return model;
}

/// A trajectory: times and, per row, the value of each movable non-mimic joint (rad or m).
struct Trajectory {
  std::vector<double> times;
  std::vector<std::vector<double>> values;  ///< [row][column of RobotModel::movable]
};

/// Checks one joint value of a trajectory row against the joint's limits.
void check_limits(const RobotModel& model, int column, double value, const std::string& file,
                  const std::string& entry, const std::string& row) {
  const urdf::Joint& j = *model.joints.at(model.movable[column]).joint;
  if (!has_limits(j)) return;
  const double lo = j.limits->lower, hi = j.limits->upper;
  if (value < lo - kLimitSlack || value > hi + kLimitSlack) {
    const char* unit = j.type == urdf::Joint::PRISMATIC ? " m" : " rad";
    throw InputError(file, entry,
                     "joint " + in_quotes(j.name) + " value " + format_number(value) + unit +
                         " at " + row + " is outside its limits [" + format_number(lo) + ", " +
                         format_number(hi) + "]" + unit);
  }
}

std::string movable_list(const RobotModel& model) {
  return "the robot's movable joints are: " + joined(model.movable);
}

/// Why a name is not a trajectory column ("" when it is one).
std::string not_a_column(const RobotModel& model, const std::string& name) {
  const auto it = model.joints.find(name);
  if (it == model.joints.end())
    return "unknown joint " + in_quotes(name) + " (" + movable_list(model) + ")";
  if (!is_movable(*it->second.joint))
    return "joint " + in_quotes(name) + " is fixed and takes no value (" + movable_list(model) +
           ")";
  if (it->second.joint->mimic) {
    return "joint " + in_quotes(name) + " mimics " +
           in_quotes(it->second.joint->mimic->joint_name) +
           ": its value follows from that joint's, leave it out";
  }
  return "";
}

std::optional<double> parse_number(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v))
    return std::nullopt;
  return v;
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) cells.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') cells.push_back("");
  return cells;
}

Trajectory read_csv_trajectory(const JsonNode& node, const std::string& path,
                               const RobotModel& model) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) node.fail("trajectory file " + path + " does not exist");
  if (!std::filesystem::is_regular_file(path, ec))
    node.fail("trajectory file " + path + " is not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) node.fail("trajectory file " + path + " cannot be opened");
  Trajectory traj;
  std::vector<int> columns;  // header column k (k ≥ 1) → movable column
  std::vector<std::string> header;
  std::string line;
  int line_no = 0;
  bool have_header = false;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string text = trim(line);
    if (text.empty() || text[0] == '#') continue;
    const std::string at_line = "line " + std::to_string(line_no);
    const std::vector<std::string> cells = split_csv(text);
    if (!have_header) {
      have_header = true;
      header = cells;
      if (cells[0] != "t") {
        throw InputError(path, at_line,
                         "the header's first column must be \"t\" (the time in s), found " +
                             in_quotes(cells[0]));
      }
      std::vector<bool> given(model.movable.size(), false);
      for (std::size_t k = 1; k < cells.size(); ++k) {
        const std::string& name = cells[k];
        const std::string column_entry = at_line + ", column " + std::to_string(k + 1);
        if (name.empty()) throw InputError(path, column_entry, "empty column name");
        const std::string why = not_a_column(model, name);
        if (!why.empty()) throw InputError(path, column_entry, why);
        const int c = model.joints.at(name).column;
        if (given[c])
          throw InputError(path, column_entry, "joint " + in_quotes(name) + " is given twice");
        given[c] = true;
        columns.push_back(c);
      }
      std::vector<std::string> missing;
      for (std::size_t c = 0; c < given.size(); ++c)
        if (!given[c]) missing.push_back(model.movable[c]);
      if (!missing.empty()) {
        throw InputError(path, at_line,
                         "the header has no column for the movable joints " + joined(missing) +
                             " (every movable joint that mimics no other must be given)");
      }
      continue;
    }
    if (cells.size() != header.size()) {
      throw InputError(path, at_line,
                       "the row has " + std::to_string(cells.size()) + " values, the header " +
                           std::to_string(header.size()) + " columns");
    }
    std::vector<double> row(model.movable.size(), 0.0);
    double t = 0.0;
    for (std::size_t k = 0; k < cells.size(); ++k) {
      const std::string cell_entry = at_line + ", column " + in_quotes(header[k]);
      const auto v = parse_number(cells[k]);
      if (!v) throw InputError(path, cell_entry, in_quotes(cells[k]) + " is not a finite number");
      if (k == 0) {
        t = *v;
      } else {
        check_limits(model, columns[k - 1], *v, path, cell_entry, at_line);
        row[columns[k - 1]] = *v;
      }
    }
    if (!(std::abs(t) <= kMaxTime)) {
      throw InputError(
          path, at_line + ", column \"t\"",
          "time " + format_number(t) + " s is beyond ±" + format_number(kMaxTime) + " s");
    }
    if (!traj.times.empty() && !(t > traj.times.back())) {
      throw InputError(path, at_line + ", column \"t\"",
                       "time " + format_number(t) + " s is not after the previous row's " +
                           format_number(traj.times.back()) + " s: times must increase strictly");
    }
    traj.times.push_back(t);
    traj.values.push_back(std::move(row));
  }
  if (traj.times.empty()) {
    throw InputError(path, "",
                     have_header ? "the trajectory has a header but no rows (at least one needed)"
                                 : "the trajectory is empty: it needs a header \"t,<joint>,...\" "
                                   "and at least one row");
  }
  return traj;
}

Trajectory read_json_trajectory(const JsonNode& list, const RobotModel& model) {
  Trajectory traj;
  if (list.array_size() == 0) list.fail("the trajectory needs at least one row");
  for (std::size_t r = 0; r < list.array_size(); ++r) {
    const JsonNode row_node = list.at(r);
    row_node.only_keys({"t", "joints"});
    const JsonNode t_node = row_node.at("t");
    const double t = t_node.number();
    if (!(std::abs(t) <= kMaxTime))
      t_node.fail("time " + format_number(t) + " s is beyond ±" + format_number(kMaxTime) + " s");
    if (!traj.times.empty() && !(t > traj.times.back())) {
      t_node.fail("time " + format_number(t) + " s is not after the previous row's " +
                  format_number(traj.times.back()) + " s: times must increase strictly");
    }
    const JsonNode joints = row_node.at("joints");
    if (!joints.is_object()) joints.fail("expected an object {\"joint\": value, ...}");
    std::vector<double> row(model.movable.size(), 0.0);
    std::vector<bool> given(model.movable.size(), false);
    for (const auto& item : joints.value().items()) {
      const JsonNode v = joints.at(item.key());
      const std::string why = not_a_column(model, item.key());
      if (!why.empty()) v.fail(why);
      const int c = model.joints.at(item.key()).column;
      const double value = v.number();
      check_limits(model, c, value, v.file(), v.pointer(), "row " + std::to_string(r));
      row[c] = value;
      given[c] = true;
    }
    std::vector<std::string> missing;
    for (std::size_t c = 0; c < given.size(); ++c)
      if (!given[c]) missing.push_back(model.movable[c]);
    if (!missing.empty()) {
      joints.fail("row " + std::to_string(r) + " gives no value for the movable joints " +
                  joined(missing) + " (every movable joint that mimics no other must be given)");
    }
    traj.times.push_back(t);
    traj.values.push_back(std::move(row));
  }
  return traj;
}

/// The sample times: one per row, `steps` evenly spaced, or `every_s` apart (and the last).
std::vector<double> sample_times(const Trajectory& traj, const JsonNode* sample) {
  if (!sample) return traj.times;
  sample->only_keys({"steps", "every_s"});
  if (sample->has("steps") == sample->has("every_s"))
    sample->fail("give exactly one of \"steps\" or \"every_s\"");
  const double t0 = traj.times.front(), t1 = traj.times.back();
  std::vector<double> times;
  if (sample->has("steps")) {
    const int n = sample->at("steps").integer_in(1, kMaxSamples);
    for (int k = 0; k < n; ++k)
      times.push_back(k == n - 1 && n > 1 ? t1 : t0 + (t1 - t0) * (double(k) / std::max(1, n - 1)));
    return times;
  }
  const JsonNode dt_node = sample->at("every_s");
  const double dt = dt_node.number();
  if (!(dt > 0)) dt_node.fail("every_s must be positive");
  const double count = std::floor((t1 - t0) / dt);
  if (count + 2 > kMaxSamples) {
    dt_node.fail("every_s " + format_number(dt) + " s over " + format_number(t1 - t0) +
                 " s gives more than " + std::to_string(kMaxSamples) + " samples");
  }
  for (int k = 0;; ++k) {
    const double t = t0 + k * dt;
    // A sample within a millionth of dt of the end is the end itself.
    if (t >= t1 - 1e-6 * dt) break;
    times.push_back(t);
  }
  times.push_back(t1);
  return times;
}

/// Joint values (trajectory columns) at time t, linear between the rows around it.
std::vector<double> interpolate(const Trajectory& traj, double t) {
  const auto& ts = traj.times;
  if (t <= ts.front()) return traj.values.front();
  if (t >= ts.back()) return traj.values.back();
  const std::size_t i =
      std::upper_bound(ts.begin(), ts.end(), t) - ts.begin();  // ts[i-1] ≤ t < ts[i]
  const double s = (t - ts[i - 1]) / (ts[i] - ts[i - 1]);
  std::vector<double> q(traj.values[i].size());
  for (std::size_t c = 0; c < q.size(); ++c)
    q[c] = (1 - s) * traj.values[i - 1][c] + s * traj.values[i][c];
  return q;
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
/// Sub-steps (at most, per piece between knots) and the margin (m) they aim for.
constexpr int kSweptSteps = 64;
constexpr double kSweptMargin = 0.005;

/// The convex hull of the points, each moved by every corner of the cube [−h, h]³ (h ≥ 0, m):
/// the hull of the points Minkowski-added the cube. Closed and outward.
TriangleMesh convex_hull_with_cube(const std::vector<Vec3>& points, double h) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Mesh = CGAL::Surface_mesh<K::Point_3>;
  std::vector<K::Point_3> cloud;
  cloud.reserve(points.size() * (h > 0 ? 8 : 1));
  for (const Vec3& p : points) {
    if (h > 0) {
      for (int c = 0; c < 8; ++c)
        cloud.emplace_back(p.x() + (c & 1 ? h : -h), p.y() + (c & 2 ? h : -h),
                           p.z() + (c & 4 ? h : -h));
    } else {
      cloud.emplace_back(p.x(), p.y(), p.z());
    }
  }
  Mesh hull;
  CGAL::convex_hull_3(cloud.begin(), cloud.end(), hull);
  TriangleMesh out;
  std::map<Mesh::Vertex_index, int> index;
  for (const auto v : hull.vertices()) {
    index[v] = static_cast<int>(out.vertices.size());
    const auto& q = hull.point(v);
    out.vertices.emplace_back(q.x(), q.y(), q.z());
  }
  for (const auto f : hull.faces()) {
    std::array<int, 3> tri{};
    int n = 0;
    for (const auto v : CGAL::vertices_around_face(hull.halfedge(f), hull)) {
      if (n < 3) tri[n] = index.at(v);
      ++n;
    }
    CAMPLACE_ASSERT(n == 3);
    out.triangles.push_back(tri);
  }
  return out;
}

struct LinkPart {
  std::string link;
  SceneObject object;  ///< mesh in the link frame
};

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

}  // namespace

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
