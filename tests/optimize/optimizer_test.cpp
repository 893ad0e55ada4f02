#include "camplace/optimize/optimizer.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

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

TEST(Optimizer, InterruptReturnsTheBestSoFar) {
  Fixture f;
  std::atomic<bool> interrupt{false};
  OptimizeOptions o;
  o.algorithm = "gaco";
  o.tolerance = 0.0;
  o.interrupt = &interrupt;
  std::thread raiser([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    interrupt = true;
  });
  const RunResult r = optimize(f.scene, f.objective, o);
  raiser.join();
  EXPECT_EQ(r.stop_reason, StopReason::interrupted);
  EXPECT_GT(r.evaluations, 0u);
  EXPECT_LE(r.err, r.start_err);
  EXPECT_EQ(r.best.size(), 3u);
  EXPECT_LT(r.seconds, 5.0);
}

TEST(Optimizer, TimeLimitReturnsTheBestSoFar) {
  Fixture f;
  for (const char* algorithm : {"gaco", "simulated_annealing"}) {
    OptimizeOptions o;
    o.algorithm = algorithm;
    o.tolerance = 0.0;
    o.time_limit = 0.4;
    const RunResult r = optimize(f.scene, f.objective, o);
    EXPECT_EQ(r.stop_reason, StopReason::time_limit) << algorithm;
    EXPECT_GE(r.seconds, 0.4);
    EXPECT_LT(r.seconds, 3.0);
    EXPECT_GT(r.evaluations, 0u);
  }
}

TEST(Optimizer, EverySolverRunsAndImprovesOrKeepsTheStart) {
  Fixture f;
  for (const std::string& algorithm : algorithm_names()) {
    OptimizeOptions o = budget(algorithm, 400, 1);
    o.start.kind = StartKind::corners;
    const RunResult r = optimize(f.scene, f.objective, o);
    EXPECT_EQ(r.evaluations, 400u) << algorithm;
    EXPECT_LE(r.err, r.start_err) << algorithm;
    voxel::Timing timing;
    EXPECT_LE(r.err, f.objective.evaluate(corner_start(f.scene), timing)) << algorithm;
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
