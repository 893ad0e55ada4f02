// The bundled work cell data/cell_ur.json (data/README.md, "cell_ur.json"): its UR5e expands,
// time step by time step, into link meshes posed exactly by the robot's published DH table and
// the trajectory's rows; it has the time steps, objects and people the README describes.
//
// Independent of the loader: the poses come from the DH formulas written out here (not from the
// URDF), the joint values from this test's own reading of the CSV file, the link-frame vertices
// from this test's own reader of the binary STL files.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "camplace/core/scene.hpp"

namespace camplace::testing {
namespace {

using core::Vec3;
using Pose = Eigen::Isometry3d;

const std::string kData = CAMPLACE_SOURCE_DIR "/data/";
const std::string kScene = kData + "cell_ur.json";

// UR5e DH parameters (m, rad): Universal Robots, "DH parameters for calculations of kinematics
// and dynamics". Index k = 0..5 is joint k+1.
constexpr std::array<double, 6> kD = {0.1625, 0.0, 0.0, 0.1333, 0.0997, 0.0996};
constexpr std::array<double, 6> kA = {0.0, -0.425, -0.3922, 0.0, 0.0, 0.0};
constexpr std::array<double, 6> kAlpha = {core::kPi / 2,  0.0, 0.0, core::kPi / 2,
                                          -core::kPi / 2, 0.0};
const std::array<std::string, 6> kJoints = {"shoulder_pan_joint", "shoulder_lift_joint",
                                            "elbow_joint",        "wrist_1_joint",
                                            "wrist_2_joint",      "wrist_3_joint"};

// The robot's base in the scene: turned 90° about z, then moved to (3, 2, 0.75) m.
Pose base_pose() {
  Pose p = Pose::Identity();
  p.translate(Vec3(3.0, 2.0, 0.75));
  p.rotate(Eigen::AngleAxisd(core::kPi / 2, Vec3::UnitZ()));
  return p;
}

// The links (in chain order; index 0..6 = base_link..wrist_3_link, 7 = the gripper on tool0)
// and their collision elements' STL files (data/cell_ur/meshes), in the URDF's order.
struct LinkFiles {
  std::string link;
  std::vector<std::string> files;
};
const std::vector<LinkFiles> kLinks = {
    {"base_link", {"base_link.stl"}},
    {"shoulder_link", {"shoulder_link.stl", "shoulder_link_1.stl"}},
    {"upper_arm_link", {"upper_arm_link.stl", "upper_arm_link_1.stl"}},
    {"forearm_link", {"forearm_link.stl"}},
    {"wrist_1_link", {"wrist_1_link.stl"}},
    {"wrist_2_link", {"wrist_2_link.stl"}},
    {"wrist_3_link", {"wrist_3_link.stl"}},
    {"gripper", {"gripper.stl", "gripper_1.stl", "gripper_2.stl"}},
};

// The object name of element k of a link: "ur5e/<link>", then "ur5e/<link>/1", ...
std::string object_name(const std::string& link, std::size_t k) {
  return "ur5e/" + link + (k == 0 ? "" : "/" + std::to_string(k));
}

// World pose of link i (0 = base_link, 1..6 = the link moved by joint i, 7 = tool0 and the
// gripper fixed to it): Base · Π_{k<i} [Rz(q_k) Tz(d_k) Tx(a_k) Rx(α_k)] · Rz(q_i).
Pose dh_link_pose(const std::array<double, 6>& q, int i) {
  Pose p = base_pose();
  const int full = i == 7 ? 6 : std::max(i - 1, 0);  // DH frame i−1 (tool0: frame 6)
  for (int k = 0; k < full; ++k) {
    p.rotate(Eigen::AngleAxisd(q[k], Vec3::UnitZ()));
    p.translate(Vec3(kA[k], 0.0, kD[k]));  // Tz(d) · Tx(a) is the translation (a, 0, d)
    p.rotate(Eigen::AngleAxisd(kAlpha[k], Vec3::UnitX()));
  }
  if (i >= 1 && i <= 6) p.rotate(Eigen::AngleAxisd(q[i - 1], Vec3::UnitZ()));
  return p;
}

// The trajectory rows of data/cell_ur/pick_place.csv: t and the six joint values (rad).
struct Row {
  double t = 0.0;
  std::array<double, 6> q{};
};
std::vector<Row> read_trajectory() {
  std::ifstream in(kData + "cell_ur/pick_place.csv");
  EXPECT_TRUE(in) << "cannot open the trajectory";
  std::vector<Row> rows;
  std::string line;
  bool header = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    EXPECT_EQ(cells.size(), 7u) << line;
    if (cells.size() != 7) continue;
    if (!header) {
      header = true;
      EXPECT_EQ(cells[0], "t");
      for (int j = 0; j < 6; ++j) EXPECT_EQ(cells[j + 1], kJoints[j]);
      continue;
    }
    Row r;
    r.t = std::stod(cells[0]);
    for (int j = 0; j < 6; ++j) r.q[j] = std::stod(cells[j + 1]);
    rows.push_back(r);
  }
  return rows;
}

// The distinct vertices of a binary STL file (little-endian float32 coordinates, as written by
// scripts/make_cell_ur.py), in the link frame.
std::vector<Vec3> read_stl_vertices(const std::string& name) {
  std::ifstream in(kData + "cell_ur/meshes/" + name, std::ios::binary);
  EXPECT_TRUE(in) << "cannot open " << name;
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 84) {
    ADD_FAILURE() << name << " is too short";
    return {};
  }
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  EXPECT_EQ(bytes.size(), 84 + 50 * std::size_t{count}) << name;
  std::set<std::array<float, 3>> distinct;
  for (std::uint32_t t = 0; t < count && 84 + 50 * std::size_t{t + 1} <= bytes.size(); ++t) {
    for (int v = 0; v < 3; ++v) {
      std::array<float, 3> p;
      std::memcpy(p.data(), bytes.data() + 84 + 50 * std::size_t{t} + 12 * (v + 1), 12);
      distinct.insert(p);
    }
  }
  std::vector<Vec3> out;
  for (const auto& p : distinct) out.emplace_back(p[0], p[1], p[2]);
  return out;
}

const core::SceneObject* find(const std::vector<core::SceneObject>& objects,
                              const std::string& name) {
  for (const core::SceneObject& o : objects) {
    if (o.name == name) return &o;
  }
  return nullptr;
}

// Largest distance from a point of `a` to the nearest point of `b` (brute force).
double one_sided_gap(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double worst = 0.0;
  for (const Vec3& p : a) {
    double best = std::numeric_limits<double>::infinity();
    for (const Vec3& q : b) best = std::min(best, (p - q).norm());
    worst = std::max(worst, best);
  }
  return worst;
}

// The cell, loaded once for all tests (a load error fails each test with its message).
const core::Scene& cell() {
  static const core::Scene scene = core::load_scene(kScene);
  return scene;
}

TEST(BundledCell, RobotLinkVerticesAreTheStlVerticesPosedByTheDhTableAtEveryStep) {
  const core::Scene& scene = cell();
  const std::vector<Row> rows = read_trajectory();
  ASSERT_EQ(rows.size(), 7u);
  ASSERT_EQ(scene.time_steps.size(), rows.size());
  for (std::size_t h = 0; h < rows.size(); ++h) {
    const core::TimeStep& step = scene.time_steps[h];
    EXPECT_DOUBLE_EQ(step.t, rows[h].t);
    for (std::size_t i = 0; i < kLinks.size(); ++i) {
      const Pose pose = dh_link_pose(rows[h].q, static_cast<int>(i));
      for (std::size_t k = 0; k < kLinks[i].files.size(); ++k) {
        const std::string name = object_name(kLinks[i].link, k);
        SCOPED_TRACE("time step " + std::to_string(h) + ", " + name);
        const core::SceneObject* obj = find(step.dynamic_obstacles, name);
        ASSERT_NE(obj, nullptr) << "no dynamic obstacle " << name;
        std::vector<Vec3> expected;
        for (const Vec3& v : read_stl_vertices(kLinks[i].files[k])) expected.push_back(pose * v);
        ASSERT_FALSE(expected.empty());
        // The loader may drop unused vertices and reorient triangles, never move a vertex:
        // compare the vertex sets both ways.
        EXPECT_LE(one_sided_gap(obj->mesh.vertices, expected), 1e-9);
        EXPECT_LE(one_sided_gap(expected, obj->mesh.vertices), 1e-9);
      }
    }
  }
}

TEST(BundledCell, HasSevenTimeStepsEachWithTheRobotsTwelveLinkObjects) {
  const core::Scene& scene = cell();
  ASSERT_EQ(scene.time_steps.size(), 7u);
  std::set<std::string> expected;
  for (const LinkFiles& l : kLinks) {
    for (std::size_t k = 0; k < l.files.size(); ++k) expected.insert(object_name(l.link, k));
  }
  ASSERT_EQ(expected.size(), 12u);
  for (std::size_t h = 0; h < scene.time_steps.size(); ++h) {
    const core::TimeStep& step = scene.time_steps[h];
    std::set<std::string> dynamic, critical;
    for (const auto& o : step.dynamic_obstacles) dynamic.insert(o.name);
    for (const auto& o : step.critical) critical.insert(o.name);
    EXPECT_EQ(dynamic, expected) << "time step " << h;
    EXPECT_EQ(step.dynamic_obstacles.size(), expected.size()) << "time step " << h;
    // No "critical" in the file: the robot's links are the critical objects (SPEC §2).
    EXPECT_EQ(critical, expected) << "time step " << h;
  }
  std::set<std::string> statics;
  for (const auto& o : scene.static_obstacles) statics.insert(o.name);
  const std::set<std::string> expected_statics = {
      "robot pedestal",     "conveyor belt",      "conveyor leg x=-0.5", "conveyor leg x=1.5",
      "conveyor leg x=3.5", "conveyor leg x=5.5", "work bench",          "parts shelf"};
  EXPECT_EQ(statics, expected_statics);
}

TEST(BundledCell, ConveyorCrossesSAndExtendsBeyondItOnBothEnds) {
  const core::Scene& scene = cell();
  const core::SceneObject* belt = find(scene.static_obstacles, "conveyor belt");
  ASSERT_NE(belt, nullptr);
  const core::Box3& s = scene.area;
  EXPECT_DOUBLE_EQ(s.min.x(), 0.0);
  EXPECT_DOUBLE_EQ(s.max.x(), 6.0);
  // The belt runs along x from −1 m to 7 m: 1 m beyond S at each end, inside S across it.
  EXPECT_DOUBLE_EQ(belt->bounds.min.x(), -1.0);
  EXPECT_DOUBLE_EQ(belt->bounds.max.x(), 7.0);
  EXPECT_GT(belt->bounds.min.y(), s.min.y());
  EXPECT_LT(belt->bounds.max.y(), s.max.y());
  EXPECT_GT(belt->bounds.min.z(), s.min.z());
  EXPECT_LT(belt->bounds.max.z(), s.max.z());
  const core::SceneObject* leg = find(scene.static_obstacles, "conveyor leg x=-0.5");
  ASSERT_NE(leg, nullptr);
  EXPECT_LT(leg->bounds.max.x(), s.min.x());  // wholly outside S
}

TEST(BundledCell, PeopleEventsWeighOnePerStepSharedAsTheZonesSay) {
  const core::Scene& scene = cell();
  // Zone "loading": 3 people, weight 0.6; zone "assembly": 2 people, weight 0.4.
  const std::map<std::string, std::pair<int, double>> zones = {{"loading", {3, 0.6}},
                                                               {"assembly", {2, 0.4}}};
  for (std::size_t h = 0; h < scene.time_steps.size(); ++h) {
    SCOPED_TRACE("time step " + std::to_string(h));
    const core::TimeStep& step = scene.time_steps[h];
    double sum = 0.0;
    std::map<std::string, int> people;
    for (const core::Event& e : step.events) {
      sum += e.weight;
      ASSERT_FALSE(e.targets.empty());
      const std::string& part = e.targets.front().name;  // "<zone>/<k>/<part>"
      const std::string zone = part.substr(0, part.find('/'));
      ASSERT_TRUE(zones.count(zone)) << part;
      ++people[zone];
      EXPECT_NEAR(e.weight, zones.at(zone).second / zones.at(zone).first, 1e-15) << part;
      for (const core::SceneObject& t : e.targets) {
        EXPECT_EQ(t.name.substr(0, zone.size() + 1), zone + "/") << "one person per event";
        EXPECT_TRUE(scene.area.contains(t.bounds.min) && scene.area.contains(t.bounds.max))
            << t.name << " leaves S";
      }
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
    for (const auto& [zone, spec] : zones) EXPECT_EQ(people[zone], spec.first) << zone;
  }
}

}  // namespace
}  // namespace camplace::testing
