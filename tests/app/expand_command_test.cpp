// `camplace expand` as a user runs it: a scene with a URDF robot on a trajectory, shared events,
// a people model and a repaired mesh is written out as plain objects and events; loading the
// written file gives the same scene (the plain loader does not know robots or people, so this
// checks the expansion against an independent reading of its result).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "camplace/core/scene.hpp"
#include "command.hpp"

namespace camplace::testing {
namespace {

namespace fs = std::filesystem;

CommandResult run(const std::string& args) { return run_camplace(CAMPLACE_BINARY, args); }

void write(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

/// A two-link arm: a revolute joint about z at the base, a second one 1 m along the first link.
const char* const kUrdf = R"(<?xml version="1.0"?>
<robot name="arm">
  <link name="base"><collision><geometry><box size="0.3 0.3 0.2"/></geometry>
    <origin xyz="0 0 0.1"/></collision></link>
  <link name="upper"><collision><origin xyz="0.5 0 0.3"/><geometry><box size="1 0.1 0.1"/>
    </geometry></collision></link>
  <link name="lower"><collision><origin xyz="0.25 0 0.3"/><geometry><box size="0.5 0.1 0.1"/>
    </geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="upper"/><child link="lower"/>
    <origin xyz="1 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>
)";

TEST(ExpandCommand, TheWrittenSceneLoadsAsTheSameScene) {
  const fs::path dir =
      fs::temp_directory_path() / ("camplace-expand-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  write(dir / "arm.urdf", kUrdf);
  write(dir / "traj.csv", "t,j1,j2\n0,0,0\n1,0.5,-0.5\n2,1.0,-1.0\n");
  // A mesh that intersects itself (two overlapping boxes in one mesh), repaired by its hull.
  nlohmann::json crossing =
      nlohmann::json::parse(R"({"name": "crossing", "repair": "hull", "mesh": {
    "vertices": [[3.2,0.2,0],[3.6,0.2,0],[3.2,0.6,0],[3.6,0.6,0],[3.2,0.2,0.4],[3.6,0.2,0.4],[3.2,0.6,0.4],[3.6,0.6,0.4],
                 [3.4,0.4,0.2],[3.8,0.4,0.2],[3.4,0.8,0.2],[3.8,0.8,0.2],[3.4,0.4,0.6],[3.8,0.4,0.6],[3.4,0.8,0.6],[3.8,0.8,0.6]],
    "triangles": [[0,4,6],[0,6,2],[1,3,7],[1,7,5],[0,1,5],[0,5,4],[2,6,7],[2,7,3],[0,2,3],[0,3,1],[4,5,7],[4,7,6],
                  [8,12,14],[8,14,10],[9,11,15],[9,15,13],[8,9,13],[8,13,12],[10,14,15],[10,15,11],[8,10,11],[8,11,9],[12,13,15],[12,15,14]]}})");
  nlohmann::json scene = nlohmann::json::parse(R"({
    "area": {"min": [-1, -1, 0], "max": [4, 3, 3]}, "voxels": [10, 8, 6],
    "cameras": {"count": 2, "half_angle_deg": 30},
    "static_obstacles": [{"name": "floor slab", "box": {"min": [-2, -2, -0.5], "max": [5, 4, -0.01]}}],
    "robots": [{"name": "arm", "urdf": "arm.urdf", "trajectory": "traj.csv"}],
    "events": [{"weight": 0.2, "targets": [{"name": "visitor", "box": {"min": [3, 2.2, 0], "max": [3.4, 2.6, 1.7]}}]}],
    "people": [{"name": "zone", "zone": {"min": [2.0, 1.8], "max": [3.8, 2.9]}, "count": 2, "seed": 7, "weight": 0.8}]
  })");
  scene["static_obstacles"].push_back(crossing);
  write(dir / "cell.json", scene.dump(1));
  const std::string out = (dir / "expanded.json").string();
  const CommandResult r = run("expand " + (dir / "cell.json").string() + " --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: "), std::string::npos)
      << "the repair is reported: " << r.output;
  EXPECT_NE(r.output.find("crossing"), std::string::npos) << r.output;

  const core::Scene a = core::load_scene((dir / "cell.json").string());
  const core::Scene b = core::load_scene(out);
  ASSERT_EQ(a.time_steps.size(), 3u);
  ASSERT_EQ(b.time_steps.size(), a.time_steps.size());
  EXPECT_TRUE(b.repairs.empty()) << "the written meshes are already valid";
  ASSERT_EQ(a.static_obstacles.size(), b.static_obstacles.size());
  for (std::size_t i = 0; i < a.static_obstacles.size(); ++i) {
    EXPECT_EQ(a.static_obstacles[i].name, b.static_obstacles[i].name);
    EXPECT_EQ(a.static_obstacles[i].mesh.vertices, b.static_obstacles[i].mesh.vertices);
  }
  for (std::size_t h = 0; h < a.time_steps.size(); ++h) {
    const core::TimeStep& sa = a.time_steps[h];
    const core::TimeStep& sb = b.time_steps[h];
    EXPECT_EQ(sa.t, sb.t);
    EXPECT_EQ(sa.t, static_cast<double>(h)) << "t comes from the trajectory";
    ASSERT_EQ(sa.dynamic_obstacles.size(), 3u) << "one object per link";
    ASSERT_EQ(sb.dynamic_obstacles.size(), sa.dynamic_obstacles.size());
    ASSERT_EQ(sb.critical.size(), 3u) << "the links are the critical objects by default";
    for (std::size_t k = 0; k < sa.dynamic_obstacles.size(); ++k) {
      EXPECT_EQ(sa.dynamic_obstacles[k].name, sb.dynamic_obstacles[k].name);
      EXPECT_EQ(sa.dynamic_obstacles[k].mesh.vertices, sb.dynamic_obstacles[k].mesh.vertices);
    }
    EXPECT_EQ(sa.dynamic_obstacles[0].name, "arm/base");
    // 1 shared event, then 2 people.
    ASSERT_EQ(sa.events.size(), 3u);
    ASSERT_EQ(sb.events.size(), 3u);
    double sum = 0;
    for (std::size_t l = 0; l < sa.events.size(); ++l) {
      EXPECT_EQ(sa.events[l].weight, sb.events[l].weight);
      ASSERT_EQ(sa.events[l].targets.size(), sb.events[l].targets.size());
      for (std::size_t k = 0; k < sa.events[l].targets.size(); ++k)
        EXPECT_EQ(sa.events[l].targets[k].mesh.vertices, sb.events[l].targets[k].mesh.vertices);
      sum += sa.events[l].weight;
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
    EXPECT_EQ(sa.events[0].targets[0].name, "visitor");
  }
  fs::remove_all(dir);
}

TEST(ExpandCommand, BadInputIsOneErrorLineAndNothingIsWritten) {
  const fs::path dir =
      fs::temp_directory_path() / ("camplace-expand-bad-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  write(dir / "arm.urdf", kUrdf);
  write(dir / "traj.csv", "t,j1,jx\n0,0,0\n");
  write(dir / "cell.json", R"({"area": {"min": [-1, -1, 0], "max": [4, 3, 3]}, "voxels": [4, 4, 4],
    "cameras": {"count": 1, "half_angle_deg": 30},
    "robots": [{"urdf": "arm.urdf", "trajectory": "traj.csv"}],
    "events": [{"weight": 1, "targets": [{"box": {"min": [3, 2.2, 0], "max": [3.4, 2.6, 1.7]}}]}]})");
  const std::string out = (dir / "expanded.json").string();
  const CommandResult r = run("expand " + (dir / "cell.json").string() + " --out " + out);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("error: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("jx"), std::string::npos) << "names the unknown joint: " << r.output;
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace camplace::testing
