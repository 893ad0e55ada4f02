#include "camplace/optimize/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "camplace/core/camera.hpp"

namespace camplace::optimize {
namespace {

constexpr double kRadToDeg = 1.0 / core::kDegree;

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t m = values.size() / 2;
  return values.size() % 2 == 1 ? values[m] : 0.5 * (values[m - 1] + values[m]);
}

nlohmann::ordered_json cameras_json(const core::CameraConfig& config) {
  // The same text `camplace evaluate --cameras` reads (core::load_camera_config).
  return nlohmann::ordered_json::parse(core::camera_config_json(config)).at("cameras");
}

nlohmann::ordered_json context_json(const RunContext& context) {
  return {{"scene", context.scene_file},        {"mode", context.mode},
          {"resolution", context.resolution},   {"start", context.start},
          {"time_limit_s", context.time_limit}, {"max_evaluations", context.max_evaluations}};
}

std::string fixed(double value, int digits) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value;
  return out.str();
}

}  // namespace

nlohmann::ordered_json run_json(const RunResult& run, const RunContext& context) {
  nlohmann::ordered_json history = nlohmann::ordered_json::array();
  for (const HistoryPoint& h : run.history) {
    history.push_back({{"evaluations", h.evaluations}, {"seconds", h.seconds}, {"err", h.err}});
  }
  nlohmann::ordered_json j;
  j["cameras"] = cameras_json(run.best);
  j["err"] = run.err;
  j["evaluations"] = run.evaluations;
  j["reached_tolerance"] = run.reached_tolerance;
  j["seconds"] = run.seconds;
  j["stop_reason"] = to_string(run.stop_reason);
  j["tolerance"] = run.tolerance;
  j["err_lower_bound"] = run.err_lower_bound;
  j["start_err"] = run.start_err;
  j["search_err"] = run.search_err;
  j["evaluations_to_best"] = run.evaluations_to_best;
  j["restarts"] = run.restarts;
  j["algorithm"] = run.algorithm;
  j["seed"] = run.seed;
  j["threads"] = run.threads;
  j["population"] = run.population;
  j["dimension"] = run.dimension;
  j["context"] = context_json(context);
  j["history"] = history;
  j["time_per_evaluation_ms"] = {{"labelling", run.mean_timing.labelling_ms},
                                 {"clustering", run.mean_timing.clustering_ms},
                                 {"distance", run.mean_timing.distance_ms},
                                 {"total", run.mean_timing.total_ms},
                                 {"wall_clock", run.wall_ms_per_evaluation}};
  j["memory_kb"] = {{"vm_hwm", run.memory.vm_hwm_kb}, {"vm_peak", run.memory.vm_peak_kb}};
  return j;
}

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
  s.median_evaluations = median(evals);
  s.median_seconds = median(secs);
  s.median_evaluations_reached = median(evals_ok);
  s.median_seconds_reached = median(secs_ok);
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
  if (!runs.empty()) {
    j["algorithm"] = runs.front().algorithm;
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
  j["median_evaluations_reached"] = s.median_evaluations_reached;
  j["median_seconds_reached"] = s.median_seconds_reached;
  if (s.best_run >= 0) {
    const RunResult& best = runs[static_cast<std::size_t>(s.best_run)];
    j["best"] = {{"seed", best.seed}, {"err", best.err}, {"cameras", cameras_json(best.best)}};
  }
  j["per_run"] = rows;
  return j;
}

std::string summary_csv(const std::vector<RunResult>& runs) {
  std::ostringstream out;
  out << std::setprecision(17);
  out << "seed,err,start_err,evaluations,evaluations_to_best,reached_tolerance,seconds,"
         "stop_reason,labelling_ms,clustering_ms,distance_ms,total_ms,wall_ms_per_evaluation,"
         "vm_hwm_kb,vm_peak_kb\n";
  for (const RunResult& r : runs) {
    out << r.seed << ',' << r.err << ',' << r.start_err << ',' << r.evaluations << ','
        << r.evaluations_to_best << ',' << (r.reached_tolerance ? "true" : "false") << ','
        << r.seconds << ',' << to_string(r.stop_reason) << ',' << r.mean_timing.labelling_ms << ','
        << r.mean_timing.clustering_ms << ',' << r.mean_timing.distance_ms << ','
        << r.mean_timing.total_ms << ',' << r.wall_ms_per_evaluation << ',' << r.memory.vm_hwm_kb
        << ',' << r.memory.vm_peak_kb << '\n';
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
      << std::setw(13) << "evaluations" << std::setw(10) << "seconds" << std::setw(11) << "ms/eval"
      << "  "
      << "stop\n";
  for (const RunResult& r : runs) {
    out << std::left << std::setw(6) << r.seed << std::right << std::setw(11) << fixed(r.err, 5)
        << std::setw(13) << r.evaluations << std::setw(10) << fixed(r.seconds, 1) << std::setw(11)
        << fixed(r.mean_timing.total_ms, 2) << "  " << to_string(r.stop_reason) << '\n';
  }
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
      << std::setw(12) << "pitch [°]" << '\n';
  for (std::size_t i = 0; i < best.best.size(); ++i) {
    const core::CameraSetting& c = best.best[i];
    out << std::left << std::setw(8) << i << std::right << std::setw(9) << fixed(c.position.x(), 3)
        << std::setw(9) << fixed(c.position.y(), 3) << std::setw(9) << fixed(c.position.z(), 3)
        << std::setw(10) << fixed(c.yaw * kRadToDeg, 2) << std::setw(11)
        << fixed(c.pitch * kRadToDeg, 2) << '\n';
  }
}

}  // namespace camplace::optimize
