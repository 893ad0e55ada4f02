// Run files (SPEC §7): writing a run as JSON, reading it back, and the seed of a run file's name.
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
#include "camplace/voxel/evaluator.hpp"
#include "run_json.hpp"

namespace camplace::optimize {
namespace {

// Degrees → radians exactly as core::load_camera_config converts them.
constexpr double kDeg = core::kDegree;
constexpr int kIntMin = std::numeric_limits<int>::min();
constexpr int kIntMax = std::numeric_limits<int>::max();

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
    // Run files written before cameras had a roll have no roll_deg: roll 0.
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
  // What the voxel evaluator accepts (voxel::refine_problem), so that a changed run file is
  // named here rather than refused later by the evaluator under the option's name.
  if (node.has("refine")) {
    c.refine = node.at("refine").integer_in(1, voxel::kMaxRefine);
    if (c.mode != "conservative") {
      node.at("refine").fail("refinement needs mode conservative, the run's mode is \"" + c.mode +
                             "\"");
    }
  }
  c.start = node.at("start").string();
  c.time_limit = node.at("time_limit_s").number();
  c.max_evaluations = read_count(node.at("max_evaluations"));
  return c;
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
  // Formats 1–3 predate the tie-breaker: their runs minimised Err alone.
  run.objective = "err";
  if (root.has("objective")) {
    const core::JsonNode objective = root.at("objective");
    run.objective = objective.string();
    const std::vector<std::string>& names = objective_names();
    if (std::find(names.begin(), names.end(), run.objective) == names.end()) {
      std::string list;
      for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
      objective.fail("unknown objective \"" + run.objective + "\" (expected one of: " + list + ")");
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

}  // namespace camplace::optimize
