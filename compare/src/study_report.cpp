// The report of a study (SPEC §9): runs.csv, report.md beside the paper's figures, and plots.
#include "study_report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <thread>

#include "camplace/core/files.hpp"
#include "camplace/core/provenance.hpp"
#include "camplace/core/statistics.hpp"
#include "format.hpp"
#include "gnuplot.hpp"

namespace camplace::compare::detail {

namespace {

/// Whether a rerun with the same seeds reproduces the rows: only when no run was ended by the
/// clock (the evaluation count reached by a time limit depends on the machine's speed).
/// This machine as /proc and the C++ runtime describe it: cores, processor model, memory.
std::string machine_text() {
  std::string model;
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; model.empty() && std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos)
      model = line.substr(line.find(':') + 2);
  }
  long mem_kb = 0;
  std::ifstream meminfo("/proc/meminfo");
  for (std::string key; meminfo >> key;) {
    if (key == "MemTotal:") {
      meminfo >> mem_kb;
      break;
    }
    meminfo.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  std::ostringstream out;
  out << std::thread::hardware_concurrency() << " cores";
  if (!model.empty()) out << ", " << model;
  if (mem_kb > 0) out << ", " << num(mem_kb / 1048576.0, 1) << " GiB";
  return out.str();
}

std::string clock_note(const std::vector<RunRow>& rows) {
  std::vector<std::string> timed;
  for (const RunRow& r : rows) {
    if (r.stop_reason == "time_limit" && (timed.empty() || timed.back() != r.group)) {
      timed.push_back(r.group);
    }
  }
  if (timed.empty()) {
    return "No run was ended by the time limit: the evaluation budget ends a run that misses the "
           "tolerance, so a rerun with the same seeds gives the same rows apart from the timing "
           "columns.\n\n";
  }
  std::string groups;
  for (const std::string& g : timed) groups += (groups.empty() ? "`" : ", `") + g + "`";
  return "The time limit ended runs of " + groups +
         " before their evaluation budget: their evaluation counts and Err depend on the "
         "machine's speed; every other row is reproduced by a rerun with the same seeds apart "
         "from the timing columns.\n\n";
}

struct GroupStats {
  std::string examination, family, group, resolution;
  int param = 0, runs = 0, reached = 0;
  RunRow shape;  // scene description
  double median_evaluations = 0, median_seconds = 0, median_err = 0;
  // quartiles (linear interpolation) for the box plots; target: median success target
  double q1_evaluations = 0, q3_evaluations = 0;
  double min_err = 0, q1_err = 0, q3_err = 0, max_err = 0, median_target = 0;
  double labelling_ms = 0, clustering_ms = 0, total_ms = 0;
  double max_vm_peak_kb = 0, max_vm_hwm_kb = 0;
  // the exact check of the group's runs (those `camplace validate` checked)
  int checked = 0, reached_exact = 0, false_successes = 0, overestimates = 0;
  double median_exact_err = 0, max_exact_err = 0;
};

/// The q-quantile of `values` (0 ≤ q ≤ 1), linearly interpolated between the order statistics
/// (R's type 7: q = ½ is the median); 0 for no values.
double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double at = q * static_cast<double>(values.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(at);
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (at - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

std::vector<GroupStats> group_stats(const std::vector<RunRow>& rows) {
  std::vector<GroupStats> out;
  std::map<std::string, std::size_t> index;
  std::map<std::string, std::vector<const RunRow*>> members;
  for (const RunRow& r : rows) {
    if (!index.count(r.group)) {
      index[r.group] = out.size();
      GroupStats g;
      g.examination = r.examination;
      g.family = r.family;
      g.group = r.group;
      g.param = r.param;
      g.resolution = r.resolution;
      g.shape = r;
      out.push_back(g);
    }
    members[r.group].push_back(&r);
  }
  for (GroupStats& g : out) {
    std::vector<double> evals, secs, errs, targets;
    for (const RunRow* r : members[g.group]) {
      ++g.runs;
      targets.push_back(r->target);
      g.reached += r->reached;
      evals.push_back(static_cast<double>(r->evaluations));
      secs.push_back(r->seconds);
      errs.push_back(r->err);
      g.labelling_ms += r->labelling_ms / members[g.group].size();
      g.clustering_ms += r->clustering_ms / members[g.group].size();
      g.total_ms += r->total_ms / members[g.group].size();
      g.max_vm_peak_kb = std::max(g.max_vm_peak_kb, static_cast<double>(r->vm_peak_kb));
      g.max_vm_hwm_kb = std::max(g.max_vm_hwm_kb, static_cast<double>(r->vm_hwm_kb));
    }
    std::vector<double> exact_errs;
    for (const RunRow* r : members[g.group]) {
      if (!r->checked) continue;
      ++g.checked;
      g.reached_exact += r->reached_exact;
      g.false_successes += r->reached && !r->reached_exact;
      g.overestimates += r->max_overestimate > 0.0;
      exact_errs.push_back(r->exact_err);
      g.max_exact_err = std::max(g.max_exact_err, r->exact_err);
    }
    g.median_exact_err = core::median(exact_errs);
    g.median_evaluations = core::median(evals);
    g.median_seconds = core::median(secs);
    g.median_err = core::median(errs);
    g.q1_evaluations = quantile(evals, 0.25);
    g.q3_evaluations = quantile(evals, 0.75);
    g.min_err = quantile(errs, 0.0);
    g.q1_err = quantile(errs, 0.25);
    g.q3_err = quantile(errs, 0.75);
    g.max_err = quantile(errs, 1.0);
    g.median_target = core::median(targets);
  }
  return out;
}

/// x value of a group for the plots of its family.
double x_value(const GroupStats& g) {
  const RunRow& s = g.shape;
  if (g.family == "resolution") return static_cast<double>(s.voxels);
  if (g.family == "static_facets") return s.static_facets;
  if (g.family == "static_objects") return s.static_objects;
  if (g.family == "dynamic_facets") return s.dynamic_facets;
  if (g.family == "dynamic_objects") return s.dynamic_objects;
  if (g.family == "dynamic_steps") return s.time_steps;
  if (g.family == "unmodelled_facets") return s.target_facets;
  if (g.family == "unmodelled_objects") return s.target_objects;
  if (g.family == "unmodelled_events") return s.events;
  if (g.family == "cameras") return s.cameras;
  return g.param;
}

using GroupValue = std::function<double(const GroupStats&)>;

/// One line of a plot: the groups of a family, titled `label`, with y values from `y` (the
/// plot's common y when empty).
struct Series {
  std::string family, label;
  GroupValue y = {};
  GroupValue lo = {}, hi = {};  ///< when set: an interval drawn as error bars (e.g. quartiles)
};

/// The markdown of a figure: the image and its caption below it.
std::string figure(const std::string& name, const std::string& title, const std::string& caption) {
  return "![" + title + "](" + name + ".png)\n\n*Figure: " + title + ".* " + caption + "\n\n";
}

/// Writes one plot's data (x, y per series; with the series' interval x, y, lo, hi) and draws
/// it; returns the markdown (figure and `caption`), or "" when the study has no group of the
/// series' families.
std::string plot(const std::string& dir, const std::string& name, const std::string& title,
                 const std::string& xlabel, const std::string& ylabel,
                 const std::vector<GroupStats>& groups, const std::vector<Series>& series,
                 const GroupValue& y, const std::string& caption) {
  std::ostringstream dat, cmd;
  int blocks = 0;
  cmd << "set title '" << title << "'\nset xlabel '" << xlabel << "'\nset ylabel '" << ylabel
      << "'\nset grid\nset key outside right top box\nset yrange [0:*]\n"
      << "set offsets graph 0.04, graph 0.04, graph 0.06, 0\n";
  std::string plot_cmd;
  for (const Series& line : series) {
    const GroupValue& value = line.y ? line.y : y;
    std::vector<const GroupStats*> members;
    for (const auto& g : groups) {
      if (g.family == line.family) members.push_back(&g);
    }
    if (members.empty()) continue;
    const bool interval = line.lo && line.hi;
    dat << "# " << line.family << ", " << line.label << ": x y" << (interval ? " lo hi" : "")
        << "\n";
    for (const GroupStats* g : members) {
      dat << num(x_value(*g), 6) << " " << num(value(*g), 6);
      if (interval) dat << " " << num(line.lo(*g), 6) << " " << num(line.hi(*g), 6);
      dat << "\n";
    }
    dat << "\n\n";
    plot_cmd += std::string(plot_cmd.empty() ? "plot " : ", ") +
                gnuplot_string(dir + "/" + name + ".dat") + " index " + std::to_string(blocks++) +
                (interval ? " using 1:2:3:4 with yerrorlines" : " using 1:2 with linespoints") +
                " title '" + line.label + "'";
  }
  if (blocks == 0) return "";
  core::write_file_atomically(dir + "/" + name + ".dat", dat.str());
  detail::gnuplot_png(dir + "/" + name + ".png", cmd.str() + plot_cmd + "\n");
  return figure(name, title, caption);
}

/// Box plot of the final Err of each group of `family` (box: quartiles, whiskers: smallest and
/// largest, bar: median), the groups evenly spaced and labelled by `label` over "reached/runs",
/// with the success target; "" when the study has no such group.
std::string err_box_plot(const std::string& dir, const std::string& name, const std::string& title,
                         const std::string& xlabel, const std::vector<GroupStats>& groups,
                         const std::string& family,
                         const std::function<std::string(const GroupStats&)>& label) {
  std::ostringstream dat;
  dat << "# " << family
      << ": index label min_err q1_err median_err q3_err max_err target reached runs (m², "
         "quartiles interpolated)\n";
  int k = 0;
  double lo = INFINITY, hi = 0.0;
  for (const GroupStats& g : groups) {
    if (g.family != family) continue;
    lo = std::min({lo, g.min_err, g.median_target});
    hi = std::max({hi, g.max_err, g.median_target});
    dat << k++ << " \"" << label(g) << "\" " << num(g.min_err, 6) << " " << num(g.q1_err, 6) << " "
        << num(g.median_err, 6) << " " << num(g.q3_err, 6) << " " << num(g.max_err, 6) << " "
        << num(g.median_target, 6) << " " << g.reached << " " << g.runs << "\n";
  }
  if (k == 0) return "";
  core::write_file_atomically(dir + "/" + name + ".dat", dat.str());
  const std::string file = gnuplot_string(dir + "/" + name + ".dat");
  std::ostringstream cmd;
  cmd << "set title '" << title << "'\nset xlabel '" << xlabel
      << " (below: runs that reached the target / runs)' offset 0,-1\nset bmargin 5\n"
      << "set grid ytics\nset key outside right top box\nset xrange [-0.6:" << k - 0.4 << "]\n";
  // Err spanning more than a factor 20 (and no Err 0): a log scale, so that no box is flat.
  if (lo > 0.0 && hi > 20.0 * lo) {
    cmd << "set ylabel 'final Err of a run [m²] (log scale)'\nset logscale y\nset yrange ["
        << num(lo / 1.5, 9) << ":" << num(hi * 1.5, 9) << "]\n";
  } else {
    cmd << "set ylabel 'final Err of a run [m²]'\nset yrange [0:*]\n";
  }
  cmd << "set boxwidth 0.5\nset style fill solid 0.3 border -1\nset xtics scale 0\n"
      << "plot " << file
      << " using 1:4:3:7:6:xtic(sprintf(\"%s\\n%d/%d\", stringcolumn(2), $9, $10)) with "
         "candlesticks whiskerbars 0.5 lc rgb '#1f77b4' title 'Err: quartiles, min–max', "
      << file << " using 1:5:5:5:5 with candlesticks lw 2 lc rgb 'black' title 'median', " << file
      << " using 1:8 with points pt 6 ps 1.5 lc rgb '#d62728' title 'success target'\n";
  detail::gnuplot_png(dir + "/" + name + ".png", cmd.str());
  return figure(name, title,
                "Box: the middle half of the runs' final Err (quartiles), bar: the median, "
                "whiskers: the smallest and the largest; red circle: the success target (median "
                "over the group's runs); below each group's label: runs that reached it / runs.");
}

/// Thousands separators for counts ("160,000").
std::string count_text(double v) {
  std::string digits = num(v, 0);
  for (int i = static_cast<int>(digits.size()) - 3; i > 0; i -= 3) digits.insert(i, ",");
  return digits;
}

/// "a of b runs" over the runs of the groups that `take` selects.
std::string success_text(const std::vector<RunRow>& rows,
                         const std::function<bool(const RunRow&)>& take) {
  int runs = 0, reached = 0;
  double worst = 0;
  for (const RunRow& r : rows) {
    if (!take(r)) continue;
    ++runs;
    reached += r.reached;
    worst = std::max(worst, r.err);
  }
  if (runs == 0) return "not in this study";
  return std::to_string(reached) + " of " + std::to_string(runs) +
         " runs reached the tolerance; largest final Err " + num(worst, 4) + " m²";
}

/// The paper's results (SPEC §9) beside the same figures computed from this study's runs.
std::string paper_comparison(const std::vector<GroupStats>& groups,
                             const std::vector<RunRow>& rows) {
  const GroupStats* fewest_cameras = nullptr;
  const GroupStats* most_cameras = nullptr;
  const GroupStats* finest = nullptr;
  double label_min = 1e300, label_max = 0, ratio_min = 1e300, ratio_max = 0;
  for (const GroupStats& g : groups) {
    if (g.family == "cameras") {
      if (!fewest_cameras || g.shape.cameras < fewest_cameras->shape.cameras) fewest_cameras = &g;
      if (!most_cameras || g.shape.cameras > most_cameras->shape.cameras) most_cameras = &g;
    }
    if (g.family == "resolution" && (!finest || g.shape.voxels > finest->shape.voxels)) finest = &g;
    if (g.shape.voxels == 16 * 12 * 12) {
      label_min = std::min(label_min, g.labelling_ms);
      label_max = std::max(label_max, g.labelling_ms);
    }
    if (g.labelling_ms > 0) {
      ratio_min = std::min(ratio_min, g.clustering_ms / g.labelling_ms);
      ratio_max = std::max(ratio_max, g.clustering_ms / g.labelling_ms);
    }
  }
  long long evals_min = 0, evals_max = 0;
  for (const RunRow& r : rows) {
    if (evals_max == 0 || r.evaluations < evals_min) evals_min = r.evaluations;
    evals_max = std::max(evals_max, r.evaluations);
  }
  const std::string none = "not in this study";
  std::ostringstream t;
  t << "Ours are computed from the runs above (times: mean per evaluation of a group, this "
       "machine).\n\n| figure | the paper (SPEC §9) | this study |\n|---|---|---|\n";
  t << "| time per iteration step | 315 ms (3 cameras) to 170 ms (9 cameras) | ";
  if (fewest_cameras && most_cameras) {
    t << num(fewest_cameras->total_ms, 2) << " ms (" << fewest_cameras->shape.cameras
      << " cameras) to " << num(most_cameras->total_ms, 2) << " ms (" << most_cameras->shape.cameras
      << " cameras)";
  } else {
    t << none;
  }
  t << " |\n| intersection test | ≤ 15 ms; 50 ms at 36×27×27 | ";
  if (label_max > 0) t << num(label_min, 2) << "–" << num(label_max, 2) << " ms at 16×12×12";
  if (finest)
    t << (label_max > 0 ? "; " : "") << num(finest->labelling_ms, 2) << " ms at "
      << finest->resolution;
  if (label_max == 0 && !finest) t << none;
  t << " |\n| clustering | 2–4× the intersection time | ";
  if (ratio_max > 0) {
    t << num(ratio_min, 2) << "–" << num(ratio_max, 2) << "× the intersection time";
  } else {
    t << none;
  }
  t << " |\n| iterations | 500–160,000 | " << count_text(static_cast<double>(evals_min)) << "–"
    << count_text(static_cast<double>(evals_max)) << " evaluations per run |\n";
  t << "| resolution | above 24×18×18 no run reached the tolerance in 3 h | above 24×18×18: "
    << success_text(
           rows,
           [](const RunRow& r) { return r.family == "resolution" && r.voxels > 24 * 18 * 18; })
    << " |\n";
  t << "| cameras | 3 cameras never reached it | 3 cameras: "
    << success_text(rows, [](const RunRow& r) { return r.family == "cameras" && r.cameras == 3; })
    << " |\n";
  t << "| domains | ceiling / upper fourth never reached 0.046 m², stayed below 0.25 m² | ceiling: "
    << success_text(rows, [](const RunRow& r) { return r.family == "domain_ceiling"; })
    << "; upper fourth: "
    << success_text(rows, [](const RunRow& r) { return r.family == "domain_upper_fourth"; })
    << " |\n";
  t << "| peak virtual memory | 32,868 kB (32.1 MiB) at 36×27×27 | ";
  if (finest) {
    t << num(finest->max_vm_peak_kb / 1024.0, 1) << " MiB virtual, "
      << num(finest->max_vm_hwm_kb / 1024.0, 1) << " MiB resident at " << finest->resolution
      << " (whole process: thread stacks and libraries are reserved, mostly untouched)";
  } else {
    t << none;
  }
  t << " |\n\n";
  return t.str();
}

/// The exact check: per group, how the runs' configurations fare in the exact
/// pipeline, and a log–log plot of exact against voxel Err; "" when no run was checked.
std::string exact_check_section(const std::vector<GroupStats>& groups,
                                const std::vector<RunRow>& rows, const std::string& dir) {
  int checked = 0;
  for (const GroupStats& g : groups) checked += g.checked;
  if (checked == 0) return "";
  std::ostringstream md;
  md << "\n## Exact check of every run\n\n"
     << "Each run's best configuration evaluated by the exact pipeline (`camplace validate`: "
        "CGAL Nef polyhedra, the inscribed pyramid FOV). *Reached (exact)*: the exact Err is "
        "within the same target as the voxel Err. *False successes*: runs whose voxel Err "
        "reached the target but whose exact Err did not. *Over-estimates*: runs where some "
        "state's voxel distance d(C, M) exceeds the exact one (same FOV): the voxel result was "
        "not conservative there. "
     << checked << " of " << rows.size() << " runs checked.\n\n"
     << "| examination | param | runs checked | reached (voxel) | reached (exact) | false "
        "successes | over-estimates | median exact Err [m²] | max exact Err [m²] |\n"
     << "|---|---|---|---|---|---|---|---|---|\n";
  for (const GroupStats& g : groups) {
    if (g.checked == 0) continue;
    int reached_checked = 0;
    for (const RunRow& r : rows) reached_checked += r.group == g.group && r.checked && r.reached;
    md << "| " << core::md_cell(g.examination) << " | " << g.param << " | " << g.checked << " | "
       << reached_checked << " | " << g.reached_exact << " | " << g.false_successes << " | "
       << g.overestimates << " | " << num(g.median_exact_err, 4) << " | " << num(g.max_exact_err, 4)
       << " |\n";
  }
  // Log–log scatter of exact against voxel Err, with the line exact = voxel and the targets.
  std::ostringstream dat;
  dat << "# voxel_err_m2 exact_err_m2 (0 drawn at 1e-6)\n";
  std::vector<double> targets;
  double lo = 1e300, hi = 0.0;
  for (const RunRow& r : rows) {
    if (!r.checked) continue;
    for (double v : {r.err, r.exact_err, r.target}) {
      lo = std::min(lo, std::max(v, 1e-6));
      hi = std::max(hi, std::max(v, 1e-6));
    }
    dat << num(std::max(r.err, 1e-6), 9) << " " << num(std::max(r.exact_err, 1e-6), 9) << "\n";
    if (std::find(targets.begin(), targets.end(), r.target) == targets.end()) {
      targets.push_back(r.target);
    }
  }
  std::sort(targets.begin(), targets.end());
  core::write_file_atomically(dir + "/exact_vs_voxel_err.dat", dat.str());
  std::ostringstream cmd;
  cmd << "set title 'Exact against voxel Err of every run'\n"
         "set xlabel 'voxel Err [m²] (as the optimizer saw it)'\nset ylabel 'exact Err [m²]'\n"
         "set logscale xy\nset grid\nset key outside right top box\n"
      << "set xrange [" << num(lo / 2, 9) << ":" << num(hi * 2, 9) << "]\nset yrange ["
      << num(lo / 2, 9) << ":" << num(hi * 2, 9) << "]\n";
  // Targets: one pair of lines when all runs share it, else the smallest and the largest.
  std::vector<double> lines = {targets.front()};
  if (targets.back() != targets.front()) lines.push_back(targets.back());
  int arrow = 1;
  for (double t : lines) {
    cmd << "set arrow " << arrow++ << " from " << num(t, 9) << ", graph 0 to " << num(t, 9)
        << ", graph 1 nohead dt 2 lc rgb 'gray40'\n";
    cmd << "set arrow " << arrow++ << " from graph 0, first " << num(t, 9) << " to graph 1, first "
        << num(t, 9) << " nohead dt 2 lc rgb 'gray40'\n";
  }
  cmd << "plot " << gnuplot_string(dir + "/exact_vs_voxel_err.dat")
      << " using 1:2 with points pt 7 ps 0.6 title 'runs', x with lines lc rgb 'black' title "
         "'exact = voxel', 1/0 with lines dt 2 lc rgb 'gray40' title 'target "
      << (lines.size() == 1 ? num(lines[0], 4) : num(lines[0], 4) + " … " + num(lines[1], 4))
      << " m²'\n";
  detail::gnuplot_png(dir + "/exact_vs_voxel_err.png", cmd.str());
  md << "\n"
     << figure("exact_vs_voxel_err", "Exact against voxel Err of every run",
               "Log–log; each point one run's best configuration. Dashed lines: the success "
               "target (tolerance, or in conservative mode max(tolerance, lower bound)); points "
               "above the horizontal line are not successes by their exact Err. Err 0 is drawn at "
               "10⁻⁶ m².");
  return md.str();
}

/// A study setting that examinations may set for themselves (`refine`, `objective`): the
/// study's value, then "; X for <examination>, …" for those that differ.
template <typename Of>
std::string setting_text(const StudySpec& spec, const std::string& study_value, Of of) {
  std::string text = study_value;
  for (const detail::Examination& e : spec.examinations) {
    const std::string own = of(e);
    if (own != study_value) text += "; " + own + " for \"" + e.name + "\"";
  }
  return text;
}

std::string refine_text(const StudySpec& spec) {
  return setting_text(spec, std::to_string(spec.refine), [&spec](const detail::Examination& e) {
    return std::to_string(detail::refine_of(spec, e));
  });
}

std::string objective_text(const StudySpec& spec) {
  return setting_text(spec, spec.objective, [&spec](const detail::Examination& e) {
    return detail::objective_of(spec, e);
  });
}

/// The report's provenance header: the study file, the base scene and the groups' scenes with
/// their SHA-256, the study's resolved settings, host and start time.
std::string study_header(const StudySpec& spec, const std::vector<RunRow>& rows,
                         const std::string& command, const std::string& dir) {
  std::vector<HeaderScene> scenes;
  if (spec.base) scenes.push_back({"base scene", spec.base_file, spec.base->hashes});
  for (const RunRow& r : rows) {
    const std::string path = "scenes/" + r.group + ".json";
    if (!scenes.empty() && scenes.back().path == path) continue;
    const std::string full = dir + "/" + path;
    if (!std::filesystem::is_regular_file(full)) continue;
    scenes.push_back(
        {"scene of " + r.group, path, core::combine_scene_hashes(core::sha256_file(full), {})});
  }
  const std::string seed_range =
      std::to_string(spec.first_seed) + "–" +
      std::to_string(spec.first_seed + static_cast<unsigned>(spec.runs_per_group) - 1);
  const std::vector<std::pair<std::string, std::string>> options = {
      {"study file", "`" + spec.file + "`"},
      {"mode", core::name_of(spec.mode)},
      {"refine", refine_text(spec)},
      {"algorithm", spec.algorithm},
      {"objective", objective_text(spec)},
      {"runs per group", std::to_string(spec.runs_per_group)},
      {"seeds", seed_range},
      {"scene seed", std::to_string(spec.scene_seed)},
      {"threads", std::to_string(spec.threads)},
      {"time limit", num(spec.time_limit, 0) + " s"},
      {"max evaluations", std::to_string(spec.max_evaluations)}};
  // The header's build is the one writing the report; the runs may have been made by others
  // (a resumed study): each distinct one with its number of runs.
  std::map<std::string, int> made_by;
  for (const RunRow& r : rows) ++made_by[r.made_by.empty() ? "unrecorded" : r.made_by];
  std::string builds;
  for (const auto& [build, count] : made_by) {
    builds += (builds.empty() ? "" : "; ") + build + " (" + std::to_string(count) + " runs)";
  }
  return provenance_header(scenes, options, command,
                           spec.started.empty() ? core::now_iso8601() : spec.started,
                           spec.base ? ""
                                     : "the groups' scenes are generated from the paper's basic "
                                       "setup (built in, as data/paper_basic.json)",
                           builds);
}

}  // namespace

void write_study_report(const StudySpec& spec, const std::vector<RunRow>& rows,
                        const std::string& command, bool interrupted, const std::string& dir) {
  // runs.csv: every finished run (timing columns: seconds, *_ms).
  std::ostringstream csv;
  csv << "examination,family,param,seed,resolution,voxels,cameras,static_objects,static_facets,"
         "dynamic_objects,dynamic_facets,time_steps,target_objects,target_facets,events,err_m2,"
         "tolerance_m2,reached_tolerance,evaluations,stop_reason,vm_peak_kb,seconds,labelling_ms,"
         "clustering_ms,distance_ms,total_ms\n";
  for (const RunRow& r : rows) {
    csv << core::csv_field(r.examination) << "," << core::csv_field(r.family) << "," << r.param
        << "," << r.seed << "," << core::csv_field(r.resolution) << "," << r.voxels << ","
        << r.cameras << "," << r.static_objects << "," << r.static_facets << ","
        << r.dynamic_objects << "," << r.dynamic_facets << "," << r.time_steps << ","
        << r.target_objects << "," << r.target_facets << "," << r.events << "," << num(r.err, 6)
        << "," << num(r.tolerance, 6) << "," << (r.reached ? 1 : 0) << "," << r.evaluations << ","
        << r.stop_reason << "," << r.vm_peak_kb << "," << num(r.seconds, 2) << ","
        << num(r.labelling_ms, 3) << "," << num(r.clustering_ms, 3) << "," << num(r.distance_ms, 3)
        << "," << num(r.total_ms, 3) << "\n";
  }
  core::write_file_atomically(dir + "/runs.csv", csv.str());

  const std::vector<GroupStats> groups = group_stats(rows);
  std::ostringstream md;
  md << "# Study `" << spec.name << "`\n\n" << study_header(spec, rows, command, dir);
  if (!spec.description.empty()) md << spec.description << "\n\n";
  md << "## Budget\n\n| | this study | the paper |\n|---|---|---|\n"
     << "| runs per group | " << spec.runs_per_group << " | 20 |\n"
     << "| stop | tolerance (½ voxel diagonal)²"
     << (spec.mode == core::LabelMode::conservative
             ? " or the conservative lower bound of Err, whichever is larger (SPEC §4)"
             : "")
     << ", or " << spec.max_evaluations << " evaluations, or " << num(spec.time_limit, 0)
     << " s | tolerance 0.046 m², or 3 h |\n"
     << "| solver | pagmo `" << spec.algorithm << "`, " << spec.threads << " threads, objective "
     << objective_text(spec) << " | MIDACO |\n"
     << "| machine (writing this report) | " << machine_text() << " | 2.8 GHz Opteron |\n"
     << "| voxel labelling | " << core::name_of(spec.mode)
     << (refine_text(spec) != "0" ? ", refined (`refine`, levels) " + refine_text(spec) : "")
     << " | centre of voxel |\n\n"
     << clock_note(rows);
  md << "## Groups\n\n| examination | param | scene | runs | "
     << (spec.mode == core::LabelMode::conservative ? "reached max(tolerance, lower bound)"
                                                    : "reached tolerance")
     << " | median "
        "evaluations | "
        "median Err [m²] |\n|---|---|---|---|---|---|---|\n";
  for (const GroupStats& g : groups) {
    const RunRow& s = g.shape;
    md << "| " << core::md_cell(g.examination) << " | " << g.param << " | " << s.resolution << ", "
       << s.cameras << " cams, static " << s.static_objects << "/" << s.static_facets
       << ", dynamic " << s.dynamic_objects << "/" << s.dynamic_facets << " in " << s.time_steps
       << " steps, targets " << s.target_objects << "/" << s.target_facets << " in " << s.events
       << " events | " << g.runs << " | " << g.reached << " | " << num(g.median_evaluations, 0)
       << " | " << num(g.median_err, 4) << " |\n";
  }
  md << "\n(objects/facets; events counted over all time steps.)\n\n"
     << "## Time and memory (vary between runs)\n\n"
     << "| examination | param | labelling ms | clustering ms | total ms per evaluation | median "
        "seconds per run | peak VM [MiB] | peak resident [MiB] |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  for (const GroupStats& g : groups) {
    md << "| " << core::md_cell(g.examination) << " | " << g.param << " | "
       << num(g.labelling_ms, 3) << " | " << num(g.clustering_ms, 3) << " | " << num(g.total_ms, 3)
       << " | " << num(g.median_seconds, 1) << " | " << num(g.max_vm_peak_kb / 1024.0, 1) << " | "
       << num(g.max_vm_hwm_kb / 1024.0, 1) << " |\n";
  }
  md << exact_check_section(groups, rows, dir);
  md << "\n## The paper's figures beside ours\n\n" << paper_comparison(groups, rows);
  md << "## Plots\n\n";
  auto evals = [](const GroupStats& g) { return g.median_evaluations; };
  auto q1_evals = [](const GroupStats& g) { return g.q1_evaluations; };
  auto q3_evals = [](const GroupStats& g) { return g.q3_evaluations; };
  const std::string evals_caption =
      "Points: the median number of evaluations of a group's runs; bars: the middle half of the "
      "runs (quartiles). A run ends at the success target or at the evaluation budget (" +
      std::to_string(spec.max_evaluations) + ").";
  md << plot(dir, "iterations_vs_resolution", "Iterations against voxel resolution",
             "voxels (nx·ny·nz)", "evaluations per run", groups,
             {{"resolution", "median, quartiles", {}, q1_evals, q3_evals}}, evals, evals_caption);
  md << err_box_plot(dir, "err_vs_resolution", "Final Err against voxel resolution",
                     "voxel resolution", groups, "resolution",
                     [](const GroupStats& g) { return g.resolution; });
  md << plot(dir, "iterations_vs_objects", "Iterations against static and dynamic objects",
             "objects", "evaluations per run", groups,
             {{"static_objects", "static objects: median, quartiles", {}, q1_evals, q3_evals},
              {"dynamic_objects", "dynamic objects: median, quartiles", {}, q1_evals, q3_evals}},
             evals, evals_caption);
  md << err_box_plot(dir, "err_vs_dynamic_objects", "Final Err against dynamic objects",
                     "dynamic objects", groups, "dynamic_objects",
                     [](const GroupStats& g) { return std::to_string(g.shape.dynamic_objects); });
  md << err_box_plot(dir, "err_vs_cameras", "Final Err against cameras", "cameras", groups,
                     "cameras",
                     [](const GroupStats& g) { return std::to_string(g.shape.cameras); });
  {
    // Time per iteration against cameras, split into intersection (labelling) and clustering.
    std::ostringstream dat;
    bool any = false;
    dat << "# cameras labelling_ms clustering_ms total_ms\n";
    for (const auto& g : groups) {
      if (g.family != "cameras") continue;
      any = true;
      dat << g.shape.cameras << " " << num(g.labelling_ms, 4) << " " << num(g.clustering_ms, 4)
          << " " << num(g.total_ms, 4) << "\n";
    }
    if (any) {
      core::write_file_atomically(dir + "/time_vs_cameras.dat", dat.str());
      detail::gnuplot_png(
          dir + "/time_vs_cameras.png",
          "set title 'Time per iteration against cameras (timing: varies between runs)'\n"
          "set xlabel 'cameras'\nset ylabel 'ms per evaluation'\nset grid\nset key outside right "
          "top box\n"
          "set style data histograms\nset style histogram rowstacked\nset style fill solid 0.7\n"
          "set boxwidth 0.6\nset yrange [0:*]\n"
          "plot " +
              gnuplot_string(dir + "/time_vs_cameras.dat") +
              " using 2:xtic(1) title 'intersection (labelling)', "
              "'' using 3 title 'clustering'\n");
      md << figure("time_vs_cameras", "Time per iteration against cameras",
                   "Mean time of one evaluation over a group's runs, split into the "
                   "intersection test (voxel labelling) and the clustering (components and "
                   "plausibility filter); the distance computation is the rest of the total "
                   "in the table above. Measured on the machine above; varies between runs.");
    }
  }
  md << plot(dir, "memory_vs_resolution", "Peak memory against resolution (varies between runs)",
             "voxels (nx·ny·nz)", "peak memory of a run [MiB]", groups,
             {{"resolution", "virtual (VmPeak)",
               [](const GroupStats& g) { return g.max_vm_peak_kb / 1024.0; }},
              {"resolution", "resident (VmHWM)",
               [](const GroupStats& g) { return g.max_vm_hwm_kb / 1024.0; }}},
             {},
             "The largest peak memory of a group's runs (each run is a process of its own), "
             "virtual (address space reserved, including thread stacks and libraries) and "
             "resident (actually used). 1 MiB = 1024 kB.");
  md << "Data: `runs.csv` (one row per run), plot data and gnuplot scripts beside each PNG, run "
        "files under `runs/`, generated scenes under `scenes/`.\n";
  if (interrupted) md << "\n**Interrupted**: rerun the same command to finish the study.\n";
  core::write_file_atomically(dir + "/report.md", md.str());
}

std::vector<std::string> study_report_files() {
  // Every plot name write_study_report passes to plot() or writes itself.
  std::vector<std::string> files = {"report.md", "runs.csv"};
  for (const char* plot :
       {"iterations_vs_resolution", "err_vs_resolution", "iterations_vs_objects",
        "err_vs_dynamic_objects", "err_vs_cameras", "time_vs_cameras", "memory_vs_resolution",
        "exact_vs_voxel_err",
        // the names of earlier versions' plots, so a restart discards them too
        "success_vs_resolution", "success_vs_dynamic_objects", "success_vs_cameras"}) {
    for (const char* extension : {".png", ".gp", ".dat"}) {
      files.push_back(std::string(plot) + extension);
    }
  }
  return files;
}

}  // namespace camplace::compare::detail
