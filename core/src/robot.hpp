#pragma once
// Robots from URDF on a joint trajectory (the scene's "robots"): each robot expands into the
// meshes of its links at every sample of the trajectory. Private to core; docs/robots.md
// describes the format.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "camplace/core/geometry.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::core::detail {

/// Makes a link's mesh (link frame, URDF scale applied) an object mesh: validates, orients and
/// repairs it as the scene says; throws InputError naming `entry`. Supplied by the scene parser.
using LinkMeshFinisher = std::function<void(TriangleMesh& mesh, const std::string& entry,
                                            const std::string& object_name)>;

/// One robot expanded over its trajectory samples.
struct RobotSteps {
  std::string name;
  std::vector<double> times;                    ///< t of each sample (s)
  std::vector<std::vector<SceneObject>> links;  ///< [sample][object], world frame, bounds set
  std::vector<std::string> files;               ///< URDF, trajectory CSV, meshes as opened
};

/// Expands one entry of the scene's "robots" array (`node`, e.g. /robots/0): parses its URDF,
/// reads its trajectory (CSV file or inline array), samples it and places every link's
/// collision (or visual) geometry at each sample by forward kinematics, in the world frame
/// (metres) given by `base`. Relative paths are relative to `scene_dir`; errors are
/// InputError naming `scene_file` (or the trajectory CSV), the entry and the reason. Each link
/// mesh is read and passed to `finish` once, in its link frame.
RobotSteps expand_robot(const JsonNode& node, const std::filesystem::path& scene_dir,
                        const std::string& scene_file, const LinkMeshFinisher& finish);

/// Sides of the polygon of a URDF <cylinder> prism (circumscribed about the circle).
constexpr int kCylinderSides = 32;
/// Bands (from pole to pole) and sectors (around z) of a URDF <sphere>'s polyhedron.
constexpr int kSphereBands = 8;
constexpr int kSphereSectors = 16;

/// The closed, outward mesh that a URDF <cylinder> (axis z, centred at the origin; metres)
/// becomes: a kCylinderSides-sided prism whose polygon circumscribes the circle (vertices at
/// radius r / cos(π/k)), so it contains the cylinder.
TriangleMesh cylinder_mesh(double radius, double length);
/// The closed, outward mesh that a URDF <sphere> (centred at the origin; metres) becomes: a
/// convex polyhedron of kSphereBands × kSphereSectors (latitude × longitude) scaled so that
/// every face plane lies at least `radius` from the centre, so it contains the sphere.
TriangleMesh sphere_mesh(double radius);

}  // namespace camplace::core::detail
