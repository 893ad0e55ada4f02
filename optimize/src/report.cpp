#include "camplace/optimize/report.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

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

namespace camplace::optimize {
namespace {

constexpr double kRadToDeg = 1.0 / core::kDegree;
// Degrees → radians exactly as core::load_camera_config converts them.
constexpr double kDeg = core::kDegree;
constexpr int kIntMin = std::numeric_limits<int>::min();
constexpr int kIntMax = std::numeric_limits<int>::max();

nlohmann::ordered_json cameras_json(const core::CameraConfig& config,
                                    const std::vector<std::string>& models) {
  // The same text `camplace evaluate --cameras` reads (core::load_camera_config), keys in
  // alphabetical order ("model" first when the models are named).
  nlohmann::json cameras = nlohmann::json::parse(core::camera_config_json(config)).at("cameras");
  if (models.size() == config.size()) {
    for (std::size_t i = 0; i < config.size(); ++i) cameras[i]["model"] = models[i];
  }
  return nlohmann::ordered_json::parse(cameras.dump());
}

nlohmann::ordered_json context_json(const RunContext& context) {
  nlohmann::ordered_json j = {
      {"scene", context.scene_file}, {"mode", context.mode}, {"resolution", context.resolution}};
  if (context.refine > 0) j["refine"] = context.refine;
  j["start"] = context.start;
  j["time_limit_s"] = context.time_limit;
  j["max_evaluations"] = context.max_evaluations;
  return j;
}

// Readers of run files: each value as run_json writes it, else InputError naming the entry.

std::uint64_t read_count(const core::JsonNode& node,
                         std::uint64_t max = std::numeric_limits<std::uint64_t>::max()) {
  if (!node.value().is_number_unsigned()) {
    node.fail(std::string("expected a non-negative integer, found ") + node.value().type_name());
  }
  const auto v = node.value().get<std::uint64_t>();
  if (v > max)
    node.fail("value " + std::to_string(v) + " out of range [0, " + std::to_string(max) + "]");
  return v;
}

bool read_bool(const core::JsonNode& node) {
  if (!node.value().is_boolean()) {
    node.fail(std::string("expected true or false, found ") + node.value().type_name());
  }
  return node.value().get<bool>();
}

StopReason read_stop_reason(const core::JsonNode& node) {
  const std::string text = node.string();
  std::string names;
  for (StopReason r : {StopReason::tolerance, StopReason::time_limit, StopReason::max_evaluations,
                       StopReason::interrupted, StopReason::lower_bound}) {
    if (text == to_string(r)) return r;
    names += (names.empty() ? "" : ", ") + std::string(to_string(r));
  }
  node.fail("unknown stop reason \"" + text + "\" (expected one of: " + names + ")");
}

core::CameraConfig read_cameras(const core::JsonNode& node, std::vector<std::string>& models) {
  core::CameraConfig config;
  models.clear();
  for (std::size_t i = 0; i < node.array_size(); ++i) {
    const core::JsonNode entry = node.at(i);
    // Run files before roll (issue 14) have no roll_deg: roll 0.
    entry.only_keys({"position", "yaw_deg", "pitch_deg", "roll_deg", "model"});
    core::CameraSetting camera;
    camera.position = entry.at("position").vec3();
    camera.yaw = entry.at("yaw_deg").number_in(-180.0, 180.0) * kDeg;
    camera.pitch = entry.at("pitch_deg").number_in(-90.0, 90.0) * kDeg;
    if (entry.has("roll_deg")) camera.roll = entry.at("roll_deg").number_in(-180.0, 180.0) * kDeg;
    if (entry.has("model")) models.push_back(entry.at("model").string());
    config.push_back(camera);
  }
  return config;
}

RunContext read_context(const core::JsonNode& node) {
  node.only_keys(
      {"scene", "mode", "resolution", "refine", "start", "time_limit_s", "max_evaluations"});
  RunContext c;
  c.scene_file = node.at("scene").string();
  c.mode = node.at("mode").string();
  const core::JsonNode resolution = node.at("resolution");
  if (resolution.array_size() != 3) resolution.fail("expected [nx, ny, nz] (3 integers)");
  for (std::size_t k = 0; k < 3; ++k) c.resolution[k] = resolution.at(k).integer_in(0, kIntMax);
  if (node.has("refine")) c.refine = node.at("refine").integer_in(1, kIntMax);
  c.start = node.at("start").string();
  c.time_limit = node.at("time_limit_s").number();
  c.max_evaluations = read_count(node.at("max_evaluations"));
  return c;
}

std::string fixed(double value, int digits) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value;
  return out.str();
}

}  // namespace

std::vector<std::string> camera_models(const core::Scene& scene) {
  std::vector<std::string> out;
  for (const core::CameraModel& m : scene.cameras.models) {
    if (m.name.empty()) return {};
    out.push_back(m.name);
  }
  return out;
}

nlohmann::ordered_json run_json(const RunResult& run, const RunContext& context) {
  nlohmann::ordered_json history = nlohmann::ordered_json::array();
  for (const HistoryPoint& h : run.history) {
    history.push_back({{"evaluations", h.evaluations}, {"seconds", h.seconds}, {"err", h.err}});
  }
  nlohmann::ordered_json j;
  j["format_version"] = kRunFileFormat;
  j["cameras"] = cameras_json(run.best, context.camera_models);
  j["err"] = run.err;
  j["evaluations"] = run.evaluations;
  j["reached_tolerance"] = run.reached_tolerance;
  j["seconds"] = run.seconds;
  j["stop_reason"] = to_string(run.stop_reason);
  j["tolerance"] = run.tolerance;
  j["err_lower_bound"] = run.err_lower_bound;
  j["start_err"] = run.start_err;
  j["search_err"] = run.search_err;
  j["tie_breaker"] = run.tie_breaker;
  j["evaluations_to_best"] = run.evaluations_to_best;
  j["restarts"] = run.restarts;
  j["algorithm"] = run.algorithm;
  j["objective"] = run.objective;
  j["seed"] = run.seed;
  j["threads"] = run.threads;
  j["population"] = run.population;
  j["dimension"] = run.dimension;
  j["context"] = context_json(context);
  if (context.provenance) j["provenance"] = core::provenance_json(*context.provenance);
  j["history"] = history;
  j["time_per_evaluation_ms"] = {{"labelling", run.mean_timing.labelling_ms},
                                 {"clustering", run.mean_timing.clustering_ms},
                                 {"distance", run.mean_timing.distance_ms},
                                 {"total", run.mean_timing.total_ms},
                                 {"wall_clock", run.wall_ms_per_evaluation}};
  j["memory_kb"] = {{"vm_hwm", run.memory.vm_hwm_kb}, {"vm_peak", run.memory.vm_peak_kb}};
  if (run.snapped) {
    const SnappedResult& snap = *run.snapped;
    nlohmann::ordered_json sj;
    sj["position_m"] = snap.grid.position_m;
    sj["angle_deg"] = snap.grid.angle / core::kDegree;
    sj["cameras"] = cameras_json(snap.cameras, context.camera_models);
    sj["err"] = snap.err;
    sj["rounded_err"] = snap.rounded_err;
    sj["evaluations"] = snap.evaluations;
    j["snapped"] = sj;
  }
  return j;
}

RunFile run_from_json(const nlohmann::json& j, const std::string& file) {
  const core::JsonNode root(j, file, "");
  // The version first: a newer format may differ in any other entry.
  if (root.has("format_version")) {
    const core::JsonNode version = root.at("format_version");
    if (!version.value().is_number_integer() || version.value().get<long long>() < 1 ||
        version.value().get<long long>() > kRunFileFormat) {
      version.fail("unknown run file format " + version.value().dump() +
                   " (this camplace reads formats 1 to " + std::to_string(kRunFileFormat) +
                   "; was the file written by a newer camplace?)");
    }
  }
  root.only_keys({"format_version",
                  "cameras",
                  "err",
                  "evaluations",
                  "reached_tolerance",
                  "seconds",
                  "stop_reason",
                  "tolerance",
                  "err_lower_bound",
                  "start_err",
                  "search_err",
                  "evaluations_to_best",
                  "restarts",
                  "algorithm",
                  "seed",
                  "threads",
                  "population",
                  "dimension",
                  "context",
                  "history",
                  "time_per_evaluation_ms",
                  "memory_kb",
                  "provenance",
                  "objective",
                  "tie_breaker",
                  "snapped"});
  RunFile out;
  out.format_version =
      root.has("format_version") ? static_cast<int>(root.at("format_version").number()) : 1;
  RunResult& run = out.run;
  std::vector<std::string> models;
  run.best = read_cameras(root.at("cameras"), models);
  run.err = root.at("err").number();
  run.evaluations = read_count(root.at("evaluations"));
  run.reached_tolerance = read_bool(root.at("reached_tolerance"));
  run.seconds = root.at("seconds").number();
  run.stop_reason = read_stop_reason(root.at("stop_reason"));
  run.tolerance = root.at("tolerance").number();
  run.err_lower_bound = root.at("err_lower_bound").number();
  run.start_err = root.at("start_err").number();
  run.search_err = root.at("search_err").number();
  run.evaluations_to_best = read_count(root.at("evaluations_to_best"));
  run.restarts = read_count(root.at("restarts"));
  run.algorithm = root.at("algorithm").string();
  // Formats 1–3 predate the tie-breaker (issue 14): their runs minimised Err alone.
  run.objective = "err";
  if (root.has("objective")) {
    const core::JsonNode objective = root.at("objective");
    run.objective = objective.string();
    const std::vector<std::string>& names = objective_names();
    if (std::find(names.begin(), names.end(), run.objective) == names.end()) {
      objective.fail("unknown objective \"" + run.objective + "\" (expected err+volume or err)");
    }
  }
  if (root.has("tie_breaker")) run.tie_breaker = root.at("tie_breaker").number_in(0.0, 1.0);
  run.seed =
      static_cast<unsigned>(read_count(root.at("seed"), std::numeric_limits<unsigned>::max()));
  run.threads = root.at("threads").integer_in(kIntMin, kIntMax);
  run.population = root.at("population").integer_in(kIntMin, kIntMax);
  run.dimension = static_cast<std::size_t>(
      read_count(root.at("dimension"), std::numeric_limits<std::size_t>::max()));
  out.context = read_context(root.at("context"));
  if (models.size() == run.best.size()) out.context.camera_models = std::move(models);
  if (root.has("provenance")) {
    out.context.provenance = core::provenance_from_json(root.at("provenance"));
  }
  if (root.has("snapped")) {
    const core::JsonNode sj = root.at("snapped");
    sj.only_keys({"position_m", "angle_deg", "cameras", "err", "rounded_err", "evaluations"});
    SnappedResult snap;
    snap.grid.position_m = sj.at("position_m").number();
    snap.grid.angle = sj.at("angle_deg").number() * core::kDegree;
    std::vector<std::string> snapped_models;
    snap.cameras = read_cameras(sj.at("cameras"), snapped_models);
    snap.err = sj.at("err").number();
    snap.rounded_err = sj.at("rounded_err").number();
    snap.evaluations = read_count(sj.at("evaluations"));
    run.snapped = std::move(snap);
  }
  const core::JsonNode history = root.at("history");
  for (std::size_t i = 0; i < history.array_size(); ++i) {
    const core::JsonNode h = history.at(i);
    h.only_keys({"evaluations", "seconds", "err"});
    run.history.push_back(
        {read_count(h.at("evaluations")), h.at("seconds").number(), h.at("err").number()});
  }
  const core::JsonNode timing = root.at("time_per_evaluation_ms");
  timing.only_keys({"labelling", "clustering", "distance", "total", "wall_clock"});
  run.mean_timing.labelling_ms = timing.at("labelling").number();
  run.mean_timing.clustering_ms = timing.at("clustering").number();
  run.mean_timing.distance_ms = timing.at("distance").number();
  run.mean_timing.total_ms = timing.at("total").number();
  run.wall_ms_per_evaluation = timing.at("wall_clock").number();
  const core::JsonNode memory = root.at("memory_kb");
  memory.only_keys({"vm_hwm", "vm_peak"});
  run.memory.vm_hwm_kb = read_count(memory.at("vm_hwm"));
  run.memory.vm_peak_kb = read_count(memory.at("vm_peak"));
  return out;
}

RunFile read_run_file(const std::string& path) {
  return run_from_json(core::read_json_file(path), path);
}

std::optional<unsigned> run_file_seed(const std::string& file_name) {
  const std::string prefix = "run-", suffix = ".json";
  if (file_name.size() <= prefix.size() + suffix.size() || file_name.rfind(prefix, 0) != 0 ||
      file_name.compare(file_name.size() - suffix.size(), suffix.size(), suffix) != 0) {
    return std::nullopt;
  }
  const std::string digits =
      file_name.substr(prefix.size(), file_name.size() - prefix.size() - suffix.size());
  // As std::to_string writes a seed: decimal digits, no sign, no leading zero.
  if (digits.size() > 10 || digits.find_first_not_of("0123456789") != std::string::npos ||
      (digits.size() > 1 && digits[0] == '0')) {
    return std::nullopt;
  }
  const unsigned long long seed = std::stoull(digits);
  if (seed > std::numeric_limits<unsigned>::max()) return std::nullopt;
  return static_cast<unsigned>(seed);
}

RunSettings recorded_settings(const RunFile& file) {
  RunSettings s;
  s.scene_file = file.context.scene_file;
  if (file.context.provenance) s.scene = file.context.provenance->scene;
  s.mode = file.context.mode;
  s.resolution = file.context.resolution;
  s.refine = file.context.refine;
  s.algorithm = file.run.algorithm;
  s.objective = file.run.objective;
  s.start = file.context.start;
  s.time_limit = file.context.time_limit;
  s.max_evaluations = file.context.max_evaluations;
  s.tolerance = file.run.tolerance;
  s.population = file.run.population;
  s.seed = file.run.seed;
  s.threads = file.run.threads;
  s.format = file.format_version;
  return s;
}

std::vector<std::string> settings_changes(const RunSettings& recorded, const RunSettings& now) {
  std::vector<std::string> out;
  auto compare = [&out](const char* name, const std::string& before, const std::string& after) {
    if (before != after) out.push_back(std::string(name) + ": " + before + " → " + after);
  };
  auto resolution = [](const std::array<int, 3>& n) {
    return std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" + std::to_string(n[2]);
  };
  if (recorded.scene && now.scene) {
    for (std::string& line : core::scene_changes(*recorded.scene, *now.scene, now.scene_file)) {
      out.push_back(std::move(line));
    }
  }
  if (now.ceiling_pitch && recorded.format < 4) {
    out.push_back(
        "cameras.domain \"ceiling\": now pitch −90°…0° (looking down or level); this run "
        "file (format " +
        std::to_string(recorded.format) +
        ", a camplace from before the ceiling preset looked only down) was made when ceiling "
        "cameras could look up");
  }
  compare("mode", recorded.mode, now.mode);
  if (recorded.resolution && now.resolution) {
    compare("resolution", resolution(*recorded.resolution), resolution(*now.resolution));
  }
  compare("refine", std::to_string(recorded.refine), std::to_string(now.refine));
  compare("algorithm", recorded.algorithm, now.algorithm);
  compare("objective", recorded.objective, now.objective);
  compare("start", recorded.start, now.start);
  // Exact comparisons: both sides hold what the run file's JSON round trip keeps exactly.
  if (recorded.time_limit != now.time_limit) {
    out.push_back("time_limit_s: " + core::format_number(recorded.time_limit) + " → " +
                  core::format_number(now.time_limit));
  }
  compare("max_evaluations", std::to_string(recorded.max_evaluations),
          std::to_string(now.max_evaluations));
  if (recorded.tolerance && now.tolerance && *recorded.tolerance != *now.tolerance) {
    out.push_back("tolerance: " + core::format_number(*recorded.tolerance) + " → " +
                  core::format_number(*now.tolerance));
  }
  if (recorded.population && now.population) {
    compare("population", std::to_string(*recorded.population), std::to_string(*now.population));
  }
  if (recorded.seed && now.seed) {
    compare("seed", std::to_string(*recorded.seed), std::to_string(*now.seed));
  }
  if (recorded.threads && now.threads) {
    compare("threads", std::to_string(*recorded.threads), std::to_string(*now.threads));
  }
  return out;
}

namespace {

std::string conflicts_text(const std::vector<SettingsConflict>& conflicts) {
  // Each distinct change once (a study of 1,100 runs with another budget is one line), with the
  // first run file showing it and how many more do; changes shared by the same runs together.
  struct Change {
    std::string text, first_run;
    int runs = 0;
  };
  std::vector<Change> changes;
  for (const SettingsConflict& c : conflicts) {
    for (const std::string& text : c.changes) {
      auto found = std::find_if(changes.begin(), changes.end(),
                                [&](const Change& seen) { return seen.text == text; });
      if (found == changes.end()) {
        changes.push_back({text, c.run_file, 1});
      } else {
        ++found->runs;
      }
    }
  }
  struct Runs {
    std::string first_run;
    int runs = 0;
    std::vector<std::string> changes;
  };
  std::vector<Runs> by_runs;
  for (const Change& change : changes) {
    auto found = std::find_if(by_runs.begin(), by_runs.end(), [&](const Runs& r) {
      return r.first_run == change.first_run && r.runs == change.runs;
    });
    if (found == by_runs.end()) {
      by_runs.push_back({change.first_run, change.runs, {change.text}});
    } else {
      found->changes.push_back(change.text);
    }
  }
  constexpr std::size_t kShown = 20;
  std::string text = "holds runs made with other settings than this command:";
  std::size_t shown = 0;
  for (const Runs& r : by_runs) {
    if (shown >= kShown) break;
    text += "\n  " + r.first_run;
    const int more = r.runs - 1;
    if (more > 0)
      text += " (and " + std::to_string(more) + (more == 1 ? " more run)" : " more runs)");
    text += ":";
    if (r.changes.size() == 1) {
      text += " " + r.changes.front();
      ++shown;
      continue;
    }
    for (const std::string& change : r.changes) {
      if (shown == kShown) break;
      text += "\n    " + change;
      ++shown;
    }
  }
  if (changes.size() > shown) {
    text += "\n  ... and " + std::to_string(changes.size() - shown) + " more differences";
  }
  return text;
}

}  // namespace

SettingsChanged::SettingsChanged(const std::string& dir,
                                 const std::vector<SettingsConflict>& conflicts)
    : core::InputError(dir, "", conflicts_text(conflicts)) {}

void check_resume(const std::string& dir, const RunSettings& now) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  std::error_code ec;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    if (it->is_regular_file() && run_file_seed(it->path().filename().string())) {
      files.push_back(it->path());
    }
  }
  std::sort(files.begin(), files.end());
  std::vector<SettingsConflict> conflicts;
  for (const fs::path& file : files) {
    RunSettings recorded = recorded_settings(read_run_file(file.string()));
    recorded.seed.reset();  // a run of any seed may join the folder
    std::vector<std::string> changes = settings_changes(recorded, now);
    if (!changes.empty()) conflicts.push_back({file.filename().string(), std::move(changes)});
  }
  if (!conflicts.empty()) throw SettingsChanged(dir, conflicts);
}

int discard_runs(const std::string& dir) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  std::error_code ec;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (it->is_regular_file() &&
        (run_file_seed(name) || name == "summary.json" || name == "summary.csv")) {
      files.push_back(it->path());
    }
  }
  int runs = 0;
  for (const fs::path& file : files) {
    std::error_code removed;
    fs::remove(file, removed);
    if (removed) {
      throw std::runtime_error("cannot remove " + file.string() + ": " + removed.message());
    }
    runs += run_file_seed(file.filename().string()).has_value();
  }
  return runs;
}

std::vector<RunResult> runs_in_folder(const std::string& dir, const std::vector<RunResult>& mine) {
  namespace fs = std::filesystem;
  std::map<unsigned, RunResult> by_seed;
  std::error_code ec;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    const std::optional<unsigned> seed = run_file_seed(it->path().filename().string());
    if (!seed || !it->is_regular_file()) continue;
    try {
      by_seed[*seed] = read_run_file(it->path().string()).run;
    } catch (const std::exception&) {
      // Not a run file this version reads (check_resume reported it when the job started).
    }
  }
  for (const RunResult& run : mine) by_seed[run.seed] = run;
  std::vector<RunResult> out;
  for (auto& [seed, run] : by_seed) out.push_back(std::move(run));
  return out;
}

FolderLock::FolderLock(const std::string& dir) {
  // The folder itself is locked (flock works on a directory's descriptor on Linux): no lock
  // file joins the user's files.
  fd_ = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error("cannot open " + dir + ": " + std::strerror(errno));
  while (::flock(fd_, LOCK_EX) != 0) {
    if (errno == EINTR) continue;  // a signal (its flag is seen after the summary is written)
    const int error = errno;
    ::close(fd_);
    throw std::runtime_error("cannot lock " + dir + ": " + std::strerror(error));
  }
}

FolderLock::~FolderLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
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
  // Issue 16: say which time each column is (threads evaluate in parallel, so they differ).
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
