#include "camplace/optimize/optimizer.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <pagmo/population.hpp>
#include <pagmo/problem.hpp>
#include <sstream>

#include "camplace/core/error.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/optimize/encoding.hpp"
#include "problem.hpp"
#include "snap.hpp"
#include "solvers.hpp"

namespace camplace::optimize {
namespace {

using detail::RunState;
using detail::Solver;
using detail::StopRequested;

/// The configuration as `camplace evaluate --cameras` will read it back from the run file.
/// Angles are stored in degrees, so rad → deg → rad may move them by an ulp; re-reading through
/// the real reader makes the reported Err exactly the one evaluate computes.
core::CameraConfig json_round_trip(const core::CameraConfig& config, const core::Scene& scene) {
  namespace fs = std::filesystem;
  std::string pattern = (fs::temp_directory_path() / "camplace-cameras-XXXXXX.json").string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  const int fd = ::mkstemps(name.data(), 5);
  if (fd < 0) return config;  // no temporary directory: keep the in-memory configuration
  ::close(fd);
  const std::string path(name.data());
  {
    std::ofstream out(path);
    out << core::camera_config_json(config) << '\n';
    out.close();
    if (!out) {
      // A full temporary directory: keep the in-memory configuration, as without one.
      std::error_code ignored;
      fs::remove(path, ignored);
      return config;
    }
  }
  core::CameraConfig reread = core::load_camera_config(path, scene);
  std::error_code ignored;
  fs::remove(path, ignored);
  return reread;
}

}  // namespace

void check_inside_domains(const core::CameraConfig& config, const core::Scene& scene,
                          const std::string& file) {
  constexpr double kSlack = 1e-9;  // rounding of written and re-read run files
  const auto inside = [](const core::Interval& iv, double v) {
    return v >= iv.lo - kSlack && v <= iv.hi + kSlack;
  };
  for (std::size_t i = 0; i < config.size(); ++i) {
    const core::CameraDomain& d = scene.cameras.domains[i];
    const core::CameraSetting& c = config[i];
    const std::string entry = "/cameras/" + std::to_string(i);
    const std::string where = " of camera " + std::to_string(i) + " in " + scene.file;
    for (const core::KeepOut& k : scene.cameras.keep_out) {
      if (k.contains(c.position)) {
        throw core::InputError(file, entry + "/position",
                               "lies in keep-out box \"" + k.name + "\" (" + k.entry + ")" + where);
      }
    }
    if (d.mount) {
      const core::Mount& m = *d.mount;
      const auto [s, t] = m.coordinates(c.position);
      const double off_plane = (m.point(s, t) - c.position).norm();
      const double tolerance = 1e-6;  // metres; run files store positions to ~1e-15 relative
      const double su = tolerance / m.u.norm(), tv = tolerance / m.v.norm();
      if (off_plane > tolerance || s < -su || s > 1.0 + su || t < -tv || t > 1.0 + tv) {
        throw core::InputError(
            file, entry + "/position",
            "lies off mount \"" + m.name + "\"" + where + " (" + core::format_number(off_plane) +
                " m from its plane, s = " + core::format_number(s) +
                ", t = " + core::format_number(t) + "; both must lie in [0, 1])");
      }
      const auto [yaw, pitch] = m.relative_angles(core::view_direction(c));
      const double angle_slack = 1e-7;  // radians; angles are stored in degrees
      const auto near_inside = [&](const core::Interval& iv, double v) {
        return v >= iv.lo - angle_slack && v <= iv.hi + angle_slack;
      };
      if (!near_inside(m.yaw, yaw) || !near_inside(m.pitch, pitch)) {
        throw core::InputError(file, entry,
                               "its viewing direction lies outside the ranges of mount \"" +
                                   m.name + "\"" + where + " (relative yaw " +
                                   core::format_number(yaw / core::kDegree) + "°, pitch " +
                                   core::format_number(pitch / core::kDegree) + "°)");
      }
      if (scene.cameras.models[i].has_roll() && !inside(d.roll, c.roll)) {
        throw core::InputError(file, entry + "/roll_deg",
                               "lies outside the roll range of mount \"" + m.name + "\"" + where);
      }
      continue;
    }
    if (!inside(d.x, c.position.x()) || !inside(d.y, c.position.y()) ||
        !inside(d.z, c.position.z())) {
      throw core::InputError(file, entry + "/position",
                             "lies outside the placement domain" + where);
    }
    if (!inside(d.yaw, c.yaw)) {
      throw core::InputError(file, entry + "/yaw_deg", "lies outside the placement domain" + where);
    }
    if (!inside(d.pitch, c.pitch)) {
      throw core::InputError(file, entry + "/pitch_deg",
                             "lies outside the placement domain" + where);
    }
    if (scene.cameras.models[i].has_roll() && !inside(d.roll, c.roll)) {
      throw core::InputError(file, entry + "/roll_deg",
                             "lies outside the placement domain" + where);
    }
  }
}

namespace {

/// Fills pop with its initial individuals: the start (if any) and random ones, evaluated as a
/// batch when the solver evaluates batches.
void fill_population(pagmo::population& pop, const std::vector<pagmo::vector_double>& xs,
                     bool batch) {
  if (batch) {
    pagmo::vector_double flat;
    for (const auto& x : xs) flat.insert(flat.end(), x.begin(), x.end());
    const pagmo::vector_double f = pop.get_problem().batch_fitness(flat);
    for (std::size_t i = 0; i < xs.size(); ++i) pop.push_back(xs[i], {f[i]});
  } else {
    for (const auto& x : xs) pop.push_back(x);
  }
}

std::vector<pagmo::vector_double> initial_points(pagmo::population& pop, unsigned size,
                                                 const std::optional<pagmo::vector_double>& start) {
  std::vector<pagmo::vector_double> xs;
  if (start) xs.push_back(*start);
  while (xs.size() < size) xs.push_back(pop.random_decision_vector());
  return xs;
}

}  // namespace

const char* to_string(StopReason reason) {
  switch (reason) {
    case StopReason::tolerance:
      return "tolerance";
    case StopReason::time_limit:
      return "time_limit";
    case StopReason::max_evaluations:
      return "max_evaluations";
    case StopReason::interrupted:
      return "interrupted";
    case StopReason::lower_bound:
      return "lower_bound";
  }
  return "unknown";
}

MemoryUsage peak_memory() {
  MemoryUsage usage;
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    std::istringstream fields(line);
    std::string key;
    std::uint64_t kb = 0;
    fields >> key >> kb;
    if (key == "VmHWM:") usage.vm_hwm_kb = kb;
    if (key == "VmPeak:") usage.vm_peak_kb = kb;
  }
  return usage;
}

int population_size(const std::string& algorithm, int population, std::size_t dimension) {
  return static_cast<int>(detail::make_solver(algorithm, 1, population, dimension).population);
}

RunResult optimize(const core::Scene& scene, const Objective& objective,
                   const OptimizeOptions& options) {
  const Encoding encoding(scene);
  if (encoding.dimension() == 0) {
    throw core::InputError(scene.file, "/cameras",
                           "the domain fixes every camera setting; there is nothing to optimise");
  }
  const std::vector<std::string>& objectives = objective_names();
  if (std::find(objectives.begin(), objectives.end(), options.objective) == objectives.end()) {
    std::string names;
    for (const std::string& name : objectives) names += (names.empty() ? "" : ", ") + name;
    throw core::OptionError(
        "objective", "unknown objective \"" + options.objective + "\" (expected " + names + ")");
  }
  const double tolerance = options.tolerance.value_or(objective.default_tolerance());

  std::optional<pagmo::vector_double> start;
  if (options.start.kind == StartKind::corners) {
    start = encoding.encode(corner_start(scene));
  } else if (options.start.kind == StartKind::file) {
    const core::CameraConfig config = core::load_camera_config(options.start.file, scene);
    check_inside_domains(config, scene, options.start.file);
    start = encoding.encode(config);
  }

  Solver solver = detail::make_solver(options.algorithm, options.seed, options.population,
                                      encoding.dimension());
  const double lower_bound = options.stop_at_lower_bound ? objective.err_lower_bound() : 0.0;
  auto state = std::make_shared<RunState>(objective, encoding, options, tolerance, lower_bound);
  const pagmo::problem problem{detail::CameraProblem{state}};

  RunResult result;
  result.algorithm = options.algorithm;
  result.objective = options.objective;
  result.seed = options.seed;
  result.threads = state->threads();
  result.population = static_cast<int>(solver.population);
  result.dimension = encoding.dimension();
  result.tolerance = tolerance;
  result.err_lower_bound = objective.err_lower_bound();

  pagmo::vector_double first_point;
  bool have_start_err = false;
  try {
    pagmo::population pop(problem, 0u, options.seed);
    std::vector<pagmo::vector_double> xs = initial_points(pop, solver.population, start);
    first_point = xs.front();
    fill_population(pop, xs, solver.batch);
    result.start_err = state->best_err();
    have_start_err = true;
    for (;;) {
      if (auto reason = state->external_stop()) {
        state->stop(*reason);
        break;
      }
      const std::uint64_t before = state->evaluations();
      pop = solver.algorithm.evolve(pop);
      if (state->evaluations() == before) {
        // The solver has converged and stopped evaluating: restart it (deterministically
        // reseeded) from a fresh population that keeps the best point found so far.
        ++result.restarts;
        const unsigned seed = options.seed + 7919u * static_cast<unsigned>(result.restarts);
        solver =
            detail::make_solver(options.algorithm, seed, options.population, encoding.dimension());
        pagmo::population fresh(problem, 0u, seed);
        fill_population(fresh, initial_points(fresh, solver.population, state->best_x()),
                        solver.batch);
        pop = std::move(fresh);
      }
    }
  } catch (const StopRequested&) {
    // A stop criterion fired inside an evaluation; the run state holds the best so far.
  }

  if (state->evaluations() == 0) {
    // Stopped before the first evaluation (an immediate Ctrl-C or a tiny time limit): evaluate
    // the first initial point so the run still has a result.
    if (first_point.empty()) first_point = encoding.encode(corner_start(scene));
    core::Timing timing;
    state->record(first_point, objective.score(encoding.decode(first_point), timing), timing);
  }
  if (!have_start_err) result.start_err = state->best_err();

  result.seconds = state->seconds();
  result.stop_reason = state->stop_reason().value_or(StopReason::interrupted);
  result.evaluations = state->evaluations();
  result.evaluations_to_best = state->best_index();
  result.history = state->history();
  result.search_err = state->best_err();
  const double n = static_cast<double>(result.evaluations);
  const core::Timing& sum = state->timing_sum();
  result.mean_timing = {sum.labelling_ms / n, sum.clustering_ms / n, sum.distance_ms / n,
                        sum.total_ms / n};
  result.wall_ms_per_evaluation = result.seconds * 1000.0 / n;

  result.best = json_round_trip(encoding.decode(state->best_x()), scene);
  core::Timing timing;
  const Score score = objective.score(result.best, timing);
  result.err = detail::checked_err(score.err);
  result.tie_breaker = score.tie_breaker;
  result.reached_tolerance = result.err <= tolerance;
  if (options.snap) {
    // The search on the grid: at most 50 evaluations per free variable (at least 100).
    const std::uint64_t budget = std::max<std::uint64_t>(100, 50 * encoding.dimension());
    result.snapped = detail::snap_and_search(
        encoding, objective, state->best_x(), *options.snap, budget,
        [&](const core::CameraConfig& config) { return json_round_trip(config, scene); },
        [&] { return state->external_stop().has_value(); });
  }
  result.memory = peak_memory();
  return result;
}

}  // namespace camplace::optimize
