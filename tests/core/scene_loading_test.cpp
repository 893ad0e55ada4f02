// Scene loading (SPEC §2): every object kind loads; every rejection class is reported with the
// file, the entry (JSON pointer) and the reason.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "camplace/core/error.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/scene.hpp"
#include "scene_builder.hpp"
#include "scene_fixtures.hpp"

namespace camplace::testing {
namespace {

using camplace::testing::expect_rejected;  // beside the overload below
using nlohmann::json;

const char* kCubeOff =
    "OFF\n8 6 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n"
    "4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n";

std::string write_scene(const json& scene, const std::string& name) {
  return write_file(temp_dir("scene-" + name) + "/scene.json", scene.dump(1));
}

void expect_rejected(const json& scene, const std::string& name, const std::string& entry,
                     const std::string& reason) {
  expect_rejected(write_scene(scene, name), entry, reason);
}

const std::vector<std::array<double, 3>> kTetV = {{1, 1, 1}, {2, 1, 1}, {1, 2, 1}, {1, 1, 2}};
const std::vector<std::array<int, 3>> kTetT = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

TEST(SceneLoading, BaseSceneLoadsWithDefaults) {
  const core::Scene s = core::load_scene(write_scene(base_scene(), "base"));
  EXPECT_EQ(s.cameras.count, 2);
  EXPECT_EQ(s.cameras.models[0].fov, core::FovShape::cone);
  EXPECT_EQ(s.cameras.models[0].sides, 16);
  EXPECT_FALSE(s.cameras.models[0].range.has_value());
  ASSERT_EQ(s.cameras.domains.size(), 2u);
  EXPECT_EQ(s.cameras.domains[1].z.hi, 3.0);
  EXPECT_EQ(s.dynamic_mode, core::DynamicMode::masked);
  ASSERT_EQ(s.time_steps.size(), 1u);
  EXPECT_EQ(s.time_steps[0].critical.size(), 1u);  // defaults to the dynamic obstacles
  EXPECT_EQ(s.time_steps[0].critical[0].name, "link");
  EXPECT_NEAR(core::signed_volume(s.static_obstacles[0].mesh), 0.8 * 0.8 * 0.8, 1e-12);
}

TEST(SceneLoading, EveryObjectKindAndMeshFormatLoads) {
  json scene = base_scene();
  const std::string dir = temp_dir("formats");
  write_file(dir + "/m/cube.off", kCubeOff);
  write_file(dir + "/m/cube.obj",
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
             "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n");
  write_file(dir + "/m/tet.stl",
             "solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 "
             "0\nendloop\nendfacet\n"
             "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 "
             "1\nendloop\nendfacet\n"
             "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 "
             "0\nendloop\nendfacet\n"
             "facet normal 0 0 0\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 "
             "1\nendloop\nendfacet\nendsolid t\n");
  write_file(dir + "/m/tet.ply",
             "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float "
             "y\nproperty float z\n"
             "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
             "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  scene["static_obstacles"] = json::array(
      {{{"name", "off"},
        {"file", "m/cube.off"},
        {"transform", {{"scale", 0.5}, {"translate", {0.1, 0.1, 0}}}}},
       {{"name", "obj"},
        {"file", "m/cube.obj"},
        {"transform",
         {{"scale", {0.5, 0.25, 1}}, {"rotate_deg", {0, 0, 90}}, {"translate", {1.5, 2.0, 0}}}}},
       {{"name", "stl"}, {"file", "m/tet.stl"}, {"transform", {{"translate", {0.1, 2.0, 0}}}}},
       {{"name", "ply"},
        {"file", "m/tet.ply"},
        {"transform", {{"scale", 0.5}, {"translate", {3.4, 0.1, 2}}}}},
       inline_mesh({{1.2, 2.2, 2}, {1.6, 2.2, 2}, {1.2, 2.6, 2}, {1.2, 2.2, 2.4}}, kTetT)});
  const core::Scene s = core::load_scene(write_file(dir + "/scene.json", scene.dump()));
  ASSERT_EQ(s.static_obstacles.size(), 5u);
  EXPECT_NEAR(core::signed_volume(s.static_obstacles[0].mesh), 0.125, 1e-12);
  EXPECT_NEAR(core::signed_volume(s.static_obstacles[1].mesh), 0.125, 1e-12);
  // The rotation by 90° about z maps the 0.5 × 0.25 footprint to x ∈ [1.25, 1.5], y ∈ [2, 2.5].
  EXPECT_NEAR(s.static_obstacles[1].bounds.min.x(), 1.25, 1e-12);
  EXPECT_NEAR(s.static_obstacles[1].bounds.max.y(), 2.5, 1e-12);
  EXPECT_NEAR(core::signed_volume(s.static_obstacles[2].mesh), 1.0 / 6, 1e-12);  // STL
  EXPECT_NEAR(core::signed_volume(s.static_obstacles[3].mesh), 1.0 / 48, 1e-9);
  EXPECT_NEAR(core::signed_volume(s.static_obstacles[4].mesh), 0.064 / 6, 1e-12);
}

TEST(SceneLoading, CameraBlockPresetsAndPerCameraDomains) {
  json scene = base_scene();
  scene["cameras"] = json::parse(R"({"count": 3, "half_angle_deg": 25, "fov": "pyramid", "sides": 8,
      "range": 6, "domain": "upper_fourth",
      "camera_domains": [null, {"preset": "ceiling", "yaw_deg": [-90, 90]}, {"x": [0, 1], "y": [0, 1], "z": [2, 3], "pitch_deg": [-90, 0]}]})");
  scene["dynamic_mode"] = "modelled";
  scene["plausibility"] = {{"min_volume", 0.01}, {"min_height", 0.5}};
  const core::Scene s = core::load_scene(write_scene(scene, "cameras"));
  EXPECT_EQ(s.cameras.models[0].fov, core::FovShape::pyramid);
  EXPECT_EQ(s.cameras.models[0].sides, 8);
  EXPECT_EQ(*s.cameras.models[0].range, 6.0);
  EXPECT_DOUBLE_EQ(s.cameras.domains[0].z.lo, 2.25);
  EXPECT_TRUE(s.cameras.domains[1].z.fixed());
  EXPECT_DOUBLE_EQ(s.cameras.domains[1].z.lo, 3.0);
  EXPECT_NEAR(s.cameras.domains[1].yaw.hi, 3.14159265358979323846 / 2, 1e-15);
  EXPECT_DOUBLE_EQ(s.cameras.domains[2].x.hi, 1.0);
  EXPECT_DOUBLE_EQ(s.cameras.domains[2].pitch.hi, 0.0);
  EXPECT_EQ(s.dynamic_mode, core::DynamicMode::modelled);
  EXPECT_DOUBLE_EQ(s.plausibility.min_height, 0.5);
}

// The presets over S = [−1, 3]×[0, 2]×[1, 5] (height 4), by hand: `ceiling` looks
// only down or level, `upper_fourth` is z ∈ [4, 5] with pitch unrestricted.
TEST(DomainPreset, CeilingLooksOnlyDownUpperFourthAndRoomAnywhere) {
  const double pi = 3.14159265358979323846;
  const core::Box3 area{core::Vec3(-1, 0, 1), core::Vec3(3, 2, 5)};
  const auto expect_interval = [](const core::Interval& iv, double lo, double hi,
                                  const char* what) {
    EXPECT_DOUBLE_EQ(iv.lo, lo) << what;
    EXPECT_DOUBLE_EQ(iv.hi, hi) << what;
  };
  for (const char* name : {"room", "ceiling", "upper_fourth"}) {
    const std::optional<core::CameraDomain> d = core::domain_preset(area, name);
    ASSERT_TRUE(d) << name;
    expect_interval(d->x, -1, 3, name);
    expect_interval(d->y, 0, 2, name);
    expect_interval(d->yaw, -pi, pi, name);
  }
  const core::CameraDomain room = *core::domain_preset(area, "room");
  expect_interval(room.z, 1, 5, "room z");
  expect_interval(room.pitch, -pi / 2, pi / 2, "room pitch");
  const core::CameraDomain ceiling = *core::domain_preset(area, "ceiling");
  expect_interval(ceiling.z, 5, 5, "ceiling z");
  expect_interval(ceiling.pitch, -pi / 2, 0, "ceiling pitch");
  const core::CameraDomain upper = *core::domain_preset(area, "upper_fourth");
  expect_interval(upper.z, 4, 5, "upper_fourth z");
  expect_interval(upper.pitch, -pi / 2, pi / 2, "upper_fourth pitch");
  EXPECT_FALSE(core::domain_preset(area, "floor"));
  EXPECT_FALSE(core::domain_preset(area, "Ceiling"));
}

// A domain object starting from `ceiling` keeps pitch ≤ 0 unless it gives pitch_deg; giving it
// brings back the old unrestricted range.
TEST(SceneLoading, CeilingPresetPitchStaysDownUnlessGiven) {
  const double pi = 3.14159265358979323846;
  json scene = base_scene();
  scene["cameras"]["domain"] = "ceiling";
  scene["cameras"]["camera_domains"] = {
      nullptr, {{"preset", "ceiling"}, {"yaw_deg", {-90, 90}}, {"pitch_deg", {-90, 90}}}};
  const core::Scene s = core::load_scene(write_scene(scene, "ceiling-pitch"));
  ASSERT_EQ(s.cameras.domains.size(), 2u);
  EXPECT_DOUBLE_EQ(s.cameras.domains[0].pitch.lo, -pi / 2);
  EXPECT_EQ(s.cameras.domains[0].pitch.hi, 0.0);
  EXPECT_DOUBLE_EQ(s.cameras.domains[1].pitch.hi, pi / 2);
  EXPECT_DOUBLE_EQ(s.cameras.domains[1].yaw.lo, -pi / 2);
  EXPECT_EQ(s.cameras.domains[1].z.lo, s.cameras.domains[1].z.hi);
  // Only the preset's own pitch range is marked (what resuming old run files checks).
  EXPECT_TRUE(s.cameras.domains[0].ceiling_pitch);
  EXPECT_FALSE(s.cameras.domains[1].ceiling_pitch);
  EXPECT_TRUE(core::has_ceiling_pitch(s.cameras));
  scene["cameras"]["domain"] = "room";
  scene["cameras"]["camera_domains"] = {nullptr, "upper_fourth"};
  const core::Scene room = core::load_scene(write_scene(scene, "room-pitch"));
  EXPECT_FALSE(core::has_ceiling_pitch(room.cameras));
}

TEST(SceneLoading, PaperBasicHasTheSetupOfTheTable) {
  const core::Scene s =
      core::load_scene(std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic.json");
  auto facets = [](const std::vector<core::SceneObject>& objects) {
    std::size_t n = 0;
    for (const auto& o : objects) n += o.mesh.triangles.size();
    return n;
  };
  EXPECT_EQ(s.static_obstacles.size(), 2u);
  EXPECT_EQ(facets(s.static_obstacles), 8u);
  ASSERT_EQ(s.time_steps.size(), 2u);
  std::size_t dynamic = 0, targets = 0;
  for (const auto& step : s.time_steps) {
    dynamic += facets(step.dynamic_obstacles);
    ASSERT_EQ(step.events.size(), 3u);
    double weights = 0;
    for (const auto& e : step.events) {
      weights += e.weight;
      EXPECT_EQ(e.targets.size(), 2u);
    }
    EXPECT_NEAR(weights, 1.0, 1e-12);
    targets += facets(step.events[0].targets) * 3 / 2;  // 3 events, counted per place
  }
  EXPECT_EQ(dynamic, 24u);
  EXPECT_EQ(targets, 24u);  // 6 target tetrahedra at 3 places
  EXPECT_EQ(s.cameras.count, 6);
  EXPECT_EQ(s.voxels, (std::array<int, 3>{16, 12, 12}));
}

TEST(SceneRejection, MissingFileAndNotJson) {
  expect_rejected(temp_dir("missing") + "/nope.json", "", "cannot open");
  expect_rejected(write_file(temp_dir("notjson") + "/s.json", "{\"area\": [1, 2,"), "",
                  "not valid JSON");
  std::string twice = base_scene().dump();
  twice.insert(1, "\"voxels\": [8, 8, 8], ");
  expect_rejected(write_file(temp_dir("twice") + "/s.json", twice), "", "\"voxels\" appears twice");
}

TEST(SceneRejection, MissingFieldAndWrongType) {
  json s = base_scene();
  s.erase("area");
  expect_rejected(s, "missing", "/", "missing required field \"area\"");
  s = base_scene();
  s["voxels"] = "16x12x12";
  expect_rejected(s, "type", "/voxels", "expected an array");
}

TEST(SceneRejection, NonFiniteNumber) {
  std::string text = base_scene().dump();
  text.replace(text.find("[4,3,3]"), 7, "[4,1e999,3]");
  expect_rejected(write_file(temp_dir("inf") + "/s.json", text), "", "number overflow");
}

TEST(SceneRejection, OutOfRangeValues) {
  json s = base_scene();
  s["cameras"]["half_angle_deg"] = 95;
  expect_rejected(s, "half", "/cameras/half_angle_deg", "(0, 90)");
  s = base_scene();
  s["cameras"]["sides"] = 2;
  expect_rejected(s, "sides", "/cameras/sides", "out of range");
  s = base_scene();
  s["cameras"]["range"] = -1;
  expect_rejected(s, "range", "/cameras/range", "positive");
  s = base_scene();
  s["plausibility"] = {{"min_volume", -0.1}};
  expect_rejected(s, "plaus", "/plausibility/min_volume", "out of range");
}

TEST(SceneRejection, MessagesShowTheValuesAsGiven) {
  json s = base_scene();
  s["cameras"]["count"] = 18446744073709551615ULL;  // read as unsigned; must not print as -1
  expect_rejected(s, "ubig", "/cameras/count", "value 18446744073709551615 out of range [1, 256]");
  s = base_scene();
  s["cameras"]["domain"] = {{"x", {0, 4.0000001}}};
  expect_rejected(s, "precise", "/cameras/domain/x",
                  "domain [0, 4.0000001] leaves the allowed range [0, 4]");
  s = base_scene();
  s["area"]["min"] = {-1e200, 0, 0};
  expect_rejected(s, "hugearea", "/area/min", "coordinates must lie within");
  EXPECT_EQ(core::format_number(180.0001), "180.0001");
  EXPECT_EQ(core::format_number(0.1), "0.1");
  EXPECT_EQ(core::format_number(4.0000001), "4.0000001");
  EXPECT_EQ(core::format_number(1.0 / 3.0), "0.3333333333333333");
}

TEST(SceneRejection, UnknownFieldIsNamed) {
  json s = base_scene();
  s["plausability"] = {{"min_volume", 0.1}};
  expect_rejected(s, "typo", "/plausability", "unknown field");
}

// Named camera models, per-model counts or a list of cameras, frusta, [near, far].
TEST(SceneLoading, CameraModelsWithCountsOrAList) {
  json scene = base_scene();
  scene["cameras"] = json::parse(R"({"count": 3, "models": [
      {"name": "rgb", "fov": "frustum", "horizontal_deg": 90, "vertical_deg": 59, "range": [0.2, 8],
       "count": 2},
      {"name": "cone", "half_angle_deg": 25, "range": 6, "count": 1}],
      "domain": {"preset": "room", "roll_deg": [-45, 45]}})");
  const core::Scene s = core::load_scene(write_scene(scene, "models"));
  ASSERT_EQ(s.cameras.count, 3);
  ASSERT_EQ(s.cameras.models.size(), 3u);
  const double deg = 3.14159265358979323846 / 180;
  for (int i = 0; i < 2; ++i) {
    const core::CameraModel& m = s.cameras.models[i];
    EXPECT_EQ(m.name, "rgb");
    EXPECT_EQ(m.fov, core::FovShape::frustum);
    EXPECT_DOUBLE_EQ(m.horizontal, 90 * deg);
    EXPECT_DOUBLE_EQ(m.vertical, 59 * deg);
    EXPECT_DOUBLE_EQ(m.near, 0.2);
    EXPECT_EQ(*m.range, 8.0);
    // atan(√(tan²45° + tan²29.5°)) = atan(√(1 + 0.565773²)) = atan(1.148959) = 48.965°.
    EXPECT_NEAR(m.bounding_half_angle() / deg, 48.9652, 1e-3);
  }
  EXPECT_EQ(s.cameras.models[2].name, "cone");
  EXPECT_EQ(s.cameras.models[2].fov, core::FovShape::cone);
  EXPECT_EQ(s.cameras.models[2].near, 0.0);
  EXPECT_DOUBLE_EQ(s.cameras.domains[1].roll.lo, -45 * deg);
  EXPECT_DOUBLE_EQ(s.cameras.domains[1].roll.hi, 45 * deg);
  // Without roll_deg the roll is fixed at 0.
  scene["cameras"]["domain"] = "room";
  EXPECT_TRUE(core::load_scene(write_scene(scene, "models-roll")).cameras.domains[0].roll.fixed());
  // A list naming each camera's model.
  scene["cameras"] = json::parse(R"({"models": [
      {"name": "a", "fov": "frustum", "horizontal_deg": 60, "vertical_deg": 40},
      {"name": "b", "fov": "pyramid", "half_angle_deg": 20, "sides": 4}],
      "list": [{"model": "b"}, {"model": "a", "domain": "ceiling"}]})");
  const core::Scene l = core::load_scene(write_scene(scene, "list"));
  ASSERT_EQ(l.cameras.count, 2);
  EXPECT_EQ(l.cameras.models[0].name, "b");
  EXPECT_EQ(l.cameras.models[1].name, "a");
  EXPECT_FALSE(l.cameras.domains[0].z.fixed());
  EXPECT_TRUE(l.cameras.domains[1].z.fixed());
  // The single-model form may be a frustum too, with a far-only range.
  scene["cameras"] = json::parse(
      R"({"count": 2, "fov": "frustum", "horizontal_deg": 87, "vertical_deg": 58, "range": 5})");
  const core::Scene f = core::load_scene(write_scene(scene, "single-frustum"));
  EXPECT_EQ(f.cameras.models[1].fov, core::FovShape::frustum);
  EXPECT_EQ(f.cameras.models[1].near, 0.0);
  EXPECT_EQ(*f.cameras.models[1].range, 5.0);
  EXPECT_EQ(f.cameras.models[1].name, "");
}

TEST(SceneRejection, BadCameraModels) {
  const json good = json::parse(R"({"models": [
      {"name": "a", "fov": "frustum", "horizontal_deg": 60, "vertical_deg": 40, "count": 1},
      {"name": "b", "half_angle_deg": 20, "count": 1}]})");
  auto with = [&](const std::string& pointer, const json& value) {
    json s = base_scene();
    s["cameras"] = good;
    s["cameras"][json::json_pointer(pointer)] = value;
    return s;
  };
  expect_rejected(with("/models/0/horizontal_deg", 180), "h180", "/cameras/models/0/horizontal_deg",
                  "must lie in (0, 180)");
  expect_rejected(with("/models/0/vertical_deg", 0), "v0", "/cameras/models/0/vertical_deg",
                  "must lie in (0, 180)");
  expect_rejected(with("/models/0/vertical_deg", -5), "vneg", "/cameras/models/0/vertical_deg",
                  "must lie in (0, 180)");
  expect_rejected(with("/models/1/half_angle_deg", 90), "half90",
                  "/cameras/models/1/half_angle_deg", "must lie in (0, 90)");
  expect_rejected(with("/models/0/half_angle_deg", 30), "frustum-half",
                  "/cameras/models/0/half_angle_deg", "not used by a frustum");
  expect_rejected(with("/models/1/vertical_deg", 30), "cone-vertical",
                  "/cameras/models/1/vertical_deg", "used only by a frustum");
  expect_rejected(with("/models/0/range", json::array({2, 2})), "near-far",
                  "/cameras/models/0/range", "must lie below far");
  expect_rejected(with("/models/0/range", json::array({-1, 2})), "near-neg",
                  "/cameras/models/0/range/0", "must not be negative");
  expect_rejected(with("/models/0/range", json::array({1, 2, 3})), "range3",
                  "/cameras/models/0/range", "[near, far]");
  expect_rejected(with("/models/1/name", "a"), "dup", "/cameras/models/1/name", "named twice");
  expect_rejected(with("/count", 3), "count", "/cameras/count", "does not match the 2 cameras");
  expect_rejected(with("/half_angle_deg", 30), "mixed", "/cameras/half_angle_deg",
                  "belongs in a model");
  json s = base_scene();
  s["cameras"] = json::parse(R"({"models": [{"name": "a", "half_angle_deg": 20}, {"name": "b",
      "half_angle_deg": 20}], "list": [{"model": "a"}, {"model": "c"}]})");
  expect_rejected(s, "unknown", "/cameras/list/1/model", "unknown model \"c\"");
  s["cameras"]["models"][0]["count"] = 1;
  expect_rejected(s, "count-list", "/cameras/models/0/count", "not used with \"list\"");
  s = base_scene();
  s["cameras"] = json::parse(R"({"models": [{"name": "a", "half_angle_deg": 20, "count": 1},
      {"name": "b", "half_angle_deg": 20}]})");
  expect_rejected(s, "nocount", "/cameras/models/1", "needs a \"count\"");
  s["cameras"]["models"][1]["count"] = 0;
  s["cameras"]["models"][0]["count"] = 0;
  expect_rejected(s, "zero", "/cameras/models", "sum to 0");
  s = base_scene();
  s["cameras"]["domain"] = {{"roll_deg", {-190, 0}}};
  expect_rejected(s, "roll", "/cameras/domain/roll_deg", "leaves the allowed range");
  s["cameras"]["domain"] = {{"roll_deg", {10, 0}}};
  expect_rejected(s, "roll-empty", "/cameras/domain/roll_deg", "lo > hi");
}

TEST(SceneRejection, CameraCountAndResolutionBelowOne) {
  json s = base_scene();
  s["cameras"]["count"] = 0;
  expect_rejected(s, "count", "/cameras/count", "out of range [1,");
  s = base_scene();
  s["voxels"] = {16, 0, 12};
  expect_rejected(s, "voxels", "/voxels/1", "out of range [1,");
  EXPECT_THROW(core::parse_resolution("16x0x12", "--resolution"), core::InputError);
  EXPECT_THROW(core::parse_resolution("16x12", "--resolution"), core::InputError);
  EXPECT_THROW(core::parse_resolution("4096x4096x4096", "--resolution"), core::InputError);
  s = base_scene();
  s["voxels"] = {4096, 4096, 4};
  expect_rejected(s, "toomany", "/voxels", "too many voxels");
  EXPECT_EQ(core::parse_resolution("20x15x15", "--resolution"), (std::array<int, 3>{20, 15, 15}));
}

TEST(SceneRejection, EmptyDomainOrOutsideArea) {
  json s = base_scene();
  s["cameras"]["domain"] = {{"x", {2, 1}}};
  expect_rejected(s, "empty", "/cameras/domain/x", "empty");
  s = base_scene();
  s["cameras"]["domain"] = {{"preset", "ceiling"}, {"z", {0, 5}}};
  expect_rejected(s, "outside", "/cameras/domain/z", "leaves");
  s = base_scene();
  s["cameras"]["domain"] = "floor";
  expect_rejected(s, "preset", "/cameras/domain", "unknown domain preset");
  s = base_scene();
  s["cameras"]["camera_domains"] = {nullptr};
  expect_rejected(s, "per-camera", "/cameras/camera_domains", "one domain per camera");
}

TEST(SceneRejection, OpenMesh) {
  json s = base_scene();
  auto tris = kTetT;
  tris.pop_back();
  s["static_obstacles"][0] = inline_mesh(kTetV, tris);
  expect_rejected(s, "open", "/static_obstacles/0", "open");
}

TEST(SceneRejection, InconsistentlyOrientedMesh) {
  json s = base_scene();
  auto tris = kTetT;
  std::swap(tris[1][1], tris[1][2]);
  s["static_obstacles"][0] = inline_mesh(kTetV, tris);
  expect_rejected(s, "orient", "/static_obstacles/0", "consistently oriented");
}

TEST(SceneRejection, SelfIntersectingMesh) {
  json s = base_scene();
  // Two interpenetrating tetrahedra in one mesh.
  std::vector<std::array<double, 3>> v = kTetV;
  for (const auto& p : kTetV) v.push_back({p[0] + 0.3, p[1] + 0.3, p[2] + 0.3});
  auto t = kTetT;
  for (const auto& tri : kTetT) t.push_back({tri[0] + 4, tri[1] + 4, tri[2] + 4});
  s["static_obstacles"][0] = inline_mesh(v, t);
  expect_rejected(s, "selfx", "/static_obstacles/0", "intersects itself");
}

TEST(SceneRejection, DegenerateMeshes) {
  json s = base_scene();
  s["static_obstacles"][0] = {{"tetrahedron", {{1, 1, 1}, {2, 1, 1}, {2, 1, 1}, {1, 1, 2}}}};
  expect_rejected(s, "degen", "/static_obstacles/0", "degenerate");
  s = base_scene();
  s["static_obstacles"][0] = {{"box", {{"min", {1, 1, 1}}, {"max", {2, 1, 2}}}}};
  expect_rejected(s, "flatbox", "/static_obstacles/0/box", "degenerate");
}

TEST(SceneRejection, BrokenOrMissingMeshFiles) {
  const std::string dir = temp_dir("meshfiles");
  write_file(dir + "/garbage.off", "OFF\n8 6\nthis is not a mesh\n");
  write_file(dir + "/open.off",
             "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n");
  json s = base_scene();
  s["static_obstacles"][0] = {{"file", "garbage.off"}};
  expect_rejected(write_file(dir + "/a.json", s.dump()), "/static_obstacles/0/file",
                  "cannot be read");
  s["static_obstacles"][0] = {{"file", "nothere.obj"}};
  expect_rejected(write_file(dir + "/b.json", s.dump()), "/static_obstacles/0/file",
                  "does not exist");
  s["static_obstacles"][0] = {{"file", "mesh.xyz"}};
  expect_rejected(write_file(dir + "/c.json", s.dump()), "/static_obstacles/0/file",
                  "unsupported format");
  s["static_obstacles"][0] = {{"file", "open.off"}};
  expect_rejected(write_file(dir + "/d.json", s.dump()), "/static_obstacles/0", "open");
}

TEST(SceneRejection, TargetLeavesArea) {
  json s = base_scene();
  s["time_steps"][0]["events"][0]["targets"][0]["box"]["max"][2] = 3.5;
  expect_rejected(s, "leaves", "/time_steps/0/events/0/targets/0", "leaves the area S");
}

TEST(SceneRejection, TargetIntersectsObstacleOfItsState) {
  json s = base_scene();
  s["time_steps"][0]["events"][0]["targets"][0]["box"] = {{"min", {0.5, 0.5, 0}},
                                                          {"max", {1.5, 1.5, 1.8}}};
  expect_rejected(s, "static", "/time_steps/0/events/0/targets/0", "intersects obstacle \"table\"");
  s = base_scene();
  s["time_steps"][0]["events"][0]["targets"][0]["box"] = {{"min", {3.05, 2.05, 0}},
                                                          {"max", {3.1, 2.1, 0.1}}};
  expect_rejected(s, "inside", "/time_steps/0/events/0/targets/0", "intersects obstacle \"link\"");
}

TEST(SceneRejection, NegativeOrAllZeroWeights) {
  json s = base_scene();
  s["time_steps"][0]["events"][0]["weight"] = -0.5;
  expect_rejected(s, "neg", "/time_steps/0/events/0/weight", "negative");
  s["time_steps"][0]["events"][0]["weight"] = 0;
  expect_rejected(s, "zero", "/time_steps", "all event weights are 0");
}

TEST(SceneRejection, WeightsWhoseErrCouldOverflow) {
  // Err ≤ Σ ω · diag(S)² must stay ≤ core::kMaxErr = 1e150 m²; S is 4×3×3 m: diag(S)² = 34 m².
  json s = base_scene();
  s["time_steps"][0]["events"][0]["weight"] = 1.7e308;  // Err would be infinite
  expect_rejected(s, "huge", "/time_steps/0/events/0/weight",
                  "weight 1.7e+308 is too large: the weights up to here sum to 1.7e+308, and Err "
                  "can reach that sum times diag(S)² = 34 m², which must not exceed 1e+150 m²");
  // Each weight alone is accepted (2e148 · 34 = 6.8e149 m²); their sum is not (1.36e150 m²),
  // named at the entry where it crosses the limit.
  s = base_scene();
  s["time_steps"][0]["events"][0]["weight"] = 2e148;
  EXPECT_NO_THROW(core::load_scene(write_scene(s, "one")));
  s["time_steps"][0]["events"].push_back(s["time_steps"][0]["events"][0]);
  expect_rejected(s, "sum", "/time_steps/0/events/1/weight",
                  "the weights up to here sum to 4e+148");
  // Across time steps too.
  s = base_scene();
  s["time_steps"][0]["events"][0]["weight"] = 2e148;
  s["time_steps"].push_back(s["time_steps"][0]);
  expect_rejected(s, "steps", "/time_steps/1/events/0/weight", "is too large");
}

TEST(SceneRejection, TimeStepWithoutCriticalObjectsOrEvents) {
  json s = base_scene();
  s["time_steps"][0].erase("dynamic_obstacles");
  expect_rejected(s, "nocrit", "/time_steps/0", "no critical objects");
  s = base_scene();
  s["time_steps"][0]["events"] = json::array();
  expect_rejected(s, "noevents", "/time_steps/0/events", "at least one event");
  s = base_scene();
  s["time_steps"] = json::array();
  expect_rejected(s, "nosteps", "/time_steps", "at least one time step");
}

}  // namespace
}  // namespace camplace::testing

namespace camplace::testing {
namespace {

// Shared events and people join every time step's own events; two zones may not share a name.
TEST(SceneLoading, SharedEventsAndPeopleJoinEachTimeStep) {
  json s = base_scene();
  s["events"] = json::parse(
      R"([{"weight": 0.5, "targets": [{"name": "visitor", "box": {"min": [2, 2, 0], "max": [2.3, 2.3, 1.7]}}]}])");
  s["people"] = json::parse(
      R"([{"name": "z", "zone": {"min": [1.2, 1.5], "max": [2.8, 2.9]}, "count": 3, "seed": 2, "weight": 0.9}])");
  const std::string path = write_scene(s, "shared_people");
  const core::Scene scene = core::load_scene(path);
  ASSERT_EQ(scene.time_steps.size(), 1u);
  const auto& events = scene.time_steps[0].events;
  ASSERT_EQ(events.size(), 5u) << "own event, the shared one, then 3 people";
  EXPECT_EQ(events[0].targets[0].name, "person");
  EXPECT_EQ(events[1].targets[0].name, "visitor");
  double people = 0;
  for (std::size_t l = 2; l < 5; ++l) people += events[l].weight;
  EXPECT_NEAR(people, 0.9, 1e-12);
  s["people"].push_back(s["people"][0]);
  expect_rejected(s, "people_twice", "/people/1", "named twice");
}

}  // namespace
}  // namespace camplace::testing

namespace camplace::testing {
namespace {

// Two robots: distinct names, the same sample times.
TEST(SceneLoading, RobotsMustHaveDistinctNamesAndTheSameSampleTimes) {
  json s = base_scene();
  s.erase("time_steps");
  s["events"] = base_scene()["time_steps"][0]["events"];
  const std::string dir = temp_dir("scene-two-robots");
  write_file(dir + "/r.urdf",
             R"(<robot name="r"><link name="body"><collision><origin xyz="3.5 2.5 0.2"/>
    <geometry><box size="0.2 0.2 0.2"/></geometry></collision></link></robot>)");
  const json still = json::parse(R"([{"t": 0, "joints": {}}, {"t": 1, "joints": {}}])");
  s["robots"] = {{{"urdf", "r.urdf"}, {"trajectory", still}},
                 {{"urdf", "r.urdf"}, {"trajectory", still}}};
  const std::string path = write_file(dir + "/a.json", s.dump(1));
  expect_rejected(path, "/robots/1", "is named twice");
  s["robots"][1]["name"] = "second";
  write_file(path, s.dump(1));
  const core::Scene ok = core::load_scene(path);
  ASSERT_EQ(ok.time_steps.size(), 2u);
  EXPECT_EQ(ok.time_steps[1].dynamic_obstacles.size(), 2u);
  EXPECT_EQ(ok.time_steps[1].dynamic_obstacles[1].name, "second/body");
  s["robots"][1]["trajectory"][1]["t"] = 2;
  write_file(path, s.dump(1));
  expect_rejected(path, "/robots/1", "must be sampled at the same times");
}

}  // namespace
}  // namespace camplace::testing
