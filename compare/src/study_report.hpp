#pragma once
// The report of a study: runs.csv, report.md and the paper's plots. Private to compare.
#include <string>
#include <vector>

#include "study_definition.hpp"

namespace camplace::compare::detail {

/// One finished run of a study: its group's scene and the run's result (from its run file).
struct RunRow {
  std::string examination, family, group;
  int param = 0;
  unsigned seed = 0;
  // x values of the group's scene
  long voxels = 0;
  int cameras = 0, static_objects = 0, static_facets = 0, dynamic_objects = 0, dynamic_facets = 0;
  int target_objects = 0, target_facets = 0, time_steps = 0, events = 0;
  std::string resolution;
  /// What made the run: "0.1.0, commit <sha>" from its run file's provenance ("" without one).
  std::string made_by;
  // the run
  double err = 0, tolerance = 0, seconds = 0;
  double target = 0;  ///< core::success_target: the tolerance, or max(tolerance, L) (conservative)
  long long evaluations = 0;
  bool reached = false;
  std::string stop_reason;
  double labelling_ms = 0, clustering_ms = 0, distance_ms = 0, total_ms = 0;
  long long vm_peak_kb = 0, vm_hwm_kb = 0;
  // the exact check (camplace validate), when there is one for this run
  bool checked = false;
  double exact_err = 0, max_overestimate = 0;
  bool reached_exact = false;
};

/// Writes DIR/runs.csv (one row per run, in the order of `rows`), DIR/report.md (quoting
/// `command`; marked unfinished when `interrupted`) and the plots with their data and scripts.
/// Throws std::runtime_error when a file cannot be written or gnuplot fails.
void write_study_report(const StudySpec& spec, const std::vector<RunRow>& rows,
                        const std::string& command, bool interrupted, const std::string& dir);

/// The names of every file write_study_report may write into DIR (report.md, runs.csv and each
/// plot's .png, .gp and .dat), for discarding a study's report.
std::vector<std::string> study_report_files();

}  // namespace camplace::compare::detail
