// The JSON object of `camplace evaluate --json` (docs/files.md), for the command-line tool and the
// Python module alike.
#include "camplace/compare/evaluation_json.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>

#include "camplace/core/camera.hpp"
#include "camplace/core/err.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/core/sensor_model.hpp"
#include "camplace/view/voxel_files.hpp"
#include "camplace/voxel/components.hpp"
#include "camplace/voxel/evaluator.hpp"
#ifdef CAMPLACE_HAVE_EXACT
#include "camplace/exact/evaluator.hpp"
#endif

namespace camplace::compare {

namespace {

/// The per-state fields both pipelines report (core::StateResult).
nlohmann::json state_json(const core::StateResult& s) {
  return {{"time_step", s.time_step},   {"event", s.event},
          {"weight", s.weight},         {"d_true", s.d_true},
          {"d_model", s.d_model},       {"model_volume", s.model_volume},
          {"components", s.components}, {"components_removed", s.components_removed}};
}

nlohmann::json voxel_json(const voxel::VoxelEvaluator& evaluator, const voxel::Evaluation& e) {
  const auto& n = evaluator.grid().n;
  nlohmann::json states = nlohmann::json::array();
  for (const auto& s : e.states) states.push_back(state_json(s));
  return {{"pipeline", core::name_of(core::Pipeline::voxel)},
          {"mode", core::name_of(evaluator.options().mode)},
          {"resolution", {n[0], n[1], n[2]}},
          {"refine", evaluator.options().refine},
          {"voxel_diagonal", evaluator.grid().step.norm()},
          {"tolerance", core::default_tolerance(evaluator.scene().area, n)},
          {"err_lower_bound", evaluator.err_lower_bound()},
          {"err", e.err},
          {"states", states},
          {"timing_ms",
           {{"labelling", e.timing.labelling_ms},
            {"clustering", e.timing.clustering_ms},
            {"distance", e.timing.distance_ms},
            {"total", e.timing.total_ms}}}};
}

/// Why the model sits where it does: per state the kept component nearest to the
/// critical objects and how many cameras observe it (label `occupied` on at least one of its
/// voxels: 0 = no camera sees that region, the usual reason for d = 0), per camera the fraction
/// of S's voxel centres inside its FOV and of the targets' voxel centres it labels occupied,
/// and warnings for d(C, M) = 0 in every state and for empty models.
nlohmann::json voxel_diagnostics(const voxel::VoxelEvaluator& evaluator,
                                 const core::CameraConfig& config,
                                 const std::function<void(const std::string&, int, int)>& progress,
                                 int only = -1) {
  const core::Scene& scene = evaluator.scene();
  const voxel::Grid& grid = evaluator.grid();
  const bool boxes = evaluator.options().mode == core::LabelMode::conservative;
  const auto all = core::states(scene);
  std::vector<long> target_voxels(config.size(), 0), target_seen(config.size(), 0);
  long targets_total = 0;
  nlohmann::json states = nlohmann::json::array();
  int zero_distance = 0, empty = 0;
  bool observed_at_zero = false;  // a nearest component at d = 0 that some camera observes
  // One state (`only` ≥ 0): its model alone; else every state's from one labelling.
  const std::vector<std::vector<std::uint8_t>> models =
      only >= 0 ? std::vector<std::vector<std::uint8_t>>{evaluator.model(config, only)}
                : evaluator.models(config);
  for (std::size_t s = 0; s < all.size(); ++s) {
    if (only >= 0 && static_cast<int>(s) != only) continue;
    progress("voxel diagnostics", static_cast<int>(s), static_cast<int>(all.size()));
    const std::vector<std::uint8_t>& model = models[only >= 0 ? 0 : s];
    const std::vector<int> component = voxel::component_labels(model, grid);
    std::vector<std::vector<voxel::Label>> labels;
    for (std::size_t c = 0; c < config.size(); ++c) {
      labels.push_back(evaluator.labels(config[c], int(s), int(c)));
    }
    // The targets' voxels (centre inside a target of the state). The winding-number test only
    // inside a target's bounding box (closed: a centre on it is tested): outside it cannot hold.
    const auto& targets = scene.time_steps[all[s].time_step].events[all[s].event].targets;
    std::vector<core::Box3> target_boxes;
    for (const auto& t : targets) target_boxes.push_back(core::bounding_box(t.mesh));
    for (int v = 0; v < grid.count(); ++v) {
      const core::Vec3 c = grid.voxel_center(v);
      bool in_target = false;
      for (std::size_t t = 0; t < targets.size() && !in_target; ++t) {
        const core::Box3& b = target_boxes[t];
        in_target = (c.array() >= b.min.array()).all() && (c.array() <= b.max.array()).all() &&
                    core::inside_mesh(targets[t].mesh, c);
      }
      if (!in_target) continue;
      ++targets_total;
      for (std::size_t c2 = 0; c2 < config.size(); ++c2)
        target_seen[c2] += labels[c2][v] == voxel::Label::occupied;
    }
    // The model voxel nearest to the critical objects (as d(C, M) measures: box or centre),
    // the first by index among equals. A voxel whose box or centre lies farther from every
    // critical object's bounding box than a value already found cannot be it (bound ≤ value):
    // the model voxel with the smallest such bound gives a first value, then only voxels whose
    // bound does not exceed it are measured.
    const auto& critical = scene.time_steps[all[s].time_step].critical;
    std::vector<core::Box3> critical_boxes;
    for (const auto& o : critical) critical_boxes.push_back(core::bounding_box(o.mesh));
    auto bound = [&](int v) {
      const core::Box3 box =
          boxes ? grid.voxel_box(v) : core::Box3{grid.voxel_center(v), grid.voxel_center(v)};
      double b = std::numeric_limits<double>::infinity();
      for (const core::Box3& c : critical_boxes) b = std::min(b, core::box_box_sq_distance(c, box));
      return b;
    };
    auto value = [&](int v) {
      double d = std::numeric_limits<double>::infinity();
      for (const auto& o : critical) {
        d = std::min(d, boxes ? core::box_solid_sq_distance(o.mesh, grid.voxel_box(v))
                              : core::point_solid_sq_distance(o.mesh, grid.voxel_center(v)));
      }
      return d;
    };
    int first = -1;
    double first_bound = 0.0;
    for (int v = 0; v < grid.count(); ++v) {
      if (!model[v]) continue;
      const double b = bound(v);
      if (first < 0 || b < first_bound) first = v, first_bound = b;
    }
    const double cutoff = first < 0 ? 0.0 : value(first);
    int nearest = -1;
    double best = 0.0;
    for (int v = 0; v < grid.count(); ++v) {
      if (!model[v] || bound(v) > cutoff) continue;
      const double d = value(v);
      if (nearest < 0 || d < best) nearest = v, best = d;
    }
    nlohmann::json entry = {{"time_step", all[s].time_step}, {"event", all[s].event}};
    if (nearest < 0) {
      ++empty;
      entry["nearest_component"] = nullptr;
    } else {
      const int id = component[nearest];
      long voxels = 0;
      std::vector<char> observing(config.size(), 0);
      for (int v = 0; v < grid.count(); ++v) {
        if (component[v] != id) continue;
        ++voxels;
        for (std::size_t c2 = 0; c2 < config.size(); ++c2)
          observing[c2] |= labels[c2][v] == voxel::Label::occupied;
      }
      const double distance = std::sqrt(best);
      zero_distance += distance == 0.0;
      observed_at_zero |= distance == 0.0 && std::count(observing.begin(), observing.end(), 1) > 0;
      entry["nearest_component"] = {
          {"index", id},
          {"voxels", voxels},
          {"volume", static_cast<double>(voxels) * grid.voxel_volume()},
          {"distance", distance},
          {"cameras_observing", std::count(observing.begin(), observing.end(), 1)}};
      if (only >= 0) {  // one state (camplace serve): which cameras, too
        nlohmann::json which = nlohmann::json::array();
        for (std::size_t c2 = 0; c2 < config.size(); ++c2) {
          if (observing[c2]) which.push_back(c2);
        }
        entry["nearest_component"]["observed_by"] = which;
      }
    }
    states.push_back(entry);
  }
  progress("voxel diagnostics", static_cast<int>(all.size()), static_cast<int>(all.size()));
  nlohmann::json cameras = nlohmann::json::array();
  for (std::size_t c = 0; c < config.size(); ++c) {
    const core::Fov fov(config[c], scene.cameras.models.at(c));
    long inside = 0;
    for (int v = 0; v < grid.count(); ++v) inside += fov.contains(grid.voxel_center(v));
    cameras.push_back(
        {{"index", c},
         {"model", scene.cameras.models.at(c).name},
         {"fov", core::name_of(scene.cameras.models.at(c).fov)},
         {"roll_deg", config[c].roll / core::kDegree},
         {"fov_fraction", static_cast<double>(inside) / grid.count()},
         {"target_seen_fraction",
          targets_total > 0 ? nlohmann::json(static_cast<double>(target_seen[c]) / targets_total)
                            : nlohmann::json(nullptr)}});
  }
  nlohmann::json warnings = nlohmann::json::array();
  if (only < 0 && !all.empty() && zero_distance == static_cast<int>(all.size())) {
    std::string why =
        "d(C, M) = 0 in every state: the model touches the critical objects everywhere; a "
        "nearest component with cameras_observing 0 lies where no camera sees";
    if (observed_at_zero && scene.dynamic_mode == core::DynamicMode::masked) {
      // The usual cause of an observed component at d = 0 (docs/scene-format.md#plausibility).
      why +=
          "; one that cameras observe is often the hull of a masked dynamic obstacle (the "
          "robot): it is larger than the obstacle and reaches up toward the cameras, and the "
          "plausibility filter keeps it when it is higher than plausibility.min_height or "
          "larger than min_volume: raise them toward the smallest target part";
    }
    warnings.push_back(why);
  }
  if (only < 0 && empty > 0) {
    warnings.push_back("the model is empty in " + std::to_string(empty) + " of " +
                       std::to_string(all.size()) +
                       " states (d(C, M) is then S's diagonal): the filter removed every "
                       "component, or the cameras see all of S free");
  }
  // Every repaired mesh is named where the results are read (docs/scene-format.md#repair).
  for (const std::string& line : core::repair_warnings(scene)) warnings.push_back(line);
  return {{"states", states}, {"cameras", cameras}, {"warnings", warnings}};
}

/// Every number in `j` is finite. nlohmann::json prints NaN and ±inf as null; the scene loader
/// bounds the weights so that Err stays finite (core::kMaxErr), so a non-finite number here is
/// an internal error, reported as such rather than printed. `pointer`: where `j` sits.
void require_finite(const nlohmann::json& j, const std::string& pointer = "") {
  if (j.is_number_float() && !std::isfinite(j.get<double>())) {
    throw std::logic_error("internal error: the result's " + pointer + " is " +
                           std::to_string(j.get<double>()) + ", not a finite number");
  }
  if (j.is_object()) {
    for (const auto& [key, value] : j.items()) require_finite(value, pointer + "/" + key);
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      require_finite(j[i], pointer + "/" + std::to_string(i));
    }
  }
}

#ifdef CAMPLACE_HAVE_EXACT
nlohmann::json exact_json(const exact::ExactEvaluation& e, bool fractions) {
  nlohmann::json states = nlohmann::json::array();
  for (const auto& s : e.states) {
    nlohmann::json j = state_json(s);
    if (fractions) {
      j["d_true_sq_exact"] = s.d_true_sq_exact;
      j["d_model_sq_exact"] = s.d_model_sq_exact;
      j["model_volume_exact"] = s.model_volume_exact;
    }
    states.push_back(j);
  }
  return {{"pipeline", core::name_of(core::Pipeline::exact)},
          {"err", e.err},
          {"states", states},
          {"timing_ms",
           {{"model", e.timing.labelling_ms},
            {"clustering", e.timing.clustering_ms},
            {"distance", e.timing.distance_ms},
            {"total", e.timing.total_ms}}}};
}

nlohmann::json differences(const nlohmann::json& vox, const nlohmann::json& ex) {
  nlohmann::json states = nlohmann::json::array();
  for (std::size_t i = 0; i < vox["states"].size(); ++i) {
    const auto& a = vox["states"][i];
    const auto& b = ex["states"][i];
    states.push_back(
        {{"time_step", a["time_step"]},
         {"event", a["event"]},
         {"d_model_voxel_minus_exact", a["d_model"].get<double>() - b["d_model"].get<double>()},
         {"model_volume_voxel_minus_exact",
          a["model_volume"].get<double>() - b["model_volume"].get<double>()}});
  }
  return {{"err_voxel_minus_exact", vox["err"].get<double>() - ex["err"].get<double>()},
          {"voxel_diagonal", vox["voxel_diagonal"]},
          {"states", states}};
}

/// The exact pipeline's result for `config` ("exact" of the JSON).
nlohmann::json exact_result(const core::Scene& scene, const core::CameraConfig& config,
                            const EvaluationOptions& options) {
  exact::ExactOptions exact_options;
  exact_options.export_dir = options.export_dir;
  exact_options.threads = options.threads;
  if (options.on_progress) {
    exact_options.on_progress = [&options](long done, long total) {
      options.on_progress("exact evaluation", static_cast<int>(done), static_cast<int>(total));
    };
  }
  return exact_json(exact::evaluate_exact(scene, config, exact_options), options.exact_fractions);
}
#else
// A build without exact/ (CAMPLACE_WITH_EXACT=OFF): asking for it is an option error.
[[noreturn]] void built_without_exact() {
  throw core::OptionError("pipeline",
                          "camplace was built without the exact pipeline (reconfigure with "
                          "-DCAMPLACE_WITH_EXACT=ON; it needs CGAL with GMP and MPFR)");
}
nlohmann::json exact_result(const core::Scene&, const core::CameraConfig&,
                            const EvaluationOptions&) {
  built_without_exact();
}
nlohmann::json differences(const nlohmann::json&, const nlohmann::json&) { built_without_exact(); }
#endif

}  // namespace

nlohmann::json voxel_diagnostics(const voxel::VoxelEvaluator& evaluator,
                                 const core::CameraConfig& config, int state) {
  const int states = static_cast<int>(core::states(evaluator.scene()).size());
  if (state >= states) {
    throw core::InputError("diagnostics", "state", "no state " + std::to_string(state));
  }
  return voxel_diagnostics(
      evaluator, config, [](const std::string&, int, int) {}, state);
}

EvaluationJson evaluate_json(const core::Scene& scene, const core::CameraConfig& config,
                             const EvaluationOptions& options) {
  const bool want_voxel = options.pipeline != core::Pipeline::exact;
  const bool want_exact = options.pipeline != core::Pipeline::voxel;
#ifndef CAMPLACE_HAVE_EXACT
  if (want_exact) built_without_exact();
#endif
  EvaluationJson out;
  nlohmann::json vox, ex;
  auto progress = [&options](const std::string& stage, int done, int total) {
    if (options.on_progress) options.on_progress(stage, done, total);
  };
  const int state_count = static_cast<int>(core::states(scene).size());
  if (want_voxel) {
    voxel::VoxelOptions voxel_options;
    voxel_options.mode = options.mode;
    voxel_options.resolution = options.resolution;
    voxel_options.refine = options.refine;
    const unsigned cores = std::thread::hardware_concurrency();
    voxel_options.threads =
        options.threads > 0 ? options.threads : static_cast<int>(std::clamp(cores, 1u, 256u));
    // SPEC §1: when voxel and exact results are compared, the voxel pipeline also uses the
    // inscribed pyramid.
    core::Scene voxel_scene = scene;
    if (want_exact) core::use_exact_models(voxel_scene.cameras);
    const std::array<int, 3> n =
        options.resolution == std::array<int, 3>{0, 0, 0} ? scene.voxels : options.resolution;
    progress("voxel set-up " + std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" +
                 std::to_string(n[2]),
             0, 0);
    const voxel::VoxelEvaluator evaluator(voxel_scene, voxel_options);
    progress("voxel evaluation", 0, state_count);
    const voxel::Evaluation evaluation = evaluator.evaluate(config);
    progress("voxel evaluation", state_count, state_count);
    vox = voxel_json(evaluator, evaluation);
    vox["diagnostics"] = voxel_diagnostics(evaluator, config, progress);
    vox["fov"] = core::name_of(voxel_scene.cameras.models.front().fov);
    if (options.voxel_models) {
      out.grid = evaluator.grid();
      const auto all = core::states(evaluator.scene());
      std::vector<std::vector<std::uint8_t>> models = evaluator.models(config);
      for (std::size_t i = 0; i < all.size(); ++i) {
        out.voxel_models.push_back({all[i].time_step, all[i].event, std::move(models[i])});
      }
    }
  }
  if (want_exact) {
    // Progress in (state, camera) steps, from the exact pipeline's worker threads.
    ex = exact_result(scene, config, options);
  }
  // One shape for every pipeline (docs/files.md): "voxel", "exact" and "differences" always,
  // null where nothing ran; one pipeline's members also at the top level.
  if (want_voxel && want_exact) {
    out.result = {{"pipeline", core::name_of(core::Pipeline::both)}};
  } else {
    out.result = want_voxel ? vox : ex;
  }
  out.result["voxel"] = want_voxel ? vox : nlohmann::json(nullptr);
  out.result["exact"] = want_exact ? ex : nlohmann::json(nullptr);
  out.result["differences"] =
      want_voxel && want_exact ? differences(vox, ex) : nlohmann::json(nullptr);
  out.result["scene"] = scene.file;
  out.result["cameras_file"] = options.cameras_file;
  require_finite(out.result);
  return out;
}

std::string voxel_models_path_problem(const std::string& npy_path) {
  const std::string suffix = ".npy";
  if (npy_path.size() > suffix.size() &&
      npy_path.compare(npy_path.size() - suffix.size(), suffix.size(), suffix) == 0)
    return "";
  return "needs a file name ending in .npy, got \"" + npy_path + "\"";
}

void write_voxel_models(const EvaluationJson& evaluation, const std::string& npy_path) {
  const nlohmann::json& result = evaluation.result.at("pipeline") == "both"
                                     ? evaluation.result.at("voxel")
                                     : evaluation.result;
  std::vector<view::VoxelLayer> layers;
  for (const auto& m : evaluation.voxel_models) layers.push_back({m.time_step, m.event, m.model});
  view::write_voxel_files(
      evaluation.grid, layers, npy_path,
      {{"pipeline", "voxel"}, {"mode", result.at("mode")}, {"fov", result.at("fov")}});
}

}  // namespace camplace::compare
