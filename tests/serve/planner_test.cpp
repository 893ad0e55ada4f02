// camplace::serve::Planner, the state behind `camplace serve`, without HTTP: every answer checked
// against an independent evaluator, the repair against hand-computed points, undo, add/remove,
// save files read back as `camplace evaluate` reads them, and the errors.
#include "camplace/serve/planner.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "camplace/compare/evaluation_json.hpp"
#include "camplace/core/camera.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/scene.hpp"
#include "command.hpp"
#include "scene_builder.hpp"

namespace camplace::serve {
namespace {

using json = nlohmann::json;

const std::string kScene = std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic.json";
const std::string kCorners = std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic_corners.json";

PlannerOptions options(const std::string& out) {
  PlannerOptions o;
  o.voxel.resolution = {16, 12, 12};
  o.voxel.threads = 2;
  o.scene_file = kScene;
  o.cameras_file = kCorners;
  o.out_dir = out;
  return o;
}

json entries(const json& view) {
  json out = json::array();
  for (const json& c : view["cameras"]) {
    out.push_back(
        {{"position", c["position"]}, {"yaw_deg", c["yaw_deg"]}, {"pitch_deg", c["pitch_deg"]}});
  }
  return out;
}

/// Err of `cameras` (camera-file entries) by a fresh evaluator of `scene`.
double reference_err(const core::Scene& scene, const json& cameras) {
  voxel::VoxelOptions o;
  o.resolution = {16, 12, 12};
  const core::CameraConfig config =
      core::camera_config_from_json(json{{"cameras", cameras}}, "test", &scene);
  return voxel::VoxelEvaluator(scene, o).evaluate(config).err;
}

TEST(Planner, MovedCameraGivesTheErrOfAnIndependentEvaluator) {
  const core::Scene scene = core::load_scene(kScene);
  Planner planner(scene, core::load_camera_config(kCorners, scene),
                  options(testing::temp_dir("planner_move")));
  json cams = entries(planner.view(0));
  EXPECT_DOUBLE_EQ(planner.view(0)["err"].get<double>(), reference_err(scene, cams));
  cams[0]["position"] = {0.5, 0.25, 2.8};
  cams[2]["yaw_deg"] = 10.0;
  const json v = planner.update({{"cameras", cams}, {"state", 3}});
  EXPECT_EQ(v["state"], 3);
  EXPECT_EQ(v["cameras"][0]["position"], json({0.5, 0.25, 2.8}));
  EXPECT_EQ(v["cameras"][0]["snapped"], "");
  EXPECT_EQ(v["err"].get<double>(), reference_err(scene, cams));
  EXPECT_EQ(v["states"].size(), 6u);
  EXPECT_FALSE(v["model"]["triangles"].empty());
  EXPECT_EQ(v["fovs"].size(), 6u);
  // The selected state's diagnostics, as `camplace evaluate` gives them for all states.
  ASSERT_EQ(v["diagnostics"]["states"].size(), 1u);
  voxel::VoxelOptions o;
  o.resolution = {16, 12, 12};
  const voxel::VoxelEvaluator evaluator(scene, o);
  const json all = compare::voxel_diagnostics(
      evaluator, core::camera_config_from_json(json{{"cameras", cams}}, "test", &scene));
  json mine = v["diagnostics"]["states"][0];
  const json observed_by = mine["nearest_component"]["observed_by"];
  EXPECT_EQ(observed_by.size(), mine["nearest_component"]["cameras_observing"].get<std::size_t>());
  mine["nearest_component"].erase("observed_by");
  EXPECT_EQ(mine, all["states"][3]);
  EXPECT_EQ(v["undo"], 1);
  EXPECT_TRUE(v["dirty"].get<bool>());
}

TEST(Planner, CamerasAreKeptInTheirDomainAndOutOfKeepOutBoxes) {
  core::Scene scene = core::load_scene(kScene);
  core::KeepOut box;
  box.name = "reach";
  box.entry = "/cameras/keep_out/0";
  box.box = {core::Vec3(1.0, 1.0, 2.0), core::Vec3(3.0, 2.0, 3.5)};
  scene.cameras.keep_out.push_back(box);
  Planner planner(scene, core::load_camera_config(kCorners, scene),
                  options(testing::temp_dir("planner_repair")));
  json cams = entries(planner.view(0));
  cams[0]["position"] = {9.0, -1.0, 1.0};  // outside S (room domain: S = [0,4]x[0,3]x[0,3])
  cams[1]["position"] = {1.2, 1.5, 2.5};   // in the box: its nearest free point is x = 1
  const json v = planner.update({{"cameras", cams}});
  EXPECT_EQ(v["cameras"][0]["position"], json({4.0, 0.0, 1.0}));
  EXPECT_EQ(v["cameras"][0]["snapped"], "kept in its domain");
  EXPECT_EQ(v["cameras"][1]["position"], json({1.0, 1.5, 2.5}));
  EXPECT_EQ(v["cameras"][1]["snapped"], "moved out of keep-out box \"reach\"");
  EXPECT_EQ(v["cameras"][2]["snapped"], "");
}

TEST(Planner, UndoStepsBackThroughCommittedChangesAndDrops) {
  const core::Scene scene = core::load_scene(kScene);
  Planner planner(scene, core::load_camera_config(kCorners, scene),
                  options(testing::temp_dir("planner_undo")));
  const json first = planner.view(0);
  json cams = entries(first);
  cams[0]["position"] = {1.0, 1.0, 3.0};
  const json second = planner.update({{"cameras", cams}});
  cams[0]["position"] = {2.0, 1.0, 3.0};
  planner.update({{"cameras", cams}, {"commit", false}});  // a drag, not released
  EXPECT_EQ(planner.undo(0)["cameras"], second["cameras"]);
  const json back = planner.undo(0);
  EXPECT_EQ(back["cameras"], first["cameras"]);
  EXPECT_EQ(back["err"], first["err"]);
  EXPECT_EQ(back["undo"], 0);
  EXPECT_FALSE(back["dirty"].get<bool>());
  EXPECT_EQ(planner.undo(0)["cameras"], first["cameras"]);  // nothing more to undo
  // The same configuration sent again is no new undo step.
  EXPECT_EQ(planner.update({{"cameras", entries(first)}})["undo"], 0);
}

TEST(Planner, AddedCamerasAreSavedWithTheirSceneAndEvaluateTheSame) {
  const core::Scene scene = core::load_scene(kScene);
  const std::string out = testing::temp_dir("planner_add");
  Planner planner(scene, core::load_camera_config(kCorners, scene), options(out));
  json v = planner.add_camera("", 0);
  ASSERT_EQ(v["cameras"].size(), 7u);
  v = planner.remove_camera(0, 0);
  ASSERT_EQ(v["cameras"].size(), 6u);
  const json saved = planner.save("six.json");
  EXPECT_EQ(saved["cameras_file"], out + "/six.json");
  EXPECT_EQ(saved["scene_file"], kScene);  // the scene's own camera list: no scene written
  planner.add_camera("", 0);
  const json seven = planner.save("seven");
  ASSERT_EQ(seven["scene_file"], out + "/seven.scene.json");
  const core::Scene written = core::load_scene(seven["scene_file"].get<std::string>());
  ASSERT_EQ(written.cameras.count, 7);
  const core::CameraConfig config =
      core::load_camera_config(seven["cameras_file"].get<std::string>(), written);
  voxel::VoxelOptions o;
  o.resolution = {16, 12, 12};
  EXPECT_EQ(voxel::VoxelEvaluator(written, o).evaluate(config).err, seven["err"].get<double>());
  EXPECT_EQ(planner.view(0)["err"].get<double>(), seven["err"].get<double>());
  // The command the page shows, run: `camplace evaluate` reads the same Err.
  std::string command = seven["command"].get<std::string>();
  ASSERT_EQ(command.rfind("camplace evaluate ", 0), 0u);
  const testing::CommandResult run =
      testing::run_camplace(CAMPLACE_BINARY, command.substr(9) + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(json::parse(run.output)["err"].get<double>(), seven["err"].get<double>());
  EXPECT_FALSE(planner.view(0)["dirty"].get<bool>());
  EXPECT_EQ(planner.save_unsaved(), "");
  // A change after the save: written as unsaved-<time>.json (with its scene), Err as shown.
  json cams = entries(planner.view(0));
  cams[6]["position"] = {2.0, 1.5, 2.0};
  const double shown = planner.update({{"cameras", cams}})["err"].get<double>();
  const std::string unsaved = planner.save_unsaved();
  ASSERT_EQ(unsaved.rfind(out + "/unsaved-", 0), 0u) << unsaved;
  const std::string unsaved_scene = unsaved.substr(0, unsaved.size() - 5) + ".scene.json";
  const core::Scene reread = core::load_scene(unsaved_scene);
  EXPECT_EQ(
      voxel::VoxelEvaluator(reread, o).evaluate(core::load_camera_config(unsaved, reread)).err,
      shown);
}

TEST(Planner, BadRequestsAreInputErrorsNamingTheEntry) {
  const core::Scene scene = core::load_scene(kScene);
  Planner planner(scene, core::load_camera_config(kCorners, scene),
                  options(testing::temp_dir("planner_errors")));
  json cams = entries(planner.view(0));
  cams[0]["yaw_deg"] = 190;
  auto message = [&](auto&& call) {
    try {
      call();
    } catch (const core::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message([&] {
              planner.update({{"cameras", cams}});
            }),
            "request: /cameras/0/yaw_deg: value 190 out of range [-180, 180]");
  EXPECT_EQ(message([&] {
              planner.update({{"cameras", json::array()}});
            }),
            "request: /cameras: holds 0 cameras but the scene " + kScene + " has 6");
  EXPECT_EQ(message([&] {
              planner.update({{"camera", 1}});
            }),
            "request: /camera: unknown field \"camera\" (expected one of: cameras, commit, state)");
  EXPECT_EQ(message([&] { planner.view(6); }),
            "request: /state: no state 6: the scene has states 0..5");
  EXPECT_EQ(message([&] { planner.add_camera("rgb", 0); }),
            "request: /model: no camera model \"rgb\" in the scene (it has \"\")");
  EXPECT_EQ(message([&] { planner.remove_camera(6, 0); }),
            "request: /camera: no camera 6: the configuration has cameras 0..5");
  EXPECT_EQ(
      message([&] { planner.save("../x"); }),
      "request: /name: \"../x\" is not a file name of 1..64 letters, digits, '-', '_' and '.'");
}

}  // namespace
}  // namespace camplace::serve
