// `camplace export --pipeline exact`: the exact model's boundary mesh and the k-sided pyramid
// FOVs in the glTF file, checked as the voxel export is (glb_checks.hpp) and against the exact
// evaluation's own numbers; with chosen states only those are evaluated exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "camplace/core/error.hpp"
#include "camplace/exact/evaluator.hpp"
#include "camplace/view/export.hpp"
#include "glb_checks.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

const std::string kData = std::string(CAMPLACE_SOURCE_DIR) + "/data/";

TEST(ExportExact, ModelMeshAndSegmentsMatchTheExactEvaluation) {
  const core::Scene scene = core::load_scene(kData + "paper_basic.json");
  const core::CameraConfig config =
      core::load_camera_config(kData + "paper_basic_corners.json", scene);
  view::ExportOptions options;
  options.pipeline = core::Pipeline::exact;
  options.states = {{0, 0}, {1, 2}};
  const std::string dir = temp_dir("export_exact");
  const view::ExportResult result = view::export_scene(scene, config, options, dir);
  ASSERT_EQ(result.states.size(), 2u);
  // Only the chosen states are evaluated, so Err sums their two terms, each the same as in the
  // evaluation of every state (the corners configuration's Err, exact pipeline, is
  // docs/reports/compare_paper_basic/err.csv's).
  const exact::ExactEvaluation every = exact::evaluate_exact(scene, config);
  EXPECT_NEAR(every.err, 0.000062907, 5e-10);
  EXPECT_EQ(result.err_states, 2);
  double err = 0.0;
  for (const view::ExportedState& s : result.states) {
    const auto same = std::find_if(every.states.begin(), every.states.end(), [&](const auto& r) {
      return r.time_step == s.state.time_step && r.event == s.state.event;
    });
    ASSERT_NE(same, every.states.end());
    EXPECT_EQ(s.result.d_model_sq_exact, same->d_model_sq_exact);
    EXPECT_EQ(s.result.d_true_sq_exact, same->d_true_sq_exact);
    err += same->weight * std::pow(same->d_true - same->d_model, 2);
  }
  EXPECT_NEAR(result.err, err, 1e-15);
  EXPECT_LT(result.err, every.err);  // the other states' terms are not in it
  for (const view::ExportedState& s : result.states) {
    check_state_file(scene, config, s, dir + "/" + s.glb);  // includes: mesh volume = reported
    EXPECT_NEAR((s.true_segment.a - s.true_segment.b).norm(), s.result.d_true, 1e-9);
    ASSERT_FALSE(s.model_empty);
    // The segment is measured on the boundary rounded to doubles; d_model is exact.
    EXPECT_NEAR((s.model_segment.a - s.model_segment.b).norm(), s.result.d_model, 1e-9);
    // The FOVs are the scene's 16-sided pyramids (SPEC §6), not the cone.
    const tinygltf::Model m = load_glb(dir + "/" + s.glb);
    for (const tinygltf::Node& node : m.nodes) {
      if (role_of(node) != "fov") continue;
      EXPECT_EQ(node.extras.Get("shape").Get<std::string>(), "pyramid");
      EXPECT_EQ(node.extras.Get("sides_drawn").GetNumberAsInt(), 16);
    }
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/voxels.npy"));  // no voxels in the exact pipeline
}

TEST(ExportExact, ExactOptionsRefuseAStateTheSceneLacks) {
  const core::Scene scene = core::load_scene(kData + "paper_basic.json");
  const core::CameraConfig config =
      core::load_camera_config(kData + "paper_basic_corners.json", scene);
  exact::ExactOptions options;
  options.states = {{1, 3}};  // paper_basic has time steps 0–1 with events 0–2
  try {
    exact::evaluate_exact(scene, config, options);
    FAIL() << "no error for a state the scene lacks";
  } catch (const core::OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("no state 1,3"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace camplace::testing
