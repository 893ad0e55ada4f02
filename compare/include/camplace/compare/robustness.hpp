#pragma once
/// `camplace robustness`: how the Err of a camera configuration changes when every camera is
/// mounted within a position and an angle tolerance of its planned setting. Seeded random
/// perturbations, a local worst-case search (coordinate ascent on the voxel Err), the Err with one
/// camera perturbed at a time, and an exact check of the worst configurations found.
#include <array>
#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/names.hpp"
#include "camplace/core/provenance.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::compare {

struct RobustnessOptions {
  double position_tol = 0.0;  ///< m: each camera's position moves by at most this (Euclidean)
  /// radians: each camera's viewing direction turns by at most this (the angle between the
  /// planned and the perturbed direction), and its roll (not for a cone) by at most this.
  double angle_tol = 0.0;
  int samples = 200;  ///< random perturbations of all cameras at once (≥ 1)
  unsigned seed = 1;  ///< seeds the random perturbations
  /// The pipeline whose Err the samples report: voxel (the scene's FOV, as `evaluate`), or
  /// exact (every sample by the exact pipeline, as `evaluate --pipeline exact`; slow). The
  /// worst-case search always climbs the voxel Err.
  core::Pipeline pipeline = core::Pipeline::voxel;
  core::LabelMode mode = core::LabelMode::conservative;
  std::array<int, 3> resolution{0, 0, 0};  ///< all 0 = the scene's `voxels`
  int refine = 0;                          ///< voxel::VoxelOptions::refine
  int threads = 1;                         ///< threads of one evaluation (both pipelines)
  /// Voxel evaluations of the worst-case search over all cameras (0 = no search); as many again
  /// for the search with one camera perturbed at a time.
  int search_evaluations = 2000;
  /// Worst distinct configurations (by the samples' pipeline) evaluated by the exact pipeline
  /// (0 = none). With pipeline exact every sample is exact already; the searched ones are added.
  int exact_checks = 3;
  const std::atomic<bool>* interrupt = nullptr;  ///< set: stop, keep what is done
  /// Called as work advances: stage ("samples", "search", "per camera", "exact check"), done,
  /// total.
  std::function<void(const std::string& stage, int done, int total)> on_progress;
};

/// One perturbed configuration.
struct Perturbed {
  std::string origin;               ///< "sample 17", "search (all cameras)", "search (camera 2)"
  core::CameraConfig cameras;       ///< as re-read from `cameras_json`
  std::string cameras_json;         ///< the camera file's text (core::camera_config_json, named
                                    ///< models): `evaluate --cameras` of it reads `cameras` exactly
  double err = 0.0;                 ///< m², by the samples' pipeline
  double voxel_err = 0.0;           ///< m², voxel pipeline (the scene's FOV)
  std::optional<double> exact_err;  ///< m², exact pipeline, when checked
  std::vector<double> moved_m;      ///< per camera: |position − planned position| (m)
  std::vector<double> turned;       ///< per camera: angle between the directions (radians)
  std::vector<double> rolled;       ///< per camera: |roll − planned roll| (radians)
};

/// With one camera perturbed, the others as planned.
struct CameraSensitivity {
  int camera = 0;
  double worst_voxel_err = 0.0;  ///< m², the worst found (samples and search)
  int evaluations = 0;
};

struct RobustnessResult {
  double nominal_err = 0.0;  ///< m², the planned configuration by the samples' pipeline
  double nominal_voxel_err = 0.0;
  std::optional<double> nominal_exact_err;
  double tolerance = 0.0;          ///< m², the scene's default (½ voxel diagonal)²
  double err_lower_bound = 0.0;    ///< m², conservative voxel lower bound (0 in center mode)
  std::vector<Perturbed> samples;  ///< in order (fewer than asked after an interrupt)
  double p95_err = 0.0;            ///< m²: the 95th percentile of the samples' Err (nearest rank)
  double median_err = 0.0;         ///< m²
  /// The worst configuration found by the samples' pipeline (samples and, for voxel, the
  /// search); an exact-checked one when the pipeline is exact.
  Perturbed worst;
  std::optional<Perturbed> searched;          ///< the search's result over all cameras
  std::vector<CameraSensitivity> per_camera;  ///< one per camera, in order
  std::vector<Perturbed> exact_checked;       ///< worst first by their pipeline's Err
  int voxel_evaluations = 0, exact_evaluations = 0;
  double seconds = 0.0;
  bool interrupted = false;
};

/// The perturbation bound check: true when every camera of `perturbed` lies within the
/// tolerances of `planned` (position within position_tol m, direction within angle_tol rad,
/// roll within angle_tol rad), up to the rounding of camera files (1e-9).
bool within_tolerance(const core::CameraConfig& planned, const core::CameraConfig& perturbed,
                      double position_tol, double angle_tol);

/// Analyses `planned` (one setting per camera of `scene`, inside its placement domains and
/// keep-out free: optimize::check_inside_domains). Every perturbed configuration is made valid
/// as the optimizer makes its own (optimize::Encoding: clamped into the domain, projected onto
/// the mount, moved out of keep-out boxes); one that the repair would move beyond the
/// tolerances is shrunk toward the planned one until it lies within them. Deterministic for
/// given options (the thread count aside). Throws core::InputError for a configuration that
/// does not fit the scene, core::OptionError for bad options.
RobustnessResult analyse_robustness(const core::Scene& scene, const core::CameraConfig& planned,
                                    const RobustnessOptions& options);

/// What the report says about how it was made.
struct RobustnessReport {
  std::string command;       ///< the command line, quoted in the report
  std::string cameras_file;  ///< the planned configuration's file as given
  core::Provenance provenance;
};

/// Writes, each atomically, into `dir` (which must exist): robustness.json (everything, with
/// the provenance and the options), robustness.md (the report), samples.csv (one row per random
/// sample) and worst-cameras.json (result.worst as a camera file: `camplace evaluate --cameras`
/// of it reproduces result.worst's Err with the same options; `--pipeline exact` its exact Err).
void write_robustness_report(const std::string& dir, const RobustnessOptions& options,
                             const RobustnessResult& result, const RobustnessReport& report);

/// The verdict lines of the report (also printed by the command).
std::string robustness_summary(const RobustnessOptions& options, const RobustnessResult& result);

}  // namespace camplace::compare
