// Voxel pipeline against the exact pipeline for one configuration (SPEC §8).
#include "camplace/compare/voxel_vs_exact.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <sstream>

#include "camplace/core/err.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/core/provenance.hpp"
#include "camplace/exact/evaluator.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "format.hpp"
#include "gnuplot.hpp"
#include "model_containment.hpp"

namespace camplace::compare {

namespace {

using detail::num;
using detail::resolution_text;

// Distances may differ by rounding of the exact value to double.
constexpr double kDistanceSlack = 1e-9;

}  // namespace

core::Scene with_pyramid_fov(const core::Scene& scene) {
  // SPEC §1: whenever voxel and exact results are compared, both use the inscribed pyramid.
  core::Scene out = scene;
  core::use_exact_models(out.cameras);
  return out;
}

CompareResult compare_voxel_exact(const core::Scene& original, const core::CameraConfig& config,
                                  const CompareOptions& options, const ComparePartial& on_partial) {
  const core::Scene scene = with_pyramid_fov(original);
  std::vector<std::array<int, 3>> resolutions = options.resolutions;
  if (resolutions.empty()) resolutions.push_back(scene.voxels);
  std::vector<int> levels = options.refine_levels;
  if (levels.empty()) levels.push_back(0);
  // Refuse a refinement the memory estimate (or the mode) rules out before the exact pipeline
  // spends its seconds.
  for (const auto& n : resolutions) {
    for (int level : levels) {
      voxel::VoxelOptions o;
      o.mode = voxel::LabelMode::conservative;
      o.resolution = n;
      o.refine = level;
      const std::string problem = voxel::refine_problem(scene, o);
      if (!problem.empty()) {
        throw core::OptionError("refine", problem + " (at " + resolution_text(n) + ")");
      }
    }
  }
  CompareResult result;
  result.started = core::now_iso8601();
  // Center mode once per resolution, conservative mode at every refinement level.
  std::vector<std::pair<voxel::LabelMode, int>> runs{{voxel::LabelMode::center, 0}};
  for (int level : levels) runs.push_back({voxel::LabelMode::conservative, level});
  result.evaluations_total = 1 + static_cast<int>(resolutions.size() * runs.size());
  auto progress = [&] {
    if (options.on_progress) options.on_progress(result.evaluations_done, result.evaluations_total);
  };
  progress();
  exact::ExactOptions exact_options;
  exact_options.keep_models = true;
  exact_options.on_progress = options.on_exact_progress;
  const exact::ExactEvaluation ex = exact::evaluate_exact(scene, config, exact_options);
  result.errs.push_back({"exact", {0, 0, 0}, 0, ex.err, ex.timing.total_ms});
  ++result.evaluations_done;
  for (const auto& n : resolutions) {
    for (const auto& [mode, level] : runs) {
      progress();
      const bool conservative = mode == voxel::LabelMode::conservative;
      voxel::VoxelOptions voxel_options;
      voxel_options.mode = mode;
      voxel_options.resolution = n;
      voxel_options.refine = level;
      const voxel::VoxelEvaluator evaluator(scene, voxel_options);
      const voxel::Evaluation ev = evaluator.evaluate(config);
      const std::vector<std::vector<std::uint8_t>> leaf_models = evaluator.leaf_models(config);
      const std::string pipeline =
          "voxel-" + core::name_of(mode) + (level > 0 ? "-refine" + std::to_string(level) : "");
      result.errs.push_back({pipeline, n, level, ev.err, ev.timing.total_ms});
      for (std::size_t s = 0; s < ev.states.size(); ++s) {
        const auto& vs = ev.states[s];
        const auto& es = ex.states[s];
        CompareRow row;
        row.time_step = vs.time_step;
        row.event = vs.event;
        row.weight = vs.weight;
        row.mode = core::name_of(mode);
        row.resolution = n;
        row.voxel_diagonal = evaluator.grid().step.norm();
        row.refine = level;
        row.cell_diagonal = evaluator.leaf_grid().step.norm();
        row.d_true = es.d_true;
        row.d_exact = es.d_model;
        row.d_voxel = vs.d_model;
        row.volume_exact = es.model_volume;
        row.volume_voxel = vs.model_volume;
        // With refinement: against the finest cells (leaf_grid() is grid() without).
        row.exact_outside =
            detail::exact_outside_voxel_model(ex.models[s], evaluator.leaf_grid(), leaf_models[s]);
        row.distance_over_estimated = row.d_voxel > row.d_exact + kDistanceSlack;
        row.filter_lost_component = vs.components_removed > 0 && vs.components < es.components;
        const bool violation = row.exact_outside > 0 || row.distance_over_estimated;
        (conservative ? result.conservative_violations : result.center_violations) += violation;
        result.rows.push_back(row);
      }
      ++result.evaluations_done;
      if (on_partial) on_partial(result);
    }
  }
  progress();
  return result;
}

void write_compare_report(const core::Scene& scene, const CompareResult& result,
                          const CompareOptions& options, const std::string& dir) {
  // compare.csv: one row per state, mode and resolution (no timing).
  std::ostringstream csv;
  csv << "time_step,event,weight,mode,resolution,voxel_diagonal_m,d_true_m,d_exact_m,d_voxel_m,"
         "d_voxel_minus_exact_m,abs_error_over_diagonal,volume_exact_m3,volume_voxel_m3,"
         "exact_voxels_outside_voxel_model,d_voxel_over_estimates,refine,cell_diagonal_m,"
         "filter_lost_component\n";
  for (const auto& r : result.rows) {
    csv << r.time_step << "," << r.event << "," << num(r.weight) << "," << r.mode << ","
        << resolution_text(r.resolution) << "," << num(r.voxel_diagonal) << "," << num(r.d_true, 9)
        << "," << num(r.d_exact, 9) << "," << num(r.d_voxel, 9) << ","
        << num(r.d_voxel - r.d_exact, 9) << ","
        << num(std::abs(r.d_voxel - r.d_exact) / r.voxel_diagonal) << "," << num(r.volume_exact, 9)
        << "," << num(r.volume_voxel, 9) << "," << r.exact_outside << ","
        << (r.distance_over_estimated ? "yes" : "no") << "," << r.refine << ","
        << num(r.cell_diagonal) << "," << (r.filter_lost_component ? "yes" : "no") << "\n";
  }
  core::write_file_atomically(dir + "/compare.csv", csv.str());
  std::ostringstream err_csv;
  err_csv << "pipeline,resolution,err_m2,ms\n";
  for (const auto& e : result.errs) {
    err_csv << e.pipeline << "," << (e.pipeline == "exact" ? "-" : resolution_text(e.resolution))
            << "," << num(e.err, 9) << "," << num(e.ms, 1) << "\n";
  }
  core::write_file_atomically(dir + "/err.csv", err_csv.str());

  // The plots' series: center, conservative, and conservative with refinement (against the
  // finest cell's diagonal, the effective resolution), the last only when it was run.
  const bool refined = std::any_of(result.rows.begin(), result.rows.end(),
                                   [](const CompareRow& r) { return r.refine > 0; });
  std::vector<std::string> series{"center", "conservative"};
  if (refined) series.push_back("conservative-refined");
  auto series_of = [](const CompareRow& r) {
    return r.refine > 0 ? std::string("conservative-refined") : r.mode;
  };

  // Plot 1: mean and max |d_voxel − d_exact| against the voxel (cell) diagonal, per series,
  // over the states whose voxel model kept the exact model's components (voxelisation error);
  // the states where the filter lost a component (the person) are drawn one by one apart.
  std::map<std::pair<std::string, double>, std::pair<double, double>>
      stats;  // (series, diag) → (sum, max)
  std::map<std::pair<std::string, double>, int> counts;
  int lost = 0;
  std::ostringstream lost_dat;
  lost_dat << "# states where the plausibility filter lost a component: cell_diagonal_m "
              "abs_error_m series\n";
  for (const auto& r : result.rows) {
    const double e = std::abs(r.d_voxel - r.d_exact);
    if (r.filter_lost_component) {
      ++lost;
      lost_dat << num(r.cell_diagonal) << " " << num(std::max(e, 1e-6), 9) << " " << series_of(r)
               << "\n";
      continue;
    }
    auto& s = stats[{series_of(r), r.cell_diagonal}];
    s.first += e;
    s.second = std::max(s.second, e);
    ++counts[{series_of(r), r.cell_diagonal}];
  }
  std::ostringstream dat;
  for (const std::string& name : series) {
    dat << "# " << name << ": " << (name == "conservative-refined" ? "cell" : "voxel")
        << "_diagonal_m mean_abs_error_m max_abs_error_m (states the filter kept whole)\n";
    for (const auto& [key, s] : stats) {
      if (key.first != name) continue;
      dat << num(key.second) << " " << num(s.first / counts[key], 9) << " " << num(s.second, 9)
          << "\n";
    }
    dat << "\n\n";
  }
  // The lost states as the last block (a dummy point off the plot when there are none, so the
  // script's index stays valid).
  dat << lost_dat.str();
  if (lost == 0) dat << "1 -1 none\n";
  dat << "\n\n";
  core::write_file_atomically(dir + "/error_vs_resolution.dat", dat.str());
  const std::string lost_index = std::to_string(series.size());
  detail::gnuplot_png(
      dir + "/error_vs_resolution.png",
      "set title 'Voxelisation error of d(C, M) against the exact pipeline'\n"
      "set xlabel '" +
          std::string(refined ? "voxel diagonal, refined: finest cell diagonal"
                              : "voxel diagonal") +
          " [m]'\nset ylabel '|d_{voxel} - d_{exact}| [m] (log scale; 0 not "
          "shown)'\n"
          "set key outside right top box\nset grid\nset logscale y\n"
          "plot '" +
          dir +
          "/error_vs_resolution.dat' index 0 using 1:2 with linespoints lc 1 pt 7 title 'center: "
          "mean', "
          "'' index 0 using 1:3 with linespoints lc 1 pt 5 dt 3 title 'center: max', "
          "'' index 1 using 1:2 with linespoints lc 2 pt 7 title 'conservative: mean', "
          "'' index 1 using 1:3 with linespoints lc 2 pt 5 dt 3 title 'conservative: max', " +
          (refined ? "'' index 2 using 1:2 with linespoints lc 4 pt 7 title 'conservative, "
                     "refined: mean', "
                     "'' index 2 using 1:3 with linespoints lc 4 pt 5 dt 3 title 'conservative, "
                     "refined: max', "
                   : "") +
          "'' index " + lost_index +
          " using 1:2 with points pt 2 ps 1.5 lc rgb '#d62728' title 'filter lost the person (not "
          "voxelisation error)', "
          "x with lines lc rgb 'gray40' dashtype 2 title 'one voxel diagonal'\n",
      1100, 560);

  // Plot 2: d_voxel against d_exact per state, one colour per resolution, one point type per
  // series.
  std::vector<std::array<int, 3>> resolutions;
  for (const auto& r : result.rows) {
    if (std::find(resolutions.begin(), resolutions.end(), r.resolution) == resolutions.end()) {
      resolutions.push_back(r.resolution);
    }
  }
  std::ostringstream scatter;
  std::string scatter_cmd;
  int block = 0;
  for (std::size_t si = 0; si < series.size(); ++si) {
    const std::string& name = series[si];
    for (std::size_t ri = 0; ri < resolutions.size(); ++ri) {
      std::ostringstream points;
      for (const auto& r : result.rows) {
        if (series_of(r) == name && r.resolution == resolutions[ri]) {
          points << num(r.d_exact, 9) << " " << num(r.d_voxel, 9) << "\n";
        }
      }
      if (points.str().empty()) continue;
      scatter << "# " << name << " " << resolution_text(resolutions[ri])
              << ": d_exact_m d_voxel_m\n"
              << points.str() << "\n\n";
      const char* point = si == 0 ? "pt 7" : si == 1 ? "pt 6 ps 1.6" : "pt 2 ps 1.3";
      scatter_cmd +=
          std::string(scatter_cmd.empty() ? "plot '" + dir + "/d_voxel_vs_d_exact.dat'" : ", ''") +
          " index " + std::to_string(block++) + " using 1:2 with points " + point + " lc " +
          std::to_string(ri + 1) + " title '" +
          (name == "conservative-refined" ? std::string("conservative, refined") : name) + " " +
          resolution_text(resolutions[ri]) + "'";
    }
  }
  core::write_file_atomically(dir + "/d_voxel_vs_d_exact.dat", scatter.str());
  detail::gnuplot_png(dir + "/d_voxel_vs_d_exact.png",
                      "set title 'd(C, M) per state: voxel pipeline against exact'\n"
                      "set xlabel 'd_{exact} [m]'\nset ylabel 'd_{voxel} [m]'\nset key outside "
                      "right top box\nset grid\nset size square\n" +
                          scatter_cmd +
                          ", x with lines lc rgb 'gray40' dashtype 2 title 'd_{voxel} = "
                          "d_{exact}'\n",
                      900, 640);

  // Plot 3 (refinement only): time per evaluation against the effective resolution (finest
  // cells per axis over S: n·2^L), unrefined and refined conservative mode. Timing: varies.
  if (refined) {
    std::ostringstream times;
    for (int with : {0, 1}) {
      times << "# conservative" << (with ? ", refined" : "")
            << ": effective_cells_along_x cell_diagonal_m ms refine\n";
      for (const auto& e : result.errs) {
        if (e.pipeline.rfind("voxel-conservative", 0) != 0 || (e.refine > 0) != (with == 1)) {
          continue;
        }
        times << (e.resolution[0] << e.refine) << " "
              << num(scene.area.size()
                         .cwiseQuotient(
                             core::Vec3(e.resolution[0], e.resolution[1], e.resolution[2]))
                         .norm() /
                     (1 << e.refine))
              << " " << num(e.ms, 3) << " " << e.refine << "\n";
      }
      times << "\n\n";
    }
    core::write_file_atomically(dir + "/time_vs_effective_resolution.dat", times.str());
    detail::gnuplot_png(dir + "/time_vs_effective_resolution.png",
                        "set title 'Time per evaluation against the effective resolution'\n"
                        "set xlabel 'finest cells along x (n_x 2^L)'\nset ylabel 'ms per "
                        "evaluation (log scale)'\n"
                        "set key top left box opaque\nset grid\nset logscale xy\n"
                        "plot '" +
                            dir +
                            "/time_vs_effective_resolution.dat' index 0 using 1:3 with "
                            "linespoints title 'conservative', '' index 1 using 1:3 with points "
                            "pt 7 title 'conservative, refined'\n");
  }

  // report.md
  std::ostringstream md;
  std::string resolution_list, level_list;
  for (const auto& n : options.resolutions) {
    resolution_list += (resolution_list.empty() ? "" : ", ") + resolution_text(n);
  }
  for (int level : options.refine_levels) {
    level_list += (level_list.empty() ? "" : ", ") + std::to_string(level);
  }
  md << "# Voxel pipeline against the exact pipeline\n\n"
     << detail::provenance_header(
            {{"scene", scene.file, core::hash_scene(scene)}},
            {{"resolutions", resolution_list.empty()
                                 ? resolution_text(scene.voxels) + " (the scene's)"
                                 : resolution_list},
             {"refine", level_list.empty() ? "0" : level_list},
             {"modes", "center, conservative"},
             {"FOV", core::fov_description(scene.cameras)}},
            options.command, result.started.empty() ? core::now_iso8601() : result.started);
  if (result.evaluations_done < result.evaluations_total) {
    md << "**Incomplete**: interrupted after " << result.evaluations_done << " of "
       << result.evaluations_total
       << " evaluations (the exact one first, then the voxel pipelines in the order of the "
          "tables); rerun the command for all.\n\n";
  }
  md << "The exact pipeline (CGAL Nef polyhedra, SPEC §6) is the reference. Both pipelines use "
     << core::fov_description(scene.cameras)
     << " (SPEC §1: whenever voxel and exact results are compared).\n\n## Checks (SPEC "
        "§8)\n\n"
     << "| mode | rows | exact model outside voxel model | d_voxel > d_exact | violations "
        "|\n|---|---|---|---|---|\n";
  for (const char* mode : {"conservative", "center"}) {
    int rows = 0, outside = 0, over = 0, bad = 0;
    for (const auto& r : result.rows) {
      if (r.mode != mode) continue;
      ++rows;
      outside += r.exact_outside > 0;
      over += r.distance_over_estimated;
      bad += r.exact_outside > 0 || r.distance_over_estimated;
    }
    md << "| " << mode << " | " << rows << " | " << outside << " | " << over << " | " << bad
       << " |\n";
  }
  md << "\n\"Exact model outside voxel model\" counts rows where some voxel outside the voxel "
        "model "
        "holds exact-model points (a boundary triangle of the exact model reaching more than 1e-9 "
        "m "
        "into it, or its centre inside the exact model). Center mode is not conservative by design "
        "(SPEC §5); its violations are reported as found.\n\n"
     << "## Err\n\n| pipeline | resolution | Err [m²] |\n|---|---|---|\n";
  // A refined pipeline's resolution with its effective one (the finest cells').
  auto resolution_cell = [](const ErrRow& e) {
    if (e.pipeline == "exact") return std::string("exact");
    std::string text = resolution_text(e.resolution);
    if (e.refine > 0) {
      const int f = 1 << e.refine;
      text += " (cells " +
              resolution_text({e.resolution[0] * f, e.resolution[1] * f, e.resolution[2] * f}) +
              ")";
    }
    return text;
  };
  for (const auto& e : result.errs) {
    md << "| " << e.pipeline << " | " << resolution_cell(e) << " | " << num(e.err) << " |\n";
  }
  md << "\n## Per state\n\n"
     << "| h | l | ω | mode | resolution | diagonal [m] | d_true [m] | d_exact [m] | d_voxel [m] | "
        "(d_voxel − d_exact)/diagonal | V_exact [m³] | V_voxel [m³] | outside | over |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : result.rows) {
    md << "| " << r.time_step << " | " << r.event << " | " << num(r.weight, 3) << " | "
       << (r.refine > 0 ? r.mode + ", refine " + std::to_string(r.refine) : r.mode) << " | "
       << resolution_text(r.resolution) << " | " << num(r.voxel_diagonal, 4) << " | "
       << num(r.d_true, 4) << " | " << num(r.d_exact, 4) << " | " << num(r.d_voxel, 4) << " | "
       << num((r.d_voxel - r.d_exact) / r.voxel_diagonal, 3) << " | " << num(r.volume_exact, 4)
       << " | " << num(r.volume_voxel, 4) << " | " << r.exact_outside << " | "
       << (r.distance_over_estimated ? "yes" : "no") << " |\n";
  }
  md << "\n## Plots\n\n![error vs resolution](error_vs_resolution.png)\n\n"
     << "*Figure: voxelisation error of d(C, M) against the voxel diagonal.* Mean and largest "
        "|d_voxel − d_exact| over the states at each resolution"
     << (refined ? " (refined rows at the finest cell's diagonal)" : "")
     << ", over the states whose voxel model kept every component the exact model keeps. Red "
        "crosses: states where the plausibility filter removed a component of the voxel model "
        "that the exact model keeps (the person lost; "
     << lost
     << " states): their error is the distance to another component or to the empty model, "
        "not a voxelisation error. Dashed: one voxel diagonal. Log scale; error 0 is not "
        "shown.\n\n"
     << "![d_voxel vs d_exact](d_voxel_vs_d_exact.png)\n\n"
     << "*Figure: d(C, M) per state, voxel against exact.* One point per state, mode and "
        "resolution: filled circles center mode, open circles conservative mode"
     << (refined ? ", crosses conservative with refinement" : "")
     << "; one colour per resolution. Conservative points must lie on or below the dashed line "
        "d_voxel = d_exact (SPEC §8).\n\n"
     << (refined ? "![time vs effective resolution](time_vs_effective_resolution.png)\n\n"
                   "*Figure: time per evaluation against the effective resolution* (timing: "
                   "varies between runs). With refinement (`refine` L levels) the voxels are "
                   "cut into cells of 1/2^L of their edge: the error plot puts those rows at the "
                   "finest cell's diagonal, the effective resolution.\n\n"
                 : "")
     << "Data: `compare.csv` (per state), `err.csv` (Err and time per pipeline); plot data and "
        "gnuplot scripts beside each PNG.\n\n"
     << "## Timing (varies between runs)\n\n| pipeline | resolution | ms per evaluation "
        "|\n|---|---|---|\n";
  for (const auto& e : result.errs) {
    md << "| " << e.pipeline << " | " << resolution_cell(e) << " | " << num(e.ms, 1) << " |\n";
  }
  core::write_file_atomically(dir + "/report.md", md.str());
}

}  // namespace camplace::compare
