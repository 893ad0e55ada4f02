// Studies of the paper's examinations (SPEC §8–9): generate each group's scene, run what is
// missing through the launcher, read the run files back and write the report.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include "camplace/compare/run_validation.hpp"
#include "camplace/compare/study.hpp"
#include "camplace/core/err.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/names.hpp"
#include "camplace/core/provenance.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/optimize/report.hpp"
#include "camplace/scenes/generator.hpp"
#include "camplace/voxel/evaluator.hpp"
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

/// The run's figures as its run file records them, and what made it.
void add_result(const optimize::RunFile& file, bool conservative, RunRow& row) {
  const optimize::RunResult& run = file.run;
  if (file.context.provenance) {
    const core::BuildInfo& build = file.context.provenance->build;
    row.made_by = build.version + ", commit " + build.commit;
  }
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
std::optional<optimize::RunFile> existing_run(const std::string& path) {
  if (!fs::exists(path)) return std::nullopt;
  return optimize::read_run_file(path);
}

/// The study's time limit as its runs are given it (and record it).
std::string time_limit_arg(const detail::StudySpec& spec) {
  return detail::num(spec.time_limit, 3);
}

/// The arguments of `camplace optimize` for one run: one seed, the study's budget, the run
/// file and summary in `run_dir`. `--out=` and `--` keep any directory or scene name (one
/// starting with '-', say) a value.
std::vector<std::string> optimize_args(const detail::StudySpec& spec,
                                       const detail::Examination& examination,
                                       const std::string& scene, unsigned seed,
                                       const std::string& run_dir) {
  std::vector<std::string> args = {"--algorithm",  spec.algorithm,
                                   "--seed",       std::to_string(seed),
                                   "--runs",       "1",
                                   "--threads",    std::to_string(spec.threads),
                                   "--time-limit", time_limit_arg(spec),
                                   "--max-evals",  std::to_string(spec.max_evaluations),
                                   "--mode",       core::name_of(spec.mode)};
  const int refine = detail::refine_of(spec, examination);
  if (refine > 0) {
    args.push_back("--refine");
    args.push_back(std::to_string(refine));
  }
  const std::string& objective = detail::objective_of(spec, examination);
  if (objective != optimize::kDefaultObjective) {
    args.push_back("--objective");
    args.push_back(objective);
  }
  for (std::string a : {std::string("--quiet"), "--out=" + run_dir, std::string("--"), scene}) {
    args.push_back(std::move(a));
  }
  return args;
}

/// One group of the study: its generated scene (not yet written) and its folders.
struct Group {
  const detail::Examination* examination = nullptr;
  std::optional<int> param;
  std::string name, scene_path, scene_text, run_dir;
};

/// The study's groups in the order of the study file.
std::vector<Group> study_groups(const detail::StudySpec& spec, const std::string& dir) {
  std::vector<Group> groups;
  for (const detail::Examination& ex : spec.examinations) {
    for (const std::optional<int>& param : ex.params) {
      Group g;
      g.examination = &ex;
      g.param = param;
      g.name = detail::group_name(ex, param);
      g.scene_path = dir + "/scenes/" + g.name + ".json";
      g.scene_text =
          scenes::generate_scene_json(ex.family, param, spec.scene_seed, spec.base.get());
      g.run_dir = dir + "/runs/" + g.name;
      groups.push_back(std::move(g));
    }
  }
  return groups;
}

/// The run files of `dir` by seed (names as camplace writes them), in seed order.
std::map<unsigned, fs::path> run_files_in(const fs::path& dir) {
  std::map<unsigned, fs::path> files;
  std::error_code ec;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    const auto seed = optimize::run_file_seed(it->path().filename().string());
    if (seed && it->is_regular_file()) files.emplace(*seed, it->path());
  }
  return files;
}

/// The folders below DIR/runs (every group a study wrote there, of this study or not).
std::vector<fs::path> run_folders(const std::string& dir) {
  std::vector<fs::path> folders;
  std::error_code ec;
  for (auto it = fs::directory_iterator(dir + "/runs", ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    if (it->is_directory()) folders.push_back(it->path());
  }
  std::sort(folders.begin(), folders.end());
  return folders;
}

/// Refuses to resume a folder holding runs that are not runs of the study as it is now (issue
/// 13): made with other settings or another scene, or of a seed or group the study no longer
/// has. Interrupted runs are run again anyway and do not count. A study that only grows (more
/// runs per group, more groups) keeps its runs. Throws optimize::SettingsChanged, or
/// core::InputError for a run file it cannot read.
void check_resume(const detail::StudySpec& spec, const std::vector<Group>& groups,
                  const std::string& dir) {
  const unsigned last_seed = spec.first_seed + static_cast<unsigned>(spec.runs_per_group) - 1;
  // "is not the study's seed 1", "is outside the study's seeds 1–3".
  const std::string seeds = last_seed == spec.first_seed
                                ? "is not the study's seed " + std::to_string(last_seed)
                                : "is outside the study's seeds " +
                                      std::to_string(spec.first_seed) + "–" +
                                      std::to_string(last_seed);
  std::vector<optimize::SettingsConflict> conflicts;
  auto relative = [&dir](const fs::path& file) {
    return fs::path(file).lexically_relative(dir).generic_string();
  };
  std::set<std::string> names;
  for (const Group& group : groups) {
    names.insert(group.name);
    // What each run of the group is made with (optimize_args): the scene's resolution and the
    // default tolerance and population follow from the scene and the solver.
    optimize::RunSettings now;
    now.scene_file = group.scene_path;
    now.scene = core::combine_scene_hashes(core::sha256_hex(group.scene_text), {});
    now.mode = core::name_of(spec.mode);
    now.refine = detail::refine_of(spec, *group.examination);
    now.objective = detail::objective_of(spec, *group.examination);
    now.algorithm = spec.algorithm;
    now.start = "random";
    now.time_limit = std::stod(time_limit_arg(spec));
    now.max_evaluations = static_cast<std::uint64_t>(spec.max_evaluations);
    now.threads = spec.threads;
    // Run files without provenance (formats 1, 2) were made on the scene the folder holds.
    std::optional<core::SceneHashes> scene_copy;
    if (fs::is_regular_file(group.scene_path)) {
      scene_copy = core::combine_scene_hashes(core::sha256_file(group.scene_path), {});
    }
    bool domains_read = false;
    for (const auto& [seed, file] : run_files_in(group.run_dir)) {
      if (seed < spec.first_seed || seed > last_seed) {
        conflicts.push_back({relative(file),
                             {"seed " + std::to_string(seed) + " " + seeds +
                              " (runs_per_group or first_seed changed)"}});
        continue;
      }
      const optimize::RunFile run = optimize::read_run_file(file.string());
      if (run.run.stop_reason == optimize::StopReason::interrupted) continue;
      optimize::RunSettings recorded = optimize::recorded_settings(run);
      if (!recorded.scene) recorded.scene = scene_copy;
      if (recorded.format < 4 && !domains_read && scene_copy) {
        // The group's camera domains, for run files made before the ceiling preset's pitch
        // changed (the folder's scene is the one its runs were made on; a changed scene is a
        // conflict of its own).
        now.ceiling_pitch = core::has_ceiling_pitch(core::load_scene(group.scene_path).cameras);
        domains_read = true;
      }
      now.seed = seed;
      std::vector<std::string> changes = optimize::settings_changes(recorded, now);
      if (!changes.empty()) conflicts.push_back({relative(file), std::move(changes)});
    }
  }
  for (const fs::path& folder : run_folders(dir)) {
    const std::string name = folder.filename().string();
    if (names.count(name) > 0) continue;
    for (const auto& entry : run_files_in(folder)) {
      conflicts.push_back({relative(entry.second),
                           {"group " + name + " is not in the study (examinations changed)"}});
    }
  }
  if (!conflicts.empty()) throw optimize::SettingsChanged(dir, conflicts);
}

/// Removes what earlier invocations of a study wrote into `dir`: the run folders' files (run
/// files, summaries, the runs' output-<seed>.txt and the last-output.txt of earlier versions) and
/// the folders once empty, the groups' scenes, the report with its plots and the exact checks.
/// Nothing else: files of other names stay. Returns the number of run files removed.
int discard_study(const std::vector<Group>& groups, const std::string& dir) {
  auto remove_file = [](const fs::path& file) {
    std::error_code ec;
    if (!fs::is_regular_file(file)) return;
    fs::remove(file, ec);
    if (ec) throw std::runtime_error("cannot remove " + file.string() + ": " + ec.message());
  };
  std::set<std::string> names;
  for (const Group& group : groups) names.insert(group.name);
  int runs = 0;
  for (const fs::path& folder : run_folders(dir)) {
    names.insert(folder.filename().string());
    runs += optimize::discard_runs(folder.string());
    remove_file(folder / "last-output.txt");
    std::vector<fs::path> outputs;  // output-<seed>.txt, as run_study names them
    std::error_code ec;
    for (auto it = fs::directory_iterator(folder, ec); !ec && it != fs::directory_iterator();
         it.increment(ec)) {
      const std::string name = it->path().filename().string();
      if (name.rfind("output-", 0) == 0 && name.size() > 11 &&
          name.compare(name.size() - 4, 4, ".txt") == 0 &&
          name.find_first_not_of("0123456789", 7) == name.size() - 4) {
        outputs.push_back(it->path());
      }
    }
    for (const fs::path& file : outputs) remove_file(file);
    std::error_code not_empty;
    fs::remove(folder, not_empty);  // only when nothing else is left in it
  }
  std::error_code not_empty;
  fs::remove(dir + "/runs", not_empty);
  for (const std::string& name : names) remove_file(dir + "/scenes/" + name + ".json");
  for (const std::string& name : detail::study_report_files()) remove_file(dir + "/" + name);
  discard_validation(dir);
  return runs;
}

/// One run of the study in the canonical order (groups as in the study file, seeds ascending).
struct PlannedRun {
  int index = 0;  ///< k in the canonical order, from 0
  RunRow row;     ///< the group's scene; the result once the run is finished
  const detail::Examination* examination = nullptr;
  std::string run_dir, run_file, scene_path;
  double cost = 0.0;  ///< PendingRun::cost
  std::optional<optimize::RunFile> before;
};

std::string run_label(const RunRow& row) { return row.group + " seed " + std::to_string(row.seed); }

/// The file that receives a run's standard output: one per run, so runs of one group may go at
/// the same time (MPI, shards).
std::string output_file(const PlannedRun& run) {
  return run.run_dir + "/output-" + std::to_string(run.row.seed) + ".txt";
}

/// Appends the runs without a finished run file to DIR/report.md (study --report-only).
void append_missing_runs(const std::string& dir, const std::vector<std::string>& missing,
                         int total) {
  const std::string report = dir + "/report.md";
  std::ifstream in(report, std::ios::binary);
  std::ostringstream read;
  read << in.rdbuf();
  std::string text = read.str();
  text += "\n## Missing runs\n\n" + std::to_string(missing.size()) + " of the study's " +
          std::to_string(total) +
          " runs have no finished run file yet (written with `--report-only`); the figures above "
          "leave them out. Run the missing shards, or the study, and report again.\n\n";
  for (const std::string& run : missing) text += "- " + run + "\n";
  core::write_file_atomically(report, text);
}

}  // namespace

StudyOutcome run_study(const StudyOptions& options) {
  const bool sharded = options.shard_count > 0;
  if (sharded && (options.shard_index < 1 || options.shard_index > options.shard_count)) {
    throw std::invalid_argument("run_study: shard index outside 1..shard_count");
  }
  if (sharded && (options.restart || options.report_only || options.validate)) {
    throw std::invalid_argument("run_study: a shard neither restarts, validates nor reports");
  }
  const detail::StudySpec spec = detail::parse_study(options.study_file);
  const std::string dir = options.out_dir;
  const std::vector<Group> groups = study_groups(spec, dir);
  StudyOutcome outcome;
  // Before anything in the folder changes: the runs found must be runs of this study (those of
  // other shards included: the same settings, groups and seeds).
  if (options.restart) {
    outcome.runs_discarded = discard_study(groups, dir);
  } else {
    check_resume(spec, groups, dir);
  }
  fs::create_directories(dir + "/scenes");
  core::remove_stale_temp_files(dir + "/scenes");
  const bool conservative = spec.mode == core::LabelMode::conservative;
  const int total_runs = static_cast<int>(groups.size()) * spec.runs_per_group;
  outcome.runs_total = total_runs;
  // Every run of the study (of the shard), finished or not; each group's scene written first
  // (atomically and always with the same content, so shards may write it at the same time).
  std::vector<PlannedRun> runs;
  int k = 0;
  for (const Group& g : groups) {
    // Rewritten only when missing or different: shards started later do not touch it.
    std::ifstream scene_in(g.scene_path, std::ios::binary);
    std::ostringstream scene_there;
    scene_there << scene_in.rdbuf();
    if (!scene_in || scene_there.str() != g.scene_text) {
      core::write_file_atomically(g.scene_path, g.scene_text);
    }
    RunRow shape;
    const core::Scene group_scene = core::load_scene(g.scene_path);
    describe_scene(group_scene, shape);
    // --report-only reports the runs found on disk as they are: each one's recorded Err must be
    // the Err of its recorded cameras (check_recorded_err), one evaluator per group and
    // settings. (A study that runs checks nothing it did not make; validate checks every run.)
    std::map<std::string, std::unique_ptr<voxel::VoxelEvaluator>> evaluators;
    shape.examination = g.examination->name;
    shape.family = g.examination->family;
    shape.group = g.name;
    shape.param = g.param.value_or(0);
    for (int r = 0; r < spec.runs_per_group; ++r, ++k) {
      if (sharded && shard_of(k, options.shard_count) != options.shard_index) continue;
      ++outcome.runs_in_shard;
      PlannedRun run;
      run.index = k;
      run.row = shape;
      run.row.seed = spec.first_seed + r;
      run.examination = g.examination;
      run.run_dir = g.run_dir;
      run.scene_path = g.scene_path;
      run.run_file = g.run_dir + "/run-" + std::to_string(run.row.seed) + ".json";
      run.cost = static_cast<double>(shape.voxels) * shape.cameras * std::max(1, shape.events);
      run.before = existing_run(run.run_file);
      if (options.report_only && run.before &&
          run.before->run.stop_reason != optimize::StopReason::interrupted) {
        const optimize::RunFile& file = *run.before;
        voxel::VoxelOptions voxel_options;
        const auto mode = core::from_name<core::LabelMode>(file.context.mode);
        if (!mode) {
          throw core::InputError(run.run_file, "/context/mode",
                                 "unknown mode \"" + file.context.mode + "\"");
        }
        voxel_options.mode = *mode;
        voxel_options.resolution = file.context.resolution;
        voxel_options.refine = file.context.refine;
        const std::string key = file.context.mode + "|" +
                                detail::resolution_text(file.context.resolution) + "|" +
                                std::to_string(file.context.refine);
        std::unique_ptr<voxel::VoxelEvaluator>& evaluator = evaluators[key];
        if (!evaluator) {
          evaluator = std::make_unique<voxel::VoxelEvaluator>(group_scene, voxel_options);
        }
        check_run_cameras(run.run_file, file, group_scene, g.scene_path);
        check_recorded_err(run.run_file, file, evaluator->err(file.run.best));
      }
      runs.push_back(std::move(run));
    }
  }
  auto finished = [](const std::optional<optimize::RunFile>& r) {
    return r && r->run.stop_reason != optimize::StopReason::interrupted;
  };
  std::vector<PlannedRun*> todo;
  for (PlannedRun& run : runs) {
    if (finished(run.before)) {
      add_result(*run.before, conservative, run.row);
      ++outcome.runs_done_before;
    } else if (options.report_only) {
      outcome.missing.push_back(run_label(run.row));
    } else {
      todo.push_back(&run);
    }
  }
  if (!todo.empty() && !options.launch && !options.dispatch) {
    throw std::invalid_argument("run_study: no launcher for the runs");
  }
  // How a launched run ended: its result, an interrupt, or an error (as std::runtime_error).
  std::vector<const PlannedRun*> done_now;
  auto settle = [&](PlannedRun& run, const LaunchOutcome& launched) {
    // Ctrl-C ends the study after this run; the report covers the runs finished so far.
    if (launched.interrupted) outcome.interrupted = true;
    const std::optional<optimize::RunFile> after = existing_run(run.run_file);
    if (finished(after)) {
      add_result(*after, conservative, run.row);
      ++outcome.runs_done_now;
      done_now.push_back(&run);
      return;
    }
    // An interrupted run writes its best result as "interrupted" and exits normally.
    if (after || launched.interrupted) {
      outcome.interrupted = true;
      return;
    }
    throw std::runtime_error("study: the run of " + run.row.group + " seed " +
                             std::to_string(run.row.seed) + " wrote no run file (" +
                             (launched.failure.empty() ? "exit status 0" : launched.failure) +
                             "; its standard output is in " + output_file(run) + ")");
  };
  auto prepare = [](const PlannedRun& run) {
    fs::create_directories(run.run_dir);
    // An interrupted run's file goes: the file found afterwards is this run's.
    if (run.before) fs::remove(run.run_file);
  };
  if (!options.dispatch) {
    for (PlannedRun* run : todo) {
      if (outcome.interrupted) break;
      std::fprintf(stderr, "study: %s (run %d of %d)\n", run_label(run->row).c_str(),
                   run->index + 1, total_runs);
      prepare(*run);
      settle(*run, options.launch({optimize_args(spec, *run->examination, run->scene_path,
                                                 run->row.seed, run->run_dir),
                                   output_file(*run)}));
    }
  } else if (!todo.empty()) {
    // Longest expected first, so the last runs to finish are short ones; ties in the canonical
    // order.
    std::vector<PlannedRun*> order = todo;
    std::stable_sort(order.begin(), order.end(),
                     [](const PlannedRun* a, const PlannedRun* b) { return a->cost > b->cost; });
    std::vector<PendingRun> pending;
    for (const PlannedRun* run : order) {
      prepare(*run);
      pending.push_back(
          {{optimize_args(spec, *run->examination, run->scene_path, run->row.seed, run->run_dir),
            output_file(*run)},
           run->run_file,
           run_label(run->row),
           run->cost});
    }
    const std::vector<LaunchOutcome> ended = options.dispatch(pending);
    if (ended.size() != order.size()) {
      throw std::logic_error("run_study: the dispatcher returned another number of runs");
    }
    // Every result is read before an error is raised, in the canonical order.
    std::string first_error;
    std::vector<std::pair<PlannedRun*, const LaunchOutcome*>> settled;
    for (std::size_t i = 0; i < order.size(); ++i) settled.emplace_back(order[i], &ended[i]);
    std::sort(settled.begin(), settled.end(),
              [](const auto& a, const auto& b) { return a.first->index < b.first->index; });
    for (auto& [run, launched] : settled) {
      try {
        settle(*run, *launched);
      } catch (const std::runtime_error& e) {
        if (first_error.empty()) first_error = e.what();
      }
    }
    if (!first_error.empty()) throw std::runtime_error(first_error);
  }
  // A shard's runs are done; the report is written once, by `--report-only` (or the study).
  if (sharded) return outcome;

  std::vector<RunRow> rows;
  std::set<const PlannedRun*> now(done_now.begin(), done_now.end());
  for (const PlannedRun& run : runs) {
    if (finished(run.before) || now.count(&run) > 0) rows.push_back(run.row);
  }
  // The exact check of every run: now, with --validate, or from an earlier
  // `camplace validate DIR`. A row counts only when it is of this very run (same voxel Err).
  if (options.validate && !outcome.interrupted && !rows.empty()) {
    ValidateOptions check;
    check.dir = dir;
    check.command = options.command;
    check.threads = options.validate_threads;
    check.on_progress = options.on_validate_progress;
    check.interrupt = options.interrupt;
    if (validate_runs(check).interrupted) outcome.interrupted = true;
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
  if (!outcome.missing.empty()) append_missing_runs(dir, outcome.missing, total_runs);
  return outcome;
}

}  // namespace camplace::compare
