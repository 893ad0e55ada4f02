#pragma once
/// The scene file of a Scene (SPEC §2 format): the inverse of load_scene. Loading what is
/// written gives back the same scene, number for number and vertex for vertex (the objects'
/// entries are the JSON pointers where they are written, the file is the new path, and no
/// mesh files are referenced: meshes are written inline).
#include <nlohmann/json.hpp>
#include <string>

#include "camplace/core/scene.hpp"

namespace camplace::core {

/// The scene file's JSON, keys in the order of data/paper_basic.json: "description" (only
/// when `description` is not empty), area, voxels, cameras, static_obstacles, time_steps,
/// dynamic_mode, plausibility (only when a threshold is set).
/// - Angles are written in degrees: the shortest decimal d with d·π/180 exactly the stored
///   radians (as the loader converts), as a JSON integer when whole ("half_angle_deg": 30).
///   Radians no degree value converts to (never from a loaded scene) are written as the
///   nearest degree value.
/// - A domain equal to a preset is written as its name; equal domains as one "domain",
///   differing ones as "camera_domains"; default yaw and pitch bounds are left out.
/// - An object whose mesh is what the loader makes of a tetrahedron or a box is written as one
///   ("tetrahedron": its 4 points, "box": min and max), any other as an inline mesh; mesh
///   files and transforms are written as the mesh they produced. Every object is named.
/// - "critical" is left out when it is the default (a copy of dynamic_obstacles, same
///   entries); "t" is always written.
/// Exact for every scene load_scene returns, and for scenes built in code that keep its
/// invariants (one domain per camera, closed outward meshes using all their vertices, angles
/// that are some degree value times kDegree).
nlohmann::ordered_json scene_json(const Scene& scene, const std::string& description = "");

/// scene_json as text: indented by one space per level, ending in a newline. Same scene and
/// description ⇒ identical text.
std::string scene_text(const Scene& scene, const std::string& description = "");

/// Writes scene_text to `path` atomically (write_file_atomically). Throws std::runtime_error
/// naming the path when it cannot be written.
void write_scene(const Scene& scene, const std::string& path, const std::string& description = "");

}  // namespace camplace::core
