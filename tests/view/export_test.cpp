// `camplace export`: the glTF files parsed back with tinygltf (a validator's checks: node,
// mesh and camera counts per role, accessor bounds against the data, every position in S, the
// camera poses), and the command's files and errors.
#include "camplace/view/export.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "camplace/core/camera.hpp"
#include "camplace/core/geometry.hpp"
#include "command.hpp"
#include "glb_checks.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

namespace fs = std::filesystem;
using core::Vec3;

const std::string kData = std::string(CAMPLACE_SOURCE_DIR) + "/data/";

TEST(Export, VoxelGlbFilesParseBackWithTheLibrary) {
  const core::Scene scene = core::load_scene(kData + "paper_basic.json");
  const core::CameraConfig config =
      core::load_camera_config(kData + "paper_basic_corners.json", scene);
  const std::string dir = temp_dir("export_voxel");
  view::ExportOptions options;
  const view::ExportResult result = view::export_scene(scene, config, options, dir);
  ASSERT_EQ(result.states.size(), 6u);
  for (const view::ExportedState& s : result.states) {
    check_state_file(scene, config, s, dir + "/" + s.glb);
    EXPECT_NEAR((s.true_segment.a - s.true_segment.b).norm(), s.result.d_true, 1e-9);
    ASSERT_FALSE(s.model_empty);
    EXPECT_NEAR((s.model_segment.a - s.model_segment.b).norm(), s.result.d_model, 1e-9);
  }
  // Err as evaluate reports it for this configuration (README, docs/files.md).
  EXPECT_NEAR(result.err, 0.083112, 5e-7);
}

// With --refine the model is drawn as its finest cells, so the d_model segment measures the
// refined distance (larger than the unrefined one in some state).
TEST(Export, RefinedModelSegmentMeasuresTheRefinedDistance) {
  const core::Scene scene = core::load_scene(kData + "paper_basic.json");
  const core::CameraConfig config =
      core::load_camera_config(kData + "paper_basic_corners.json", scene);
  view::ExportOptions options;
  options.voxel.refine = 3;
  const std::string dir = temp_dir("export_refine");
  const view::ExportResult refined = view::export_scene(scene, config, options, dir);
  const view::ExportResult plain = view::export_scene(scene, config, {}, temp_dir("export_plain"));
  ASSERT_EQ(refined.states.size(), 6u);
  bool farther = false;
  for (std::size_t i = 0; i < refined.states.size(); ++i) {
    const view::ExportedState& s = refined.states[i];
    check_state_file(scene, config, s, dir + "/" + s.glb);
    ASSERT_FALSE(s.model_empty);
    EXPECT_NEAR((s.model_segment.a - s.model_segment.b).norm(), s.result.d_model, 1e-9);
    farther |= s.result.d_model > plain.states[i].result.d_model + 1e-6;
  }
  EXPECT_TRUE(farther);
  EXPECT_LT(refined.err, plain.err);
}

TEST(Export, CenterModeSegmentEndsAtAVoxelCentre) {
  const core::Scene scene = core::load_scene(kData + "paper_basic.json");
  const core::CameraConfig config =
      core::load_camera_config(kData + "paper_basic_corners.json", scene);
  view::ExportOptions options;
  options.voxel.mode = core::LabelMode::center;
  options.states = {{1, 2}};
  const std::string dir = temp_dir("export_center");
  const view::ExportResult result = view::export_scene(scene, config, options, dir);
  ASSERT_EQ(result.states.size(), 1u);
  const view::ExportedState& s = result.states[0];
  check_state_file(scene, config, s, dir + "/state-1-2.glb");
  EXPECT_FALSE(fs::exists(dir + "/state-0-0.glb"));
  if (!s.model_empty) {
    EXPECT_NEAR((s.model_segment.a - s.model_segment.b).norm(), s.result.d_model, 1e-9);
    // 16×12×12 over 4×3×3 m: centres at odd multiples of 0.125 m.
    for (int a = 0; a < 3; ++a) {
      const double q = s.model_segment.b[a] / 0.125;
      EXPECT_NEAR(q, std::round(q), 1e-9);
      EXPECT_EQ(static_cast<long>(std::round(q)) % 2 != 0, true);
    }
  }
}

// ---- the command line ----------------------------------------------------------------------

CommandResult run(const std::string& args) { return run_camplace(CAMPLACE_BINARY, args); }

TEST(ExportCommand, WritesGlbPagePosesAndVoxels) {
  const std::string dir = temp_dir("export_cli") + "/out";
  const CommandResult r = run("export " + kData + "paper_basic.json --cameras " + kData +
                              "paper_basic_corners.json --out " + dir);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("Err = 0.083112"), std::string::npos) << r.output;
  for (const char* file : {"state-0-0.glb", "state-0-1.glb", "state-0-2.glb", "state-1-0.glb",
                           "state-1-1.glb", "state-1-2.glb", "index.html", "viewer-data.js",
                           "three/three.min.js", "three/OrbitControls.js", "three/GLTFLoader.js",
                           "poses.json", "poses.yaml", "voxels.npy", "voxels.json", "voxels.vtk"}) {
    EXPECT_TRUE(fs::is_regular_file(dir + "/" + file)) << file;
  }
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
  }
  // The page loads the copied scripts and its data with plain <script src> (works from file://).
  const std::string page = read_text(dir + "/index.html");
  for (const char* src :
       {"three/three.min.js", "three/OrbitControls.js", "three/GLTFLoader.js", "viewer-data.js"}) {
    EXPECT_NE(page.find(std::string("<script src=\"") + src + "\"></script>"), std::string::npos);
  }
  EXPECT_EQ(page.find("http://"), std::string::npos);
  EXPECT_EQ(page.find("https://"), std::string::npos);
  EXPECT_EQ(read_text(dir + "/three/three.min.js"),
            read_text(std::string(view::kDefaultThreeDir) + "/three.min.js"));
  const auto poses = nlohmann::json::parse(read_text(dir + "/poses.json"));
  ASSERT_EQ(poses["cameras"].size(), 6u);
  EXPECT_EQ(poses["cameras"][4]["position"], nlohmann::json({2.0, 0.0, 3.0}));
  const auto voxels = nlohmann::json::parse(read_text(dir + "/voxels.json"));
  EXPECT_EQ(voxels["shape"], nlohmann::json({6, 12, 12, 16}));
}

TEST(ExportCommand, OpensAnOptimizeRunFile) {
  const std::string dir = temp_dir("export_run") + "/out";
  const std::string run_file =
      std::string(CAMPLACE_SOURCE_DIR) + "/docs/reports/optimizer_paper_basic/runs/run-1.json";
  const CommandResult r = run("export " + kData + "paper_basic.json --cameras " + run_file +
                              " --state 0,1 --out " + dir);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::is_regular_file(dir + "/state-0-1.glb"));
  EXPECT_FALSE(fs::exists(dir + "/state-0-0.glb"));
  const std::string data = read_text(dir + "/viewer-data.js");
  EXPECT_NE(data.find("run-1.json"), std::string::npos);
}

TEST(ExportCommand, BadInputsExitOneNamingTheOptionAndWriteNothing) {
  const std::string dir = temp_dir("export_bad");
  const std::string two = write_file(
      dir + "/two.json",
      R"({"cameras": [{"position": [1,1,1], "yaw_deg": 0, "pitch_deg": 0}, {"position": [1,1,1], "yaw_deg": 0, "pitch_deg": 0}]})");
  const std::string a_file = write_file(dir + "/a_file", "x");
  const std::string basic =
      "export " + kData + "paper_basic.json --cameras " + kData + "paper_basic_corners.json";
  const std::string out = dir + "/out";
  struct Case {
    std::string args, expect;
  } cases[] = {
      {basic + " --out /proc/camplace-test", "--out: cannot create directory"},
      {basic + " --out " + a_file, "--out: cannot create directory"},
      {basic + " --state 2,0 --out " + out,
       "--state: no state 2,0: " + kData + "paper_basic.json has time steps 0..1"},
      {basic + " --state 1,3 --out " + out, "--state: no state 1,3: time step 1 of"},
      {basic + " --state 1 --out " + out, "--state: expected H,L"},
      {"export " + kData + "paper_basic.json --cameras " + two + " --out " + out,
       "two.json: /cameras: holds 2 cameras but the scene"},
      {basic + " --pipeline both --out " + out, "--pipeline"},
      {basic + " --three-dir " + dir + "/nothing --out " + out, "--three-dir: " + dir +
                                                                    "/nothing/three.min.js cannot "
                                                                    "be read"},
      {basic + " --resolution 0x1x1 --out " + out, "--resolution"},
      {basic, "--out"},
  };
  for (const Case& c : cases) {
    const CommandResult r = run(c.args);
    EXPECT_EQ(r.exit_code, 1) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_EQ(r.output.rfind("error: ", 0), 0u) << r.output;
    EXPECT_FALSE(fs::exists(out)) << c.args;  // refused before anything was written
  }
  // A file that cannot be written: the error names it; no temporary or partial file remains.
  fs::create_directories(out + "/index.html");
  const CommandResult r = run(basic + " --out " + out);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("--out: " + out + "/index.html: is a directory"), std::string::npos)
      << r.output;
  for (const auto& entry : fs::recursive_directory_iterator(out)) {
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
  }
}

}  // namespace
}  // namespace camplace::testing
