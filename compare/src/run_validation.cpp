// `camplace validate` (SPEC §8): each run file's best configuration evaluated by the
// exact pipeline and by the voxel pipeline with the same (pyramid) FOV; cached per run.
#include "camplace/compare/run_validation.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#include "camplace/core/err.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/names.hpp"
#include "camplace/core/provenance.hpp"
#include "camplace/core/sensor_model.hpp"
#include "camplace/core/table_text.hpp"
#include "camplace/exact/evaluator.hpp"
#include "camplace/optimize/report.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "format.hpp"

namespace camplace::compare {

namespace fs = std::filesystem;
using detail::num;
using detail::resolution_text;

namespace {

/// Bump when the cached numbers change meaning (a cache entry of another version is ignored).
constexpr int kCacheFormat = 3;  // 2: exact doubles correctly rounded from the exact values;
                                 // 3: the recorded voxel Err checked first
constexpr const char* kCacheDir = "validation-cache";

using Clock = std::chrono::steady_clock;

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw core::InputError(path, "", "cannot open the file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Every run-*.json below dir (not in the cache folder), sorted.
std::vector<fs::path> find_run_files(const fs::path& dir) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::end(it);
       it.increment(ec)) {
    if (it->is_directory() && it->path().filename() == kCacheDir) {
      it.disable_recursion_pending();
      continue;
    }
    const std::string name = it->path().filename().string();
    if (it->is_regular_file() && name.rfind("run-", 0) == 0 && it->path().extension() == ".json") {
      out.push_back(it->path());
    }
  }
  if (ec) throw core::InputError(dir.string(), "", "cannot list the folder: " + ec.message());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

// Named rather than anonymous: RunChecker::Impl holds a SceneCache, and a class with linkage
// must not have a member of a type in an anonymous namespace.
namespace detail {

/// A scene with what the checks need, loaded once and shared by the threads (read-only).
struct LoadedScene {
  core::Scene scene;
  core::Scene pyramid_scene;  ///< the same with the exact pipeline's FOV (SPEC §1)
  core::SceneHashes hashes;   ///< of the scene and its mesh files, as they are now
};

class SceneCache {
 public:
  /// The scene at `path`; throws what core::load_scene throws.
  std::shared_ptr<const LoadedScene> get(const std::string& path) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto found = scenes_.find(path);
    if (found != scenes_.end()) return found->second;
    auto loaded = std::make_shared<LoadedScene>();
    loaded->scene = core::load_scene(path);
    loaded->pyramid_scene = loaded->scene;
    core::use_exact_models(loaded->pyramid_scene.cameras);
    loaded->hashes = core::hash_scene(loaded->scene);
    scenes_.emplace(path, loaded);
    return loaded;
  }

  /// Every scene loaded so far, in path order, for the report's header.
  std::vector<detail::HeaderScene> loaded() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<detail::HeaderScene> out;
    for (const auto& [path, scene] : scenes_) out.push_back({"scene", path, scene->hashes});
    return out;
  }

  /// The voxel evaluator for (scene, mode, resolution, refinement) with the pyramid FOV.
  /// With `own_fov`, the scene's own FOV (what the run was optimised with).
  std::shared_ptr<const voxel::VoxelEvaluator> evaluator(const std::string& path,
                                                         const LoadedScene& scene,
                                                         const voxel::VoxelOptions& options,
                                                         bool own_fov = false) {
    const std::string key = path + "|" + core::name_of(options.mode) + "|" +
                            resolution_text(options.resolution) + "|" +
                            std::to_string(options.refine) + (own_fov ? "|own" : "|pyramid");
    {
      std::lock_guard<std::mutex> lock(mutex_);
      auto found = evaluators_.find(key);
      if (found != evaluators_.end()) return found->second;
    }
    // Built outside the lock (it takes a while); a second thread may build the same one, and
    // the first stored wins — both are equal.
    auto built = std::make_shared<const voxel::VoxelEvaluator>(
        own_fov ? scene.scene : scene.pyramid_scene, options);
    std::lock_guard<std::mutex> lock(mutex_);
    return evaluators_.emplace(key, built).first->second;
  }

 private:
  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<const LoadedScene>> scenes_;
  std::map<std::string, std::shared_ptr<const voxel::VoxelEvaluator>> evaluators_;
};

}  // namespace detail

using detail::LoadedScene;
using detail::SceneCache;

namespace {

/// The scene path a run recorded, resolved: as recorded (relative to the working directory),
/// or else the study layout's copy DIR/scenes/<file name>.
std::optional<std::string> resolve_scene(const std::string& recorded, const fs::path& dir) {
  if (fs::is_regular_file(recorded)) return recorded;
  const fs::path in_study = dir / "scenes" / fs::path(recorded).filename();
  if (fs::path(recorded).is_relative() && fs::is_regular_file(in_study)) return in_study.string();
  return std::nullopt;
}

nlohmann::ordered_json cache_json(const RunValidation& r) {
  return {{"format", kCacheFormat},
          {"voxel_err_same_fov", r.voxel_err_same_fov},
          {"exact_err", r.exact_err},
          {"max_overestimate", r.max_overestimate},
          {"seconds", r.seconds}};
}

bool read_cache(const fs::path& file, RunValidation& r) {
  std::ifstream in(file);
  if (!in) return false;
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    if (j.at("format").get<int>() != kCacheFormat) return false;
    r.voxel_err_same_fov = j.at("voxel_err_same_fov").get<double>();
    r.exact_err = j.at("exact_err").get<double>();
    r.max_overestimate = j.at("max_overestimate").get<double>();
    r.seconds = j.at("seconds").get<double>();
  } catch (const std::exception&) {
    return false;  // a damaged cache entry is recomputed
  }
  return true;
}

/// How a check evaluates exactly: its threads, its (state, camera) progress, the hook before.
struct ExactCheck {
  int threads = 1;
  std::function<void(long done, long total)> on_progress;
  std::function<void(const core::Scene&, int)> before;
};

/// Checks one run file; fills `row` (its error on failure). With `cache_only`, a run without a
/// cache entry is not checked and false returned.
bool check_run(const fs::path& dir, const fs::path& file, SceneCache& scenes, RunValidation& row,
               bool cache_only = false, const ExactCheck& how = {}) {
  row.run = fs::relative(file, dir).generic_string();
  const auto start = Clock::now();
  try {
    const std::string text = read_text(file.string());
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error&) {
      throw core::InputError(file.string(), "", "not valid JSON (a damaged run file?)");
    }
    const optimize::RunFile run = optimize::run_from_json(j, file.string());
    const optimize::RunContext& context = run.context;
    row.scene = context.scene_file;
    row.mode = context.mode;
    row.resolution = context.resolution;
    row.voxel_err = run.run.err;
    row.tolerance = run.run.tolerance;
    row.err_lower_bound = run.run.err_lower_bound;
    const auto mode = core::from_name<core::LabelMode>(context.mode);
    if (!mode) {
      throw core::InputError(file.string(), "/context/mode",
                             "unknown mode \"" + context.mode + "\"");
    }
    const auto scene_path = resolve_scene(context.scene_file, dir);
    if (!scene_path) {
      throw core::InputError(file.string(), "/context/scene",
                             "the scene file \"" + context.scene_file + "\" does not exist");
    }
    const auto scene = scenes.get(*scene_path);
    if (context.provenance) {
      core::check_same_scene(context.provenance->scene, scene->hashes, *scene_path, file.string());
    }
    check_run_cameras(file.string(), run, scene->scene, *scene_path);
    row.target = core::success_target(*mode == core::LabelMode::conservative, row.tolerance,
                                      row.err_lower_bound);
    const fs::path cache_file = dir / kCacheDir /
                                (core::sha256_hex(text + "\n" + scene->hashes.combined + "\n" +
                                                  std::to_string(kCacheFormat)) +
                                 ".json");
    row.cached = read_cache(cache_file, row);
    if (!row.cached && cache_only) return false;
    if (!row.cached) {
      voxel::VoxelOptions options;
      options.mode = *mode;
      options.resolution = context.resolution;
      options.refine = context.refine;  // the run's model: refined as the run was
      // The recorded Err must be the Err of the recorded cameras (a file changed by hand, or
      // damaged, is not checked against the exact pipeline as if it were a run).
      check_recorded_err(file.string(), run,
                         scenes.evaluator(*scene_path, *scene, options, true)->err(run.run.best));
      const auto evaluator = scenes.evaluator(*scene_path, *scene, options);
      const core::Evaluation voxel = evaluator->evaluate(run.run.best);
      exact::ExactOptions exact_options;
      exact_options.threads = std::max(1, how.threads);
      exact_options.on_progress = how.on_progress;
      if (how.before) how.before(scene->scene, exact_options.threads);
      const exact::ExactEvaluation exact =
          exact::evaluate_exact(scene->scene, run.run.best, exact_options);
      row.voxel_err_same_fov = voxel.err;
      row.exact_err = exact.err;
      row.max_overestimate = -std::numeric_limits<double>::infinity();
      for (std::size_t s = 0; s < voxel.states.size(); ++s) {
        row.max_overestimate =
            std::max(row.max_overestimate, voxel.states[s].d_model - exact.states[s].d_model);
      }
      row.seconds = std::chrono::duration<double>(Clock::now() - start).count();
      core::write_file_atomically(cache_file.string(), cache_json(row).dump(1) + "\n");
    }
    row.reached_voxel = row.voxel_err <= row.target;
    row.reached_exact = row.exact_err <= row.target;
  } catch (const core::InputError& e) {
    row.error = e.what();
  } catch (const std::exception& e) {
    row.error = file.string() + ": " + e.what();
  }
  return !cache_only || row.error.empty();
}

const char* kCsvHeader =
    "run,scene,mode,resolution,voxel_err,voxel_err_same_fov,exact_err,tolerance,reached_voxel,"
    "reached_exact,max_overestimate,seconds,err_lower_bound,target,error";

std::string csv_text(const std::vector<RunValidation>& rows) {
  std::ostringstream out;
  out << kCsvHeader << "\n";
  for (const RunValidation& r : rows) {
    const bool ok = r.error.empty();
    auto number = [&](double v) { return ok ? core::format_number(v) : std::string(); };
    auto flag = [&](bool v) { return ok ? std::string(v ? "true" : "false") : std::string(); };
    out << core::csv_field(r.run) << ',' << core::csv_field(r.scene) << ',' << r.mode << ','
        << (r.resolution[0] > 0 ? resolution_text(r.resolution) : std::string()) << ','
        << number(r.voxel_err) << ',' << number(r.voxel_err_same_fov) << ',' << number(r.exact_err)
        << ',' << number(r.tolerance) << ',' << flag(r.reached_voxel) << ','
        << flag(r.reached_exact) << ',' << number(r.max_overestimate) << ',' << number(r.seconds)
        << ',' << number(r.err_lower_bound) << ',' << number(r.target) << ','
        << core::csv_field(r.error) << "\n";
  }
  return out.str();
}

std::string markdown_text(const ValidateOptions& options, const ValidationOutcome& outcome,
                          const std::vector<detail::HeaderScene>& scenes, int threads,
                          const std::string& started) {
  const auto& rows = outcome.rows;
  int checked = 0, reached_voxel = 0, reached_exact = 0, false_successes = 0, over = 0;
  double worst_over = -std::numeric_limits<double>::infinity();
  for (const RunValidation& r : rows) {
    if (!r.error.empty()) continue;
    ++checked;
    reached_voxel += r.reached_voxel;
    reached_exact += r.reached_exact;
    false_successes += r.reached_voxel && !r.reached_exact;
    over += r.max_overestimate > 0.0;
    worst_over = std::max(worst_over, r.max_overestimate);
  }
  std::ostringstream md;
  md << "# Exact check of the optimizer results in " << options.dir << "\n\n"
     << detail::provenance_header(scenes,
                                  {{"folder", "`" + options.dir + "`"},
                                   {"threads", std::to_string(threads)},
                                   {"run files", std::to_string(rows.size())}},
                                  options.command, started,
                                  scenes.empty() ? "none could be read" : "")
     << "Each run's best configuration evaluated by the exact pipeline (CGAL Nef polyhedra, "
        "inscribed "
     << "pyramid FOV) and by the voxel pipeline at the run's mode and resolution with the same "
        "pyramid FOV (`voxel_err_same_fov`). A run *reached* its target when Err ≤ the tolerance "
        "(center mode) or ≤ max(tolerance, conservative lower bound) (conservative mode, SPEC "
        "§4); the same target judges voxel and exact Err. A *false success* reached it by its "
        "voxel Err but not by its exact Err. `max_overestimate` = max over states of d_voxel − "
        "d_exact (same FOV); > 0 means the voxel result over-estimated a distance.\n\n";
  md << "| runs | checked | failed | from cache | reached (voxel) | reached (exact) | false "
        "successes | runs with max_overestimate > 0 | largest overestimate [m] |\n"
     << "|---|---|---|---|---|---|---|---|---|\n"
     << "| " << rows.size() << " | " << checked << " | " << outcome.failed << " | "
     << outcome.from_cache << " | " << reached_voxel << " | " << reached_exact << " | "
     << false_successes << " | " << over << " | "
     << (checked > 0 ? num(worst_over, 4) : std::string("–")) << " |\n\n";
  if (outcome.interrupted) {
    md << "**Interrupted**: the runs not listed were not checked; rerun the command to "
          "resume.\n\n";
  }
  if (outcome.failed > 0) {
    md << "## Runs that could not be checked\n\n";
    for (const RunValidation& r : rows) {
      if (!r.error.empty()) md << "- " << core::md_cell("`" + r.run + "`: " + r.error) << "\n";
    }
    md << "\n";
  }
  md << "## Runs\n\n| run | mode | resolution | voxel Err [m²] | voxel Err, pyramid FOV [m²] | "
        "exact Err [m²] | target [m²] | reached voxel / exact | max overestimate [m] |\n"
     << "|---|---|---|---|---|---|---|---|---|\n";
  for (const RunValidation& r : rows) {
    if (!r.error.empty()) continue;
    md << "| " << core::md_cell(r.run) << " | " << r.mode << " | " << resolution_text(r.resolution)
       << " | " << num(r.voxel_err, 5) << " | " << num(r.voxel_err_same_fov, 5) << " | "
       << num(r.exact_err, 5) << " | " << num(r.target, 5) << " | "
       << (r.reached_voxel ? "yes" : "no") << " / " << (r.reached_exact ? "yes" : "no") << " | "
       << num(r.max_overestimate, 4) << " |\n";
  }
  md << "\nAll values: `validation.csv` (full precision).\n";
  return md.str();
}

}  // namespace

void check_run_cameras(const std::string& file, const optimize::RunFile& run,
                       const core::Scene& scene, const std::string& scene_path) {
  const std::size_t count = static_cast<std::size_t>(scene.cameras.count);
  if (run.run.best.size() != count) {
    throw core::InputError(file, "/cameras",
                           "holds " + std::to_string(run.run.best.size()) + " cameras, the scene " +
                               scene_path + " has " + std::to_string(count) +
                               " (a damaged run file, or one of another scene?)");
  }
  if (run.run.snapped && run.run.snapped->cameras.size() != count) {
    throw core::InputError(file, "/snapped/cameras",
                           "holds " + std::to_string(run.run.snapped->cameras.size()) +
                               " cameras, the scene " + scene_path + " has " +
                               std::to_string(count));
  }
}

void check_recorded_err(const std::string& file, const optimize::RunFile& run, double recomputed) {
  const double recorded = run.run.err;
  if (std::abs(recorded - recomputed) <= 1e-9 * std::max(1.0, std::abs(recomputed))) return;
  throw core::InputError(
      file, "/err",
      "the recorded Err " + core::format_number(recorded) +
          " m² is not the Err of the recorded cameras, " + core::format_number(recomputed) +
          " m² (recomputed in " + run.context.mode + " mode at " +
          resolution_text(run.context.resolution) +
          (run.context.refine > 0 ? ", refine " + std::to_string(run.context.refine) : "") +
          "): the run file was changed after the run");
}

std::vector<std::string> find_validation_runs(const std::string& dir) {
  std::vector<std::string> out;
  for (const fs::path& file : find_run_files(dir)) out.push_back(file.string());
  return out;
}

struct RunChecker::Impl {
  fs::path dir;
  SceneCache scenes;
};

RunChecker::RunChecker(std::string dir) : impl_(std::make_unique<Impl>()) {
  impl_->dir = std::move(dir);
}

RunChecker::~RunChecker() = default;

RunValidation RunChecker::check(const std::string& run_file) {
  RunValidation row;
  check_run(impl_->dir, run_file, impl_->scenes, row);
  return row;
}

ValidationOutcome validate_runs(const ValidateOptions& options) {
  const fs::path dir(options.dir);
  if (!fs::is_directory(dir)) throw core::InputError(options.dir, "", "not a folder");
  const std::vector<fs::path> files = find_run_files(dir);
  if (files.empty()) {
    throw core::InputError(options.dir, "",
                           "holds no run file (run-<seed>.json of camplace optimize or study)");
  }
  // What an earlier validate, killed mid-write, left behind.
  core::remove_stale_temp_files(dir.string());
  core::remove_stale_temp_files((dir / kCacheDir).string());
  const std::string started = core::now_iso8601();
  const int all_threads =
      std::max(1, options.threads > 0 ? options.threads
                                      : static_cast<int>(std::thread::hardware_concurrency()));
  const int threads = std::min<int>(all_threads, static_cast<int>(files.size()));
  std::vector<RunValidation> rows(files.size());
  std::vector<char> done(files.size(), 0);
  SceneCache scenes;
  std::atomic<std::size_t> next{0};
  std::mutex progress_mutex;
  int finished = 0, finished_from_cache = 0;
  // Threads held by the checks under way, and each check's (state, camera) steps (done, total),
  // all under progress_mutex.
  int busy_threads = 0;
  std::map<std::size_t, std::pair<long, long>> exact_steps;
  const auto start = Clock::now();
  auto report = [&] {  // progress_mutex held
    if (!options.on_progress) return;
    ValidationProgress p{finished, static_cast<int>(files.size()), finished_from_cache,
                         std::chrono::duration<double>(Clock::now() - start).count()};
    for (const auto& [run, steps] : exact_steps) {
      p.exact_done += steps.first;
      p.exact_total += steps.second;
    }
    options.on_progress(p);
  };
  auto stop_requested = [&] { return options.interrupt != nullptr && options.interrupt->load(); };
  auto worker = [&] {
    for (;;) {
      if (stop_requested()) return;
      const std::size_t i = next.fetch_add(1);
      if (i >= files.size()) return;
      ExactCheck how;
      {
        // The threads no check holds, shared among the runs not yet started (this one
        // included): one each while there are more runs than threads, all of them for the last.
        const std::lock_guard<std::mutex> lock(progress_mutex);
        const int left = static_cast<int>(files.size() - i);
        how.threads = std::max(1, (all_threads - busy_threads) / left);
        busy_threads += how.threads;
      }
      how.before = options.before_exact;
      if (options.on_progress) {
        how.on_progress = [&, i](long steps_done, long steps_total) {
          const std::lock_guard<std::mutex> lock(progress_mutex);
          exact_steps[i] = {steps_done, steps_total};
          report();
        };
      }
      const bool checked = check_run(dir, files[i], scenes, rows[i], options.cache_only, how);
      const std::lock_guard<std::mutex> lock(progress_mutex);
      busy_threads -= how.threads;
      exact_steps.erase(i);
      if (!checked) continue;
      done[i] = 1;
      ++finished;
      finished_from_cache += rows[i].cached;
      report();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();

  ValidationOutcome outcome;
  outcome.interrupted = finished < static_cast<int>(files.size());
  for (std::size_t i = 0; i < files.size(); ++i) {
    if (!done[i]) continue;
    outcome.from_cache += rows[i].cached;
    outcome.failed += !rows[i].error.empty();
    outcome.rows.push_back(std::move(rows[i]));
  }
  core::write_file_atomically((dir / "validation.csv").string(), csv_text(outcome.rows));
  core::write_file_atomically((dir / "validation.md").string(),
                              markdown_text(options, outcome, scenes.loaded(), threads, started));
  return outcome;
}

int discard_validation(const std::string& dir) {
  std::vector<fs::path> files;
  for (const char* name : {"validation.csv", "validation.md"}) {
    if (fs::is_regular_file(fs::path(dir) / name)) files.push_back(fs::path(dir) / name);
  }
  const fs::path cache = fs::path(dir) / kCacheDir;
  std::error_code ec;
  for (auto it = fs::directory_iterator(cache, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    // Only the entries check_run writes: 64 hex digits + ".json".
    const std::string name = it->path().filename().string();
    if (it->is_regular_file() && name.size() == 64 + 5 &&
        name.find_first_not_of("0123456789abcdef") == 64 && name.substr(64) == ".json") {
      files.push_back(it->path());
    }
  }
  for (const fs::path& file : files) {
    std::error_code removed;
    fs::remove(file, removed);
    if (removed) {
      throw std::runtime_error("cannot remove " + file.string() + ": " + removed.message());
    }
  }
  std::error_code not_empty;
  fs::remove(cache, not_empty);  // only when empty; else it keeps what is not ours
  return static_cast<int>(files.size());
}

std::vector<RunValidation> read_validation_csv(const std::string& dir) {
  const fs::path path = fs::path(dir) / "validation.csv";
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  std::ostringstream text;
  text << in.rdbuf();
  const std::string file = path.string();
  // validate_runs writes this file; one changed by hand (or cut short) is refused by name, as
  // a rerun of `camplace validate` rewrites it from the cache.
  const std::string remedy = " (rerun `camplace validate " + dir + "` to write it anew)";
  std::vector<std::vector<std::string>> records;
  try {
    records = core::csv_records(text.str());
  } catch (const std::invalid_argument& e) {
    throw core::InputError(file, "", std::string(e.what()) + remedy);
  }
  // Another header: a file of another camplace version, whose checks are not read.
  std::string header;
  if (!records.empty()) {
    for (const std::string& f : records[0]) header += (header.empty() ? "" : ",") + f;
  }
  if (header != kCsvHeader) return {};
  std::vector<RunValidation> out;
  for (std::size_t k = 1; k < records.size(); ++k) {
    const std::vector<std::string>& f = records[k];
    const std::string row = "record " + std::to_string(k + 1);
    if (f.size() != 15) {
      throw core::InputError(file, row,
                             std::to_string(f.size()) + " fields instead of 15" + remedy);
    }
    auto number = [&](int column, const char* name) {
      const std::string& v = f[static_cast<std::size_t>(column)];
      std::size_t used = 0;
      double x = 0.0;
      try {
        x = std::stod(v, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (v.empty() || used != v.size()) {
        throw core::InputError(file, row + ", " + name, "not a number: \"" + v + "\"" + remedy);
      }
      return x;
    };
    auto flag = [&](int column, const char* name) {
      const std::string& v = f[static_cast<std::size_t>(column)];
      if (v != "true" && v != "false") {
        throw core::InputError(file, row + ", " + name,
                               "neither true nor false: \"" + v + "\"" + remedy);
      }
      return v == "true";
    };
    RunValidation r;
    r.run = f[0];
    r.scene = f[1];
    r.mode = f[2];
    r.error = f[14];
    if (r.error.empty()) {
      char end = 0;
      if (std::sscanf(f[3].c_str(), "%dx%dx%d%c", &r.resolution[0], &r.resolution[1],
                      &r.resolution[2], &end) != 3) {
        throw core::InputError(file, row + ", resolution",
                               "not NXxNYxNZ: \"" + f[3] + "\"" + remedy);
      }
      r.voxel_err = number(4, "voxel_err");
      r.voxel_err_same_fov = number(5, "voxel_err_same_fov");
      r.exact_err = number(6, "exact_err");
      r.tolerance = number(7, "tolerance");
      r.reached_voxel = flag(8, "reached_voxel");
      r.reached_exact = flag(9, "reached_exact");
      r.max_overestimate = number(10, "max_overestimate");
      r.seconds = number(11, "seconds");
      r.err_lower_bound = number(12, "err_lower_bound");
      r.target = number(13, "target");
    }
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace camplace::compare
