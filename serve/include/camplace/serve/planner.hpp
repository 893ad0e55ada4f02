#pragma once
/// The state behind `camplace serve` (docs/serve.md): one scene, a warm voxel evaluator, the
/// current camera configuration with its undo history, and the answers the page asks for, as
/// JSON. No HTTP here (server.hpp); every member is thread-safe.
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/voxel/evaluator.hpp"

namespace camplace::serve {

struct PlannerOptions {
  /// Mode, resolution and refinement of the voxel pipeline; `threads` per evaluation.
  voxel::VoxelOptions voxel;
  std::string scene_file;    ///< the scene as named on the command line
  std::string cameras_file;  ///< the start configuration's file ("" = the corner heuristic)
  std::string out_dir;       ///< where save() and save_unsaved() write (created when needed)
};

/// What the page and the long jobs need of the current state, copied under the lock.
struct Snapshot {
  std::shared_ptr<const core::Scene> scene;  ///< with the current cameras (count, models)
  core::CameraConfig config;
  PlannerOptions options;
};

class Planner {
 public:
  /// Sets up the evaluator for `scene` and starts from `start` (repaired into the domains as
  /// the optimizer repairs). Throws core::InputError / core::OptionError as VoxelEvaluator does.
  Planner(core::Scene scene, const core::CameraConfig& start, PlannerOptions options);
  ~Planner();

  /// What does not change while cameras move: S, the objects of every state (meshes in the
  /// z-up world frame), the d_true segments, the camera models, the role colours and the
  /// settings (mode, resolution, refine, files).
  nlohmann::json scene_json() const;

  /// Sets the configuration from a request {"cameras": [camera-file entries], "state": i,
  /// "commit": bool} and returns view(i). The cameras are read as a camera file is
  /// (core::camera_config_from_json, named "request" in errors), then kept in their domains and
  /// out of the keep-out boxes by the optimizer's repair (optimize::Encoding::clamp), then
  /// rounded as their camera-file text is re-read, so that a saved file gives the same Err.
  /// `commit` (default true) makes the new configuration an undo step; false (while dragging)
  /// only shows it. Throws core::InputError naming the request entry.
  nlohmann::json update(const nlohmann::json& request);
  /// The current configuration evaluated, with state `state`'s model boundary, d_model segment
  /// and diagnostics: {"cameras", "snapped", "err", "err_lower_bound", "tolerance", "states",
  /// "state", "model", "d_model", "fovs", "diagnostics", "timing_ms", "undo", "dirty"}. Throws
  /// core::InputError("request", "/state", ...) for a state out of range.
  nlohmann::json view(int state) const;
  /// Back to the configuration before the last committed change (or, after an uncommitted one,
  /// to the last committed); then view(state). Nothing to undo: the same configuration.
  nlohmann::json undo(int state);
  /// Adds a camera of the scene's model `model` ("" = the single model), placed by the corner
  /// heuristic (optimize::corner_start) in that model's domain; removes camera `index`. Both
  /// rebuild the evaluator and are undo steps. Throws core::InputError for an unknown model, an
  /// index out of range or the last camera.
  nlohmann::json add_camera(const std::string& model, int state);
  nlohmann::json remove_camera(int index, int state);

  /// Sets the configuration (an optimizer's or another job's result) as an undo step.
  void commit(const core::CameraConfig& config);

  /// Writes the current configuration as OUT_DIR/NAME.json, a camera file with provenance that
  /// `camplace evaluate` reads (and, when cameras were added or removed, the scene with the
  /// current camera list as OUT_DIR/NAME.scene.json), each atomically. `name`: letters, digits,
  /// '-', '_' and '.', 1..64 characters. Returns {"cameras_file", "scene_file", "err",
  /// "command"} (the evaluate command that reproduces the Err). Throws core::InputError for a
  /// bad name, std::runtime_error when a file cannot be written.
  nlohmann::json save(const std::string& name);
  /// When the configuration changed since it was loaded or saved: writes it as
  /// OUT_DIR/unsaved-<time>.json (as save()) and returns its path; "" otherwise.
  std::string save_unsaved();

  Snapshot snapshot() const;
  int state_count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace camplace::serve
