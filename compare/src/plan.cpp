#include "camplace/compare/plan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "format.hpp"
#include "gnuplot.hpp"

namespace camplace::compare {
core::Scene scene_with_cameras(const core::Scene& scene, int count) {
  CAMPLACE_ASSERT(count >= 1 && scene.cameras.count >= 1);
  core::Scene out = scene;
  const std::vector<core::CameraModel> models = scene.cameras.models;
  const std::vector<core::CameraDomain> domains = scene.cameras.domains;
  const std::size_t n = models.size();
  out.cameras.models.clear();
  out.cameras.domains.clear();
  for (int i = 0; i < count; ++i) {
    out.cameras.models.push_back(models[static_cast<std::size_t>(i) % n]);
    out.cameras.domains.push_back(domains[static_cast<std::size_t>(i) % n]);
  }
  out.cameras.count = count;
  return out;
}

std::optional<double> cameras_cost(const core::Scene& scene) {
  double total = 0.0;
  for (const core::CameraModel& m : scene.cameras.models) {
    if (!m.cost) return std::nullopt;
    total += *m.cost;
  }
  return total;
}

std::optional<int> recommended_count(const std::vector<PlanRow>& rows) {
  std::optional<int> best;
  for (const PlanRow& r : rows) {
    if (r.reached_exact() && (!best || r.cameras < *best)) best = r.cameras;
  }
  return best;
}

bool recommendation_is_final(const std::vector<PlanRow>& rows) {
  const std::optional<int> recommended = recommended_count(rows);
  for (const PlanRow& r : rows) {
    if (recommended && r.cameras > *recommended) continue;
    if (r.runs_done < r.runs_planned || !r.exact_err) return false;
  }
  return true;
}

void write_plan_report(const std::string& dir, const std::vector<PlanRow>& rows,
                       const PlanReport& report) {
  const std::optional<int> recommended = recommended_count(rows);

  std::ostringstream csv;
  csv << "cameras,cost,runs_planned,runs_done,best_seed,voxel_err,voxel_err_pyramid,exact_err,"
         "err_lower_bound,tolerance,reached_exact,max_overestimate_m,median_voxel_err,"
         "median_evaluations,median_seconds,recommended\n";
  for (const PlanRow& r : rows) {
    csv << r.cameras << "," << (r.cost ? detail::full_number(*r.cost) : "") << "," << r.runs_planned
        << "," << r.runs_done << "," << (r.best_seed ? std::to_string(*r.best_seed) : "") << ","
        << (r.best_seed ? detail::full_number(r.voxel_err) : "") << ","
        << (r.exact_err ? detail::full_number(r.voxel_err_pyramid) : "") << ","
        << (r.exact_err ? detail::full_number(*r.exact_err) : "") << ","
        << detail::full_number(r.err_lower_bound) << "," << detail::full_number(r.tolerance) << ","
        << (r.exact_err ? (r.reached_exact() ? "1" : "0") : "") << ","
        << (r.exact_err ? detail::full_number(r.max_overestimate) : "") << ","
        << (r.runs_done > 0 ? detail::full_number(r.median_voxel_err) : "") << ","
        << (r.runs_done > 0 ? detail::full_number(r.median_evaluations) : "") << ","
        << (r.runs_done > 0 ? detail::full_number(r.median_seconds) : "") << ","
        << (recommended && *recommended == r.cameras ? "1" : "0") << "\n";
  }
  core::write_file_atomically(dir + "/plan.csv", csv.str());

  nlohmann::ordered_json j;
  j["format_version"] = 1;
  j["command"] = report.command;
  j["provenance"] = core::provenance_json(report.provenance);
  j["settings"] = report.settings;
  j["recommended_cameras"] =
      recommended ? nlohmann::ordered_json(*recommended) : nlohmann::ordered_json();
  j["recommendation_final"] = recommendation_is_final(rows);
  j["interrupted"] = report.interrupted;
  j["missing_runs"] = report.missing;
  nlohmann::ordered_json counts = nlohmann::ordered_json::array();
  for (const PlanRow& r : rows) {
    nlohmann::ordered_json c;
    c["cameras"] = r.cameras;
    c["cost"] = r.cost ? nlohmann::ordered_json(*r.cost) : nullptr;
    c["runs_planned"] = r.runs_planned;
    c["runs_done"] = r.runs_done;
    c["best_run"] = r.best_seed ? nlohmann::ordered_json(r.best_run_file) : nullptr;
    c["voxel_err"] = r.best_seed ? nlohmann::ordered_json(r.voxel_err) : nullptr;
    c["voxel_err_pyramid"] = r.exact_err ? nlohmann::ordered_json(r.voxel_err_pyramid) : nullptr;
    c["exact_err"] = r.exact_err ? nlohmann::ordered_json(*r.exact_err) : nullptr;
    c["err_lower_bound"] = r.err_lower_bound;
    c["tolerance"] = r.tolerance;
    c["reached_exact"] = r.reached_exact();
    c["max_overestimate_m"] = r.exact_err ? nlohmann::ordered_json(r.max_overestimate) : nullptr;
    c["check_error"] = r.check_error;
    counts.push_back(c);
  }
  j["counts"] = counts;
  core::write_file_atomically(dir + "/plan.json", j.dump(2) + "\n");

  // The plot: one block per series, count against Err (log scale).
  std::ostringstream dat;
  dat << "# cameras exact_err voxel_err lower_bound tolerance (m²) cost\n";
  bool costs = !rows.empty();
  for (const PlanRow& r : rows) costs = costs && r.cost.has_value();
  bool any = false;
  double lo = 1e300, hi = 0.0;
  for (const PlanRow& r : rows) {
    if (!r.best_seed) continue;
    const double exact = r.exact_err ? *r.exact_err : std::nan("");
    dat << r.cameras << " " << (r.exact_err ? detail::full_number(exact) : "NaN") << " "
        << detail::full_number(r.voxel_err) << " " << detail::full_number(r.err_lower_bound) << " "
        << detail::full_number(r.tolerance) << " "
        << (r.cost ? detail::full_number(*r.cost) : "NaN") << "\n";
    for (const double v : {exact, r.voxel_err, r.err_lower_bound, r.tolerance}) {
      if (std::isfinite(v) && v > 0.0) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    }
    any = true;
  }
  const std::string dat_file = dir + "/plan.dat";
  core::write_file_atomically(dat_file, dat.str());
  if (any && hi > 0.0) {
    const std::string file = detail::gnuplot_string(dat_file);
    std::ostringstream cmd;
    cmd << "set title 'Best configuration per camera count'\n"
        << "set xlabel 'cameras'\nset ylabel 'Err [m²] (log scale)'\nset logscale y\nset format y "
           "'%g'\n"
        << "set yrange [" << detail::full_number(lo / 3) << ":" << detail::full_number(hi * 3)
        << "]\nset xtics 1\nset grid\n"
        << "set key outside right top box\nset offsets 0.3, 0.3, 0, 0\n"
        << "plot " << file << " using 1:2 with linespoints pt 7 lw 2 title 'exact Err', " << file
        << " using 1:3 with linespoints pt 5 title 'voxel Err', " << file
        << " using 1:4 with lines dt 2 lw 2 title 'lower bound (voxel)', " << file
        << " using 1:5 with lines dt 3 lw 2 title 'tolerance'";
    if (recommended) {
      for (const PlanRow& r : rows) {
        if (r.cameras == *recommended && r.exact_err) {
          cmd << ", '-' using 1:2 with points pt 6 ps 3 lw 2 title 'recommended'\n"
              << r.cameras << " " << detail::full_number(*r.exact_err) << "\ne";
        }
      }
    }
    cmd << "\n";
    detail::gnuplot_png(dir + "/plan.png", cmd.str());
    if (costs) {
      std::ostringstream by_cost;
      by_cost << "set title 'Best configuration per camera count, against its cost'\n"
              << "set xlabel 'total cost of the cameras'\nset ylabel 'Err [m²] (log scale)'\n"
              << "set logscale y\nset format y '%g'\nset yrange [" << detail::full_number(lo / 3)
              << ":" << detail::full_number(hi * 3)
              << "]\nset grid\nset key outside right top box\nset offsets graph 0.05, graph "
                 "0.05, 0, 0\n"
              << "plot " << file
              << " using 6:2 with linespoints pt 7 lw 2 title 'exact Err', '' using "
                 "6:2:(sprintf('%d', $1)) with labels offset 0,1 notitle, "
              << file << " using 6:3 with linespoints pt 5 title 'voxel Err', " << file
              << " using 6:5 with lines dt 3 lw 2 title 'tolerance'\n";
      detail::gnuplot_png(dir + "/plan_cost.png", by_cost.str());
    }
  }

  std::ostringstream md;
  const core::BuildInfo& b = report.provenance.build;
  md << "# How many cameras\n\nMade by `" << report.command << "` (camplace " << b.version
     << ", commit " << b.commit << "; scene " << report.provenance.scene_file << ", sha256 "
     << report.provenance.scene.combined.substr(0, 12) << "…; " << report.provenance.host << ", "
     << report.provenance.started << "). " << report.settings << "\n\n";
  if (report.interrupted) {
    md << "**Interrupted**: the table covers the runs finished before the signal; rerun the "
          "same command to resume.\n\n";
  }
  if (recommended) {
    md << "**Recommendation: " << *recommended
       << " cameras**, the smallest count whose best configuration reaches the tolerance by its "
          "exact Err"
       << (recommendation_is_final(rows) ? ".\n\n"
                                         : " (provisional: some runs or exact checks of the counts "
                                           "up to it are missing).\n\n");
  } else {
    md << "**No count up to " << (rows.empty() ? 0 : rows.back().cameras)
       << " cameras reaches the tolerance by its exact Err** (best configuration of each count, "
          "within the budget above).\n\n";
  }
  md << "| cameras | cost | runs | best run | voxel Err [m²] | exact Err [m²] | lower bound [m²] | "
        "tolerance [m²] | reached (exact) | largest over-estimate [m] | median voxel Err [m²] | "
        "median evaluations |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const PlanRow& r : rows) {
    md << "| " << r.cameras << (recommended && *recommended == r.cameras ? " ←" : "") << " | "
       << (r.cost ? detail::full_number(*r.cost) : "–") << " | " << r.runs_done << "/"
       << r.runs_planned << " | " << (r.best_seed ? "seed " + std::to_string(*r.best_seed) : "–")
       << " | " << (r.best_seed ? detail::num(r.voxel_err, 4) : "–") << " | "
       << (r.exact_err ? detail::num(*r.exact_err, 4)
                       : (r.check_error.empty() ? "–" : "check failed: " + r.check_error))
       << " | " << detail::num(r.err_lower_bound, 4) << " | " << detail::num(r.tolerance, 4)
       << " | " << (r.exact_err ? (r.reached_exact() ? "yes" : "no") : "–") << " | "
       << (r.exact_err ? detail::num(r.max_overestimate, 4) : "–") << " | "
       << (r.runs_done > 0 ? detail::num(r.median_voxel_err, 4) : "–") << " | "
       << (r.runs_done > 0 ? detail::num(r.median_evaluations, 0) : "–") << " |\n";
  }
  md << "\nVoxel Err with the scene's FOV, as the optimizer minimised it; the exact Err (CGAL Nef "
        "pipeline, inscribed pyramids) of the same cameras is what the recommendation trusts. "
        "The lower bound is the conservative voxel bound at the runs' resolution: no "
        "configuration has a smaller voxel Err, whatever the count. A largest over-estimate "
        "> 0 would mean the voxel model over-estimated a distance (never in conservative "
        "mode).\n\n";
  if (any) md << "![Err against the camera count](plan.png)\n\n";
  if (any && costs) md << "![Err against the cameras' total cost](plan_cost.png)\n\n";
  if (!costs) {
    md << "Cost: not every camera model of the scene has a `cost`, so no cost is shown.\n\n";
  }
  if (!report.missing.empty()) {
    md << "Missing runs (" << report.missing.size() << "):";
    for (const std::string& m : report.missing) md << " " << m << ";";
    md << "\n\n";
  }
  md << "Files: `plan.csv` (one row per count), `plan.json` (the same with the provenance), "
        "`plan.png` (data `plan.dat`, script `plan.gp`), `scenes/cameras-N.json` (the scene with "
        "N cameras), `runs/N/run-SEED.json` (each run; `camplace evaluate SCENE --cameras` reads "
        "them), `validation-cache/` (the exact checks).\n";
  core::write_file_atomically(dir + "/plan.md", md.str());
}

}  // namespace camplace::compare
