// The exact reference pipeline (SPEC §6). All Nef code of camplace lives in this one translation
// unit (STYLE.md: each Nef TU costs ~35 s and ~1.6 GB to compile); its stages are private headers
// that only this file includes:
//   internal/kernel.hpp    kernel, number type, exact conversions
//   internal/solids.hpp    scene objects in exact coordinates, convex hulls, unions
//   internal/cones.hpp     FOVs, shadow volumes and silhouette cones of one camera
//   internal/outline.hpp   occupied outlines in a camera's image plane (2D, in outline.cpp)
//   internal/pipeline.hpp  the model of each state, with per-camera caches
//   internal/shadow_check.hpp  a test of the shadows' two constructions
//   internal/soup.hpp      Nef → exact triangle soup, OFF export
//   internal/model.hpp     components, exact volumes, plausibility filter, d(C, M)
// Every double input is converted exactly to a rational.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "camplace/core/distance.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/sensor_model.hpp"
#include "camplace/exact/evaluator.hpp"
#include "internal/kernel.hpp"
#include "internal/model.hpp"
#include "internal/pipeline.hpp"
#include "internal/shadow_check.hpp"
#include "internal/soup.hpp"

namespace camplace::exact {

using namespace internal;

ExactModel::ExactModel() : impl_(std::make_shared<Impl>()) {}
ExactModel::ExactModel(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
bool ExactModel::contains(const core::Vec3& p) const { return impl_->contains(to_point(p)); }
bool ExactModel::empty() const {
  return std::none_of(impl_->components.begin(), impl_->components.end(),
                      [](const Impl::Component& c) { return c.kept; });
}
double ExactModel::volume() const { return nearest_double(impl_->kept_volume); }
int ExactModel::components() const {
  return int(std::count_if(impl_->components.begin(), impl_->components.end(),
                           [](const Impl::Component& c) { return c.kept; }));
}
std::vector<ExactComponent> ExactModel::component_info() const {
  std::vector<ExactComponent> out;
  for (const auto& c : impl_->components)
    out.push_back(
        {nearest_double(c.volume_exact), nearest_double(c.z_min), nearest_double(c.z_max), c.kept});
  return out;
}
core::TriangleMesh ExactModel::boundary_mesh() const {
  core::TriangleMesh mesh;
  for (const auto& c : impl_->components) {
    if (!c.kept) continue;
    const int base = int(mesh.vertices.size());
    for (const auto& p : c.points) mesh.vertices.push_back(to_vec3(p));
    for (const auto& t : c.triangles)
      mesh.triangles.push_back({base + int(t[0]), base + int(t[1]), base + int(t[2])});
  }
  return mesh;
}

std::string ExactModel::squared_distance_fraction(const std::vector<core::TriangleMesh>& solids,
                                                  bool filtered) const {
  std::vector<Solid> owned;
  owned.reserve(solids.size());
  for (const auto& mesh : solids) owned.emplace_back(mesh);
  std::vector<const Solid*> critical;
  for (const auto& s : owned) critical.push_back(&s);
  const auto d = filtered ? model_squared_distance(*impl_, critical)
                          : model_squared_distance_by_boxes(*impl_, critical);
  return d ? fraction_string(*d) : std::string();
}

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

void export_fovs(const Pipeline& pipeline, const std::string& dir) {
  for (std::size_t c = 0; c < pipeline.camera_count(); ++c) {
    const TriangleSoup soup = nef_soup(pipeline.fov(c));
    export_soup(dir + "/camera-" + std::to_string(c) + "-pyramid.off", soup.points, soup.triangles);
  }
}

void export_model(const ExactModel::Impl& model, const core::StateIndex& s,
                  const std::string& dir) {
  std::vector<Point> pts;
  std::vector<std::array<std::size_t, 3>> tris;
  for (const auto& c : model.components) {
    if (!c.kept) continue;
    const std::size_t base = pts.size();
    pts.insert(pts.end(), c.points.begin(), c.points.end());
    for (const auto& t : c.triangles) tris.push_back({base + t[0], base + t[1], base + t[2]});
  }
  export_soup(dir + "/state-h" + std::to_string(s.time_step) + "-e" + std::to_string(s.event) +
                  "-model.off",
              pts, tris);
}

/// The outcome of one state, computed by whichever thread evaluated it.
struct StateOutput {
  core::StateResult result;
  std::shared_ptr<ExactModel::Impl> model;
  double labelling_ms = 0.0, clustering_ms = 0.0, distance_ms = 0.0;
};

StateOutput evaluate_state(
    Pipeline& pipeline, const core::Scene& scene, const core::StateIndex& s,
    const ExactOptions& options, const std::function<void()>& camera_done,
    const std::function<void(std::size_t, const std::optional<core::Box3>&)>& before_camera) {
  const std::string& export_dir = options.export_dir;
  StateOutput out;
  auto t0 = Clock::now();
  auto [m, discarded] = pipeline.model(s, camera_done, before_camera);
  out.labelling_ms = ms_since(t0);

  t0 = Clock::now();
  out.model = cluster(std::move(m), scene.plausibility);
  out.clustering_ms = ms_since(t0);

  t0 = Clock::now();
  core::StateResult& r = out.result;
  r.time_step = s.time_step;
  r.event = s.event;
  r.weight = scene.time_steps[s.time_step].events[s.event].weight;
  const auto d_true = core::true_squared_distance(scene, s);
  r.d_true = std::sqrt(d_true.value);
  r.d_true_sq_exact = d_true.fraction;
  const auto d_model =
      options.filtered_distances
          ? model_squared_distance(*out.model, pipeline.critical(s.time_step))
          : model_squared_distance_by_boxes(*out.model, pipeline.critical(s.time_step));
  // SPEC §4: d(C, ∅) is S's diagonal.
  const FT d_model_sq = d_model ? *d_model : core::empty_model_squared_distance<FT>(scene.area);
  r.d_model = std::sqrt(nearest_double(d_model_sq));
  r.d_model_sq_exact = fraction_string(d_model_sq);
  out.distance_ms = ms_since(t0);

  r.model_volume = nearest_double(out.model->kept_volume);
  r.model_volume_exact = fraction_string(out.model->kept_volume);
  r.components_removed = discarded;
  for (const auto& c : out.model->components) (c.kept ? r.components : r.components_removed)++;
  if (!export_dir.empty()) export_model(*out.model, s, export_dir);
  return out;
}

/// The number of worker threads for ExactOptions::threads (0: one per core). CGAL built without
/// thread support keeps shared statics in its lazy numbers, so it gets one thread.
std::size_t thread_count(int requested) {
#ifdef CGAL_HAS_THREADS
  if (requested > 0) return std::size_t(requested);
  return std::max(1u, std::thread::hardware_concurrency());
#else
  (void)requested;
  return 1;
#endif
}

/// The states (indices into `states`) split into tasks for the worker threads: whole time steps,
/// so that a thread reuses its per-step caches, largest first; a time step's events are split
/// only when there are fewer time steps than threads.
std::vector<std::vector<std::size_t>> make_tasks(const std::vector<core::StateIndex>& states,
                                                 int threads) {
  std::vector<std::vector<std::size_t>> steps;
  for (std::size_t i = 0; i < states.size(); ++i) {
    if (i == 0 || states[i].time_step != states[i - 1].time_step) steps.emplace_back();
    steps.back().push_back(i);
  }
  const std::size_t workers = thread_count(threads);
  const std::size_t chunks = steps.empty() ? 1 : (workers + steps.size() - 1) / steps.size();
  std::vector<std::vector<std::size_t>> tasks;
  for (const auto& step : steps) {
    const std::size_t n = std::min(chunks, step.size());
    for (std::size_t k = 0; k < n; ++k)
      tasks.emplace_back(step.begin() + k * step.size() / n,
                         step.begin() + (k + 1) * step.size() / n);
  }
  std::stable_sort(tasks.begin(), tasks.end(),
                   [](const auto& a, const auto& b) { return a.size() > b.size(); });
  return tasks;
}

/// The (state, camera) units of one task, whose parts that do not depend on the model
/// (Pipeline::prefill) helper threads build ahead of the task's worker when there are more threads
/// than tasks. Units are claimed in order by whoever comes first: a helper builds its unit in a
/// Pipeline of its own, destroyed before the parts are put on the board, and the worker moves them
/// into its pipeline's caches (Pipeline::adopt) when it comes to that camera; a unit nobody has
/// claimed yet the worker builds itself, as without helpers, and while it waits for a helper it
/// builds later units itself. A part is handed from one thread to another only through the board's
/// mutex, after its builder has finished with it (docs/design/exact-model.md E4).
class PartsBoard {
 public:
  PartsBoard(const core::Scene& scene, const core::CameraConfig& config,
             const ExactOptions& options, std::vector<core::StateIndex> states)
      : scene_(scene),
        config_(config),
        options_(options),
        states_(std::move(states)),
        cameras_(config.size()),
        units_(states_.size() * cameras_) {}

  /// Helper: claims the next unit and builds its parts; false when no unit is left. Waits while
  /// the next unit is more than one state ahead of the worker's: parts wait on the board until
  /// the worker adopts them, so the board holds at most two states' units.
  bool help() {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(
        lock, [&] { return closed_ || next_ >= units_.size() || next_ / cameras_ <= state_ + 1; });
    if (closed_ || next_ >= units_.size()) return false;
    const std::size_t u = next_++;
    units_[u].status = Status::helper;
    const std::size_t k = u / cameras_, c = u % cameras_;
    const std::optional<core::Box3> box = k == state_ ? box_ : std::nullopt;
    lock.unlock();
    try {
      std::optional<Pipeline::CameraParts> parts;
      {
        Pipeline pipeline(scene_, config_, options_);
        pipeline.prefill(c, states_[k], box);
        parts = pipeline.take_parts(c, states_[k]);
      }  // the helper's pipeline ends here: the parts' handles are the only ones left
      lock.lock();
      parts_built_ += parts->count();
      units_[u].parts = std::move(parts);
      parts.reset();  // a Nef copies its handle when moved: drop ours before the worker takes it
      units_[u].status = Status::ready;
    } catch (...) {
      if (!lock.owns_lock()) lock.lock();
      units_[u].status = Status::failed;
      if (!error_) error_ = std::current_exception();
      closed_ = true;
    }
    changed_.notify_all();
    return true;
  }

  /// Worker: before camera c of the task's k-th state, whose free region will be built within
  /// `box` (none: whole). Adopts the unit's parts a helper built (waiting for them, and building
  /// later units itself meanwhile), or claims the unit. Rethrows a helper's error.
  void before_camera(Pipeline& pipeline, std::size_t k, std::size_t c,
                     const std::optional<core::Box3>& box) {
    const std::size_t u = k * cameras_ + c;
    std::unique_lock<std::mutex> lock(mutex_);
    state_ = k;
    box_ = box;
    changed_.notify_all();  // helpers waiting for the worker to move on
    if (next_ <= u) {
      next_ = u + 1;  // the worker builds it in model(), as without helpers
      return;
    }
    while (units_[u].status == Status::helper) {
      if (!closed_ && next_ < units_.size()) {
        const std::size_t v = next_++;
        units_[v].status = Status::worker;
        const std::size_t kv = v / cameras_;
        lock.unlock();
        pipeline.prefill(v % cameras_, states_[kv], kv == k ? box : std::nullopt);
        lock.lock();
        continue;
      }
      changed_.wait(lock);
    }
    if (units_[u].status == Status::failed) std::rethrow_exception(error_);
    if (units_[u].status != Status::ready) return;
    std::optional<Pipeline::CameraParts> parts = std::move(units_[u].parts);
    units_[u].parts.reset();
    units_[u].status = Status::adopted;
    lock.unlock();
    pipeline.adopt(std::move(*parts));
  }

  /// Worker: the task's k-th state is done; its units nobody has claimed are left out (cameras
  /// skipped because the model was already empty).
  void state_done(std::size_t k) {
    const std::lock_guard<std::mutex> lock(mutex_);
    next_ = std::max(next_, (k + 1) * cameras_);
    if (state_ <= k) {
      state_ = k + 1;  // no box known yet for the next state
      box_.reset();
    }
    changed_.notify_all();
  }

  /// No unit is claimed any more (the task is done, or failed).
  void close() {
    const std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
    changed_.notify_all();
  }

  /// The parts helpers built (adopted or not).
  long parts_built() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return parts_built_;
  }

 private:
  enum class Status { open, helper, worker, ready, adopted, failed };
  struct Unit {
    Status status = Status::open;
    std::optional<Pipeline::CameraParts> parts;
  };

  const core::Scene& scene_;
  const core::CameraConfig& config_;
  const ExactOptions& options_;
  const std::vector<core::StateIndex> states_;
  const std::size_t cameras_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<Unit> units_;  ///< unit k · cameras + c: camera c of the k-th state
  std::size_t next_ = 0;     ///< the first unit nobody has claimed
  bool closed_ = false;
  std::size_t state_ = 0;          ///< the state the worker is in,
  std::optional<core::Box3> box_;  ///< and the box of its last camera's free region
  long parts_built_ = 0;
  std::exception_ptr error_;
};

/// The scene's states (core::states) that `wanted` names, in the scene's order; all of them when
/// `wanted` is empty. core::OptionError ("states") for a state the scene does not have.
std::vector<core::StateIndex> chosen_states(const core::Scene& scene,
                                            const std::vector<core::StateIndex>& wanted) {
  const std::vector<core::StateIndex> all = core::states(scene);
  if (wanted.empty()) return all;
  auto same = [](const core::StateIndex& a, const core::StateIndex& b) {
    return a.time_step == b.time_step && a.event == b.event;
  };
  for (const auto& w : wanted)
    if (std::none_of(all.begin(), all.end(), [&](const auto& s) { return same(s, w); }))
      throw core::OptionError("states", "the scene has no state " + std::to_string(w.time_step) +
                                            "," + std::to_string(w.event) + " (time step, event)");
  std::vector<core::StateIndex> out;
  for (const auto& s : all)
    if (std::any_of(wanted.begin(), wanted.end(), [&](const auto& w) { return same(s, w); }))
      out.push_back(s);
  return out;
}

}  // namespace

ExactEvaluation evaluate_exact(const core::Scene& scene, const core::CameraConfig& config,
                               const ExactOptions& options) {
  const auto t_total = Clock::now();
  core::check_configuration(scene, config);
  if (!options.export_dir.empty()) {
    std::filesystem::create_directories(options.export_dir);
    export_fovs(Pipeline(scene, config, options), options.export_dir);
  }
  const std::vector<core::StateIndex> states = chosen_states(scene, options.states);
  const auto tasks = make_tasks(states, options.threads);
  // Progress in (state, camera) steps, reported one call at a time.
  const long total_steps = long(states.size()) * long(config.size());
  long steps_done = 0;
  std::mutex progress_mutex;
  std::function<void()> camera_done;
  if (options.on_progress) {
    options.on_progress(0, total_steps);
    camera_done = [&] {
      const std::lock_guard<std::mutex> lock(progress_mutex);
      options.on_progress(++steps_done, total_steps);
    };
  }
  std::vector<StateOutput> outputs(states.size());
  // Each thread owns its Pipeline: CGAL's lazy exact numbers and Nef polyhedra are never shared
  // between threads; a model built by a worker is handed over when the worker has joined. The
  // threads beyond one per task help the tasks' workers: they build camera parts ahead, each unit
  // in a Pipeline of its own (PartsBoard), so that one state or a few use every thread.
  const std::size_t threads_wanted = thread_count(options.threads);
  const std::size_t workers = std::min(threads_wanted, tasks.size());
  std::size_t helpers = threads_wanted - workers;
  std::vector<std::unique_ptr<PartsBoard>> boards;
  if (helpers > 0) {
    std::size_t units = 0;
    for (const auto& task : tasks) {
      std::vector<core::StateIndex> task_states;
      for (std::size_t i : task) task_states.push_back(states[i]);
      units += task_states.size() * config.size();
      boards.push_back(
          std::make_unique<PartsBoard>(scene, config, options, std::move(task_states)));
    }
    helpers = std::min(helpers, units);
  }
  std::atomic<std::size_t> next_task{0};
  std::mutex error_mutex;
  std::exception_ptr error;
  auto fail = [&] {
    const std::lock_guard<std::mutex> lock(error_mutex);
    if (!error) error = std::current_exception();
    next_task = tasks.size();
    for (auto& board : boards) board->close();
  };
  auto work = [&] {
    try {
      std::optional<Pipeline> pipeline;
      for (std::size_t t = next_task++; t < tasks.size(); t = next_task++) {
        if (!pipeline) pipeline.emplace(scene, config, options);
        PartsBoard* board = boards.empty() ? nullptr : boards[t].get();
        for (std::size_t k = 0; k < tasks[t].size(); ++k) {
          const std::size_t i = tasks[t][k];
          std::function<void(std::size_t, const std::optional<core::Box3>&)> before_camera;
          if (board)
            before_camera = [&, k](std::size_t c, const std::optional<core::Box3>& box) {
              board->before_camera(*pipeline, k, c, box);
            };
          outputs[i] =
              evaluate_state(*pipeline, scene, states[i], options, camera_done, before_camera);
          if (board) board->state_done(k);
          // A model's Nef polyhedron is large and its results are in outputs[i].result: held
          // until the end only when asked for, so the memory does not grow with the states.
          if (!options.keep_models) outputs[i].model.reset();
        }
        if (board) board->close();
      }
    } catch (...) {
      fail();
    }
  };
  auto help = [&](std::size_t first) {
    try {
      // Round the boards, a unit at a time, until no board has one left.
      for (std::size_t b = first;; ++b) {
        bool any = false;
        for (std::size_t j = 0; j < boards.size() && !any; ++j)
          any = boards[(b + j) % boards.size()]->help();
        if (!any) break;
      }
    } catch (...) {
      fail();
    }
  };
  if (workers + helpers <= 1) {
    work();
  } else {
    std::vector<std::thread> threads;
    for (std::size_t w = 0; w < workers; ++w) threads.emplace_back(work);
    for (std::size_t h = 0; h < helpers; ++h) threads.emplace_back(help, h);
    for (auto& thread : threads) thread.join();
  }
  // A helper's error on a unit the worker never came to (a camera skipped once the model was
  // empty) is not one: one thread would not have built that unit.
  if (error) std::rethrow_exception(error);

  ExactEvaluation result;
  for (const auto& board : boards) result.parts_built_ahead += board->parts_built();
  for (auto& out : outputs) {
    result.timing.labelling_ms += out.labelling_ms;
    result.timing.clustering_ms += out.clustering_ms;
    result.timing.distance_ms += out.distance_ms;
    result.states.push_back(std::move(out.result));
    if (options.keep_models) result.models.emplace_back(std::move(out.model));
  }
  result.err = core::error_of(result.states);
  result.timing.total_ms = ms_since(t_total);
  return result;
}

ExactModel build_exact_model(const core::Scene& scene, const core::CameraConfig& config,
                             const core::StateIndex& state, const ExactOptions& options) {
  Pipeline pipeline(scene, config, options);
  return ExactModel(cluster(pipeline.model(state).nef, scene.plausibility));
}

}  // namespace camplace::exact

namespace camplace::exact::internal {

ShadowCheck check_shadow(const core::TriangleMesh& mesh, const core::CameraSetting& setting,
                         const core::CameraModel& model, const core::Box3& box) {
  ShadowCheck out;
  const Solid solid(mesh);
  const ViewPoint cam = view_point(setting, box);
  out.convex = solid.convex;
  if (solid_contains(solid, cam.position)) {
    out.camera_inside = true;
    return out;
  }
  const ImagePlane image = image_plane(setting, model);
  out.front_faces = int(front_faces(cam, solid).size());
  if (!solid.convex) {
    const ShadowPatches split = shadow_patches(image, solid);
    out.patches = int(split.patches.size());
    out.single = int(split.single.size());
  }
  const Nef fov = fov_nef(cam, setting, model) * box_nef(box);
  const Nef fast = (shadow(cam, image, solid, false) * fov).regularization();
  const Nef reference = (shadow(cam, image, solid, true) * fov).regularization();
  out.same = ((fast - reference) + (reference - fast)).regularization().is_empty();
  return out;
}

}  // namespace camplace::exact::internal
