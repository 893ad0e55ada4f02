// Statistics and summaries over runs: summary.json, summary.csv and the printed summary.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "camplace/core/camera.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/statistics.hpp"
#include "camplace/optimize/report.hpp"
#include "run_json.hpp"

namespace camplace::optimize {
namespace {

constexpr double kRadToDeg = 1.0 / core::kDegree;

std::string fixed(double value, int digits) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value;
  return out.str();
}

}  // namespace

Summary summarize(const std::vector<RunResult>& runs) {
  Summary s;
  s.runs = static_cast<int>(runs.size());
  std::vector<double> evals, secs, evals_ok, secs_ok;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const RunResult& r = runs[i];
    evals.push_back(static_cast<double>(r.evaluations));
    secs.push_back(r.seconds);
    if (r.stop_reason == StopReason::lower_bound) ++s.reached_lower_bound;
    if (r.reached_tolerance) {
      ++s.reached;
      evals_ok.push_back(static_cast<double>(r.evaluations));
      secs_ok.push_back(r.seconds);
    }
    if (s.best_run < 0 || r.err < runs[static_cast<std::size_t>(s.best_run)].err) {
      s.best_run = static_cast<int>(i);
    }
  }
  s.median_evaluations = core::median(evals);
  s.median_seconds = core::median(secs);
  s.median_evaluations_reached = core::median(evals_ok);
  s.median_seconds_reached = core::median(secs_ok);
  return s;
}

nlohmann::ordered_json summary_json(const std::vector<RunResult>& runs, const RunContext& context,
                                    bool interrupted) {
  const Summary s = summarize(runs);
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const RunResult& r : runs) {
    rows.push_back({{"seed", r.seed},
                    {"file", "run-" + std::to_string(r.seed) + ".json"},
                    {"err", r.err},
                    {"tie_breaker", r.tie_breaker},
                    {"start_err", r.start_err},
                    {"evaluations", r.evaluations},
                    {"evaluations_to_best", r.evaluations_to_best},
                    {"reached_tolerance", r.reached_tolerance},
                    {"seconds", r.seconds},
                    {"stop_reason", to_string(r.stop_reason)},
                    {"ms_per_evaluation", r.mean_timing.total_ms},
                    {"vm_peak_kb", r.memory.vm_peak_kb}});
  }
  nlohmann::ordered_json j;
  j["context"] = context_json(context);
  if (context.provenance) j["provenance"] = core::provenance_json(*context.provenance);
  if (!runs.empty()) {
    j["algorithm"] = runs.front().algorithm;
    j["objective"] = runs.front().objective;
    j["threads"] = runs.front().threads;
    j["population"] = runs.front().population;
    j["tolerance"] = runs.front().tolerance;
    j["err_lower_bound"] = runs.front().err_lower_bound;
  }
  j["interrupted"] = interrupted;
  j["runs"] = s.runs;
  j["reached_tolerance"] = s.reached;
  j["reached_lower_bound"] = s.reached_lower_bound;
  j["success_rate"] = s.runs > 0 ? static_cast<double>(s.reached) / s.runs : 0.0;
  j["median_evaluations"] = s.median_evaluations;
  j["median_seconds"] = s.median_seconds;
  // null when no run reached the tolerance (a median of nothing, not 0)
  j["median_evaluations_reached"] =
      s.reached > 0 ? nlohmann::ordered_json(s.median_evaluations_reached) : nullptr;
  j["median_seconds_reached"] =
      s.reached > 0 ? nlohmann::ordered_json(s.median_seconds_reached) : nullptr;
  if (s.best_run >= 0) {
    const RunResult& best = runs[static_cast<std::size_t>(s.best_run)];
    j["best"] = {{"seed", best.seed},
                 {"err", best.err},
                 {"cameras", cameras_json(best.best, context.camera_models)}};
  }
  j["per_run"] = rows;
  return j;
}

std::string summary_csv(const std::vector<RunResult>& runs) {
  std::ostringstream out;
  out << std::setprecision(17);
  out << "seed,err,start_err,evaluations,evaluations_to_best,reached_tolerance,seconds,"
         "stop_reason,labelling_ms,clustering_ms,distance_ms,total_ms,wall_ms_per_evaluation,"
         "vm_hwm_kb,vm_peak_kb,tie_breaker\n";
  for (const RunResult& r : runs) {
    out << r.seed << ',' << r.err << ',' << r.start_err << ',' << r.evaluations << ','
        << r.evaluations_to_best << ',' << (r.reached_tolerance ? "true" : "false") << ','
        << r.seconds << ',' << to_string(r.stop_reason) << ',' << r.mean_timing.labelling_ms << ','
        << r.mean_timing.clustering_ms << ',' << r.mean_timing.distance_ms << ','
        << r.mean_timing.total_ms << ',' << r.wall_ms_per_evaluation << ',' << r.memory.vm_hwm_kb
        << ',' << r.memory.vm_peak_kb << ',' << r.tie_breaker << '\n';
  }
  return out.str();
}

void print_summary(std::ostream& out, const std::vector<RunResult>& runs) {
  if (runs.empty()) {
    out << "no runs finished\n";
    return;
  }
  const Summary s = summarize(runs);
  out << std::left << std::setw(6) << "seed" << std::right << std::setw(12) << "Err [m²]"
      << std::setw(13) << "evaluations" << std::setw(10) << "seconds" << std::setw(9) << "ms/eval"
      << std::setw(10) << "wall/eval"
      << "  "
      << "stop\n";
  for (const RunResult& r : runs) {
    out << std::left << std::setw(6) << r.seed << std::right << std::setw(11) << fixed(r.err, 5)
        << std::setw(13) << r.evaluations << std::setw(10) << fixed(r.seconds, 1) << std::setw(9)
        << fixed(r.mean_timing.total_ms, 2) << std::setw(10) << fixed(r.wall_ms_per_evaluation, 2)
        << "  " << to_string(r.stop_reason) << '\n';
  }
  // Say which time each column is (threads evaluate in parallel, so they differ).
  out << "ms/eval: mean duration of one evaluation (wall clock on the thread running it); "
         "wall/eval: the run's wall-clock time per evaluation (seconds / evaluations, ms)\n";
  const double rate = 100.0 * s.reached / s.runs;
  out << "\nreached tolerance " << fixed(runs.front().tolerance, 4) << " m²: " << s.reached << "/"
      << s.runs << " (" << fixed(rate, 0) << "%)\n";
  out << "median evaluations " << fixed(s.median_evaluations, 0) << ", median seconds "
      << fixed(s.median_seconds, 1) << " (all runs)";
  if (s.reached > 0) {
    out << "; " << fixed(s.median_evaluations_reached, 0) << " evaluations, "
        << fixed(s.median_seconds_reached, 1) << " s (runs that reached it)";
  }
  out << "\n";
  const RunResult& first = runs.front();
  if (first.objective == "err+volume") {
    out << "objective err+volume: ties of Err broken by the model's volume (tie_breaker)\n";
  } else if (first.objective == "err+touching-volume") {
    out << "objective err+touching-volume: the solver minimised Err plus the touching states' "
           "volume term; Err above is Err alone\n";
  }
  if (first.err_lower_bound > first.tolerance) {
    // Conservative mode: voxels touching a target are always in the model (SPEC §5), so Err
    // cannot fall below this bound whatever the cameras.
    out << "no configuration can reach the tolerance: Err >= " << fixed(first.err_lower_bound, 4)
        << " m² for every configuration at this resolution (conservative lower bound)\n";
    out << "reached that lower bound (provably optimal): " << s.reached_lower_bound << "/" << s.runs
        << "\n";
  }
  out << "\n";
  const RunResult& best = runs[static_cast<std::size_t>(s.best_run)];
  out << "best configuration (seed " << best.seed << "), Err = " << fixed(best.err, 5) << " m²\n";
  out << std::left << std::setw(8) << "camera" << std::right << std::setw(9) << "x [m]"
      << std::setw(9) << "y [m]" << std::setw(9) << "z [m]" << std::setw(11) << "yaw [°]"
      << std::setw(12) << "pitch [°]" << std::setw(11) << "roll [°]" << '\n';
  for (std::size_t i = 0; i < best.best.size(); ++i) {
    const core::CameraSetting& c = best.best[i];
    out << std::left << std::setw(8) << i << std::right << std::setw(9) << fixed(c.position.x(), 3)
        << std::setw(9) << fixed(c.position.y(), 3) << std::setw(9) << fixed(c.position.z(), 3)
        << std::setw(10) << fixed(c.yaw * kRadToDeg, 2) << std::setw(11)
        << fixed(c.pitch * kRadToDeg, 2) << std::setw(10) << fixed(c.roll * kRadToDeg, 2) << '\n';
  }
}

}  // namespace camplace::optimize
