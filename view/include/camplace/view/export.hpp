#pragma once
/// `camplace export`: each state of a camera configuration as a binary glTF 2.0 file, a
/// self-contained three.js viewer page, camera pose files and the voxel model (docs/export.md).
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/closest_points.hpp"
#include "camplace/core/evaluation.hpp"
#include "camplace/core/names.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/voxel/evaluator.hpp"

namespace camplace::view {

/// Where Debian's libjs-three installs three.js (three.min.js, examples/js/...).
inline constexpr const char* kDefaultThreeDir = "/usr/share/javascript/three";

/// The roles of the nodes of an exported glTF file (node extras "role"), in drawing order.
inline const std::array<const char*, 9> kRoles{
    "static_obstacle", "dynamic_obstacle", "critical_object", "target", "model", "camera", "fov",
    "true_distance",   "model_distance"};

struct ExportOptions {
  /// voxel or exact (both is refused: one model per file).
  core::Pipeline pipeline = core::Pipeline::voxel;
  voxel::VoxelOptions voxel;  ///< mode, resolution and threads of the voxel pipeline
  int threads = 0;            ///< exact pipeline threads, 0 = one per core
  /// States to export (each must exist); empty = every state.
  std::vector<core::StateIndex> states;
  /// libjs-three's directory; three.min.js, OrbitControls.js and GLTFLoader.js are copied from
  /// it into the output's three/ folder.
  std::string three_dir = kDefaultThreeDir;
  /// The scene and camera files as named on the command line (shown by the page).
  std::string scene_file, cameras_file;
  /// Called as the exact pipeline advances: its (state, camera) steps done and their total
  /// (exact::ExactOptions::on_progress). Empty: none.
  std::function<void(long done, long total)> on_exact_progress;
};

/// What one state's file holds.
struct ExportedState {
  core::StateIndex state;
  std::string glb;                    ///< file name in the output directory
  core::StateResult result;           ///< d_true, d_model, weight of the pipeline
  std::map<std::string, int> nodes;   ///< glTF nodes per role (kRoles)
  core::ClosestPoints true_segment;   ///< between the critical objects and the targets
  bool model_empty = false;           ///< M is empty: no model mesh, no model segment
  core::ClosestPoints model_segment;  ///< between the critical objects and M
};

struct ExportResult {
  /// Err (m²) over err_states states: every state of the scene, whichever states were exported,
  /// except with the exact pipeline and chosen states (ExportOptions::states), which evaluates
  /// and sums only those.
  double err = 0.0;
  int err_states = 0;
  std::vector<ExportedState> states;
  std::vector<std::string> files;  ///< every file written, relative to the output directory
};

/// The colour of each role (kRoles; linear RGBA in [0, 1]) as the glTF materials and the viewer's
/// legend use them: {"static_obstacle": [r, g, b, a], ...}.
nlohmann::ordered_json role_colors_json();

/// d(C, M) on voxels as the voxel pipeline measures it (SPEC §5), with its closest points: from
/// the `critical` meshes (a) to the nearest model voxel's box (conservative) or centre (center
/// mode) (b). `model`: one byte per cell of `grid` (1 = in M), not all 0; `critical` not empty.
core::ClosestPoints voxel_model_segment(const voxel::Grid& grid,
                                        const std::vector<std::uint8_t>& model,
                                        const std::vector<const core::TriangleMesh*>& critical,
                                        core::LabelMode mode);

/// Checks the options against the scene before any work: pipeline voxel or exact and built,
/// every state present, the three.js files readable. Throws core::OptionError naming "pipeline",
/// "state" or "three-dir".
void check_export_options(const core::Scene& scene, const ExportOptions& options);

/// Evaluates `config` on `scene` with the chosen pipeline and writes into `out_dir` (which must
/// exist): state-H-L.glb per state, index.html + viewer-data.js + three/, poses.json,
/// poses.yaml and, voxel pipeline, voxels.npy/.json/.vtk. Everything is computed before the
/// first file is written; each file is written atomically. Throws what check_export_options
/// throws, core::InputError from the pipelines, and core::OptionError("out", ...) when a file
/// cannot be written.
ExportResult export_scene(const core::Scene& scene, const core::CameraConfig& config,
                          const ExportOptions& options, const std::string& out_dir);

}  // namespace camplace::view
