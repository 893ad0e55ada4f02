// The obstacles subtracted from each state's model once, after the cameras' free regions
// (ExactOptions::obstacles_last, the default), against the former order, which starts from S
// minus the obstacles: every state's d_model², model volume and kept components are the same
// exact fractions, on random scenes with fine meshes (50–800 triangles per object, 2 time steps
// × 2 events, either dynamic mode, the plausibility filter on in half of them, so that pieces
// are discarded between cameras while they still hold obstacles). And the model files exported
// from the two orders are the same bytes.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/exact/evaluator.hpp"
#include "environment.hpp"
#include "same_results.hpp"
#include "scene_builder.hpp"

namespace camplace {
namespace {

TEST(ObstacleOrder, RandomFineMeshScenesGiveTheFormerOrdersFractions) {
  // CAMPLACE_EXACT_ORDER_TRIALS=N runs N scenes (longer checks by hand, up to 800 triangles;
  // default 4, up to 200), CAMPLACE_EXACT_ORDER_SEED another seed.
  const int trials = int(testing::env_number("CAMPLACE_EXACT_ORDER_TRIALS", 4));
  const unsigned default_seed = 20261204u;
  const auto seed = unsigned(testing::env_number("CAMPLACE_EXACT_ORDER_SEED", default_seed));
  std::mt19937 rng(seed);
  const int triangles[] = {50, 120, 200, 60, 400, 800};
  int filtered_states = 0, nonempty_states = 0;
  for (int trial = 0; trial < trials; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const int n = triangles[trial % 6];
    core::Scene scene = testing::with_fine_meshes(testing::random_scene(rng, {8, 6, 6}), n);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    if (trial % 2 == 1) scene.plausibility = {0.002 + 0.02 * unit(rng), 0.1 + 0.5 * unit(rng)};
    const core::CameraConfig config = testing::random_config(rng, scene);
    exact::ExactOptions last;
    last.threads = 1;
    exact::ExactOptions former = last;
    former.obstacles_last = false;
    const auto b = exact::evaluate_exact(scene, config, former);
    SCOPED_TRACE(std::to_string(n) + " triangles");
    // The count of removed components may differ (pieces are discarded at other times).
    testing::expect_same_exact_results(exact::evaluate_exact(scene, config, last), b,
                                       /*removed_may_differ=*/true);
    for (const auto& r : b.states) {
      filtered_states += r.components_removed > 0;
      nonempty_states += r.components > 0;
    }
  }
  // The default scenes exercise both the filter and non-empty models (other seeds may not).
  if (trials >= 4 && seed == default_seed) {
    EXPECT_GT(filtered_states, 0);
    EXPECT_GT(nonempty_states, 0);
  }
  std::printf("%d scenes: %d states with removed components, %d with a non-empty model\n", trials,
              filtered_states, nonempty_states);
}

/// The whole text of the file at `path`.
std::string file_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(ObstacleOrder, TheExportedFilesDoNotDependOnTheOrderTheModelWasBuiltIn) {
  // The two orders build each state's model by other Boolean operations, so its Nef polyhedron
  // lists its volumes, facets and vertices in another order (as when helper threads build a
  // camera's parts); the point sets are the same, and so must the exported files be.
  const std::string source = CAMPLACE_SOURCE_DIR;
  const core::Scene scene = core::load_scene(source + "/data/paper_basic.json");
  const core::CameraConfig corners =
      core::load_camera_config(source + "/data/paper_basic_corners.json", scene);
  const std::string dir = testing::temp_dir("exact-export-order");
  exact::ExactOptions last;
  last.threads = 1;
  last.export_dir = dir + "/last";
  exact::ExactOptions former = last;
  former.obstacles_last = false;
  former.export_dir = dir + "/former";
  exact::evaluate_exact(scene, corners, last);
  exact::evaluate_exact(scene, corners, former);
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(last.export_dir)) {
    const std::string name = entry.path().filename().string();
    SCOPED_TRACE(name);
    const std::string text = file_text(entry.path());
    EXPECT_GT(text.size(), 20u);
    EXPECT_EQ(text, file_text(former.export_dir + "/" + name));
    ++files;
  }
  EXPECT_EQ(files, 6 + 6);  // a model per state, a pyramid per camera
}

}  // namespace
}  // namespace camplace
