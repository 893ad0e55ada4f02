// Studies of the paper's examinations (SPEC §8–9).
#include "camplace/compare/study.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <sstream>

#include "camplace/compare/scene_generator.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/scene.hpp"
#include "format.hpp"
#include "gnuplot.hpp"

namespace camplace::compare {

namespace {

using detail::num;

namespace fs = std::filesystem;

struct Examination {
  std::string name, family;
  std::vector<std::optional<int>> params;  ///< one empty entry for families without a param
};

struct StudySpec {
  std::string description, algorithm = "gaco", mode = "conservative";
  int runs_per_group = 3, threads = 2;
  unsigned first_seed = 1, scene_seed = 1;
  double time_limit = 600.0;
  long long max_evaluations = 10000;
  std::vector<Examination> examinations;
};

StudySpec parse_study(const std::string& path, const std::vector<std::string>& algorithms) {
  const nlohmann::json doc = core::read_json_file(path);
  const core::JsonNode root(doc, path, "");
  root.only_keys({"description", "algorithm", "mode", "runs_per_group", "threads", "first_seed",
                  "scene_seed", "time_limit_s", "max_evaluations", "examinations"});
  StudySpec s;
  if (root.has("description")) s.description = root.at("description").string();
  if (root.has("algorithm")) {
    s.algorithm = root.at("algorithm").string();
    if (!algorithms.empty() &&
        std::find(algorithms.begin(), algorithms.end(), s.algorithm) == algorithms.end()) {
      std::string list;
      for (const std::string& a : algorithms) list += (list.empty() ? "" : ", ") + a;
      root.at("algorithm")
          .fail("unknown solver \"" + s.algorithm + "\" (expected one of: " + list + ")");
    }
  }
  if (root.has("mode")) {
    s.mode = root.at("mode").string();
    if (s.mode != "center" && s.mode != "conservative")
      root.at("mode").fail("expected center or conservative");
  }
  s.runs_per_group = root.at("runs_per_group").integer_in(1, 1000);
  if (root.has("threads")) s.threads = root.at("threads").integer_in(1, 256);
  if (root.has("first_seed")) s.first_seed = root.at("first_seed").integer_in(0, 1 << 30);
  if (root.has("scene_seed")) s.scene_seed = root.at("scene_seed").integer_in(0, 1 << 30);
  s.time_limit = root.at("time_limit_s").number_in(0.1, 1e7);
  s.max_evaluations = root.at("max_evaluations").integer_in(1, 2000000000);
  const core::JsonNode list = root.at("examinations");
  if (list.array_size() == 0) list.fail("a study needs at least one examination");
  for (std::size_t i = 0; i < list.array_size(); ++i) {
    const core::JsonNode e = list.at(i);
    e.only_keys({"name", "family", "params"});
    Examination ex;
    ex.family = e.at("family").string();
    ex.name = e.has("name") ? e.at("name").string() : ex.family;
    if (e.has("params")) {
      const core::JsonNode p = e.at("params");
      for (std::size_t k = 0; k < p.array_size(); ++k)
        ex.params.push_back(p.at(k).integer_in(-1000, 1000));
    }
    if (ex.params.empty()) ex.params.push_back(std::nullopt);
    for (const std::optional<int>& param : ex.params) {
      try {
        generate_scene_json(ex.family, param, s.scene_seed);  // validates family and param
      } catch (const core::InputError& err) {
        e.fail(err.reason());
      }
    }
    s.examinations.push_back(ex);
  }
  return s;
}

/// One finished run as read back from its run file.
struct RunRow {
  std::string examination, family, group;
  int param = 0;
  unsigned seed = 0;
  // x values of the group's scene
  long voxels = 0;
  int cameras = 0, static_objects = 0, static_facets = 0, dynamic_objects = 0, dynamic_facets = 0;
  int target_objects = 0, target_facets = 0, time_steps = 0, events = 0;
  std::string resolution;
  // the run
  double err = 0, tolerance = 0, seconds = 0;
  long long evaluations = 0;
  bool reached = false;
  std::string stop_reason;
  double labelling_ms = 0, clustering_ms = 0, distance_ms = 0, total_ms = 0;
  long long vm_peak_kb = 0, vm_hwm_kb = 0;
};

std::string group_name(const Examination& e, const std::optional<int>& param) {
  return param ? e.family + "-" + std::to_string(*param) : e.family;
}

std::string quote(const std::string& s) { return "'" + s + "'"; }

void describe_scene(const core::Scene& scene, RunRow& row) {
  auto facets = [](const std::vector<core::SceneObject>& objects) {
    int n = 0;
    for (const auto& o : objects) n += static_cast<int>(o.mesh.triangles.size());
    return n;
  };
  row.voxels = static_cast<long>(scene.voxels[0]) * scene.voxels[1] * scene.voxels[2];
  row.resolution = std::to_string(scene.voxels[0]) + "x" + std::to_string(scene.voxels[1]) + "x" +
                   std::to_string(scene.voxels[2]);
  row.cameras = scene.cameras.count;
  row.static_objects = static_cast<int>(scene.static_obstacles.size());
  row.static_facets = facets(scene.static_obstacles);
  row.time_steps = static_cast<int>(scene.time_steps.size());
  for (const auto& step : scene.time_steps) {
    row.dynamic_objects += static_cast<int>(step.dynamic_obstacles.size());
    row.dynamic_facets += facets(step.dynamic_obstacles);
    for (const auto& e : step.events) {
      ++row.events;
      row.target_objects += static_cast<int>(e.targets.size());
      row.target_facets += facets(e.targets);
    }
  }
}

bool read_run(const std::string& path, RunRow& row) {
  std::ifstream in(path);
  if (!in) return false;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
    row.stop_reason = j.at("stop_reason").get<std::string>();
    if (row.stop_reason == "interrupted") return false;  // not finished: run again
    row.err = j.at("err").get<double>();
    row.tolerance = j.at("tolerance").get<double>();
    row.seconds = j.at("seconds").get<double>();
    row.evaluations = j.at("evaluations").get<long long>();
    row.reached = j.at("reached_tolerance").get<bool>();
    const auto& t = j.at("time_per_evaluation_ms");
    row.labelling_ms = t.at("labelling").get<double>();
    row.clustering_ms = t.at("clustering").get<double>();
    row.distance_ms = t.at("distance").get<double>();
    row.total_ms = t.at("total").get<double>();
    row.vm_peak_kb = j.at("memory_kb").at("vm_peak").get<long long>();
    row.vm_hwm_kb = j.at("memory_kb").at("vm_hwm").get<long long>();
  } catch (const std::exception&) {
    return false;  // unreadable: run again
  }
  return true;
}

/// Whether a rerun with the same seeds reproduces the rows: only when no run was ended by the
/// clock (the evaluation count reached by a time limit depends on the machine's speed).
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

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct GroupStats {
  std::string examination, family, group, resolution;
  int param = 0, runs = 0, reached = 0;
  RunRow shape;  // scene description
  double median_evaluations = 0, median_seconds = 0, median_err = 0;
  double labelling_ms = 0, clustering_ms = 0, total_ms = 0;
  double max_vm_peak_kb = 0, max_vm_hwm_kb = 0;
};

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
    std::vector<double> evals, secs, errs;
    for (const RunRow* r : members[g.group]) {
      ++g.runs;
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
    g.median_evaluations = median(evals);
    g.median_seconds = median(secs);
    g.median_err = median(errs);
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
};

/// Writes one plot's data (x, y per series) and draws it; returns the markdown line, or "" when
/// the study has no group of the series' families. `percent_bars`: y is a percentage, drawn
/// as boxes on [0, 105].
std::string plot(const std::string& dir, const std::string& name, const std::string& title,
                 const std::string& xlabel, const std::string& ylabel,
                 const std::vector<GroupStats>& groups, const std::vector<Series>& series,
                 const GroupValue& y, bool percent_bars = false) {
  std::ostringstream dat, cmd;
  int blocks = 0;
  cmd << "set title '" << title << "'\nset xlabel '" << xlabel << "'\nset ylabel '" << ylabel
      << "'\nset grid\nset key outside right top box\n";
  if (percent_bars)
    cmd << "set style fill solid 0.6\nset boxwidth 0.6 relative\nset yrange [0:105]\n";
  std::string plot_cmd;
  for (const auto& [family, label, series_y] : series) {
    const GroupValue& value = series_y ? series_y : y;
    std::vector<const GroupStats*> members;
    for (const auto& g : groups) {
      if (g.family == family) members.push_back(&g);
    }
    if (members.empty()) continue;
    dat << "# " << family << ", " << label << ": x y\n";
    for (const GroupStats* g : members)
      dat << num(x_value(*g), 6) << " " << num(value(*g), 6) << "\n";
    dat << "\n\n";
    plot_cmd += std::string(plot_cmd.empty() ? "plot " : ", ") + "'" + dir + "/" + name +
                ".dat' index " + std::to_string(blocks++) + " using 1:2 with " +
                (percent_bars ? "boxes" : "linespoints") + " title '" + label + "'";
  }
  if (blocks == 0) return "";
  core::write_file_atomically(dir + "/" + name + ".dat", dat.str());
  detail::gnuplot_png(dir + "/" + name + ".png", cmd.str() + plot_cmd + "\n");
  return "![" + title + "](" + name + ".png)\n\n";
}

}  // namespace

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
  t << "| peak virtual memory | 32,868 kB at 36×27×27 | ";
  if (finest) {
    t << count_text(finest->max_vm_peak_kb) << " kB virtual, " << count_text(finest->max_vm_hwm_kb)
      << " kB resident at " << finest->resolution
      << " (whole process: thread stacks and libraries are reserved, mostly untouched)";
  } else {
    t << none;
  }
  t << " |\n\n";
  return t.str();
}

StudyOutcome run_study(const StudyOptions& options) {
  const StudySpec spec = parse_study(options.study_file, options.algorithms);
  const std::string dir = options.out_dir;
  fs::create_directories(dir + "/scenes");
  StudyOutcome outcome;
  std::vector<RunRow> rows;
  int total_runs = 0;
  for (const Examination& ex : spec.examinations) {
    total_runs += static_cast<int>(ex.params.size()) * spec.runs_per_group;
  }
  for (const Examination& ex : spec.examinations) {
    for (const std::optional<int>& param : ex.params) {
      const std::string group = group_name(ex, param);
      const std::string scene_path = dir + "/scenes/" + group + ".json";
      core::write_file_atomically(scene_path,
                                  generate_scene_json(ex.family, param, spec.scene_seed));
      RunRow shape;
      describe_scene(core::load_scene(scene_path), shape);
      shape.examination = ex.name;
      shape.family = ex.family;
      shape.group = group;
      shape.param = param.value_or(0);
      const std::string run_dir = dir + "/runs/" + group;
      for (int r = 0; r < spec.runs_per_group; ++r) {
        ++outcome.runs_total;
        RunRow row = shape;
        row.seed = spec.first_seed + r;
        const std::string run_file = run_dir + "/run-" + std::to_string(row.seed) + ".json";
        if (read_run(run_file, row)) {
          ++outcome.runs_done_before;
          rows.push_back(row);
          continue;
        }
        if (outcome.interrupted) continue;
        std::fprintf(stderr, "study: %s seed %u (run %d of %d)\n", group.c_str(), row.seed,
                     outcome.runs_total, total_runs);
        const std::string cmd =
            quote(options.camplace) + " optimize " + quote(scene_path) + " --algorithm " +
            spec.algorithm + " --seed " + std::to_string(row.seed) + " --runs 1 --threads " +
            std::to_string(spec.threads) + " --time-limit " + num(spec.time_limit, 3) +
            " --max-evals " + std::to_string(spec.max_evaluations) + " --mode " + spec.mode +
            " --quiet --out " + quote(run_dir) + " > " + quote(run_dir + "/last-output.txt");
        fs::create_directories(run_dir);
        const int status = std::system(cmd.c_str());
        // system() ignores SIGINT in this process while the child runs; the child writes its
        // best result and reports "interrupted", which ends the study here.
        if (read_run(run_file, row)) {
          ++outcome.runs_done_now;
          rows.push_back(row);
          continue;
        }
        // Ctrl-C reaches the whole foreground process group: the run file then says
        // "interrupted", or the shell around the child died of SIGINT.
        const bool by_sigint = (WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) ||
                               (WIFEXITED(status) && WEXITSTATUS(status) == 130) ||
                               read(run_file).find("\"interrupted\"") != std::string::npos;
        if (!by_sigint) {
          throw std::runtime_error("study: camplace optimize failed for " + group + " seed " +
                                   std::to_string(row.seed) + " (see " + run_dir +
                                   "/last-output.txt)");
        }
        outcome.interrupted = true;
      }
    }
  }

  // runs.csv: every finished run (timing columns: seconds, *_ms).
  std::ostringstream csv;
  csv << "examination,family,param,seed,resolution,voxels,cameras,static_objects,static_facets,"
         "dynamic_objects,dynamic_facets,time_steps,target_objects,target_facets,events,err_m2,"
         "tolerance_m2,reached_tolerance,evaluations,stop_reason,vm_peak_kb,seconds,labelling_ms,"
         "clustering_ms,distance_ms,total_ms\n";
  for (const RunRow& r : rows) {
    csv << r.examination << "," << r.family << "," << r.param << "," << r.seed << ","
        << r.resolution << "," << r.voxels << "," << r.cameras << "," << r.static_objects << ","
        << r.static_facets << "," << r.dynamic_objects << "," << r.dynamic_facets << ","
        << r.time_steps << "," << r.target_objects << "," << r.target_facets << "," << r.events
        << "," << num(r.err, 6) << "," << num(r.tolerance, 6) << "," << (r.reached ? 1 : 0) << ","
        << r.evaluations << "," << r.stop_reason << "," << r.vm_peak_kb << "," << num(r.seconds, 2)
        << "," << num(r.labelling_ms, 3) << "," << num(r.clustering_ms, 3) << ","
        << num(r.distance_ms, 3) << "," << num(r.total_ms, 3) << "\n";
  }
  core::write_file_atomically(dir + "/runs.csv", csv.str());

  const std::vector<GroupStats> groups = group_stats(rows);
  std::ostringstream md;
  md << "# Study: the paper's examinations\n\n";
  if (!spec.description.empty()) md << spec.description << "\n\n";
  md << "Made by:\n\n    " << options.command << "\n\n"
     << "## Budget\n\n| | this study | the paper |\n|---|---|---|\n"
     << "| runs per group | " << spec.runs_per_group << " | 20 |\n"
     << "| stop | tolerance (½ voxel diagonal)², or " << spec.max_evaluations << " evaluations, or "
     << num(spec.time_limit, 0) << " s | tolerance 0.046 m², or 3 h |\n"
     << "| solver | pagmo `" << spec.algorithm << "`, " << spec.threads << " threads | MIDACO |\n"
     << "| machine | 2 cores (this project's) | 2.8 GHz Opteron |\n"
     << "| voxel labelling | " << spec.mode << " | centre of voxel |\n\n"
     << clock_note(rows);
  md << "## Groups\n\n| examination | param | scene | runs | reached tolerance | median "
        "evaluations | "
        "median Err [m²] |\n|---|---|---|---|---|---|---|\n";
  for (const GroupStats& g : groups) {
    const RunRow& s = g.shape;
    md << "| " << g.examination << " | " << g.param << " | " << s.resolution << ", " << s.cameras
       << " cams, static " << s.static_objects << "/" << s.static_facets << ", dynamic "
       << s.dynamic_objects << "/" << s.dynamic_facets << " in " << s.time_steps
       << " steps, targets " << s.target_objects << "/" << s.target_facets << " in " << s.events
       << " events | " << g.runs << " | " << g.reached << " | " << num(g.median_evaluations, 0)
       << " | " << num(g.median_err, 4) << " |\n";
  }
  md << "\n(objects/facets; events counted over all time steps.)\n\n"
     << "## Time and memory (vary between runs)\n\n"
     << "| examination | param | labelling ms | clustering ms | total ms per evaluation | median "
        "seconds per run | peak VM [kB] | peak resident [kB] |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  for (const GroupStats& g : groups) {
    md << "| " << g.examination << " | " << g.param << " | " << num(g.labelling_ms, 3) << " | "
       << num(g.clustering_ms, 3) << " | " << num(g.total_ms, 3) << " | "
       << num(g.median_seconds, 1) << " | " << num(g.max_vm_peak_kb, 0) << " | "
       << num(g.max_vm_hwm_kb, 0) << " |\n";
  }
  md << "\n## The paper's figures beside ours\n\n" << paper_comparison(groups, rows);
  md << "## Plots\n\n";
  auto evals = [](const GroupStats& g) { return g.median_evaluations; };
  auto success = [](const GroupStats& g) { return g.runs ? 100.0 * g.reached / g.runs : 0.0; };
  md << plot(dir, "iterations_vs_resolution", "Iterations against voxel resolution",
             "voxels (nx·ny·nz)", "median evaluations", groups,
             {{"resolution", "median evaluations"}}, evals);
  md << plot(dir, "success_vs_resolution", "Success against voxel resolution", "voxels (nx·ny·nz)",
             "runs reaching the tolerance [%]", groups, {{"resolution", "success"}}, success, true);
  md << plot(dir, "iterations_vs_objects", "Iterations against static and dynamic objects",
             "objects", "median evaluations", groups,
             {{"static_objects", "static objects"}, {"dynamic_objects", "dynamic objects"}}, evals);
  md << plot(dir, "success_vs_dynamic_objects", "Success against dynamic objects",
             "dynamic objects", "runs reaching the tolerance [%]", groups,
             {{"dynamic_objects", "success"}}, success, true);
  md << plot(dir, "success_vs_cameras", "Success against cameras", "cameras",
             "runs reaching the tolerance [%]", groups, {{"cameras", "success"}}, success, true);
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
          "plot '" +
              dir +
              "/time_vs_cameras.dat' using 2:xtic(1) title 'intersection (labelling)', "
              "'' using 3 title 'clustering'\n");
      md << "![Time per iteration against cameras](time_vs_cameras.png)\n\n";
    }
  }
  md << plot(
      dir, "memory_vs_resolution", "Peak memory against resolution (varies between runs)",
      "voxels (nx·ny·nz)", "peak memory of a run [kB]", groups,
      {{"resolution", "virtual (VmPeak)", [](const GroupStats& g) { return g.max_vm_peak_kb; }},
       {"resolution", "resident (VmHWM)", [](const GroupStats& g) { return g.max_vm_hwm_kb; }}},
      {});
  md << "Data: `runs.csv` (one row per run), plot data and gnuplot scripts beside each PNG, run "
        "files under `runs/`, generated scenes under `scenes/`.\n";
  if (outcome.interrupted) md << "\n**Interrupted**: rerun the same command to finish the study.\n";
  core::write_file_atomically(dir + "/report.md", md.str());
  return outcome;
}

}  // namespace camplace::compare
