// The page's long work on worker threads: optimise from here, check exactly (jobs.hpp).
#include "jobs.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "camplace/core/error.hpp"
#include "camplace/core/evaluation.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/names.hpp"
#include "camplace/optimize/optimizer.hpp"
#include "camplace/optimize/voxel_objective.hpp"
#include "camplace/voxel/evaluator.hpp"
#ifdef CAMPLACE_SERVE_HAVE_EXACT
#include "camplace/exact/evaluator.hpp"
#endif

namespace camplace::serve::detail {

namespace {

using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

json cameras_json(const core::Scene& scene, const core::CameraConfig& config) {
  return json::parse(core::camera_config_json(config, -1, &scene))["cameras"];
}

/// The optimizer's objective with the best configuration it has seen, for the page to follow.
class TrackingObjective : public optimize::Objective {
 public:
  explicit TrackingObjective(const optimize::VoxelObjective& inner) : inner_(inner) {}
  double evaluate(const core::CameraConfig& config, core::Timing& timing) const override {
    const double err = inner_.evaluate(config, timing);
    note(config, err);
    return err;
  }
  optimize::Score score(const core::CameraConfig& config, core::Timing& timing) const override {
    const optimize::Score s = inner_.score(config, timing);
    note(config, s.err);
    return s;
  }
  double default_tolerance() const override { return inner_.default_tolerance(); }
  double err_lower_bound() const override { return inner_.err_lower_bound(); }
  /// The best configuration so far and its Err (infinite before the first evaluation).
  std::pair<core::CameraConfig, double> best() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return {best_, best_err_};
  }

 private:
  void note(const core::CameraConfig& config, double err) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (err < best_err_) best_err_ = err, best_ = config;
  }
  const optimize::VoxelObjective& inner_;
  mutable std::mutex mutex_;
  mutable core::CameraConfig best_;
  mutable double best_err_ = std::numeric_limits<double>::infinity();
};

}  // namespace

void Job::emit(json event) {
  std::lock_guard<std::mutex> lock(mutex_);
  event["job"] = id_;
  event["seq"] = events_.size();
  if (event.value("type", "") == "done") finished_ = true;
  events_.push_back(std::move(event));
  changed_.notify_all();
}

std::vector<json> Job::events_from(std::size_t from, std::chrono::milliseconds timeout,
                                   bool& finished) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait_for(lock, timeout, [&] { return events_.size() > from || finished_; });
  finished = finished_;
  if (from >= events_.size()) return {};
  return {events_.begin() + static_cast<std::ptrdiff_t>(from), events_.end()};
}

bool Job::finished() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return finished_;
}

Jobs::~Jobs() { stop_all(); }

std::shared_ptr<Job> Jobs::get(int id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = jobs_.find(id);
  if (it == jobs_.end()) {
    throw core::InputError("request", "/job", "no job " + std::to_string(id));
  }
  return it->second;
}

void Jobs::stop_all() {
  std::vector<std::thread> threads;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto& [id, job] : jobs_) job->cancel();
    threads.swap(threads_);
  }
  for (std::thread& t : threads) t.join();
}

std::shared_ptr<Job> Jobs::start(const std::string& kind, std::function<void(Job&)> work) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [id, job] : jobs_) {
    if (job->kind() == kind && !job->finished()) {
      throw core::InputError(
          "request", "",
          kind + " is already running (job " + std::to_string(id) + "); cancel it first");
    }
  }
  auto job = std::make_shared<Job>(next_id_++, kind);
  jobs_[job->id()] = job;
  threads_.emplace_back([job, work = std::move(work)] {
    try {
      work(*job);
    } catch (const std::exception& e) {
      job->emit(
          {{"type", "done"}, {"status", "failed"}, {"error", std::string("error: ") + e.what()}});
    }
  });
  return job;
}

std::shared_ptr<Job> Jobs::start_optimise(const json& request) {
  const core::JsonNode root(request, "request", "");
  if (!request.is_object()) root.fail("expected a JSON object");
  root.only_keys({"algorithm", "time_limit", "max_evaluations", "seed", "threads"});
  optimize::OptimizeOptions options;
  if (root.has("algorithm")) {
    options.algorithm = root.at("algorithm").string();
    const auto& names = optimize::algorithm_names();
    if (std::find(names.begin(), names.end(), options.algorithm) == names.end()) {
      std::string all;
      for (const auto& n : names) all += (all.empty() ? "" : ", ") + n;
      root.at("algorithm")
          .fail("unknown algorithm \"" + options.algorithm + "\" (expected one of " + all + ")");
    }
  }
  options.time_limit = root.has("time_limit") ? root.at("time_limit").number_in(0.1, 86400) : 60.0;
  if (root.has("max_evaluations")) {
    options.max_evaluations =
        static_cast<std::uint64_t>(root.at("max_evaluations").integer_in(1, 1000000000));
  }
  options.seed =
      root.has("seed") ? static_cast<unsigned>(root.at("seed").integer_in(0, 1 << 30)) : 1;
  options.threads = root.has("threads") ? root.at("threads").integer_in(1, core::kMaxThreads) : 0;
  Planner& planner = planner_;
  return start("optimise", [&planner, options](Job& job) mutable {
    const Snapshot snap = planner.snapshot();
    const core::Scene& scene = *snap.scene;
    job.emit({{"type", "progress"}, {"stage", "setting up the optimizer's evaluator"}});
    voxel::VoxelOptions voxel = snap.options.voxel;
    voxel.threads = 1;  // the optimizer evaluates a population in parallel itself
    const optimize::VoxelObjective inner(scene, voxel);
    const TrackingObjective objective(inner);
    // The optimizer starts from a camera file: the current configuration, in a temporary file.
    const std::string start_file =
        (std::filesystem::temp_directory_path() / ("camplace-serve-" + std::to_string(::getpid()) +
                                                   "-start-" + std::to_string(job.id()) + ".json"))
            .string();
    core::write_file_atomically(start_file, core::camera_config_json(snap.config, 2, &scene));
    options.start = {optimize::StartKind::file, start_file};
    options.interrupt = &job.cancel_flag();
    double shown = std::numeric_limits<double>::infinity();
    auto last = Clock::now() - std::chrono::seconds(1);
    options.on_progress = [&](const optimize::Progress& p) {
      const auto now = Clock::now();
      const auto [best, err] = objective.best();
      const bool better = err < shown;
      // At most 5 events a second: a person follows, the optimizer does not wait.
      if (now - last < std::chrono::milliseconds(200)) return;
      last = now;
      job.emit({{"type", "progress"},
                {"stage", "optimising"},
                {"evaluations", p.evaluations},
                {"best_err", p.best_err},
                {"seconds", p.seconds}});
      if (better && !best.empty()) {
        shown = err;
        job.emit({{"type", "best"}, {"err", err}, {"cameras", cameras_json(scene, best)}});
      }
    };
    optimize::RunResult run;
    try {
      run = optimize::optimize(scene, objective, options);
    } catch (...) {
      std::filesystem::remove(start_file);
      throw;
    }
    std::filesystem::remove(start_file);
    // The result becomes the current configuration (an undo step), as the page showed it.
    planner.commit(run.best);
    const bool cancelled = run.stop_reason == optimize::StopReason::interrupted;
    job.emit({{"type", "done"},
              {"status", cancelled ? "cancelled" : "finished"},
              {"stop_reason", optimize::to_string(run.stop_reason)},
              {"err", run.err},
              {"start_err", run.start_err},
              {"evaluations", run.evaluations},
              {"seconds", run.seconds},
              {"algorithm", run.algorithm},
              {"seed", run.seed},
              {"cameras", cameras_json(scene, run.best)}});
  });
}

std::shared_ptr<Job> Jobs::start_exact() {
#ifdef CAMPLACE_SERVE_HAVE_EXACT
  Planner& planner = planner_;
  return start("check exactly", [&planner](Job& job) {
    const Snapshot snap = planner.snapshot();
    const core::Scene& scene = *snap.scene;
    const auto all = core::states(scene);
    // Like with like (SPEC §1, as `evaluate --pipeline both`): the voxel pipeline with the
    // inscribed pyramids the exact pipeline uses.
    core::Scene pyramids = scene;
    core::use_exact_models(pyramids.cameras);
    voxel::VoxelOptions voxel = snap.options.voxel;
    const core::Evaluation shown = voxel::VoxelEvaluator(scene, voxel).evaluate(snap.config);
    const core::Evaluation like = voxel::VoxelEvaluator(pyramids, voxel).evaluate(snap.config);
    std::vector<core::StateResult> exact_states;
    json states = json::array();
    const auto start = Clock::now();
    for (std::size_t i = 0; i < all.size(); ++i) {
      job.emit({{"type", "progress"},
                {"stage", "exact pipeline"},
                {"done", i},
                {"total", all.size()},
                {"seconds", std::chrono::duration<double>(Clock::now() - start).count()}});
      if (job.cancel_flag().load()) {
        job.emit({{"type", "done"}, {"status", "cancelled"}, {"states", states}});
        return;
      }
      // One state at a time (a scene of that time step with that event alone), so that the
      // check can be cancelled between states and reports each as it comes.
      core::Scene one = scene;
      core::TimeStep step = scene.time_steps[all[i].time_step];
      step.events = {scene.time_steps[all[i].time_step].events[all[i].event]};
      one.time_steps = {step};
      exact::ExactOptions options;
      options.threads = 1;
      core::StateResult r = exact::evaluate_exact(one, snap.config, options).states.at(0);
      r.time_step = all[i].time_step;
      r.event = all[i].event;
      exact_states.push_back(r);
      states.push_back({{"time_step", r.time_step},
                        {"event", r.event},
                        {"weight", r.weight},
                        {"d_true", r.d_true},
                        {"d_model_exact", r.d_model},
                        {"d_model_voxel", like.states[i].d_model},
                        {"d_model_voxel_shown", shown.states[i].d_model},
                        {"d_model_voxel_minus_exact", like.states[i].d_model - r.d_model},
                        {"model_volume_exact", r.model_volume},
                        {"model_volume_voxel", like.states[i].model_volume}});
      job.emit({{"type", "state"}, {"state", states.back()}});
    }
    const double exact_err = core::error_of(exact_states);
    job.emit({{"type", "done"},
              {"status", "finished"},
              {"exact_err", exact_err},
              {"voxel_err", like.err},
              {"voxel_err_shown", shown.err},
              {"err_voxel_minus_exact", like.err - exact_err},
              {"fov", core::fov_description(scene.cameras)},
              {"seconds", std::chrono::duration<double>(Clock::now() - start).count()},
              {"states", states}});
  });
#else
  throw core::InputError("request", "",
                         "camplace was built without the exact pipeline (reconfigure with "
                         "-DCAMPLACE_WITH_EXACT=ON)");
#endif
}

}  // namespace camplace::serve::detail
