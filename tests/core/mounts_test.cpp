// Mounts and keep-out boxes: the mount frame against hand-computed vectors,
// loading and every rejection, the keep-out repair against hand cases and a brute-force search.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <random>

#include "camplace/core/error.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/core/scene_writer.hpp"
#include "scene_builder.hpp"
#include "scene_fixtures.hpp"

namespace camplace::testing {
namespace {

using nlohmann::json;
constexpr double kDeg = M_PI / 180.0;

std::string write_scene(const json& scene, const std::string& name) {
  return write_file(temp_dir("mounts-" + name) + "/scene.json", scene.dump(1));
}

/// The base scene (S = [0,4]×[0,3]×[0,3]) with a ceiling mount and a wall mount, two frustum
/// cameras listed on them.
json mount_scene() {
  json s = base_scene();
  s["cameras"] = json::parse(R"({
    "models": [{"name": "rgb", "fov": "frustum", "horizontal_deg": 90, "vertical_deg": 59}],
    "mounts": [
      {"name": "ceiling", "corner": [0, 0, 3], "edges": [[0, 3, 0], [4, 0, 0]],
       "pitch_deg": [-30, 30], "roll_deg": [-10, 10]},
      {"name": "wall", "corner": [0, 3, 1], "edges": [[4, 0, 0], [0, 0, 2]], "yaw_deg": [-45, 45]}
    ],
    "list": [{"model": "rgb", "mount": "ceiling"}, {"model": "rgb", "domain": {"mount": "wall"}}]
  })");
  return s;
}

TEST(Mount, FrameMatchesHandComputedVectors) {
  core::Mount m;
  m.corner = core::Vec3(0, 0, 3);
  m.u = core::Vec3(0, 3, 0);
  m.v = core::Vec3(4, 0, 0);
  // u × v = (0, 3, 0) × (4, 0, 0) = (0, 0, −12): a ceiling looking down.
  EXPECT_TRUE(m.normal().isApprox(core::Vec3(0, 0, -1)));
  EXPECT_TRUE(m.e1().isApprox(core::Vec3(0, 1, 0)));
  EXPECT_TRUE(m.e2().isApprox(core::Vec3(1, 0, 0)));  // n × e1
  EXPECT_TRUE(m.point(0.5, 0.25).isApprox(core::Vec3(1, 1.5, 3)));
  // ψ' = 30°: cos 30° n + sin 30° e1.
  EXPECT_TRUE(m.direction(30 * kDeg, 0).isApprox(core::Vec3(0, 0.5, -std::sqrt(3.0) / 2)));
  // θ' = 45°: cos 45° n + sin 45° e2.
  EXPECT_TRUE(m.direction(0, 45 * kDeg).isApprox(core::Vec3(std::sqrt(0.5), 0, -std::sqrt(0.5))));
  const auto [yaw, pitch] = m.relative_angles(m.direction(-20 * kDeg, 35 * kDeg));
  EXPECT_NEAR(yaw, -20 * kDeg, 1e-12);
  EXPECT_NEAR(pitch, 35 * kDeg, 1e-12);
  const auto [s, t] = m.coordinates(core::Vec3(1, 1.5, 2));  // 1 m below (1, 1.5, 3)
  EXPECT_NEAR(s, 0.5, 1e-12);
  EXPECT_NEAR(t, 0.25, 1e-12);
}

TEST(Mount, SceneLoadsMountsPerCameraAndShared) {
  const core::Scene scene = core::load_scene(write_scene(mount_scene(), "load"));
  const core::CameraSpec& c = scene.cameras;
  ASSERT_EQ(c.mounts.size(), 2u);
  ASSERT_EQ(c.count, 2);
  ASSERT_TRUE(c.domains[0].mount && c.domains[1].mount);
  EXPECT_EQ(c.domains[0].mount->name, "ceiling");
  EXPECT_EQ(c.domains[1].mount->name, "wall");
  EXPECT_NEAR(c.domains[0].mount->pitch.lo, -30 * kDeg, 1e-12);
  EXPECT_NEAR(c.domains[0].roll.hi, 10 * kDeg, 1e-12);  // the mount's roll range
  EXPECT_NEAR(c.domains[1].mount->yaw.hi, 45 * kDeg, 1e-12);
  EXPECT_EQ(c.domains[1].mount->pitch.hi, M_PI / 2);  // default: the whole half-space
  // The box fields hold the rectangle's bounding box.
  EXPECT_EQ(c.domains[1].y.lo, 3.0);
  EXPECT_EQ(c.domains[1].y.hi, 3.0);
  EXPECT_EQ(c.domains[1].z.lo, 1.0);
  EXPECT_EQ(c.domains[1].z.hi, 3.0);
  // The wall's normal (4,0,0) × (0,0,2) = (0, −8, 0) points into the room.
  EXPECT_TRUE(c.domains[1].mount->normal().isApprox(core::Vec3(0, -1, 0)));

  // Shared: "mount" in the cameras block.
  json shared = mount_scene();
  shared["cameras"].erase("list");
  shared["cameras"]["models"][0]["count"] = 3;
  shared["cameras"]["mount"] = "wall";
  const core::Scene s2 = core::load_scene(write_scene(shared, "shared"));
  ASSERT_EQ(s2.cameras.count, 3);
  for (const auto& d : s2.cameras.domains) EXPECT_EQ(d.mount->name, "wall");
}

TEST(Mount, ScenesWithMountsAndKeepOutSurviveTheWriter) {
  json s = mount_scene();
  s["cameras"]["keep_out"] =
      json::parse(R"([{"name": "reach", "min": [1, 1, 0], "max": [3, 2, 2]}])");
  const core::Scene scene = core::load_scene(write_scene(s, "writer-in"));
  const std::string out = temp_dir("mounts-writer-out") + "/scene.json";
  core::write_scene(scene, out);
  const core::Scene back = core::load_scene(out);
  ASSERT_EQ(back.cameras.mounts.size(), 2u);
  EXPECT_EQ(back.cameras.mounts[1].name, "wall");
  EXPECT_TRUE(back.cameras.mounts[1].v.isApprox(core::Vec3(0, 0, 2)));
  EXPECT_NEAR(back.cameras.mounts[0].pitch.lo, -30 * kDeg, 1e-12);
  EXPECT_EQ(back.cameras.domains[0].mount->name, "ceiling");
  EXPECT_EQ(back.cameras.domains[1].mount->name, "wall");
  ASSERT_EQ(back.cameras.keep_out.size(), 1u);
  EXPECT_EQ(back.cameras.keep_out[0].name, "reach");
  EXPECT_TRUE(back.cameras.keep_out[0].box.max.isApprox(core::Vec3(3, 2, 2)));
}

TEST(Mount, BadMountsAndKeepOutAreRejected) {
  auto with = [&](const std::string& pointer, const json& value) {
    json s = mount_scene();
    s["cameras"][json::json_pointer(pointer)] = value;
    return s;
  };
  expect_rejected(write_scene(with("/mounts/1/edges", json::parse("[[4,0,0],[2,0,0]]")), "par"),
                  "/cameras/mounts/1/edges", "degenerate");
  expect_rejected(write_scene(with("/mounts/1/edges", json::parse("[[0,0,0],[0,0,2]]")), "zero"),
                  "/cameras/mounts/1/edges", "zero area");
  expect_rejected(write_scene(with("/mounts/1/corner", json::parse("[0, 3, 1.5]")), "out"),
                  "/cameras/mounts/1", "leaves the area S");
  expect_rejected(write_scene(with("/list/0/mount", "floor"), "unknown"), "/cameras/list/0/mount",
                  "unknown mount \"floor\"");
  expect_rejected(write_scene(with("/list/0/domain", "room"), "both"), "/cameras/list/0/mount",
                  "not both");
  expect_rejected(write_scene(with("/mounts/0/pitch_deg", json::parse("[-95, 0]")), "pitch"),
                  "/cameras/mounts/0/pitch_deg", "leaves the allowed range");
  expect_rejected(write_scene(with("/mounts/1/name", "ceiling"), "twice"), "/cameras/mounts/1/name",
                  "named twice");
  // A keep-out box covering the whole wall mount (y = 3, z ∈ [1, 3]): camera 1 has nowhere to go.
  expect_rejected(
      write_scene(with("/keep_out", json::parse(R"([{"min": [-1, 2, 0.5], "max": [5, 4, 4]}])")),
                  "cover-mount"),
      "/cameras/list/1/domain", "cover the whole mount \"wall\" of camera 1");
  // Two boxes that together cover the room domain of every camera.
  json room = base_scene();
  room["cameras"]["keep_out"] = json::parse(
      R"([{"min": [-1, -1, -1], "max": [2.5, 4, 4]}, {"min": [2, -1, -1], "max": [5, 4, 4]}])");
  expect_rejected(write_scene(room, "cover-room"), "/cameras (domain room)",
                  "cover the whole placement domain of camera 0");
  room["cameras"]["keep_out"] = json::parse(R"([{"min": [1, 1, 1], "max": [1, 2, 2]}])");
  expect_rejected(write_scene(room, "flat-box"), "/cameras/keep_out/0", "degenerate");
}

/// The box domain [0, 4] × [0, 3] × [0, 3] (m), angles unrestricted.
core::CameraDomain room_domain() {
  core::CameraDomain room;
  room.x = {0, 4};
  room.y = {0, 3};
  room.z = {0, 3};
  return room;
}

TEST(KeepOut, RepairMovesToTheNearestFreePoint) {
  const core::CameraDomain room = room_domain();
  std::vector<core::KeepOut> boxes(1);
  boxes[0].box = {core::Vec3(1, 1, 0), core::Vec3(3, 2, 2.5)};
  // Nearest face: x = 1 (0.2 away) for (1.2, 1.5, 1); y = 1 (0.4 away) for (2, 1.4, 1).
  EXPECT_TRUE(
      core::keep_out_repair(room, boxes, core::Vec3(1.2, 1.5, 1))->isApprox(core::Vec3(1, 1.5, 1)));
  EXPECT_TRUE(
      core::keep_out_repair(room, boxes, core::Vec3(2, 1.4, 1))->isApprox(core::Vec3(2, 1, 1)));
  // A free point stays; a point outside the domain is clamped first.
  EXPECT_TRUE(core::keep_out_repair(room, boxes, core::Vec3(0.5, 0.5, 0.5))
                  ->isApprox(core::Vec3(0.5, 0.5, 0.5)));
  EXPECT_TRUE(core::keep_out_repair(room, boxes, core::Vec3(-1, 0.5, 0.5))
                  ->isApprox(core::Vec3(0, 0.5, 0.5)));
  // A second box blocks the x = 1 face near (1, 1.5, 1): the repair takes the top face z = 2.5.
  boxes.push_back({"b", "", {core::Vec3(0, 0, 0), core::Vec3(1.5, 3, 2.4)}});
  EXPECT_TRUE(core::keep_out_repair(room, boxes, core::Vec3(1.2, 1.5, 2.3))
                  ->isApprox(core::Vec3(1.2, 1.5, 2.5)));

  // A ceiling mount (z = 3) cut by a box reaching above it: (s, t) moves along the mount.
  core::Mount m;
  m.corner = core::Vec3(0, 0, 3);
  m.u = core::Vec3(0, 3, 0);
  m.v = core::Vec3(4, 0, 0);
  core::CameraDomain on_mount;
  on_mount.mount = m;
  std::vector<core::KeepOut> reach(1);
  reach[0].box = {core::Vec3(1, 1, 2), core::Vec3(3, 2, 4)};
  EXPECT_TRUE(core::keep_out_repair(on_mount, reach, core::Vec3(2.9, 1.5, 3))
                  ->isApprox(core::Vec3(3, 1.5, 3)));
  // A point below the mount is projected onto it first.
  EXPECT_TRUE(core::keep_out_repair(on_mount, reach, core::Vec3(1.1, 1.2, 1))
                  ->isApprox(core::Vec3(1, 1.2, 3)));  // x = 1 is 0.1 away
}

// Against a brute-force search on a fine grid: the repair is free, in the domain and no farther
// than the nearest free grid point (up to the grid's spacing).
TEST(KeepOut, RepairIsNoFartherThanABruteForceSearch) {
  const core::CameraDomain room = room_domain();
  std::vector<core::KeepOut> boxes(3);
  boxes[0].box = {core::Vec3(0.5, 0.5, 0), core::Vec3(2.5, 2, 2)};
  boxes[1].box = {core::Vec3(2, 1, 1), core::Vec3(3.5, 3, 3)};
  boxes[2].box = {core::Vec3(1, 0, 1.5), core::Vec3(2.2, 1.2, 3)};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(0, 4), uy(0, 3), uz(0, 3);
  const double step = 0.05;
  for (int trial = 0; trial < 40; ++trial) {
    const core::Vec3 p(ux(rng), uy(rng), uz(rng));
    const auto q = core::keep_out_repair(room, boxes, p);
    ASSERT_TRUE(q);
    for (const auto& b : boxes) EXPECT_FALSE(b.contains(*q)) << p.transpose();
    EXPECT_TRUE((q->array() >= -1e-12).all() && q->x() <= 4 + 1e-12 && q->y() <= 3 + 1e-12 &&
                q->z() <= 3 + 1e-12);
    double brute = 1e9;
    for (double x = 0; x <= 4 + 1e-9; x += step) {
      for (double y = 0; y <= 3 + 1e-9; y += step) {
        for (double z = 0; z <= 3 + 1e-9; z += step) {
          const core::Vec3 g(x, y, z);
          bool free = true;
          for (const auto& b : boxes) free = free && !b.contains(g);
          if (free) brute = std::min(brute, (g - p).norm());
        }
      }
    }
    EXPECT_LE((*q - p).norm(), brute + 1e-9) << p.transpose();
  }
}

}  // namespace
}  // namespace camplace::testing
