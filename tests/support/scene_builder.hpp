#pragma once
// Scenes built in code for tests and benchmarks.
#include <random>
#include <string>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::testing {

/// Axis-aligned box object (outward triangles).
core::SceneObject box_object(const std::string& name, const core::Vec3& min, const core::Vec3& max);
/// A closed, outward triangle mesh of exactly `triangles` triangles approximating the ellipsoid
/// inscribed in `box` (centre and semi-axes from the box): a latitude–longitude sphere of b
/// bands and m segments (2·m·(b − 1) triangles: fans at the poles, quads split in two between),
/// scaled; every vertex lies on the ellipsoid, the poles at the box's top and bottom faces. b − 1
/// is the divisor of triangles/2 nearest to √(triangles/4) (m ≈ 2(b − 1): near-square quads),
/// so counts with few divisors give long thin triangles. Throws std::invalid_argument when
/// `triangles` is odd or below 6 (m ≥ 3) or the box is empty along an axis.
core::TriangleMesh ellipsoid_mesh(const core::Box3& box, int triangles);
/// An object of ellipsoid_mesh(box, triangles), bounds set.
/// An object named `name` (its entry too) of the given mesh, with its bounds.
core::SceneObject mesh_object(const std::string& name, core::TriangleMesh mesh);
core::SceneObject ellipsoid_object(const std::string& name, const core::Box3& box, int triangles);
/// Tetrahedron object, oriented outward whatever the order of the points.
core::SceneObject tetra_object(const std::string& name, const core::Vec3& a, const core::Vec3& b,
                               const core::Vec3& c, const core::Vec3& d);

/// A scene over `area` with one time step holding the given critical objects and one event
/// (weight 1) with the given targets; `count` cone cameras of half angle `half_angle_deg`.
core::Scene simple_scene(const core::Box3& area, std::array<int, 3> voxels, int count,
                         double half_angle_deg, std::vector<core::SceneObject> critical,
                         std::vector<core::SceneObject> targets);

/// Camera setting from degrees.
core::CameraSetting camera_at(const core::Vec3& position, double yaw_deg, double pitch_deg);

/// Random scene in a 4×3×3 m room: static, dynamic and target boxes/tetrahedra in disjoint
/// cells (so targets never meet obstacles), 2 time steps × 2 events, random FOV shape, range and
/// dynamic mode.
core::Scene random_scene(std::mt19937& rng, std::array<int, 3> voxels);
/// `scene` with every object's mesh (static and dynamic obstacles, critical objects, targets)
/// replaced by ellipsoid_mesh(its bounding box, `triangles`): the same layout with fine meshes.
core::Scene with_fine_meshes(core::Scene scene, int triangles);
/// Random camera configuration inside the scene's area.
core::CameraConfig random_config(std::mt19937& rng, const core::Scene& scene);
/// Moves every other camera of `config` (0, 2, 4, ...) onto an x or y wall of S, looking at a
/// random point of S's lower half: the model then shrinks well inside S, and a box around it
/// leaves such cameras outside (the exact pipeline's model box).
void put_on_walls(std::mt19937& rng, const core::Scene& scene, core::CameraConfig& config);
/// Gives the scene's cameras a mix of models: camera i is a frustum when i % 3 is
/// 0 or 1 (full angles H ∈ [20°, 170°], V ∈ [20°, 150°]), else a pyramid (3–16 sides) or a
/// cone; each with a near plane (0.05–0.8 m) half of the time and a far plane (2–5 m) a third
/// of the time. Models are named "m<i>".
void randomize_camera_models(std::mt19937& rng, core::Scene& scene);
/// A 4×3×3 m room for random exact-pipeline scenes whose object groups never meet: the room's
/// scene (simple_scene with 8×6×6 voxels and no objects, 2–3 cameras of random models,
/// randomize_camera_models, as the exact pipeline reads them, core::use_exact_models) and the
/// centres of its 4×3×2 cells of 1×1×1.5 m in random order, one per object group (next_cell).
struct CellRoom {
  core::Scene scene;
  std::vector<core::Vec3> cells;
  std::size_t next = 0;
  core::Vec3 next_cell() { return cells.at(next++); }
};
CellRoom cell_room(std::mt19937& rng);
/// A random roll in [−180°, 180°] for every camera of `config`.
void randomize_rolls(std::mt19937& rng, core::CameraConfig& config);
/// `base`, `jittered` copies of it moved by ~0.1 m and ~3° (near-optimal when `base` is) and
/// `random` random configurations, all from `seed`.
std::vector<core::CameraConfig> configs_around(const core::CameraConfig& base,
                                               const core::Scene& scene, unsigned seed,
                                               int jittered, int random);

/// Writes text to a file (creating directories) and returns the path.
std::string write_file(const std::string& path, const std::string& text);
/// A fresh empty directory under the system temporary directory, removed when the test
/// program ends (kept if CAMPLACE_KEEP_TEST_FILES is set).
std::string temp_dir(const std::string& name);

}  // namespace camplace::testing
