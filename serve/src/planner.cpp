// The state of `camplace serve`: scene, warm evaluator, configuration, undo (planner.hpp).
#include "camplace/serve/planner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <map>
#include <utility>

#include "camplace/compare/evaluation_json.hpp"
#include "camplace/core/closest_points.hpp"
#include "camplace/core/err.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/names.hpp"
#include "camplace/core/provenance.hpp"
#include "camplace/core/scene_writer.hpp"
#include "camplace/optimize/encoding.hpp"
#include "camplace/view/export.hpp"
#include "camplace/view/meshing.hpp"

namespace camplace::serve {

namespace {

using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

json vec_json(const core::Vec3& v) { return {v.x(), v.y(), v.z()}; }

/// A triangle mesh for three.js: flat vertex coordinates rounded to micrometres (plenty for
/// drawing, and short in JSON) and flat triangle indices, camplace's z-up world frame.
json mesh_json(const core::TriangleMesh& mesh) {
  std::vector<double> xyz;
  xyz.reserve(3 * mesh.vertices.size());
  for (const core::Vec3& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) xyz.push_back(std::round(v[k] * 1e6) / 1e6);
  }
  std::vector<int> triangles;
  triangles.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles) triangles.insert(triangles.end(), t.begin(), t.end());
  return {{"vertices", xyz}, {"triangles", triangles}};
}

std::vector<const core::TriangleMesh*> meshes_of(const std::vector<core::SceneObject>& objects) {
  std::vector<const core::TriangleMesh*> out;
  for (const auto& o : objects) out.push_back(&o.mesh);
  return out;
}

/// A configuration as its camera-file text is read back (what `evaluate --cameras` sees).
core::CameraConfig round_trip(const core::Scene& scene, const core::CameraConfig& config) {
  return core::camera_config_from_json(json::parse(core::camera_config_json(config, -1, &scene)),
                                       "camplace serve", &scene);
}

/// The cameras as camera-file entries (the text save() writes).
json cameras_json(const core::Scene& scene, const core::CameraConfig& config) {
  return json::parse(core::camera_config_json(config, -1, &scene))["cameras"];
}

}  // namespace

/// One camera configuration of the session with what it needs: the scene (its camera list
/// changes when cameras are added or removed), the evaluator and the optimizer's encoding. Not in
/// the anonymous namespace: Planner::Impl, which holds it, has external linkage.
struct PlannerSetup {
  std::shared_ptr<const core::Scene> scene;
  std::shared_ptr<const voxel::VoxelEvaluator> evaluator;
  std::shared_ptr<const optimize::Encoding> encoding;
  core::CameraConfig config;
  /// Per camera moved by the repair: why ("" = not moved).
  std::vector<std::string> snapped;
};

struct Planner::Impl {
  mutable std::mutex mutex;
  PlannerOptions options;
  PlannerSetup current;               ///< shown
  PlannerSetup committed;             ///< the last undo step (current after a commit)
  std::vector<PlannerSetup> history;  ///< earlier undo steps, oldest first
  core::CameraConfig saved;           ///< as loaded or last saved
  bool saved_cameras_changed = false;
  int loaded_count = 0;                    ///< the scene file's camera count
  std::vector<std::string> loaded_models;  ///< the scene file's model per camera
  /// One camera model and domain per model name of the scene file (add_camera).
  std::vector<std::pair<core::CameraModel, core::CameraDomain>> templates;
  std::vector<core::ClosestPoints> true_segments;  ///< per state (empty: no segment)
  std::vector<bool> has_true_segment;

  PlannerSetup make_setup(std::shared_ptr<const core::Scene> scene,
                          std::shared_ptr<const voxel::VoxelEvaluator> evaluator,
                          const core::CameraConfig& wanted) const {
    PlannerSetup s;
    s.scene = std::move(scene);
    s.evaluator = evaluator
                      ? std::move(evaluator)
                      : std::make_shared<const voxel::VoxelEvaluator>(*s.scene, options.voxel);
    s.encoding = std::make_shared<const optimize::Encoding>(*s.scene);
    const core::CameraConfig clamped = s.encoding->clamp(wanted);
    s.config = round_trip(*s.scene, clamped);
    // What the repair changed, and why: a position in a keep-out box (after clamping into the
    // domain) or the domain itself. Rounding of the re-read text (< 1e-12) is no snap.
    const core::CameraConfig unrepaired = s.encoding->decode(s.encoding->encode(wanted), false);
    for (std::size_t i = 0; i < wanted.size(); ++i) {
      const double moved = (wanted[i].position - s.config[i].position).norm();
      const double turned =
          std::max({std::abs(std::remainder(wanted[i].yaw - s.config[i].yaw, 2 * core::kPi)),
                    std::abs(wanted[i].pitch - s.config[i].pitch),
                    std::abs(std::remainder(wanted[i].roll - s.config[i].roll, 2 * core::kPi))});
      std::string why;
      if (moved > 1e-6 || turned > 1e-6) {
        why = "kept in its domain";
        for (const core::KeepOut& k : s.scene->cameras.keep_out) {
          if (k.contains(unrepaired[i].position))
            why = "moved out of keep-out box \"" + k.name + "\"";
        }
        if (s.scene->cameras.domains[i].mount) {
          why = "kept on mount \"" + s.scene->cameras.domains[i].mount->name + "\"" +
                (why.rfind("moved", 0) == 0 ? ", " + why : "");
        }
      }
      s.snapped.push_back(why);
    }
    return s;
  }

  void push_undo(PlannerSetup next) {
    // The same configuration again (a camera put back where it was) is no new undo step.
    if (next.scene == committed.scene && same(next.config, committed.config)) {
      current = std::move(next);
      return;
    }
    history.push_back(committed);
    if (history.size() > 200) history.erase(history.begin());
    committed = next;
    current = std::move(next);
  }

  bool cameras_changed(const core::Scene& scene) const {
    if (scene.cameras.count != loaded_count) return true;
    for (int i = 0; i < scene.cameras.count; ++i) {
      if (scene.cameras.models[i].name != loaded_models[i]) return true;
    }
    return false;
  }

  void check_state(int state) const {
    const int count = static_cast<int>(true_segments.size());
    if (state < 0 || state >= count) {
      throw core::InputError("request", "/state",
                             "no state " + std::to_string(state) + ": the scene has states 0.." +
                                 std::to_string(count - 1));
    }
  }

  json view(const PlannerSetup& s, int state, int undo_steps, bool dirty) const {
    const auto start = Clock::now();
    const core::Evaluation e = s.evaluator->evaluate(s.config);
    const double evaluate_ms = ms_since(start);
    const core::Scene& scene = *s.scene;
    const auto all = core::states(scene);
    const core::StateIndex index = all[state];

    const auto model_start = Clock::now();
    const voxel::Grid cells = s.evaluator->leaf_grid();
    const std::vector<std::uint8_t> model = s.evaluator->leaf_model(s.config, state);
    const core::TriangleMesh boundary = view::voxel_boundary_mesh(cells, model);
    const auto critical = meshes_of(scene.time_steps[index.time_step].critical);
    json d_model = nullptr;
    if (!boundary.triangles.empty() && !critical.empty()) {
      const core::ClosestPoints p =
          view::voxel_model_segment(cells, model, critical, s.evaluator->options().mode);
      d_model = {{"from", vec_json(p.a)}, {"to", vec_json(p.b)}};
    }
    json fovs = json::array();
    for (std::size_t c = 0; c < s.config.size(); ++c) {
      fovs.push_back(mesh_json(view::fov_mesh(s.config[c], scene.cameras.models[c], scene.area)));
    }
    const double model_ms = ms_since(model_start);

    const auto diagnostics_start = Clock::now();
    const json diagnostics = compare::voxel_diagnostics(*s.evaluator, s.config, state);
    const double diagnostics_ms = ms_since(diagnostics_start);

    json states = json::array();
    for (const core::StateResult& r : e.states) {
      states.push_back({{"time_step", r.time_step},
                        {"event", r.event},
                        {"weight", r.weight},
                        {"d_true", r.d_true},
                        {"d_model", r.d_model},
                        {"err_term", r.weight * std::pow(r.d_true - r.d_model, 2)},
                        {"model_volume", r.model_volume},
                        {"components", r.components},
                        {"components_removed", r.components_removed}});
    }
    json cameras = cameras_json(scene, s.config);
    for (std::size_t c = 0; c < cameras.size(); ++c) {
      cameras[c]["model"] = scene.cameras.models[c].name;
      cameras[c]["snapped"] = s.snapped[c];
      cameras[c]["has_roll"] = scene.cameras.models[c].has_roll();
    }
    const auto& n = s.evaluator->grid().n;
    return {{"cameras", cameras},
            {"err", e.err},
            {"err_lower_bound", s.evaluator->err_lower_bound()},
            {"tolerance", core::default_tolerance(scene.area, n)},
            {"states", states},
            {"state", state},
            {"model", mesh_json(boundary)},
            {"d_model", d_model},
            {"fovs", fovs},
            {"diagnostics", diagnostics},
            {"undo", undo_steps},
            {"dirty", dirty},
            {"timing_ms",
             {{"evaluate", evaluate_ms},
              {"labelling", e.timing.labelling_ms},
              {"clustering", e.timing.clustering_ms},
              {"distance", e.timing.distance_ms},
              {"model_mesh", model_ms},
              {"diagnostics", diagnostics_ms},
              {"total", ms_since(start)}}}};
  }

  json view_locked(std::unique_lock<std::mutex>& lock, int state) const {
    check_state(state);
    const PlannerSetup s = current;
    const int undo_steps =
        static_cast<int>(history.size()) + (current.config.size() == committed.config.size() &&
                                                    current.scene == committed.scene &&
                                                    same(current.config, committed.config)
                                                ? 0
                                                : 1);
    const bool dirty = !same(s.config, saved) || cameras_changed(*s.scene) != saved_cameras_changed;
    lock.unlock();  // evaluate outside the lock: a slow view never blocks another request
    return view(s, state, undo_steps, dirty);
  }

  static bool same(const core::CameraConfig& a, const core::CameraConfig& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (a[i].position != b[i].position || a[i].yaw != b[i].yaw || a[i].pitch != b[i].pitch ||
          a[i].roll != b[i].roll)
        return false;
    }
    return true;
  }

  /// Writes the camera file (and, with another camera list than the scene file's, the scene)
  /// for `s` as OUT_DIR/<stem>.json.
  json write(const PlannerSetup& s, const std::string& stem) const {
    const core::Scene& scene = *s.scene;
    const bool own_scene = cameras_changed(scene);
    const std::string cameras_path = options.out_dir + "/" + stem + ".json";
    std::string scene_path = options.scene_file;
    if (own_scene) {
      scene_path = options.out_dir + "/" + stem + ".scene.json";
      core::write_scene(scene, scene_path,
                        "camplace serve: " + options.scene_file + " with " +
                            std::to_string(scene.cameras.count) + " cameras");
    }
    const core::Evaluation e = s.evaluator->evaluate(s.config);
    const auto& n = s.evaluator->grid().n;
    const std::string mode = core::name_of(s.evaluator->options().mode);
    const std::string resolution =
        std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" + std::to_string(n[2]);
    std::string command = "camplace evaluate " + scene_path + " --cameras " + cameras_path +
                          " --mode " + mode + " --resolution " + resolution;
    if (s.evaluator->options().refine > 0) {
      command += " --refine " + std::to_string(s.evaluator->options().refine);
    }
    nlohmann::ordered_json doc;
    doc["cameras"] = cameras_json(scene, s.config);
    doc["err"] = e.err;
    doc["mode"] = mode;
    doc["resolution"] = {n[0], n[1], n[2]};
    if (s.evaluator->options().refine > 0) doc["refine"] = s.evaluator->options().refine;
    doc["scene"] = scene_path;
    doc["evaluate"] = command;
    doc["written_by"] = "camplace serve";
    doc["provenance"] = core::provenance_json(core::make_provenance(scene));
    core::write_file_atomically(cameras_path, doc.dump(1) + "\n");
    return {{"cameras_file", cameras_path},
            {"scene_file", scene_path},
            {"err", e.err},
            {"command", command}};
  }
};

Planner::Planner(core::Scene scene, const core::CameraConfig& start, PlannerOptions options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.options = std::move(options);
  m.loaded_count = scene.cameras.count;
  for (const core::CameraModel& model : scene.cameras.models) {
    m.loaded_models.push_back(model.name);
    const bool known = std::any_of(m.templates.begin(), m.templates.end(),
                                   [&](const auto& t) { return t.first.name == model.name; });
    if (!known) {
      const std::size_t i = m.loaded_models.size() - 1;
      m.templates.emplace_back(model, scene.cameras.domains[i]);
    }
  }
  for (const core::StateIndex& s : core::states(scene)) {
    const auto& step = scene.time_steps[s.time_step];
    const auto critical = meshes_of(step.critical);
    const auto targets = meshes_of(step.events[s.event].targets);
    const bool has = !critical.empty() && !targets.empty();
    m.true_segments.push_back(has ? core::closest_points(critical, targets)
                                  : core::ClosestPoints{});
    m.has_true_segment.push_back(has);
  }
  auto shared = std::make_shared<const core::Scene>(std::move(scene));
  m.current = m.make_setup(shared, nullptr, start);
  m.committed = m.current;
  m.saved = m.options.cameras_file.empty() ? core::CameraConfig{} : m.current.config;
}

Planner::~Planner() = default;

json Planner::scene_json() const {
  std::unique_lock<std::mutex> lock(impl_->mutex);
  const Impl& m = *impl_;
  const core::Scene& scene = *m.current.scene;
  const auto& options = m.current.evaluator->options();
  const auto& n = m.current.evaluator->grid().n;
  // Meshes once each; an object shared by several states (static obstacles) is sent once.
  json meshes = json::array();
  std::map<const core::TriangleMesh*, int> ids;
  auto objects = [&](const std::vector<core::SceneObject>& list, const char* role) {
    json out = json::array();
    for (const core::SceneObject& o : list) {
      auto [it, added] = ids.emplace(&o.mesh, static_cast<int>(meshes.size()));
      if (added) meshes.push_back(mesh_json(o.mesh));
      out.push_back({{"role", role}, {"name", o.name}, {"mesh", it->second}});
    }
    return out;
  };
  json states = json::array();
  const auto all = core::states(scene);
  const json statics = objects(scene.static_obstacles, "static_obstacle");
  for (std::size_t i = 0; i < all.size(); ++i) {
    const auto& step = scene.time_steps[all[i].time_step];
    const auto& event = step.events[all[i].event];
    json list = statics;
    for (const json& o : objects(step.dynamic_obstacles, "dynamic_obstacle")) list.push_back(o);
    for (const json& o : objects(step.critical, "critical_object")) list.push_back(o);
    for (const json& o : objects(event.targets, "target")) list.push_back(o);
    json entry = {{"time_step", all[i].time_step},
                  {"event", all[i].event},
                  {"weight", event.weight},
                  {"objects", list},
                  {"d_true", nullptr}};
    if (m.has_true_segment[i]) {
      entry["d_true"] = {{"from", vec_json(m.true_segments[i].a)},
                         {"to", vec_json(m.true_segments[i].b)},
                         {"length", std::sqrt(m.true_segments[i].sq_distance)}};
    }
    states.push_back(entry);
  }
  json models = json::array();
  for (const auto& [model, domain] : m.templates) {
    json j = {{"name", model.name},
              {"fov", core::name_of(model.fov)},
              {"bounding_half_angle_deg", model.bounding_half_angle() / core::kDegree},
              {"has_roll", model.has_roll()}};
    models.push_back(j);
  }
  json keep_out = json::array();
  for (const core::KeepOut& k : scene.cameras.keep_out) {
    keep_out.push_back(
        {{"name", k.name}, {"min", vec_json(k.box.min)}, {"max", vec_json(k.box.max)}});
  }
  return {{"scene_file", m.options.scene_file},
          {"cameras_file", m.options.cameras_file},
          {"out_dir", m.options.out_dir},
          {"area", {{"min", vec_json(scene.area.min)}, {"max", vec_json(scene.area.max)}}},
          {"mode", core::name_of(options.mode)},
          {"resolution", {n[0], n[1], n[2]}},
          {"refine", options.refine},
          {"meshes", meshes},
          {"states", states},
          {"models", models},
          {"keep_out", keep_out},
          {"role_colors", view::role_colors_json()},
          {"camplace", core::build_info().version}};
}

json Planner::update(const json& request) {
  const core::JsonNode root(request, "request", "");
  if (!request.is_object()) root.fail("expected a JSON object");
  root.only_keys({"cameras", "state", "commit"});
  const int state = root.has("state") ? root.at("state").integer_in(0, 1 << 30) : 0;
  bool commit = true;
  if (root.has("commit")) {
    if (!request["commit"].is_boolean()) root.at("commit").fail("expected true or false");
    commit = request["commit"].get<bool>();
  }
  std::unique_lock<std::mutex> lock(impl_->mutex);
  Impl& m = *impl_;
  m.check_state(state);
  const PlannerSetup base = m.current;
  lock.unlock();
  // Read as a camera file (the same messages), against the current camera list.
  json doc = {{"cameras", root.has("cameras") ? request["cameras"] : json()}};
  if (!root.has("cameras")) root.at("cameras");  // "missing" message
  const core::CameraConfig wanted = core::camera_config_from_json(doc, "request", base.scene.get());
  PlannerSetup next = m.make_setup(base.scene, base.evaluator, wanted);
  lock.lock();
  if (m.current.scene != base.scene) {
    throw core::InputError("request", "/cameras",
                           "the cameras were added or removed meanwhile; reload the page");
  }
  if (commit) {
    m.push_undo(std::move(next));
  } else {
    m.current = std::move(next);
  }
  return m.view_locked(lock, state);
}

json Planner::view(int state) const {
  std::unique_lock<std::mutex> lock(impl_->mutex);
  return impl_->view_locked(lock, state);
}

json Planner::undo(int state) {
  std::unique_lock<std::mutex> lock(impl_->mutex);
  Impl& m = *impl_;
  m.check_state(state);
  if (m.current.scene != m.committed.scene || !Impl::same(m.current.config, m.committed.config)) {
    m.current = m.committed;
  } else if (!m.history.empty()) {
    m.committed = m.history.back();
    m.history.pop_back();
    m.current = m.committed;
  }
  return m.view_locked(lock, state);
}

json Planner::add_camera(const std::string& model, int state) {
  std::unique_lock<std::mutex> lock(impl_->mutex);
  Impl& m = *impl_;
  m.check_state(state);
  const auto t = std::find_if(m.templates.begin(), m.templates.end(),
                              [&](const auto& x) { return x.first.name == model; });
  if (t == m.templates.end()) {
    std::string names;
    for (const auto& x : m.templates)
      names += (names.empty() ? "\"" : ", \"") + x.first.name + "\"";
    throw core::InputError("request", "/model",
                           "no camera model \"" + model + "\" in the scene (it has " + names + ")");
  }
  if (m.current.scene->cameras.count >= 256) {
    throw core::InputError("request", "/model", "the scene has 256 cameras, the most allowed");
  }
  auto scene = std::make_shared<core::Scene>(*m.current.scene);
  scene->cameras.models.push_back(t->first);
  scene->cameras.domains.push_back(t->second);
  ++scene->cameras.count;
  core::CameraConfig wanted = m.current.config;
  wanted.push_back(optimize::corner_start(*scene).back());
  lock.unlock();
  PlannerSetup next = m.make_setup(scene, nullptr, wanted);
  lock.lock();
  m.push_undo(std::move(next));
  return m.view_locked(lock, state);
}

json Planner::remove_camera(int index, int state) {
  std::unique_lock<std::mutex> lock(impl_->mutex);
  Impl& m = *impl_;
  m.check_state(state);
  const int count = m.current.scene->cameras.count;
  if (index < 0 || index >= count) {
    throw core::InputError("request", "/camera",
                           "no camera " + std::to_string(index) +
                               ": the configuration has cameras 0.." + std::to_string(count - 1));
  }
  if (count == 1) {
    throw core::InputError("request", "/camera", "the last camera cannot be removed");
  }
  auto scene = std::make_shared<core::Scene>(*m.current.scene);
  scene->cameras.models.erase(scene->cameras.models.begin() + index);
  scene->cameras.domains.erase(scene->cameras.domains.begin() + index);
  --scene->cameras.count;
  core::CameraConfig wanted = m.current.config;
  wanted.erase(wanted.begin() + index);
  lock.unlock();
  PlannerSetup next = m.make_setup(scene, nullptr, wanted);
  lock.lock();
  m.push_undo(std::move(next));
  return m.view_locked(lock, state);
}

void Planner::commit(const core::CameraConfig& config) {
  std::unique_lock<std::mutex> lock(impl_->mutex);
  Impl& m = *impl_;
  const PlannerSetup base = m.current;
  lock.unlock();
  PlannerSetup next = m.make_setup(base.scene, base.evaluator, config);
  lock.lock();
  if (m.current.scene != base.scene) return;  // cameras added or removed meanwhile
  m.push_undo(std::move(next));
}

json Planner::save(const std::string& name) {
  const bool good_name =
      !name.empty() && name.size() <= 64 && name != "." && name != ".." &&
      std::all_of(name.begin(), name.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
      });
  if (!good_name) {
    throw core::InputError(
        "request", "/name",
        "\"" + name + "\" is not a file name of 1..64 letters, digits, '-', '_' and '.'");
  }
  std::string stem = name;
  if (stem.size() > 5 && stem.compare(stem.size() - 5, 5, ".json") == 0) {
    stem.resize(stem.size() - 5);
  }
  std::unique_lock<std::mutex> lock(impl_->mutex);
  Impl& m = *impl_;
  const PlannerSetup s = m.current;
  lock.unlock();
  const json written = m.write(s, stem);
  lock.lock();
  m.saved = s.config;
  m.saved_cameras_changed = m.cameras_changed(*s.scene);
  return written;
}

std::string Planner::save_unsaved() {
  std::unique_lock<std::mutex> lock(impl_->mutex);
  Impl& m = *impl_;
  const PlannerSetup s = m.current;
  if (Impl::same(s.config, m.saved) && m.cameras_changed(*s.scene) == m.saved_cameras_changed) {
    return "";
  }
  lock.unlock();
  char stamp[32];
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &local);
  return m.write(s, std::string("unsaved-") + stamp)["cameras_file"].get<std::string>();
}

Snapshot Planner::snapshot() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return {impl_->current.scene, impl_->current.config, impl_->options};
}

int Planner::state_count() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return static_cast<int>(impl_->true_segments.size());
}

}  // namespace camplace::serve
