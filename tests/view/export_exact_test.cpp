// `camplace export --pipeline exact`: the exact model's boundary mesh and the k-sided pyramid
// FOVs in the glTF file, checked as the voxel export is (glb_checks.hpp) and against the exact
// evaluation's own numbers.
#include <gtest/gtest.h>

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
  // Err of the corners configuration, exact pipeline (docs/reports/compare_paper_basic/err.csv).
  EXPECT_NEAR(result.err, 0.000062907, 5e-10);
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

}  // namespace
}  // namespace camplace::testing
