// d(C_h, M) against the brute-force minimum over every voxel of the filtered model, on random
// scenes: a sweep that takes seconds in a Release build and half a minute under ASan, so it is
// in reference_sweep_tests (label slow). The hand cases of the model are in model_test.cpp.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>

#include "camplace/core/distance.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using voxel::LabelMode;

// d(C_h, M) against the brute-force minimum over every voxel of the filtered model: the
// distance from the step's critical objects to its box (conservative) or centre (center), by
// core's plain mesh distances. Random scenes and configurations, both modes, two resolutions.
TEST(Model, DistanceIsTheMinimumOverEveryModelVoxel) {
  std::mt19937 rng(2911);
  long states = 0;
  for (int s = 0; s < 6; ++s) {
    core::Scene scene = random_scene(rng, {12, 9, 9});
    scene.plausibility = {};  // keep every component: more voxels to get wrong
    const core::CameraConfig config = random_config(rng, scene);
    for (const LabelMode mode : {LabelMode::conservative, LabelMode::center}) {
      for (const std::array<int, 3> n : {std::array<int, 3>{12, 9, 9}, {20, 15, 15}}) {
        const voxel::VoxelEvaluator evaluator(scene, {mode, n});
        const voxel::Evaluation e = evaluator.evaluate(config);
        for (int st = 0; st < static_cast<int>(e.states.size()); ++st) {
          const auto model = evaluator.model(config, st);
          const auto& critical = scene.time_steps[e.states[st].time_step].critical;
          double best = std::numeric_limits<double>::infinity();
          for (int v = 0; v < evaluator.grid().count(); ++v) {
            if (!model[v]) continue;
            for (const core::SceneObject& c : critical) {
              best = std::min(
                  best,
                  mode == LabelMode::conservative
                      ? core::box_solid_sq_distance(c.mesh, evaluator.grid().voxel_box(v))
                      : core::point_solid_sq_distance(c.mesh, evaluator.grid().voxel_center(v)));
            }
          }
          if (!std::isfinite(best)) continue;  // empty model
          ++states;
          EXPECT_NEAR(e.states[st].d_model, std::sqrt(best), 1e-9 * (1.0 + std::sqrt(best)))
              << "scene " << s << " state " << st << " mode " << static_cast<int>(mode);
        }
      }
    }
  }
  EXPECT_GT(states, 50);
}

}  // namespace
}  // namespace camplace::testing
