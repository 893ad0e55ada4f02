// The exact pipeline's threads (ExactOptions::threads, docs/design/exact-model.md E4): with more
// threads than tasks, helper threads build camera parts ahead of the worker; every state's
// d_model², model volume, kept components and count of removed components must be the same exact
// values with 1, 2 and 3 threads, on single states (one task: every thread beyond the first is a
// helper) and on whole scenes, on random scenes (either dynamic mode, boxes and tetrahedra or fine
// meshes, the plausibility filter on in half of them, some cameras on the walls so that the box
// around the model leaves kinds of objects out) and on paper_basic. The helpers' parts are counted
// (ExactEvaluation::parts_built_ahead), so the tests cannot pass without them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/exact/evaluator.hpp"
#include "environment.hpp"
#include "same_results.hpp"
#include "scene_builder.hpp"

namespace camplace {
namespace {

/// Evaluates `options.states` of `scene` with 1, 2 and 3 threads, expects the same exact results
/// and a progress call per (state, camera) step, adds the parts the helpers built to `ahead` and
/// returns the one thread's evaluation.
exact::ExactEvaluation expect_threads_change_nothing(const core::Scene& scene,
                                                     const core::CameraConfig& config,
                                                     exact::ExactOptions options, long& ahead) {
  options.threads = 1;
  const auto reference = exact::evaluate_exact(scene, config, options);
  EXPECT_EQ(reference.parts_built_ahead, 0);
  for (const int threads : {2, 3}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    options.threads = threads;
    long calls = 0, last = -1, total = 0;
    options.on_progress = [&](long done, long of) {
      ++calls;
      last = done;
      total = of;
    };
    const auto e = exact::evaluate_exact(scene, config, options);
    testing::expect_same_exact_results(e, reference);
    EXPECT_EQ(total, long(reference.states.size() * config.size()));
    EXPECT_EQ(last, total);
    EXPECT_EQ(calls, total + 1);
    ahead += e.parts_built_ahead;
  }
  return reference;
}

TEST(ThreadCount, RandomScenesGiveTheSameFractionsAndCountsWithOneTwoAndThreeThreads) {
  // CAMPLACE_EXACT_THREAD_TRIALS=N runs N scenes (default 4), CAMPLACE_EXACT_THREAD_SEED another
  // seed.
  const int trials = int(testing::env_number("CAMPLACE_EXACT_THREAD_TRIALS", 4));
  const auto seed = unsigned(testing::env_number("CAMPLACE_EXACT_THREAD_SEED", 20261204u));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  long single_ahead = 0, step_ahead = 0;
  int filtered_states = 0;
  for (int trial = 0; trial < trials; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    core::Scene scene = testing::random_scene(rng, {8, 6, 6});
    if (trial % 4 == 3) scene = testing::with_fine_meshes(std::move(scene), 120);
    if (trial % 2 == 1) scene.plausibility = {0.002 + 0.02 * unit(rng), 0.1 + 0.5 * unit(rng)};
    // Five cameras, every other one on a wall looking at a point of S (as model_box_test), so
    // that the model shrinks well inside S and the box around it leaves kinds of objects out.
    scene.cameras.resize(5);
    core::CameraConfig config = testing::random_config(rng, scene);
    testing::put_on_walls(rng, scene, config);
    // One state (one task: the other threads help), then the two events of the other time step
    // (with two threads a task each, with three a task each and a helper).
    const int h = trial % 2;
    exact::ExactOptions one;
    one.states = {{h, trial / 2 % 2}};
    exact::ExactOptions step;
    step.states = {{1 - h, 0}, {1 - h, 1}};
    for (const auto& [what, options, ahead] :
         {std::tuple{"one state", one, &single_ahead}, std::tuple{"one step", step, &step_ahead}}) {
      SCOPED_TRACE(what);
      for (const auto& r : expect_threads_change_nothing(scene, config, options, *ahead).states)
        filtered_states += r.components_removed > 0;
    }
  }
  std::printf(
      "%d scenes: helpers built %ld parts for single states, %ld for a step's events; %d "
      "states with removed components\n",
      trials, single_ahead, step_ahead, filtered_states);
  EXPECT_GT(single_ahead, 0);
  EXPECT_GT(step_ahead, 0);
  if (trials >= 4) {
    EXPECT_GT(filtered_states, 0);
  }
}

TEST(ThreadCount, PaperBasicSingleStatesGiveTheSameFractionsAndCountsWithOneTwoAndThreeThreads) {
  const std::string source = CAMPLACE_SOURCE_DIR;
  const core::Scene scene = core::load_scene(source + "/data/paper_basic.json");
  const core::CameraConfig corners =
      core::load_camera_config(source + "/data/paper_basic_corners.json", scene);
  long ahead = 0;
  for (const core::StateIndex s : {core::StateIndex{0, 0}, core::StateIndex{1, 2}}) {
    SCOPED_TRACE("state " + std::to_string(s.time_step) + "," + std::to_string(s.event));
    exact::ExactOptions options;
    options.states = {s};
    expect_threads_change_nothing(scene, corners, options, ahead);
  }
  EXPECT_GT(ahead, 0);
}

TEST(ThreadCount, HelpersOfTasksOfSeveralStatesGiveTheSameFractionsAndCounts) {
  // paper_basic with time step 1's three events twice over (six states) and time step 0's first
  // event: with four threads, step 0 is one task of one state and step 1 two tasks of three
  // states, so the fourth thread helps tasks of several states (it waits while a task's next unit
  // is more than one state ahead of its worker).
  const std::string source = CAMPLACE_SOURCE_DIR;
  core::Scene scene = core::load_scene(source + "/data/paper_basic.json");
  const core::CameraConfig corners =
      core::load_camera_config(source + "/data/paper_basic_corners.json", scene);
  auto& events = scene.time_steps[1].events;
  const std::size_t n = events.size();
  for (std::size_t l = 0; l < n; ++l) events.push_back(events[l]);
  for (auto& e : events) e.weight /= 2.0;
  exact::ExactOptions options;
  options.states = {{0, 0}};
  for (int l = 0; l < int(events.size()); ++l) options.states.push_back({1, l});
  options.threads = 1;
  const auto reference = exact::evaluate_exact(scene, corners, options);
  options.threads = 4;
  const auto e = exact::evaluate_exact(scene, corners, options);
  testing::expect_same_exact_results(e, reference);
  EXPECT_GT(e.parts_built_ahead, 0);
}

}  // namespace
}  // namespace camplace
