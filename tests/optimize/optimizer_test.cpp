#include "camplace/optimize/optimizer.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <mutex>
#include <vector>

#include "camplace/core/error.hpp"
#include "camplace/optimize/encoding.hpp"
#include "camplace/optimize/voxel_objective.hpp"
#include "test_scene.hpp"

namespace camplace::optimize {
namespace {

using testing::small_scene;

voxel::VoxelOptions mode(voxel::LabelMode m) {
  voxel::VoxelOptions o;
  o.mode = m;
  return o;
}

// Center labelling (the paper's basic version) by default: with 3 cameras of 30° the conservative
// model of this coarse scene never leaves the plateau Err = Σ ω d_true² (the model always reaches
// the robot), so there would be nothing to optimise.
struct Fixture {
  explicit Fixture(const std::string& domain = "\"room\"",
                   voxel::LabelMode label_mode = voxel::LabelMode::center)
      : scene(small_scene(domain)), objective(scene, mode(label_mode)) {}
  core::Scene scene;
  VoxelObjective objective;
};

OptimizeOptions budget(const std::string& algorithm, std::uint64_t evaluations, unsigned seed) {
  OptimizeOptions o;
  o.algorithm = algorithm;
  o.max_evaluations = evaluations;
  o.seed = seed;
  o.threads = 2;
  o.tolerance = 0.0;  // never reached: the budget decides
  return o;
}

TEST(Optimizer, ReachesErrWellBelowTheStart) {
  Fixture f;
  const RunResult r = optimize(f.scene, f.objective, budget("gaco", 3000, 3));
  // The initial population (random, seeded) is what the solver starts from.
  EXPECT_GT(r.start_err, 0.0);
  EXPECT_LT(r.err, 0.5 * r.start_err) << "start " << r.start_err << " end " << r.err;
  EXPECT_EQ(r.err, r.search_err);
  // Err of the returned configuration, recomputed independently of the run.
  voxel::Timing timing;
  EXPECT_EQ(f.objective.evaluate(r.best, timing), r.err);
  // The history is the best Err, falling, against increasing evaluation counts.
  ASSERT_FALSE(r.history.empty());
  for (std::size_t i = 1; i < r.history.size(); ++i) {
    EXPECT_LT(r.history[i].err, r.history[i - 1].err);
    EXPECT_GT(r.history[i].evaluations, r.history[i - 1].evaluations);
  }
  EXPECT_EQ(r.history.back().err, r.search_err);
  EXPECT_EQ(r.history.back().evaluations, r.evaluations_to_best);
}

TEST(Optimizer, StartsFromTheCornerHeuristicAndNeverLosesIt) {
  Fixture f;
  OptimizeOptions o = budget("cmaes", 1500, 1);
  o.start.kind = StartKind::corners;
  const RunResult r = optimize(f.scene, f.objective, o);
  voxel::Timing timing;
  const double corners = f.objective.evaluate(corner_start(f.scene), timing);
  EXPECT_EQ(r.history.front().evaluations, 1u);  // the start is the first evaluation
  EXPECT_EQ(r.history.front().err, corners);
  EXPECT_LE(r.err, corners);
}

TEST(Optimizer, SameSeedGivesTheSameResult) {
  Fixture f;
  for (const char* algorithm : {"gaco", "sade"}) {
    const RunResult a = optimize(f.scene, f.objective, budget(algorithm, 1200, 11));
    const RunResult b = optimize(f.scene, f.objective, budget(algorithm, 1200, 11));
    EXPECT_EQ(a.err, b.err) << algorithm;
    EXPECT_EQ(a.evaluations, b.evaluations) << algorithm;
    EXPECT_EQ(a.evaluations_to_best, b.evaluations_to_best) << algorithm;
    ASSERT_EQ(a.best.size(), b.best.size());
    for (std::size_t i = 0; i < a.best.size(); ++i) {
      EXPECT_EQ(a.best[i].position, b.best[i].position) << algorithm;
      EXPECT_EQ(a.best[i].yaw, b.best[i].yaw) << algorithm;
      EXPECT_EQ(a.best[i].pitch, b.best[i].pitch) << algorithm;
    }
    ASSERT_EQ(a.history.size(), b.history.size()) << algorithm;
    for (std::size_t i = 0; i < a.history.size(); ++i) {
      EXPECT_EQ(a.history[i].evaluations, b.history[i].evaluations);
      EXPECT_EQ(a.history[i].err, b.history[i].err);
    }
  }
}

TEST(Optimizer, ThreadCountDoesNotChangeTheResult) {
  Fixture f;
  OptimizeOptions one = budget("gaco", 1000, 5);
  one.threads = 1;
  OptimizeOptions two = one;
  two.threads = 2;
  const RunResult a = optimize(f.scene, f.objective, one);
  const RunResult b = optimize(f.scene, f.objective, two);
  EXPECT_EQ(a.err, b.err);
  EXPECT_EQ(a.evaluations_to_best, b.evaluations_to_best);
}

TEST(Optimizer, DifferentSeedsExploreDifferently) {
  Fixture f;
  const RunResult a = optimize(f.scene, f.objective, budget("gaco", 300, 1));
  const RunResult b = optimize(f.scene, f.objective, budget("gaco", 300, 2));
  EXPECT_NE(a.best[0].position, b.best[0].position);
}

TEST(Optimizer, CeilingDomainKeepsEveryCameraAtTheTop) {
  Fixture f("\"ceiling\"");
  for (const char* algorithm : {"gaco", "cmaes"}) {
    const RunResult r = optimize(f.scene, f.objective, budget(algorithm, 600, 2));
    EXPECT_EQ(r.dimension, 12u);
    for (const core::CameraSetting& c : r.best) EXPECT_EQ(c.position.z(), 2.5) << algorithm;
  }
}

TEST(Optimizer, BudgetStopsAtExactlyThatManyEvaluations) {
  Fixture f;
  for (const char* algorithm : {"gaco", "cmaes", "simulated_annealing"}) {
    const RunResult r = optimize(f.scene, f.objective, budget(algorithm, 777, 4));
    EXPECT_EQ(r.evaluations, 777u) << algorithm;
    EXPECT_EQ(r.stop_reason, StopReason::max_evaluations) << algorithm;
    EXPECT_FALSE(r.reached_tolerance);
  }
}

TEST(Optimizer, ToleranceStopsTheRun) {
  Fixture f;
  OptimizeOptions o = budget("gaco", 100000, 1);
  o.tolerance = 1e9;  // the first evaluation reaches it
  const RunResult r = optimize(f.scene, f.objective, o);
  EXPECT_EQ(r.stop_reason, StopReason::tolerance);
  EXPECT_TRUE(r.reached_tolerance);
  EXPECT_LE(r.evaluations, 32u);  // within the first (batch-evaluated) population
}

TEST(Optimizer, DefaultToleranceIsHalfTheVoxelDiagonalSquared) {
  Fixture f;
  const RunResult r = optimize(f.scene, f.objective, [] {
    OptimizeOptions o;
    o.max_evaluations = 50;
    return o;
  }());
  const double half_diagonal = 0.5 * std::sqrt(3.0 / 9 * 3.0 / 9 * 2 + 2.5 / 8 * 2.5 / 8);
  EXPECT_NEAR(r.tolerance, half_diagonal * half_diagonal, 1e-12);
}

// The interrupt is raised on an event (the 50th evaluation), not after a delay, so what the test
// sees does not depend on the machine's speed (sanitizers, load). The evaluation budget only
// ends the run if the interrupt is ignored.
TEST(Optimizer, InterruptStopsWithinTheRunningBatchAndReturnsTheBestSoFar) {
  Fixture f;
  constexpr std::uint64_t kRaiseAt = 50;
  for (const char* algorithm : {"gaco", "cmaes"}) {  // batch-parallel and sequential
    std::atomic<bool> interrupt{false};
    OptimizeOptions o = budget(algorithm, 5000, 1);
    o.interrupt = &interrupt;
    o.on_progress = [&interrupt](const Progress& p) {
      if (p.evaluations == kRaiseAt) interrupt = true;
    };
    const RunResult r = optimize(f.scene, f.objective, o);
    EXPECT_EQ(r.stop_reason, StopReason::interrupted) << algorithm;
    // Evaluations already started finish; no new batch (or single evaluation) begins.
    EXPECT_GE(r.evaluations, kRaiseAt) << algorithm;
    EXPECT_LT(r.evaluations, kRaiseAt + static_cast<std::uint64_t>(r.population)) << algorithm;
    EXPECT_LE(r.err, r.start_err) << algorithm;
    ASSERT_FALSE(r.history.empty()) << algorithm;
    EXPECT_EQ(r.history.back().err, r.search_err) << algorithm;
    EXPECT_EQ(r.best.size(), 3u) << algorithm;
    voxel::Timing timing;
    EXPECT_EQ(f.objective.evaluate(r.best, timing), r.err) << algorithm;
  }
}

// Only the lower bound of the elapsed time is asserted (a slow machine cannot make a run end
// early); that the run stops promptly is checked through the evaluations recorded after the
// limit, which no machine speed changes.
TEST(Optimizer, TimeLimitStopsWithinTheRunningBatchAndReturnsTheBestSoFar) {
  Fixture f;
  constexpr double kLimit = 0.4;                                   // s
  for (const char* algorithm : {"gaco", "simulated_annealing"}) {  // batch and sequential
    OptimizeOptions o;  // no evaluation budget: only the time limit ends the run
    o.algorithm = algorithm;
    o.tolerance = 0.0;
    o.threads = 2;
    o.time_limit = kLimit;
    std::uint64_t recorded_after_limit = 0;
    o.on_progress = [&recorded_after_limit](const Progress& p) {
      if (p.seconds >= kLimit) ++recorded_after_limit;
    };
    const RunResult r = optimize(f.scene, f.objective, o);
    EXPECT_EQ(r.stop_reason, StopReason::time_limit) << algorithm;
    EXPECT_GE(r.seconds, kLimit) << algorithm;
    EXPECT_GT(r.evaluations, 0u) << algorithm;
    // Evaluations that started before the limit may be recorded after it: at most one batch
    // (a population) for a batch solver, one evaluation for a sequential one.
    EXPECT_LE(recorded_after_limit, static_cast<std::uint64_t>(r.population)) << algorithm;
    EXPECT_LE(r.err, r.start_err) << algorithm;
    EXPECT_EQ(r.best.size(), 3u) << algorithm;
  }
}

/// Passes evaluations through to another objective and records each configuration with its Err,
/// so a test can check a run against what the objective actually saw.
class RecordingObjective : public Objective {
 public:
  struct Call {
    core::CameraConfig config;
    double err = 0.0;
  };
  explicit RecordingObjective(const Objective& inner) : inner_(inner) {}
  double evaluate(const core::CameraConfig& config, voxel::Timing& timing) const override {
    const double err = inner_.evaluate(config, timing);
    std::lock_guard<std::mutex> lock(mutex_);
    calls_.push_back({config, err});
    return err;
  }
  double default_tolerance() const override { return inner_.default_tolerance(); }
  double err_lower_bound() const override { return inner_.err_lower_bound(); }
  const std::vector<Call>& calls() const { return calls_; }

 private:
  const Objective& inner_;
  mutable std::mutex mutex_;
  mutable std::vector<Call> calls_;
};

bool inside(const core::Interval& range, double v) {
  return v >= range.lo - 1e-9 && v <= range.hi + 1e-9;
}

/// Whether every camera of config lies in its placement domain (position, yaw, pitch).
::testing::AssertionResult inside_domains(const core::Scene& scene,
                                          const core::CameraConfig& config) {
  for (std::size_t i = 0; i < config.size(); ++i) {
    const core::CameraDomain& d = scene.cameras.domains[i];
    const core::CameraSetting& c = config[i];
    if (!inside(d.x, c.position.x()) || !inside(d.y, c.position.y()) ||
        !inside(d.z, c.position.z()) || !inside(d.yaw, c.yaw) || !inside(d.pitch, c.pitch)) {
      return ::testing::AssertionFailure() << "camera " << i << " at (" << c.position.transpose()
                                           << "), yaw " << c.yaw << ", pitch " << c.pitch;
    }
  }
  return ::testing::AssertionSuccess();
}

bool same_cameras(const core::CameraConfig& a, const core::CameraConfig& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if ((a[i].position - b[i].position).norm() > 1e-9 || std::abs(a[i].yaw - b[i].yaw) > 1e-9 ||
        std::abs(a[i].pitch - b[i].pitch) > 1e-9) {
      return false;
    }
  }
  return true;
}

// Each solver, from a random start (seeded) in the room domain, with 400 evaluations, checked
// against what the objective itself saw: exactly the budget of evaluations, each inside the
// placement domains; the reported start and best Err are the minima of the initial population and
// of all evaluations; the search improves strictly on its initial population (a solver that does
// not search fails here: every solver does within 400 evaluations, found between the 107th and
// the 380th); the returned cameras are the best evaluated ones and have the reported Err.
TEST(Optimizer, EverySolverSearchesWithinTheBudgetAndTheDomainsAndReportsWhatItFound) {
  Fixture f;
  constexpr std::size_t kBudget = 400;
  for (const std::string& algorithm : algorithm_names()) {
    const RecordingObjective recording(f.objective);
    const RunResult r = optimize(f.scene, recording, budget(algorithm, kBudget, 1));
    // The search's evaluations, then one that recomputes Err of the returned cameras.
    const std::vector<RecordingObjective::Call>& calls = recording.calls();
    ASSERT_EQ(calls.size(), kBudget + 1) << algorithm;
    EXPECT_EQ(r.evaluations, kBudget) << algorithm;
    EXPECT_EQ(r.stop_reason, StopReason::max_evaluations) << algorithm;
    const auto search_end = calls.begin() + kBudget;
    for (auto call = calls.begin(); call != search_end; ++call) {
      EXPECT_TRUE(inside_domains(f.scene, call->config))
          << algorithm << ", evaluation " << (call - calls.begin() + 1);
    }
    const auto by_err = [](const auto& a, const auto& b) { return a.err < b.err; };
    // The initial population is evaluated first, as one batch or one by one.
    ASSERT_GT(r.population, 0) << algorithm;
    const double initial_best =
        std::min_element(calls.begin(), calls.begin() + r.population, by_err)->err;
    const double best_seen = std::min_element(calls.begin(), search_end, by_err)->err;
    EXPECT_EQ(r.start_err, initial_best) << algorithm;
    EXPECT_EQ(r.search_err, best_seen) << algorithm;
    EXPECT_LT(r.search_err, r.start_err) << algorithm << ": no improvement on the start";
    EXPECT_GT(r.evaluations_to_best, static_cast<std::uint64_t>(r.population)) << algorithm;
    // The returned cameras: a configuration evaluated with the best Err (up to the rounding of
    // the run file's degrees), inside the domains, whose Err, recomputed here, is r.err.
    EXPECT_TRUE(std::any_of(calls.begin(), search_end,
                            [&](const auto& call) {
                              return call.err == best_seen && same_cameras(call.config, r.best);
                            }))
        << algorithm << ": the returned cameras are not the best evaluated ones";
    EXPECT_TRUE(inside_domains(f.scene, r.best)) << algorithm;
    voxel::Timing timing;
    EXPECT_EQ(f.objective.evaluate(r.best, timing), r.err) << algorithm;
  }
}

TEST(Optimizer, RecordsTimingAndMemory) {
  Fixture f("\"room\"", voxel::LabelMode::conservative);
  const RunResult r = optimize(f.scene, f.objective, budget("gaco", 200, 1));
  EXPECT_GT(r.mean_timing.total_ms, 0.0);
  EXPECT_GE(r.mean_timing.total_ms + 1e-9, r.mean_timing.labelling_ms);
  EXPECT_GT(r.wall_ms_per_evaluation, 0.0);
  EXPECT_GT(r.memory.vm_hwm_kb, 0u);
  EXPECT_GE(r.memory.vm_peak_kb, r.memory.vm_hwm_kb);
}

TEST(Optimizer, ConservativeErrNeverFallsBelowTheRecordedLowerBound) {
  Fixture f("\"room\"", voxel::LabelMode::conservative);
  OptimizeOptions o = budget("gaco", 300, 1);
  o.start.kind = StartKind::corners;
  const RunResult r = optimize(f.scene, f.objective, o);
  EXPECT_GT(r.err_lower_bound, 0.0);
  EXPECT_GE(r.err, r.err_lower_bound);
  for (const HistoryPoint& h : r.history) EXPECT_GE(h.err, r.err_lower_bound);
}

/// Err = 0.5 + (max(0, |x₀ − 1| − 0.2))² for camera 0's x: its lower bound 0.5 is reached on a
/// whole interval, so a solver can hit it exactly.
class FlatBottomObjective : public Objective {
 public:
  double evaluate(const core::CameraConfig& config, voxel::Timing& timing) const override {
    timing = voxel::Timing{};
    const double excess = std::max(0.0, std::abs(config[0].position.x() - 1.0) - 0.2);
    return 0.5 + excess * excess;
  }
  double default_tolerance() const override { return 0.1; }
  double err_lower_bound() const override { return 0.5; }
};

TEST(Optimizer, StopsWhenErrReachesTheLowerBound) {
  const core::Scene scene = small_scene();
  const FlatBottomObjective objective;
  OptimizeOptions o = budget("cmaes", 20000, 1);
  o.tolerance.reset();  // 0.1: below the bound, never reached
  const RunResult r = optimize(scene, objective, o);
  EXPECT_EQ(r.stop_reason, StopReason::lower_bound);
  EXPECT_EQ(r.err, 0.5);
  EXPECT_FALSE(r.reached_tolerance);
  EXPECT_LT(r.evaluations, 20000u);

  o.stop_at_lower_bound = false;
  o.max_evaluations = 300;
  EXPECT_EQ(optimize(scene, objective, o).stop_reason, StopReason::max_evaluations);
}

/// Err = `value` (+inf or NaN) everywhere: what a weight of 1.7e308 made of the voxel Err
/// before the scene loader bounded the weights (core::kMaxErr).
class NonFiniteObjective : public Objective {
 public:
  explicit NonFiniteObjective(double value) : value_(value) {}
  double evaluate(const core::CameraConfig&, voxel::Timing& timing) const override {
    timing = voxel::Timing{};
    return value_;
  }
  double default_tolerance() const override { return 0.1; }
  double err_lower_bound() const override { return 0.0; }

 private:
  double value_;
};

TEST(Optimizer, NonFiniteErrIsAClearErrorNotAFailedInternalCheck) {
  // Such an Err never became the best, so the run ended without a best point and decoding it
  // failed an internal check (encoding.cpp). Now the first such Err ends the run with an error.
  const core::Scene scene = small_scene();
  for (const double value :
       {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
    for (const char* algorithm : {"gaco", "cmaes"}) {
      const NonFiniteObjective objective(value);
      try {
        optimize(scene, objective, budget(algorithm, 200, 1));
        ADD_FAILURE() << algorithm << ": no error for Err = " << value;
      } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("not a finite number"), std::string::npos) << e.what();
      }
    }
  }
}

/// A dead plateau: Err = `err` for every configuration, tie-breaker |x₀ − 1| / 3
/// (camera 0's x in [0, 3]: in [0, 2/3]).
class PlateauObjective : public Objective {
 public:
  explicit PlateauObjective(double err) : err_(err) {}
  double evaluate(const core::CameraConfig&, voxel::Timing& timing) const override {
    timing = voxel::Timing{};
    return err_;
  }
  Score score(const core::CameraConfig& config, voxel::Timing& timing) const override {
    return {evaluate(config, timing), std::abs(config[0].position.x() - 1.0) / 3.0};
  }
  double default_tolerance() const override { return 0.1; }

 private:
  double err_;
};

TEST(Optimizer, TieBreakerGivesTheSolversADirectionOnAPlateauAndErrStaysTheTrueErr) {
  const core::Scene scene = small_scene();
  const PlateauObjective objective(1.25);
  for (const char* algorithm : {"gaco", "cmaes", "pso"}) {
    OptimizeOptions o = budget(algorithm, 1500, 1);
    o.objective = "err+volume";
    const RunResult tie = optimize(scene, objective, o);
    EXPECT_EQ(tie.objective, "err+volume");
    EXPECT_EQ(tie.err, 1.25) << algorithm;
    EXPECT_EQ(tie.search_err, 1.25) << algorithm;
    EXPECT_EQ(tie.start_err, 1.25) << algorithm;
    // One history point: the Err never improved, whatever the tie-breaker did.
    ASSERT_EQ(tie.history.size(), 1u) << algorithm;
    EXPECT_EQ(tie.history[0].err, 1.25) << algorithm;
    // The solver followed the tie-breaker to x₀ ≈ 1 (a random x₀ in [0, 3] has |x₀ − 1| / 3
    // ≈ 0.28 on average), and the returned configuration's tie-breaker is reported.
    EXPECT_LT(tie.tie_breaker, 1e-3) << algorithm;
    EXPECT_NEAR(tie.tie_breaker, std::abs(tie.best[0].position.x() - 1.0) / 3.0, 1e-12);

    o.objective = "err";
    const RunResult plain = optimize(scene, objective, o);
    EXPECT_EQ(plain.objective, "err");
    EXPECT_EQ(plain.err, 1.25) << algorithm;
    // Without the tie-breaker every configuration ties: the first one evaluated stays the best.
    EXPECT_EQ(plain.evaluations_to_best, 1u) << algorithm;
    EXPECT_GT(plain.tie_breaker, tie.tie_breaker) << algorithm;
  }
}

/// Err 1.25 where the model touches the robot, which is everywhere except a small square of
/// camera 0's x and camera 1's x around (1, 2), where Err is 0.05; the touching excess falls
/// toward the square: 1.25 · (|x₀ − 1| + |x₁ − 2|) / 6.
class TouchingObjective : public Objective {
 public:
  double evaluate(const core::CameraConfig& config, voxel::Timing& timing) const override {
    return score(config, timing).err;
  }
  Score score(const core::CameraConfig& config, voxel::Timing& timing) const override {
    timing = voxel::Timing{};
    const double off =
        std::abs(config[0].position.x() - 1.0) + std::abs(config[1].position.x() - 2.0);
    if (std::abs(config[0].position.x() - 1.0) < 0.01 &&
        std::abs(config[1].position.x() - 2.0) < 0.01) {
      return {0.05, 0.0, 0.0};
    }
    return {1.25, 0.0, 1.25 * off / 6.0};
  }
  double default_tolerance() const override { return 0.1; }
};

TEST(Optimizer, TouchingVolumeLeadsTheSolversOffAPartialPlateauAndReportsTheTrueErr) {
  const core::Scene scene = small_scene();
  const TouchingObjective objective;
  for (const char* algorithm : {"gaco", "cmaes", "pso"}) {
    OptimizeOptions o = budget(algorithm, 1500, 1);
    o.tolerance = 0.1;
    o.objective = "err+touching-volume";
    const RunResult shaped = optimize(scene, objective, o);
    EXPECT_EQ(shaped.objective, "err+touching-volume");
    EXPECT_EQ(shaped.stop_reason, StopReason::tolerance) << algorithm;
    // The reported Err is Err alone, not the fitness the solver saw.
    EXPECT_EQ(shaped.err, 0.05) << algorithm;
    EXPECT_EQ(shaped.start_err, 1.25) << algorithm;
    // Err alone is flat outside the square (a random point hits it with probability 1/22,500):
    // the same budget finds nothing.
    o.objective = "err";
    const RunResult plain = optimize(scene, objective, o);
    EXPECT_EQ(plain.err, 1.25) << algorithm;
    EXPECT_EQ(plain.stop_reason, StopReason::max_evaluations) << algorithm;
  }
}

TEST(Optimizer, StopRulesCompareTheTrueErrNotTheRoundedFitness) {
  // Err one ulp above the tolerance: the fitness (Err rounded down to 32 significant bits, the
  // tie-breaker 0 at x₀ = 1 aside) equals the tolerance, the true Err does not reach it.
  const core::Scene scene = small_scene();
  const double err = std::nextafter(1.25, 2.0);
  ASSERT_EQ(tie_break_fitness(err, 0.0), 1.25);
  const PlateauObjective objective(err);
  OptimizeOptions o = budget("gaco", 200, 1);
  o.objective = "err+volume";
  o.tolerance = 1.25;
  const RunResult r = optimize(scene, objective, o);
  EXPECT_EQ(r.stop_reason, StopReason::max_evaluations);
  EXPECT_FALSE(r.reached_tolerance);
  EXPECT_EQ(r.err, err);
  EXPECT_EQ(r.search_err, err);
  o.tolerance = err;
  EXPECT_EQ(optimize(scene, objective, o).stop_reason, StopReason::tolerance);
}

TEST(Optimizer, UnknownObjectiveIsAnOptionError) {
  Fixture f;
  OptimizeOptions o = budget("gaco", 10, 1);
  for (const char* name : {"volume", "ERR", ""}) {
    o.objective = name;
    try {
      optimize(f.scene, f.objective, o);
      ADD_FAILURE() << "objective \"" << name << "\" was accepted";
    } catch (const core::OptionError& e) {
      EXPECT_EQ(e.option(), "objective");
      EXPECT_NE(e.reason().find("err+volume"), std::string::npos) << e.what();
    }
  }
}

TEST(Optimizer, BadAlgorithmOrPopulationIsAnInputError) {
  Fixture f;
  EXPECT_THROW(optimize(f.scene, f.objective, budget("midaco", 10, 1)), core::InputError);
  OptimizeOptions o = budget("sade", 10, 1);
  o.population = 3;
  EXPECT_THROW(optimize(f.scene, f.objective, o), core::InputError);
}

TEST(Optimizer, StartFileOutsideThePlacementDomainIsAnInputError) {
  Fixture f("\"ceiling\"");  // z fixed at S's top, 2.5 m
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("camplace-start-" + std::to_string(::getpid()) + ".json"))
                               .string();
  const auto write_start = [&](double z) {
    std::ofstream(path) << R"({"cameras": [)"
                        << R"({"position": [1, 1, 2.5], "yaw_deg": 0, "pitch_deg": -45},)"
                        << R"({"position": [2, 1, )" << z
                        << R"(], "yaw_deg": 0, "pitch_deg": -45},)"
                        << R"({"position": [3, 1, 2.5], "yaw_deg": 0, "pitch_deg": -45}]})";
  };
  OptimizeOptions o = budget("gaco", 50, 1);
  o.start = {StartKind::file, path};
  write_start(1.0);
  try {
    optimize(f.scene, f.objective, o);
    ADD_FAILURE() << "a start below the ceiling was accepted";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.entry(), "/cameras/1/position");
    EXPECT_NE(e.reason().find("outside the placement domain"), std::string::npos) << e.what();
  }
  write_start(2.5);
  EXPECT_NO_THROW(optimize(f.scene, f.objective, o));
  std::filesystem::remove(path);
}

TEST(Optimizer, FixedEverythingIsAnInputError) {
  Fixture f(
      R"({"preset": "ceiling", "x": [1, 1], "y": [1, 1], "yaw_deg": [0, 0], "pitch_deg": [-90, -90]})");
  EXPECT_THROW(optimize(f.scene, f.objective, budget("gaco", 10, 1)), core::InputError);
}

}  // namespace
}  // namespace camplace::optimize
