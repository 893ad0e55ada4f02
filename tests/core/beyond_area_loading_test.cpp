// Scene loading with objects beyond the area S (SPEC §2): obstacles (static, dynamic) and
// critical objects may cross any face of S or lie wholly outside it; a target that leaves S is
// refused, naming the file, the target's entry and the reason.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "camplace/core/scene.hpp"
#include "scene_builder.hpp"
#include "scene_fixtures.hpp"

namespace camplace::testing {
namespace {

using nlohmann::json;

std::string write_scene(const json& scene, const std::string& name) {
  return write_file(temp_dir("beyond-" + name) + "/scene.json", scene.dump(1));
}

/// A box reaching 0.5 m into S = [0, 4]×[0, 3]×[0, 3] through face f (axis f / 2, low side when
/// f is even) and 1.5 m beyond it, [1.2, 1.6] m along the other axes: clear of base_scene()'s
/// table, robot link and person (so that only leaving S can be the reason for a refusal).
json crossing_box(int f) {
  const double max[3] = {4, 3, 3};
  json lo = json::array({1.2, 1.2, 1.2}), hi = json::array({1.6, 1.6, 1.6});
  const int a = f / 2;
  lo[a] = f % 2 ? max[a] - 0.5 : -1.5;
  hi[a] = f % 2 ? max[a] + 1.5 : 0.5;
  return {{"min", lo}, {"max", hi}};
}

TEST(SceneLoading, ObstaclesAndCriticalObjectsCrossingEachFaceOfSAreAccepted) {
  for (int f = 0; f < 6; ++f) {
    json s = base_scene();
    s["static_obstacles"].push_back({{"name", "wall"}, {"box", crossing_box(f)}});
    s["time_steps"][0]["dynamic_obstacles"].push_back(
        {{"name", "conveyor"}, {"box", crossing_box((f + 1) % 6)}});
    s["time_steps"][0]["critical"] = {{{"name", "arm"}, {"box", crossing_box((f + 2) % 6)}}};
    const core::Scene scene = core::load_scene(write_scene(s, "cross" + std::to_string(f)));
    ASSERT_EQ(scene.static_obstacles.size(), 2u);
    const core::Box3& wall = scene.static_obstacles[1].bounds;
    EXPECT_TRUE((wall.min.array() < scene.area.min.array()).any() ||
                (wall.max.array() > scene.area.max.array()).any())
        << "face " << f;
    EXPECT_EQ(scene.time_steps[0].dynamic_obstacles.size(), 2u);
    EXPECT_EQ(scene.time_steps[0].critical.at(0).name, "arm");
  }
}

TEST(SceneLoading, ObstacleWhollyOutsideSIsAccepted) {
  json s = base_scene();
  s["static_obstacles"].push_back(
      {{"name", "shelf"}, {"box", {{"min", {5, 0, 0}}, {"max", {6, 1, 2}}}}});
  const core::Scene scene = core::load_scene(write_scene(s, "outside"));
  EXPECT_EQ(scene.static_obstacles.back().bounds.min.x(), 5.0);
}

TEST(SceneRejection, TargetCrossingEachFaceOfSLeavesTheArea) {
  for (int f = 0; f < 6; ++f) {
    json s = base_scene();
    s["time_steps"][0]["events"][0]["targets"].push_back(
        {{"name", "arm of a person"}, {"box", crossing_box(f)}});
    expect_rejected(write_scene(s, "target" + std::to_string(f)),
                    "/time_steps/0/events/0/targets/1",
                    "target \"arm of a person\" leaves the area S");
  }
}

}  // namespace
}  // namespace camplace::testing
