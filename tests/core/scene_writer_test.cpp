// The scene writer is the inverse of the scene loader (SPEC §2): load → write → load gives the
// same scene, every number and every vertex bit for bit, and write → load → write the same
// text; angles come back as the degrees the file gave; the paper's basic setup is written as
// the file it was read from.
#include "camplace/core/scene_writer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "camplace/core/scene.hpp"
#include "command.hpp"
#include "scene_builder.hpp"
#include "scene_fixtures.hpp"

namespace camplace::testing {
namespace {

using nlohmann::json;

const std::string kBasicScene = std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic.json";

// The written JSON with unordered keys, to compare with json values.
json unordered(const nlohmann::ordered_json& j) { return json::parse(j.dump()); }

void expect_same_interval(const core::Interval& a, const core::Interval& b,
                          const std::string& what) {
  EXPECT_EQ(a.lo, b.lo) << what;
  EXPECT_EQ(a.hi, b.hi) << what;
}

void expect_same_objects(const std::vector<core::SceneObject>& a,
                         const std::vector<core::SceneObject>& b, const std::string& what,
                         bool entries) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const std::string object = what + "[" + std::to_string(k) + "]";
    EXPECT_EQ(a[k].name, b[k].name) << object;
    if (entries) {
      EXPECT_EQ(a[k].entry, b[k].entry) << object;
    }
    EXPECT_EQ(a[k].mesh.vertices, b[k].mesh.vertices) << object;
    EXPECT_EQ(a[k].mesh.triangles, b[k].mesh.triangles) << object;
    EXPECT_EQ(a[k].bounds.min, b[k].bounds.min) << object;
    EXPECT_EQ(a[k].bounds.max, b[k].bounds.max) << object;
  }
}

// Every field of the scene but the files it came from (the scene file and its mesh files: the
// writer writes meshes inline); the objects' entries (JSON pointers) only when both scenes were
// loaded from files.
void expect_same_scene(const core::Scene& a, const core::Scene& b, bool entries = true) {
  EXPECT_EQ(a.area.min, b.area.min);
  EXPECT_EQ(a.area.max, b.area.max);
  EXPECT_EQ(a.voxels, b.voxels);
  EXPECT_EQ(a.cameras.count, b.cameras.count);
  ASSERT_EQ(a.cameras.models.size(), b.cameras.models.size());
  for (std::size_t i = 0; i < a.cameras.models.size(); ++i) {
    const core::CameraModel& ma = a.cameras.models[i];
    const core::CameraModel& mb = b.cameras.models[i];
    const std::string what = "model of camera " + std::to_string(i);
    EXPECT_EQ(ma.name, mb.name) << what;
    EXPECT_EQ(ma.half_angle, mb.half_angle) << what;
    EXPECT_EQ(ma.fov, mb.fov) << what;
    EXPECT_EQ(ma.sides, mb.sides) << what;
    EXPECT_EQ(ma.horizontal, mb.horizontal) << what;
    EXPECT_EQ(ma.vertical, mb.vertical) << what;
    EXPECT_EQ(ma.near, mb.near) << what;
    EXPECT_EQ(ma.range, mb.range) << what;
  }
  ASSERT_EQ(a.cameras.domains.size(), b.cameras.domains.size());
  for (std::size_t i = 0; i < a.cameras.domains.size(); ++i) {
    const std::string what = "domain " + std::to_string(i);
    expect_same_interval(a.cameras.domains[i].x, b.cameras.domains[i].x, what + " x");
    expect_same_interval(a.cameras.domains[i].y, b.cameras.domains[i].y, what + " y");
    expect_same_interval(a.cameras.domains[i].z, b.cameras.domains[i].z, what + " z");
    expect_same_interval(a.cameras.domains[i].yaw, b.cameras.domains[i].yaw, what + " yaw");
    expect_same_interval(a.cameras.domains[i].pitch, b.cameras.domains[i].pitch, what + " pitch");
    expect_same_interval(a.cameras.domains[i].roll, b.cameras.domains[i].roll, what + " roll");
  }
  expect_same_objects(a.static_obstacles, b.static_obstacles, "static", entries);
  ASSERT_EQ(a.time_steps.size(), b.time_steps.size());
  for (std::size_t h = 0; h < a.time_steps.size(); ++h) {
    const core::TimeStep& sa = a.time_steps[h];
    const core::TimeStep& sb = b.time_steps[h];
    const std::string what = "step " + std::to_string(h);
    EXPECT_EQ(sa.t, sb.t) << what;
    expect_same_objects(sa.dynamic_obstacles, sb.dynamic_obstacles, what + " dynamic", entries);
    expect_same_objects(sa.critical, sb.critical, what + " critical", entries);
    ASSERT_EQ(sa.events.size(), sb.events.size()) << what;
    for (std::size_t l = 0; l < sa.events.size(); ++l) {
      EXPECT_EQ(sa.events[l].weight, sb.events[l].weight) << what << " event " << l;
      expect_same_objects(sa.events[l].targets, sb.events[l].targets,
                          what + " event " + std::to_string(l), entries);
    }
  }
  EXPECT_EQ(a.dynamic_mode, b.dynamic_mode);
  EXPECT_EQ(a.plausibility.min_volume, b.plausibility.min_volume);
  EXPECT_EQ(a.plausibility.min_height, b.plausibility.min_height);
}

// Writes `scene` into `dir`, loads it back, expects the same scene and, written again, the same
// text. Returns the reloaded scene.
core::Scene expect_round_trip(const core::Scene& scene, const std::string& dir,
                              bool entries = true) {
  const std::string text = core::scene_text(scene);
  const core::Scene back = core::load_scene(write_file(dir + "/written.json", text));
  expect_same_scene(scene, back, entries);
  EXPECT_EQ(core::scene_text(back), text);
  return back;
}

TEST(SceneWriter, PapersBasicSetupIsWrittenAsTheFileItWasReadFrom) {
  const core::Scene basic = core::load_scene(kBasicScene);
  expect_round_trip(basic, temp_dir("writer-basic"));
  // Value for value the hand-written file (0 and 0.0 compare equal), tetrahedra as tetrahedra
  // with their points in the file's order, 30° as 30, the domain as its preset.
  json original = json::parse(read_text(kBasicScene));
  const std::string description = original["description"];
  original.erase("description");
  EXPECT_EQ(json::parse(core::scene_text(basic)), original);
  const nlohmann::ordered_json with = core::scene_json(basic, description);
  EXPECT_EQ(with.begin().key(), "description");
  EXPECT_EQ(with["description"], description);
  EXPECT_TRUE(with["cameras"]["half_angle_deg"].is_number_integer());
}

// The scenes of the paper study (written by `camplace generate`'s generator through this
// writer) load and are written back byte for byte: the writer is the inverse of the loader on
// them, with the pyramids' vertex order, the tetrahedra, 30°, the presets and "t" as written.
TEST(SceneWriter, GeneratedStudyScenesAreWrittenBackByteForByte) {
  const std::string dir = std::string(CAMPLACE_SOURCE_DIR) + "/docs/reports/study_paper/scenes";
  int scenes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string path = entry.path().string();
    const std::string text = read_text(path);
    const std::string description = json::parse(text)["description"];
    EXPECT_EQ(core::scene_text(core::load_scene(path), description), text) << path;
    ++scenes;
  }
  EXPECT_EQ(scenes, 55);
}

// Every key the loader reads, objects of every kind (mesh files with transforms, boxes,
// tetrahedra given inward, inline meshes, unnamed objects), per-camera domains with presets,
// yaw and pitch bounds, range, pyramid FOV, modelled mode, plausibility, explicit critical
// objects (different from the dynamic obstacles, equal to them, without dynamic obstacles),
// default and explicit times, a zero weight and event names (which the scene does not keep).
json every_feature_scene(const std::string& dir) {
  // A unit cube of quads (the reader fans them) and a unit tetrahedron.
  write_file(dir + "/m/cube.off",
             "OFF\n8 6 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n"
             "4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n");
  write_file(dir + "/m/tet.obj",
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  return json::parse(R"({
    "name": "every feature",
    "description": "not kept by the scene",
    "area": {"min": [-1, -0.5, 0], "max": [3.3, 2.7, 3.1]},
    "voxels": [10, 7, 9],
    "cameras": {
      "count": 4, "half_angle_deg": 27.3, "fov": "pyramid", "sides": 5, "range": 6.25,
      "domain": {"preset": "upper_fourth", "yaw_deg": [-90, 45.5]},
      "camera_domains": [null, "ceiling",
                         {"x": [0, 1], "y": [0.5, 0.5], "z": [1, 2], "pitch_deg": [-60.1, -10]},
                         "room"]
    },
    "static_obstacles": [
      {"name": "table", "box": {"min": [0.2, 0.2, 0], "max": [1, 1, 0.8]}},
      {"tetrahedron": [[2, 0, 0], [2, 1, 0], [3, 0, 0], [2.2, 0.2, 1]]},
      {"name": "cabinet", "file": "m/cube.off",
       "transform": {"scale": [0.3, 0.4, 0.5], "rotate_deg": [5, -4, 17.5], "translate": [-0.7, 1.5, 0]}},
      {"name": "lamp", "mesh": {
        "vertices": [[1.5, 2.2, 2.2], [1.5, 2.2, 2.8], [1.2, 2.2, 2.5], [1.8, 2.2, 2.5],
                     [1.5, 1.9, 2.5], [1.5, 2.5, 2.5]],
        "triangles": [[0, 2, 4], [0, 4, 3], [0, 3, 5], [0, 5, 2],
                      [1, 4, 2], [1, 3, 4], [1, 5, 3], [1, 2, 5]]}}
    ],
    "time_steps": [
      {"t": 0.25,
       "dynamic_obstacles": [{"name": "arm", "tetrahedron": [[0.2, 1.8, 0], [0.6, 1.8, 0], [0.2, 2.2, 0], [0.3, 1.9, 0.9]]}],
       "critical": [{"name": "tool", "box": {"min": [1.2, 0.2, 1.5], "max": [1.4, 0.4, 1.7]}}],
       "events": [
         {"name": "left", "weight": 0.7, "targets": [{"name": "person", "box": {"min": [1.8, 1.2, 0], "max": [2.2, 1.6, 1.8]}}]},
         {"weight": 0.3, "targets": [{"tetrahedron": [[-0.5, -0.3, 0], [0, -0.3, 0], [-0.3, 0.2, 0], [-0.3, -0.1, 1.6]]}]}
       ]},
      {"dynamic_obstacles": [{"name": "crate", "file": "m/tet.obj", "transform": {"scale": 0.5, "translate": [2.5, 2, 2]}}],
       "critical": [{"name": "crate", "file": "m/tet.obj", "transform": {"scale": 0.5, "translate": [2.5, 2, 2]}}],
       "events": [
         {"weight": 0, "targets": [{"name": "person", "box": {"min": [1.8, 1.2, 0], "max": [2.2, 1.6, 1.8]}}]},
         {"weight": 1.0, "targets": [{"name": "child", "box": {"min": [0.1, 1.05, 0], "max": [0.5, 1.3, 1.7]}}]}
       ]},
      {"t": 7.5,
       "critical": [{"name": "hand", "tetrahedron": [[2.8, 2.2, 1], [3.2, 2.2, 1], [2.8, 2.6, 1], [2.9, 2.3, 1.4]]}],
       "events": [{"weight": 0.5, "targets": [{"name": "person", "box": {"min": [1.8, 1.2, 0], "max": [2.2, 1.6, 1.8]}}]}]}
    ],
    "dynamic_mode": "modelled",
    "plausibility": {"min_volume": 0.001, "min_height": 0.5}
  })");
}

TEST(SceneWriter, SceneWithEveryFeatureRoundTripsExactly) {
  const std::string dir = temp_dir("writer-features");
  const core::Scene scene =
      core::load_scene(write_file(dir + "/scene.json", every_feature_scene(dir).dump()));
  // The features are really there (so the round trip below covers them).
  ASSERT_EQ(scene.cameras.domains.size(), 4u);
  EXPECT_EQ(scene.cameras.domains[0].yaw.hi, 45.5 * core::kDegree);
  EXPECT_EQ(scene.cameras.domains[1].z.lo, 3.1);
  ASSERT_EQ(scene.time_steps.size(), 3u);
  EXPECT_EQ(scene.time_steps[1].t, 1.0);
  EXPECT_EQ(scene.time_steps[1].critical[0].entry, "/time_steps/1/critical/0");
  EXPECT_EQ(scene.static_obstacles[1].name, "/static_obstacles/1");

  const core::Scene back = expect_round_trip(scene, dir);
  EXPECT_FALSE(scene.mesh_files.empty());
  EXPECT_TRUE(back.mesh_files.empty());  // the meshes are written inline

  // Each object keeps its form: a tetrahedron's points in the order given (the loader turned
  // its faces outward), a box as min and max, anything else as a mesh.
  const json written = unordered(core::scene_json(scene));
  const json& statics = written["static_obstacles"];
  EXPECT_EQ(statics[0]["box"], json::parse(R"({"min": [0.2, 0.2, 0], "max": [1, 1, 0.8]})"));
  EXPECT_EQ(statics[1]["tetrahedron"],
            json::parse("[[2, 0, 0], [2, 1, 0], [3, 0, 0], [2.2, 0.2, 1]]"));
  EXPECT_EQ(statics[1]["name"], "/static_obstacles/1");
  EXPECT_EQ(statics[2]["mesh"]["triangles"].size(), 12u);  // the transformed file
  EXPECT_TRUE(statics[3].contains("mesh"));
  // The camera block: per-camera domains (the shared one with its yaw bound, the presets by
  // name), angles as the file gave them.
  const json& cameras = written["cameras"];
  EXPECT_EQ(cameras["half_angle_deg"], 27.3);
  EXPECT_EQ(cameras["fov"], "pyramid");
  EXPECT_EQ(cameras["range"], 6.25);
  EXPECT_FALSE(cameras.contains("domain"));
  const json& domains = cameras["camera_domains"];
  EXPECT_EQ(domains[0], json::parse(R"({"x": [-1, 3.3], "y": [-0.5, 2.7], "z": [2.325, 3.1],
                                        "yaw_deg": [-90, 45.5]})"));
  EXPECT_EQ(domains[1], "ceiling");
  EXPECT_EQ(domains[2], json::parse(R"({"x": [0, 1], "y": [0.5, 0.5], "z": [1, 2],
                                        "pitch_deg": [-60.1, -10]})"));
  EXPECT_EQ(domains[3], "room");
  // Critical objects: written when they are not the default copy of the dynamic obstacles.
  EXPECT_TRUE(written["time_steps"][0].contains("critical"));
  EXPECT_TRUE(written["time_steps"][1].contains("critical"));  // equal meshes, other entries
  EXPECT_TRUE(written["time_steps"][2].contains("critical"));
  EXPECT_EQ(written["time_steps"][1]["t"], 1.0);
  EXPECT_EQ(written["dynamic_mode"], "modelled");
}

// Camera models: per-model counts, a list of cameras naming their models, frusta,
// near planes and roll domains are written back as the loader reads them.
TEST(SceneWriter, CameraModelsAndRollDomainsRoundTrip) {
  json scene = json::parse(read_text(kBasicScene));
  scene["cameras"] = json::parse(R"({"models": [
      {"name": "rgb", "fov": "frustum", "horizontal_deg": 90, "vertical_deg": 59.5,
       "range": [0.25, 7], "count": 2},
      {"name": "wide", "half_angle_deg": 40, "fov": "pyramid", "sides": 5, "range": 6, "count": 1}],
      "domain": {"preset": "room", "roll_deg": [-30, 45]}})");
  const std::string dir = temp_dir("writer-models");
  const core::Scene grouped = core::load_scene(write_file(dir + "/grouped.json", scene.dump()));
  ASSERT_EQ(grouped.cameras.count, 3);
  const core::Scene back = expect_round_trip(grouped, dir);
  EXPECT_EQ(core::scene_json(back)["cameras"]["models"][0]["count"], 2);
  // Not grouped: a list naming each camera's model, and per-camera domains.
  scene["cameras"] = json::parse(R"({"models": [
      {"name": "rgb", "fov": "frustum", "horizontal_deg": 90, "vertical_deg": 59.5},
      {"name": "cone", "half_angle_deg": 30}],
      "list": [{"model": "rgb"}, {"model": "cone"}, {"model": "rgb", "domain": "ceiling"}]})");
  const core::Scene listed = core::load_scene(write_file(dir + "/listed.json", scene.dump()));
  ASSERT_EQ(listed.cameras.count, 3);
  EXPECT_EQ(listed.cameras.models[1].name, "cone");
  EXPECT_EQ(listed.cameras.models[2].fov, core::FovShape::frustum);
  EXPECT_TRUE(listed.cameras.domains[2].z.fixed());
  const nlohmann::ordered_json written = core::scene_json(expect_round_trip(listed, dir));
  EXPECT_EQ(written["cameras"]["list"].size(), 3u);
}

TEST(SceneWriter, SharedDomainIsWrittenOnceAndDefaultCriticalIsLeftOut) {
  const std::string dir = temp_dir("writer-shared");
  json file = base_scene();
  file["cameras"]["domain"] = {{"preset", "ceiling"}, {"yaw_deg", {-30, 30}}};
  const core::Scene scene = core::load_scene(write_file(dir + "/scene.json", file.dump()));
  const core::Scene back = expect_round_trip(scene, dir);
  const json written = unordered(core::scene_json(back));
  EXPECT_FALSE(written["cameras"].contains("camera_domains"));
  // The ceiling preset's pitch range [−90°, 0] is not the unrestricted one: written out.
  EXPECT_EQ(written["cameras"]["domain"],
            json::parse(R"({"x": [0, 4], "y": [0, 3], "z": [3, 3], "yaw_deg": [-30, 30],
                            "pitch_deg": [-90, 0]})"));
  EXPECT_FALSE(written["time_steps"][0].contains("critical"));
  EXPECT_EQ(written["time_steps"][0]["t"], 0.0);
  EXPECT_FALSE(written.contains("plausibility"));  // no threshold set
  EXPECT_EQ(written["dynamic_mode"], "masked");
}

// Degrees d are read as d · π/180; the writer finds a degree value that reads back as exactly
// the same radians: the decimal the file gave when it was short, some value otherwise. Each
// scene's 256 cameras have their own yaw and pitch bounds: 1024 angles per scene.
void expect_angles_round_trip(const std::vector<double>& yaw, const std::vector<double>& pitch,
                              double half_angle_deg, bool short_decimals) {
  const std::string dir = temp_dir("writer-angles");
  const std::size_t n = std::max(yaw.size(), pitch.size());
  for (std::size_t start = 0; start < n; start += 512) {
    const std::size_t cameras = std::min<std::size_t>(256, (n - start + 1) / 2);
    auto value = [&](const std::vector<double>& v, std::size_t k) { return v[k % v.size()]; };
    auto interval = [&](const std::vector<double>& v, std::size_t k) {
      return json::array(
          {std::min(value(v, k), value(v, k + 1)), std::max(value(v, k), value(v, k + 1))});
    };
    json domains = json::array();
    for (std::size_t i = 0; i < cameras; ++i) {
      const std::size_t k = start + 2 * i;
      domains.push_back({{"yaw_deg", interval(yaw, k)}, {"pitch_deg", interval(pitch, k)}});
    }
    json file = base_scene();
    file["cameras"]["count"] = cameras;
    file["cameras"]["half_angle_deg"] = half_angle_deg;
    file["cameras"]["camera_domains"] = domains;
    const core::Scene scene = core::load_scene(write_file(dir + "/angles.json", file.dump()));
    SCOPED_TRACE("cameras from value " + std::to_string(start));
    expect_round_trip(scene, dir);
    if (short_decimals) {
      const json written = json::parse(core::scene_text(scene));
      for (std::size_t i = 0; i < cameras; ++i) {
        const json& d = written["cameras"]["camera_domains"][i];
        EXPECT_EQ(d["yaw_deg"], domains[i]["yaw_deg"]) << "camera " << i;
        EXPECT_EQ(d["pitch_deg"], domains[i]["pitch_deg"]) << "camera " << i;
      }
      EXPECT_EQ(written["cameras"]["half_angle_deg"], half_angle_deg);
    }
  }
}

TEST(SceneWriter, AnglesReadBackAsExactlyTheSameRadians) {
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Whole degrees, random ones with 3 or 4 decimals, tiny ones.
  std::vector<double> yaw, pitch;
  for (int d = -180; d <= 180; ++d) yaw.push_back(d);
  for (int d = -90; d <= 90; ++d) pitch.push_back(d);
  for (int k = 0; k < 400; ++k) {
    yaw.push_back(std::round((-180 + 360 * unit(rng)) * 1000) / 1000);
    pitch.push_back(std::round((-90 + 180 * unit(rng)) * 10000) / 10000);
  }
  yaw.push_back(1e-7);
  pitch.push_back(-2.5e-5);
  expect_angles_round_trip(yaw, pitch, 30, true);
  expect_angles_round_trip(yaw, pitch, 27.3, true);
  // Full double precision.
  std::vector<double> long_yaw, long_pitch;
  for (int k = 0; k < 1024; ++k) {
    long_yaw.push_back(-180 + 360 * unit(rng));
    long_pitch.push_back(-90 + 180 * unit(rng));
  }
  expect_angles_round_trip(long_yaw, long_pitch, 1 + 88 * unit(rng), false);
  // Whole degrees are written as integers, as in hand-written scene files.
  const std::string dir = temp_dir("writer-integers");
  json file = base_scene();
  file["cameras"]["half_angle_deg"] = 30.0;
  file["cameras"]["domain"] = {{"yaw_deg", {-45.0, 90.0}}, {"pitch_deg", {-60.5, 0.0}}};
  const json written =
      unordered(core::scene_json(core::load_scene(write_file(dir + "/scene.json", file.dump()))));
  EXPECT_TRUE(written["cameras"]["half_angle_deg"].is_number_integer());
  EXPECT_EQ(written["cameras"]["domain"]["yaw_deg"].dump(), "[-45,90]");
  EXPECT_EQ(written["cameras"]["domain"]["pitch_deg"].dump(), "[-60.5,0]");
}

// Scenes built in code (the tests' random scenes: boxes and tetrahedra, both FOV shapes,
// ranges, both modes) are written so that they load as the same scene.
TEST(SceneWriter, ScenesBuiltInCodeLoadAsTheSameScene) {
  const std::string dir = temp_dir("writer-random");
  std::mt19937 rng(7);
  for (int k = 0; k < 6; ++k) {
    SCOPED_TRACE("random scene " + std::to_string(k));
    const core::Scene scene = random_scene(rng, {8, 6, 6});
    expect_round_trip(scene, dir, /*entries=*/false);
  }
}

TEST(SceneWriter, WriteSceneWritesTheTextAtomically) {
  const std::string dir = temp_dir("writer-file");
  const core::Scene scene = core::load_scene(kBasicScene);
  const std::string path = dir + "/sub/scene.json";
  core::write_scene(scene, path, "the basic setup");
  EXPECT_EQ(read_text(path), core::scene_text(scene, "the basic setup"));
  int files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir + "/sub"))
    ++files;
  EXPECT_EQ(files, 1);  // no temporary file left behind
  write_file(dir + "/plain", "x");
  EXPECT_THROW(core::write_scene(scene, dir + "/plain/scene.json"), std::runtime_error);
}

}  // namespace
}  // namespace camplace::testing
