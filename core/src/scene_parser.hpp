#pragma once
// The scene parser (SPEC §2), private to core: the class that reads a scene JSON file into a
// Scene, whose members scene_parser.cpp (area, voxels, cameras, mounts, keep-out boxes) and
// scene_parser_objects.cpp (objects, events, robots, time steps and their checks) define.
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "camplace/core/json_reader.hpp"
#include "camplace/core/scene.hpp"
#include "mesh_checks.hpp"
#include "mesh_repair.hpp"
#include "robot.hpp"

namespace camplace::core {

namespace {

// Vertices may leave S by this much (metres) to absorb rounding of transformed meshes.
constexpr double kAreaSlack = 1e-9;

std::string format_vec(const Vec3& v) {
  return "[" + format_number(v.x()) + ", " + format_number(v.y()) + ", " + format_number(v.z()) +
         "]";
}

}  // namespace

namespace detail {

class SceneParser {
 public:
  explicit SceneParser(std::string path) : path_(std::move(path)) {
    dir_ = std::filesystem::path(path_).parent_path();
  }

  Scene parse();

 private:
  void parse_area(const JsonNode& node);

  std::array<int, 3> parse_voxels(const JsonNode& node) const;

  Interval parse_interval(const JsonNode& node, double lo, double hi, double unit) const;

  CameraDomain parse_domain(const JsonNode& node) const;

  /// A range: a far plane `far` (> 0) or [near, far] with 0 ≤ near < far (m).
  static void parse_range(const JsonNode& r, CameraModel& m);

  /// The model keys of `node` (a model of "models", or the cameras block itself in the
  /// single-model form).
  static CameraModel parse_model(const JsonNode& node);

  void parse_cameras(const JsonNode& node);

  void parse_mounts(const JsonNode& list);

  void parse_keep_out(const JsonNode& list);

  /// The domain of a camera on the mount `node` names.
  CameraDomain mount_domain(const JsonNode& node) const;

  /// What an object is in its state: obstacles and critical objects may reach beyond S (they
  /// occlude and, masked, change pixels wherever they are); targets must lie in S (SPEC §2).
  enum class Role { static_obstacle, dynamic_obstacle, critical, target };

  static const char* role_name(Role role);

  SceneObject parse_object(const JsonNode& node, Role role) const;

  std::vector<SceneObject> parse_objects(const JsonNode& list, Role role) const;

  /// An event as parsed, with the JSON pointer of its weight (for the weight checks).
  struct ParsedEvent {
    Event event;
    std::string weight_entry;
  };

  std::vector<ParsedEvent> parse_events(const JsonNode& events) const;

  /// The robots of "robots", each expanded into its links at every sample of its trajectory.
  std::vector<detail::RobotSteps> parse_robots(const JsonNode& list);

  // The time steps (SPEC §2): those of "time_steps" and, with "robots", one per sample of the
  // robots' trajectories (the robots' links join each step's dynamic obstacles); each step's
  // events are its own, then the scene's shared "events", then the people generated for it.
  void parse_time_steps(const JsonNode& root);

  void check_targets_clear_of_obstacles(const JsonNode& root) const;

  /// Records a file the scene reads (for provenance), once.
  void note_file(const std::string& full) const;

  /// Validates and orients an object's mesh, repairing it as `repair` asks; records the repair.
  void finish_object_mesh(TriangleMesh& mesh, const detail::RepairOptions& repair,
                          const std::string& entry, const std::string& name,
                          const char* role) const;

  static bool boxes_meet(const Box3& a, const Box3& b);

  static inline const nlohmann::json kRoom = "room";
  std::string path_;
  std::filesystem::path dir_;
  Scene scene_;
  mutable std::vector<std::string> mesh_files_;  ///< filled while objects are parsed
  mutable std::vector<MeshRepair> repairs_;      ///< filled while objects are parsed
  detail::RepairOptions default_repair_;         ///< the root "repair" (default: none)
};

}  // namespace detail
}  // namespace camplace::core
