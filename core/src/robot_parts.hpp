#pragma once
// The parts of the robot expansion (robot.hpp) that its translation units share: the URDF model
// and its joints (robot_urdf.cpp), the trajectory and its sampling (robot_trajectory.cpp), the
// link meshes (robot_meshes.cpp); robot.cpp poses them. Private to core.
#include <urdf_model/model.h>
#include <urdf_world/types.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "camplace/core/geometry.hpp"
#include "camplace/core/json_reader.hpp"

namespace camplace::core::detail::robot_parts {

inline std::string in_quotes(const std::string& s) { return "\"" + s + "\""; }

/// `s` without leading and trailing blanks (space, tab, CR, LF).
inline std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
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

/// Revolute, continuous or prismatic.
bool is_movable(const urdf::Joint& j);
/// Revolute or prismatic (a continuous joint has none).
bool has_limits(const urdf::Joint& j);

/// Reads the URDF file `path` that `urdf_node` (the robot's "urdf" entry) names: its joints,
/// which of them the trajectory gives, and mimic joints resolved to the column they follow.
/// Errors are InputError naming `scene_file` and the entry (and the joint).
RobotModel read_urdf(const JsonNode& urdf_node, const std::string& path,
                     const std::string& scene_file);

/// A trajectory: times and, per row, the value of each movable non-mimic joint (rad or m).
struct Trajectory {
  std::vector<double> times;
  std::vector<std::vector<double>> values;  ///< [row][column of RobotModel::movable]
};

/// The trajectory of CSV file `path` (named by `node`): a header "t,<joint>,..." then rows;
/// errors name the file, the line and the column.
Trajectory read_csv_trajectory(const JsonNode& node, const std::string& path,
                               const RobotModel& model);
/// The trajectory of an inline array `list` of {"t", "joints"} rows.
Trajectory read_json_trajectory(const JsonNode& list, const RobotModel& model);

/// The sample times: one per row, `steps` evenly spaced, or `every_s` apart (and the last).
std::vector<double> sample_times(const Trajectory& traj, const JsonNode* sample);

/// Joint values (trajectory columns) at time t, linear between the rows around it.
std::vector<double> interpolate(const Trajectory& traj, double t);

/// The convex hull of the points, each moved by every corner of the cube [−h, h]³ (h > 0, m):
/// the hull of the points Minkowski-added the cube (detail::convex_hull). Closed and outward.
TriangleMesh convex_hull_with_cube(const std::vector<Vec3>& points, double h);

/// The file a URDF <mesh filename> `uri` names: package://PKG/... through the robot's
/// "package_paths" (`node`, relative to `scene_dir`), file:// or a path (relative to
/// `urdf_dir`). Errors are InputError naming `scene_file` and `entry`.
std::string resolve_mesh_path(const std::string& uri, const JsonNode& node,
                              const std::filesystem::path& scene_dir,
                              const std::filesystem::path& urdf_dir, const std::string& scene_file,
                              const std::string& entry);

}  // namespace camplace::core::detail::robot_parts
