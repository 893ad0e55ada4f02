#pragma once
/// What an evaluation of a camera configuration reports (SPEC §4–6), filled alike by the voxel
/// and the exact pipeline, so that both are printed, compared and validated by one code path.
#include <string>
#include <vector>

namespace camplace::core {

/// Result for one state (time step h, event l); distances in m, volume in m³.
struct StateResult {
  int time_step = 0;
  int event = 0;
  double weight = 0.0;
  double d_true = 0.0;        ///< d(C_h, O_u(a_lh))
  double d_model = 0.0;       ///< d(C_h, M); empty_model_distance() when M is empty (SPEC §4)
  double model_volume = 0.0;  ///< after the plausibility filter
  int components = 0;         ///< components kept by the plausibility filter
  /// Components the filter discarded (exact pipeline: pieces discarded as soon as they certainly
  /// fail the filter, one each; docs/files.md).
  int components_removed = 0;
  /// Exact pipeline only: d_true² and d_model² as exact fractions "p/q" (empty otherwise).
  std::string d_true_sq_exact;
  std::string d_model_sq_exact;
  /// Exact pipeline only: model_volume (m³) as an exact fraction "p/q" (empty otherwise).
  std::string model_volume_exact;
};

/// Wall-clock split of one evaluation in milliseconds (SPEC §5).
struct Timing {
  /// Building the unfiltered model from the cameras: the voxel labelling (the paper's
  /// "intersection test"), or the exact FOVs, shadows, silhouette cones and Nef booleans.
  double labelling_ms = 0.0;
  double clustering_ms = 0.0;  ///< components and the plausibility filter
  double distance_ms = 0.0;    ///< d(C, M) (and, exact pipeline, d_true)
  double total_ms = 0.0;
};

/// One evaluation of all states.
struct Evaluation {
  double err = 0.0;  ///< Σ ω (d_true − d_model)², m² (SPEC §4)
  std::vector<StateResult> states;
  Timing timing;
};

/// Err of the states' results (SPEC §4), m².
double error_of(const std::vector<StateResult>& states);

}  // namespace camplace::core
