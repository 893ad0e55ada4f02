// Studies of the paper's examinations (SPEC §8–9): generate each group's scene, run what is
// missing through the launcher, read the run files back and write the report.
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>

#include "camplace/compare/run_validation.hpp"
#include "camplace/compare/scene_generator.hpp"
#include "camplace/compare/study.hpp"
#include "camplace/core/err.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/optimize/report.hpp"
#include "format.hpp"
#include "study_definition.hpp"
#include "study_report.hpp"

namespace camplace::compare {

namespace {

namespace fs = std::filesystem;
using detail::RunRow;

void describe_scene(const core::Scene& scene, RunRow& row) {
  auto facets = [](const std::vector<core::SceneObject>& objects) {
    int n = 0;
    for (const auto& o : objects) n += static_cast<int>(o.mesh.triangles.size());
    return n;
  };
  row.voxels = static_cast<long>(scene.voxels[0]) * scene.voxels[1] * scene.voxels[2];
  row.resolution = detail::resolution_text(scene.voxels);
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

/// The run's figures as its run file records them.
void add_result(const optimize::RunResult& run, bool conservative, RunRow& row) {
  row.stop_reason = optimize::to_string(run.stop_reason);
  row.err = run.err;
  row.tolerance = run.tolerance;
  row.seconds = run.seconds;
  row.evaluations = static_cast<long long>(run.evaluations);
  row.target = core::success_target(conservative, run.tolerance, run.err_lower_bound);
  row.reached = run.err <= row.target;
  row.labelling_ms = run.mean_timing.labelling_ms;
  row.clustering_ms = run.mean_timing.clustering_ms;
  row.distance_ms = run.mean_timing.distance_ms;
  row.total_ms = run.mean_timing.total_ms;
  row.vm_peak_kb = static_cast<long long>(run.memory.vm_peak_kb);
  row.vm_hwm_kb = static_cast<long long>(run.memory.vm_hwm_kb);
}

/// The run file at `path`, or nothing when there is none yet. A damaged file, or one of a
/// format this version does not read, is an error (core::InputError naming it): running again
/// would overwrite what may be a finished run.
std::optional<optimize::RunResult> existing_run(const std::string& path) {
  if (!fs::exists(path)) return std::nullopt;
  return optimize::read_run_file(path).run;
}

/// The arguments of `camplace optimize` for one run: one seed, the study's budget, the run
/// file and summary in `run_dir`. `--out=` and `--` keep any directory or scene name (one
/// starting with '-', say) a value.
std::vector<std::string> optimize_args(const detail::StudySpec& spec, const std::string& scene,
                                       unsigned seed, const std::string& run_dir) {
  return {"--algorithm",  spec.algorithm,
          "--seed",       std::to_string(seed),
          "--runs",       "1",
          "--threads",    std::to_string(spec.threads),
          "--time-limit", detail::num(spec.time_limit, 3),
          "--max-evals",  std::to_string(spec.max_evaluations),
          "--mode",       core::name_of(spec.mode),
          "--quiet",      "--out=" + run_dir,
          "--",           scene};
}

}  // namespace

StudyOutcome run_study(const StudyOptions& options) {
  const detail::StudySpec spec = detail::parse_study(options.study_file);
  const std::string dir = options.out_dir;
  fs::create_directories(dir + "/scenes");
  StudyOutcome outcome;
  std::vector<RunRow> rows;
  int total_runs = 0;
  for (const detail::Examination& ex : spec.examinations) {
    total_runs += static_cast<int>(ex.params.size()) * spec.runs_per_group;
  }
  for (const detail::Examination& ex : spec.examinations) {
    for (const std::optional<int>& param : ex.params) {
      const std::string group = detail::group_name(ex, param);
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
        const std::optional<optimize::RunResult> before = existing_run(run_file);
        if (before && before->stop_reason != optimize::StopReason::interrupted) {
          add_result(*before, spec.mode == core::LabelMode::conservative, row);
          ++outcome.runs_done_before;
          rows.push_back(row);
          continue;
        }
        if (outcome.interrupted) continue;
        if (!options.launch) throw std::invalid_argument("run_study: no launcher for the runs");
        std::fprintf(stderr, "study: %s seed %u (run %d of %d)\n", group.c_str(), row.seed,
                     outcome.runs_total, total_runs);
        fs::create_directories(run_dir);
        // An interrupted run's file goes: the file found afterwards is this run's.
        if (before) fs::remove(run_file);
        const LaunchOutcome launched = options.launch(
            {optimize_args(spec, scene_path, row.seed, run_dir), run_dir + "/last-output.txt"});
        // Ctrl-C ends the study after this run; the report covers the runs finished so far.
        if (launched.interrupted) outcome.interrupted = true;
        const std::optional<optimize::RunResult> after = existing_run(run_file);
        if (after && after->stop_reason != optimize::StopReason::interrupted) {
          add_result(*after, spec.mode == core::LabelMode::conservative, row);
          ++outcome.runs_done_now;
          rows.push_back(row);
          continue;
        }
        // An interrupted run writes its best result as "interrupted" and exits normally.
        if (after || launched.interrupted) {
          outcome.interrupted = true;
          continue;
        }
        throw std::runtime_error("study: the run of " + group + " seed " +
                                 std::to_string(row.seed) + " wrote no run file (" +
                                 (launched.failure.empty() ? "exit status 0" : launched.failure) +
                                 "; its standard output is in " + run_dir + "/last-output.txt)");
      }
    }
  }
  // The exact check of every run (issue 10): now, with --validate, or from an earlier
  // `camplace validate DIR`. A row counts only when it is of this very run (same voxel Err).
  if (options.validate && !outcome.interrupted) {
    ValidateOptions check;
    check.dir = dir;
    check.command = options.command;
    check.threads = options.validate_threads;
    check.on_progress = options.on_validate_progress;
    validate_runs(check);
  }
  std::map<std::string, RunValidation> checks;
  for (RunValidation& v : read_validation_csv(dir)) {
    if (v.error.empty()) checks.emplace(v.run, std::move(v));
  }
  for (RunRow& row : rows) {
    const auto found =
        checks.find("runs/" + row.group + "/run-" + std::to_string(row.seed) + ".json");
    if (found == checks.end() || found->second.voxel_err != row.err) continue;
    row.checked = true;
    row.exact_err = found->second.exact_err;
    row.max_overestimate = found->second.max_overestimate;
    row.reached_exact = row.exact_err <= row.target;
  }
  detail::write_study_report(spec, rows, options.command, outcome.interrupted, dir);
  return outcome;
}

}  // namespace camplace::compare
