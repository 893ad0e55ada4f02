#pragma once
/// The result of `camplace evaluate --json` (docs/files.md, "evaluate --json"): one camera
/// configuration evaluated by the voxel pipeline, the exact pipeline or both, as one JSON object.
/// The command-line tool and the Python module (python/) both print or return this object.
#include <array>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/names.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "camplace/voxel/grid.hpp"

namespace camplace::compare {

/// What `camplace evaluate` takes besides the scene and the cameras.
struct EvaluationOptions {
  core::Pipeline pipeline = core::Pipeline::voxel;
  core::LabelMode mode = core::LabelMode::conservative;  ///< voxel labelling mode
  std::array<int, 3> resolution{0, 0, 0};  ///< nx, ny, nz; all 0 = the scene's `voxels`
  /// States evaluated in parallel, both pipelines; 0 = one thread per core.
  int threads = 0;
  /// Voxel pipeline, conservative mode: adaptive refinement levels (voxel::VoxelOptions::refine).
  int refine = 0;
  /// Exact pipeline: add each state's squared distances and volume as exact fractions "p/q".
  bool exact_fractions = false;
  /// Exact pipeline: write each state's model and each camera's pyramid as OFF files to this
  /// directory (exact::ExactOptions::export_dir); empty = none.
  std::string export_dir;
  /// The camera file's path as the result names it ("cameras_file").
  std::string cameras_file;
  /// Voxel pipeline: also return each state's filtered model (Evaluation::voxel_models).
  bool voxel_models = false;
  /// Called as the work advances: the stage ("voxel set-up 16x12x12", "voxel evaluation",
  /// "voxel diagnostics", "exact evaluation"), the steps done in it and their total (0: the stage
  /// reports no count): states, and for "exact evaluation" (state, camera) steps, reported from
  /// the exact pipeline's worker threads one call at a time; the others from the calling thread.
  /// Empty: none.
  std::function<void(const std::string& stage, int done, int total)> on_progress;
};

/// What evaluate_json returns.
struct EvaluationJson {
  /// The object `camplace evaluate --json` prints, of one shape for every pipeline:
  /// {"pipeline", "scene" (the scene's path as loaded), "cameras_file", "voxel", "exact",
  /// "differences"}, where "voxel" and "exact" are each pipeline's result (voxel: with "mode",
  /// "fov", "resolution", "voxel_diagonal", "tolerance" and "err_lower_bound") or null when it
  /// did not run, and "differences" is null unless both ran. With one pipeline its result's
  /// members also stand at the top level ("err", "states", ...). Every number is finite.
  nlohmann::json result;
  /// With EvaluationOptions::voxel_models and a voxel pipeline: the voxel grid and each state's
  /// filtered model (1 = in M, index i + nx·(j + ny·k)), what `--voxels-out` writes
  /// (view::write_voxel_files); empty otherwise.
  struct StateModel {
    int time_step = 0, event = 0;
    std::vector<std::uint8_t> model;
  };
  voxel::Grid grid;
  std::vector<StateModel> voxel_models;
};

/// Evaluates `config` (one setting per camera of `scene`) as `camplace evaluate` does: with
/// pipeline both the voxel pipeline uses the inscribed pyramid (SPEC §1). Throws
/// core::InputError for a configuration that does not fit the scene or a bad resolution,
/// core::OptionError("pipeline", ...) when the exact pipeline is asked for but not built, and
/// std::runtime_error when an export file cannot be written.
EvaluationJson evaluate_json(const core::Scene& scene, const core::CameraConfig& config,
                             const EvaluationOptions& options);

/// The "diagnostics" member of evaluate_json's voxel result for `config` on `evaluator`'s scene
/// (docs/files.md, "evaluate --json"): per state the kept component nearest to the critical
/// objects and how many cameras observe it, per camera the fraction of S in its FOV and of the
/// targets it sees, and the warnings. For callers that keep an evaluator (camplace serve). With
/// `state` ≥ 0 (an index of core::states()) only that state is examined: "states" holds its
/// entry alone (its nearest component also lists the observing cameras' indices as
/// "observed_by"), the cameras' target fractions count its targets, and the warnings about all
/// states (d = 0 everywhere, empty models) are left out; a sixth of the work on 6 states.
nlohmann::json voxel_diagnostics(const voxel::VoxelEvaluator& evaluator,
                                 const core::CameraConfig& config, int state = -1);

/// Why `npy_path` cannot receive the voxel models ("needs a file name ending in .npy, got ..."),
/// or "" when it can (the check `evaluate --voxels-out` and the Python module make first).
std::string voxel_models_path_problem(const std::string& npy_path);

/// Writes the voxel models of `evaluation` (EvaluationOptions::voxel_models) as `npy_path`
/// (ending in ".npy") with its ".json" sidecar and ".vtk" twin (view::write_voxel_files; the
/// sidecar names the pipeline, mode and FOV), each file atomically: `evaluate --voxels-out`.
/// Throws std::runtime_error naming a path that cannot be written.
void write_voxel_models(const EvaluationJson& evaluation, const std::string& npy_path);

}  // namespace camplace::compare
