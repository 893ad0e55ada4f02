// Each camera's free region built only within a box around the model
// (ExactOptions::model_box_fraction, docs/design/exact-model.md E3) against the whole free region
// (fraction 0, the reference): every state's d_model², model volume, kept components and count of
// removed components are the same exact values, on random scenes (either dynamic mode, boxes and
// tetrahedra or fine meshes, the plausibility filter on in half of them, some cameras on the
// walls) and on paper_basic with jittered corner configurations (cameras outside the boxes, so
// that whole kinds of objects are left out), with the box used from the first camera on
// (fraction 1) and by default (once it fills at most half the box around S).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/exact/evaluator.hpp"
#include "environment.hpp"
#include "same_results.hpp"
#include "scene_builder.hpp"

namespace camplace {
namespace {

/// Evaluates `config` with the whole free regions (`options` with model_box_fraction 0) and with
/// the box from the first camera on (1) and by default (0.5), expects the same exact results, and
/// returns the whole free regions' evaluation.
exact::ExactEvaluation expect_box_changes_nothing(const core::Scene& scene,
                                                  const core::CameraConfig& config,
                                                  exact::ExactOptions options) {
  options.model_box_fraction = 0.0;
  const auto reference = exact::evaluate_exact(scene, config, options);
  for (const double fraction : {1.0, 0.5}) {
    SCOPED_TRACE("model_box_fraction " + std::to_string(fraction));
    options.model_box_fraction = fraction;
    testing::expect_same_exact_results(exact::evaluate_exact(scene, config, options), reference);
  }
  return reference;
}

TEST(ModelBox, RandomScenesGiveTheWholeFreeRegionsFractionsAndCounts) {
  // CAMPLACE_EXACT_MODEL_BOX_TRIALS=N runs N scenes (default 6), CAMPLACE_EXACT_MODEL_BOX_SEED
  // another seed.
  const int trials = int(testing::env_number("CAMPLACE_EXACT_MODEL_BOX_TRIALS", 6));
  const unsigned default_seed = 20261205u;
  const auto seed = unsigned(testing::env_number("CAMPLACE_EXACT_MODEL_BOX_SEED", default_seed));
  std::mt19937 rng(seed);
  int filtered_states = 0, nonempty_states = 0;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < trials; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    core::Scene scene = testing::random_scene(rng, {8, 6, 6});
    if (trial % 3 == 2) scene = testing::with_fine_meshes(std::move(scene), 120);
    if (trial % 2 == 1) scene.plausibility = {0.002 + 0.02 * unit(rng), 0.1 + 0.5 * unit(rng)};
    // More cameras than random_scene's, so that the model shrinks well inside S; every other one
    // on a wall, looking at a point of S, so that the box around the model leaves it out and
    // whole kinds of objects can be left out (a camera in the box sees every object's rays meet
    // it).
    scene.cameras.resize(5);
    core::CameraConfig config = testing::random_config(rng, scene);
    testing::put_on_walls(rng, scene, config);
    exact::ExactOptions whole;
    whole.threads = 1;
    const auto reference = expect_box_changes_nothing(scene, config, whole);
    for (const auto& r : reference.states) {
      filtered_states += r.components_removed > 0;
      nonempty_states += r.components > 0;
    }
  }
  // The default scenes exercise both the filter and non-empty models (other seeds may not).
  if (trials >= 6 && seed == default_seed) {
    EXPECT_GT(filtered_states, 0);
    EXPECT_GT(nonempty_states, 0);
  }
  std::printf("%d scenes: %d states with removed components, %d with a non-empty model\n", trials,
              filtered_states, nonempty_states);
}

TEST(ModelBox, PaperBasicJitteredCornersGiveTheWholeFreeRegionsFractionsAndCounts) {
  const std::string source = CAMPLACE_SOURCE_DIR;
  const core::Scene scene = core::load_scene(source + "/data/paper_basic.json");
  const core::CameraConfig corners =
      core::load_camera_config(source + "/data/paper_basic_corners.json", scene);
  for (const auto& config : testing::configs_around(corners, scene, 20261205u, 2, 0)) {
    expect_box_changes_nothing(scene, config, {});
  }
}

}  // namespace
}  // namespace camplace
