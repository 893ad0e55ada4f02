#pragma once
/// The exact reference pipeline of SPEC §6: the model of SPEC §3–4 built with CGAL Nef polyhedra
/// (Epeck) on the inscribed k-sided camera pyramids, exact component volumes and z-extents for the
/// plausibility filter, exact squared distances. No CGAL type appears here.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/evaluation.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::exact {

/// Options of the exact evaluation.
struct ExactOptions {
  /// Empty: no export. Otherwise a directory (created if missing) that receives each state's
  /// model as `state-h<H>-e<L>-model.off` and each camera's pyramid (clipped to S) as
  /// `camera-<i>-pyramid.off` (triangle meshes, metres, world frame; readable by MeshLab).
  std::string export_dir;
  /// Keep each state's model in ExactEvaluation::models (for validation).
  bool keep_models = false;
  /// Threads (0 = std::thread::hardware_concurrency()), each with its own Nef objects: worker
  /// threads evaluate states in parallel, whole time steps per thread (so the per-step caches
  /// still help; a step's events are split only when there are fewer steps than threads); the
  /// threads beyond one per such task help the workers by building each camera's shadows, cones
  /// and free-region pieces ahead (they do not depend on the model), so that a single state also
  /// uses them. Each state's model is still built camera after camera by one thread. The results,
  /// the count of removed components included, do not depend on it and are always in state order
  /// (docs/design/exact-model.md E4).
  int threads = 0;
  /// Build each silhouette cone as the union of one cone per visible face (the former
  /// construction: the same model exactly, much slower on fine meshes; a reference for tests and
  /// benchmarks) instead of the cones over the objects' outlines in each camera's image plane.
  bool face_cones = false;
  /// Build each non-convex occluding object's shadow as the union of one shadow per front face
  /// (the former construction: the same model exactly, much slower on fine meshes; a reference
  /// for tests and benchmarks) instead of the shadows of patches of front faces whose images in
  /// the camera's image plane overlap nowhere (docs/design/exact-model.md E2).
  bool face_shadows = false;
  /// Share the targets' silhouette cones between the states whose targets have the same meshes
  /// (vertex for vertex) and whose occluding objects have the same meshes, e.g. a person standing
  /// at the same place in every time step. Off: every state builds its own (the reference for
  /// tests). The results do not depend on it.
  bool reuse_poses = true;
  /// Exact distances d(C, M) only for the pairs of triangles that double-precision bounds cannot
  /// rule out (a certified lower bound against the smallest approximate distance). Off: every
  /// pair whose boxes are nearer than the best exact distance so far (the reference for tests).
  /// The results do not depend on it.
  bool filtered_distances = true;
  /// Subtract the obstacles from each state's model once, after the cameras' free regions, rather
  /// than start from S minus the obstacles (then a fine robot's facets enter every camera's
  /// boolean). Off: the former order (the reference for tests). The distances, volumes and kept
  /// components do not depend on it; the count of removed components may (pieces are discarded
  /// at other times).
  bool obstacles_last = true;
  /// Build each camera's free region only within a box around the model once that box fills at
  /// most this fraction of the box around S (docs/design/exact-model.md E3): 0 never (the whole
  /// free region, the reference for tests), 1 from the first camera on. The results do not
  /// depend on it, the count of removed components included.
  double model_box_fraction = 0.5;
  /// The states to evaluate (each once). Empty: every state of the scene. Otherwise
  /// ExactEvaluation::states (and models) hold only these, in the scene's state order, and its
  /// err sums only their terms. A state the scene does not have is a core::OptionError
  /// ("states").
  std::vector<core::StateIndex> states;
  /// Called as the work advances with the (state, camera) steps done and their total (states ×
  /// cameras); from the worker threads, one call at a time. Empty: none.
  std::function<void(long done, long total)> on_progress;
};

/// One connected component of a model (connected through interiors), before the filter.
struct ExactComponent {
  double volume = 0.0;              ///< m³ (exact value rounded)
  double z_min = 0.0, z_max = 0.0;  ///< m
  bool kept = true;                 ///< survived the plausibility filter
};

/// The exact model M of one state after the plausibility filter (SPEC §4). Cheap to copy
/// (shared, immutable).
class ExactModel {
 public:
  ExactModel();
  /// True when p (m, world frame) lies in the closed model (points on the boundary count).
  bool contains(const core::Vec3& p) const;
  /// True when the model is empty.
  bool empty() const;
  /// Exact volume rounded to double (m³).
  double volume() const;
  /// Number of connected components (connected through interiors) kept by the filter.
  int components() const;
  /// Every component found before the filter, kept or not.
  std::vector<ExactComponent> component_info() const;
  /// The model's boundary as a triangle soup rounded to double (outward orientation).
  core::TriangleMesh boundary_mesh() const;
  /// The exact squared distance (m², a fraction "p/q", "0/1" for 0) between the union of the
  /// closed solids `solids` (closed outward triangle meshes, m, world frame) and the model, as
  /// d(C, M) of SPEC §4 with C = `solids`; empty when the model is empty. `filtered`:
  /// ExactOptions::filtered_distances (off: the reference; the value does not depend on it).
  std::string squared_distance_fraction(const std::vector<core::TriangleMesh>& solids,
                                        bool filtered = true) const;

  struct Impl;
  explicit ExactModel(std::shared_ptr<const Impl> impl);

 private:
  std::shared_ptr<const Impl> impl_;
};

/// Exact evaluation of every state (SPEC §6): Err, the states' results (with d_true² and d_model²
/// as exact fractions) and the timing (labelling_ms: FOVs, shadows, silhouette cones and the Nef
/// model).
struct ExactEvaluation : core::Evaluation {
  std::vector<ExactModel> models;  ///< one per state when ExactOptions::keep_models
  /// Camera parts (shadows, cones, free-region pieces of one camera for one state) that helper
  /// threads built ahead (ExactOptions::threads); 0 without helpers.
  long parts_built_ahead = 0;
};

/// Evaluates Err exactly for `config` (one setting per camera of `scene`). The FOV is always
/// each cone camera's inscribed pyramid (its model's `sides` sides, SPEC §1), pyramids and frusta
/// as they are, each cut at its near and far planes.
/// Throws core::InputError when the configuration does not match the scene
/// (core::check_configuration) and std::runtime_error when an export file cannot be written.
ExactEvaluation evaluate_exact(const core::Scene& scene, const core::CameraConfig& config,
                               const ExactOptions& options = {});

/// The exact model of one state (for validation). Same semantics as evaluate_exact.
ExactModel build_exact_model(const core::Scene& scene, const core::CameraConfig& config,
                             const core::StateIndex& state, const ExactOptions& options = {});

}  // namespace camplace::exact
