// The Python module's optimize() and algorithms(): one run of `camplace optimize` on a thread
// of its own, with progress callbacks and Ctrl-C, its run file returned as a dict.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include "bindings.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/names.hpp"
#include "camplace/core/provenance.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/core/threads.hpp"
#include "camplace/optimize/optimizer.hpp"
#include "camplace/optimize/report.hpp"
#include "camplace/optimize/voxel_objective.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "json_python.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace camplace::python {

namespace {

/// What the run's thread shares with the calling thread.
struct RunChannel {
  std::mutex mutex;
  std::condition_variable finished_cv;
  bool finished = false;
  bool progressed = false;
  optimize::Progress latest;
  std::exception_ptr error;
};

py::dict optimize_run(const PyScene& scene, const std::string& algorithm,
                      const std::string& objective, unsigned seed, double time_limit,
                      std::uint64_t max_evaluations, const std::string& mode,
                      const py::object& resolution, int refine, std::optional<double> tolerance,
                      const py::object& start, int threads, int population,
                      const py::object& callback, double progress_interval) {
  // The checks of `camplace optimize`'s options, named as the keyword arguments.
  if (!std::isfinite(time_limit) || time_limit < 0.0 || time_limit > 1e7) {
    throw core::OptionError("time_limit", "must be a number of seconds in [0, 1e7] (0 = no limit)");
  }
  if (max_evaluations > 1000000000000ULL) {
    throw core::OptionError("max_evaluations", "must lie in [0, 1e12] (0 = no limit)");
  }
  if (tolerance && !(std::isfinite(*tolerance) && *tolerance >= 0.0)) {
    throw core::OptionError("tolerance", "must be a finite number >= 0 (m²)");
  }
  if (threads < 0 || threads > core::kMaxThreads) {
    throw core::OptionError(
        "threads", "must lie in [0, " + std::to_string(core::kMaxThreads) + "] (0 = all cores)");
  }
  if (population < 0 || population > 100000) {
    throw core::OptionError("population", "must lie in [0, 100000] (0 = the solver's default)");
  }
  if (!(std::isfinite(progress_interval) && progress_interval > 0.0)) {
    throw core::OptionError("progress_interval", "must be a positive number of seconds");
  }
  if (!callback.is_none() && !PyCallable_Check(callback.ptr())) {
    throw py::type_error("callback must be callable(evaluations, best_err, seconds) or None");
  }
  voxel::VoxelOptions voxel_options;
  voxel_options.mode = enum_argument<core::LabelMode>("mode", mode);
  voxel_options.resolution = resolution_argument(resolution);
  voxel_options.refine = refine;

  std::atomic<bool> stop{false};
  optimize::OptimizeOptions options;
  options.algorithm = algorithm;
  options.objective = objective;
  options.seed = seed;
  options.time_limit = time_limit;
  options.max_evaluations = max_evaluations;
  options.tolerance = tolerance;
  options.threads = threads;
  options.population = population;
  options.interrupt = &stop;
  std::string start_name;
  if (py::isinstance<py::str>(start) &&
      (start.cast<std::string>() == "random" || start.cast<std::string>() == "corners")) {
    start_name = start.cast<std::string>();
    options.start.kind =
        start_name == "random" ? optimize::StartKind::random : optimize::StartKind::corners;
  } else if (py::isinstance<py::str>(start) || py::hasattr(start, "__fspath__")) {
    start_name = start.cast<std::filesystem::path>().string();
    options.start = {optimize::StartKind::file, start_name};
  } else {
    throw core::OptionError("start", "expected \"random\", \"corners\" or a camera file's path");
  }

  auto channel = std::make_shared<RunChannel>();
  options.on_progress = [channel](const optimize::Progress& p) {
    const std::lock_guard<std::mutex> lock(channel->mutex);
    channel->latest = p;
    channel->progressed = true;
  };
  std::shared_ptr<const core::Scene> scene_ptr = scene.scene;
  optimize::RunResult result;
  optimize::RunContext context;
  // The run works in its own thread, so that this thread (holding the GIL only while it calls
  // Python) sees Ctrl-C (PyErr_CheckSignals works in the main thread only) and calls the
  // callback at its interval, whichever thread pagmo evaluates in.
  std::thread worker([&, channel] {
    try {
      const optimize::VoxelObjective objective(*scene_ptr, voxel_options);
      context.scene_file = scene_ptr->file;
      context.mode = core::name_of(voxel_options.mode);
      context.resolution = objective.evaluator().grid().n;
      context.refine = refine;
      context.start = start_name;
      context.time_limit = time_limit;
      context.max_evaluations = max_evaluations;
      context.provenance = core::make_provenance(*scene_ptr);
      context.camera_models = optimize::camera_models(*scene_ptr);
      result = optimize::optimize(*scene_ptr, objective, options);
    } catch (...) {
      channel->error = std::current_exception();
    }
    {
      const std::lock_guard<std::mutex> lock(channel->mutex);
      channel->finished = true;
    }
    channel->finished_cv.notify_all();
  });
  // Whatever happens here, the run stops and its thread ends before this function returns.
  struct JoinGuard {
    std::thread& worker;
    std::atomic<bool>& stop;
    ~JoinGuard() {
      if (!worker.joinable()) return;
      stop.store(true);
      py::gil_scoped_release release;
      worker.join();
    }
  } guard{worker, stop};

  using Clock = std::chrono::steady_clock;
  const auto interval =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(progress_interval));
  auto next_call = Clock::now() + interval;
  std::optional<py::error_already_set> raised;
  for (;;) {
    bool finished = false, progressed = false;
    optimize::Progress progress;
    {
      py::gil_scoped_release release;
      std::unique_lock<std::mutex> lock(channel->mutex);
      const auto wake = std::min(next_call, Clock::now() + std::chrono::milliseconds(50));
      channel->finished_cv.wait_until(lock, wake, [&] { return channel->finished; });
      finished = channel->finished;
      progressed = channel->progressed;
      progress = channel->latest;
    }
    if (finished) break;
    if (stop.load()) continue;  // wait for the run to end
    if (PyErr_CheckSignals() != 0) {
      // Ctrl-C (KeyboardInterrupt) stops the run, which returns its best so far; any other
      // exception a signal handler raises stops it too and is raised once the run has ended.
      stop.store(true);
      if (PyErr_ExceptionMatches(PyExc_KeyboardInterrupt)) {
        PyErr_Clear();
      } else {
        raised.emplace();
      }
      continue;
    }
    if (!callback.is_none() && progressed && Clock::now() >= next_call) {
      try {
        const py::object answer =
            callback(progress.evaluations, progress.best_err, progress.seconds);
        if (py::isinstance<py::bool_>(answer) && !answer.cast<bool>()) stop.store(true);
      } catch (py::error_already_set& e) {
        stop.store(true);
        if (e.matches(PyExc_KeyboardInterrupt)) continue;
        raised.emplace(std::move(e));
      }
      next_call = Clock::now() + interval;
    }
  }
  {
    py::gil_scoped_release release;
    worker.join();
  }
  if (raised) throw std::move(*raised);
  if (channel->error) std::rethrow_exception(channel->error);
  return to_python(optimize::run_json(result, context));
}

}  // namespace

void bind_optimize(py::module_& m) {
  m.def("optimize", &optimize_run, "scene"_a, py::kw_only(), "algorithm"_a = "gaco",
        "objective"_a = optimize::kDefaultObjective, "seed"_a = 1u, "time_limit"_a = 300.0,
        "max_evaluations"_a = std::uint64_t{0}, "mode"_a = "conservative",
        "resolution"_a = py::none(), "refine"_a = 0, "tolerance"_a = py::none(),
        "start"_a = "random", "threads"_a = 0, "population"_a = 0, "callback"_a = py::none(),
        "progress_interval"_a = 0.5,
        R"(One optimisation run of `camplace optimize` (SPEC §7) minimising the voxel Err.

algorithm: a solver of algorithms(). objective: 'err' (Err alone), 'err+volume' (Err, its
ties on the plateau broken by the model's volume, the run file's 'tie_breaker') or
'err+touching-volume' (Err plus, for each state whose model touches the critical objects, its
term once more scaled by the fraction of S its model fills), as `--objective`; the reported Err is the true Err either way. seed: seeds the population and the solver.
time_limit: seconds of wall clock, 0 = none. max_evaluations: Err evaluations, 0 = none.
mode, resolution, refine: the voxel pipeline's (refine: as `--refine`). tolerance: stop at Err <= tolerance (m²); None = (½ voxel
diagonal)². start: 'random', 'corners' or a camera file's path. threads: batch evaluation,
0 = all cores. population: 0 = the solver's default.
callback(evaluations, best_err, seconds): called every `progress_interval` seconds while the run
goes on (best_err in m²); returning False stops the run.
Ctrl-C (KeyboardInterrupt) stops the run too. A stopped run returns its best so far, with
'stop_reason' 'interrupted'.

Returns the run file's content (docs/files.md, "run-<seed>.json"): 'cameras' (the best
configuration, a camera list evaluate() takes), 'err' (m²), 'evaluations', 'stop_reason',
'history', ...)");

  m.def(
      "algorithms", [] { return optimize::algorithm_names(); },
      "The solver names optimize() accepts, default first.");
}

}  // namespace camplace::python
