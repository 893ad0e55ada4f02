// Robots from URDF on a joint trajectory (detail::expand_robot): link poses against forward
// kinematics written out by hand, trajectory sampling and interpolation, mesh paths, the
// primitive meshes, and one clear error for every kind of bad input.
#include "../../core/src/robot.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "../../core/src/mesh_checks.hpp"
#include "camplace/core/error.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using core::kPi;
using core::Vec3;
using nlohmann::json;
using Mat3 = Eigen::Matrix3d;

constexpr double kTol = 1e-9;

// ---- rotations written out entry by entry (the test's own kinematics) ----
Mat3 rot_x(double a) {
  Mat3 m;
  m << 1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a);
  return m;
}
Mat3 rot_y(double a) {
  Mat3 m;
  m << std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a);
  return m;
}
Mat3 rot_z(double a) {
  Mat3 m;
  m << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  return m;
}
// Rotation by a about the unit axis (1, 1, 0)/√2 (Rodrigues: cI + s[k]× + (1 − c)kkᵀ, written
// out).
Mat3 rot_diagonal_xy(double a) {
  const double c = std::cos(a), s = std::sin(a), h = std::sqrt(0.5);
  Mat3 m;
  m << c + (1 - c) * 0.5, (1 - c) * 0.5, s * h,  //
      (1 - c) * 0.5, c + (1 - c) * 0.5, -s * h,  //
      -s * h, s * h, c;
  return m;
}

// The 8 corners of a box of `size` centred at the origin.
std::vector<Vec3> box_corners(const Vec3& size) {
  std::vector<Vec3> out;
  for (int i = 0; i < 8; ++i) {
    out.emplace_back((i & 1 ? 0.5 : -0.5) * size.x(), (i & 2 ? 0.5 : -0.5) * size.y(),
                     (i & 4 ? 0.5 : -0.5) * size.z());
  }
  return out;
}

// Every expected point is a vertex of the mesh (within kTol), and the counts agree.
void expect_vertices(const core::TriangleMesh& mesh, const std::vector<Vec3>& expected,
                     const std::string& what) {
  ASSERT_EQ(mesh.vertices.size(), expected.size()) << what;
  for (const Vec3& e : expected) {
    double best = 1e300;
    for (const Vec3& v : mesh.vertices) best = std::min(best, (v - e).norm());
    EXPECT_LT(best, kTol) << what << ": no vertex at " << e.transpose();
  }
}

// A planar chain: revolute j1 (z) carries l1, a box 1 × 0.1 × 0.1 from x = 0 to 1; revolute j2
// (z) at x = 1 of l1 carries l2, a box 0.5 × 0.1 × 0.1 from x = 0 to 0.5.
const std::string kPlanarUrdf = R"(<robot name="planar">
  <link name="base"/>
  <link name="l1"><collision><origin xyz="0.5 0 0"/><geometry><box size="1 0.1 0.1"/></geometry>
  </collision></link>
  <link name="l2"><collision><origin xyz="0.25 0 0"/><geometry><box size="0.5 0.1 0.1"/>
  </geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit lower="-3.2" upper="3.2" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="1 0 0"/>
    <axis xyz="0 0 1"/><limit lower="-3.2" upper="3.2" effort="1" velocity="1"/></joint>
</robot>
)";

// One revolute joint j (z) carrying a 0.2 m cube centred at x = 1: its centre is (cos q, sin q).
const std::string kOneJointUrdf = R"(<robot name="one">
  <link name="base"/>
  <link name="arm"><collision><origin xyz="1 0 0"/><geometry><box size="0.2 0.2 0.2"/>
  </geometry></collision></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
</robot>
)";

// Runs expand_robot on `robot` as entry /robots/0 of a scene in `dir`; the finisher validates
// and orients each mesh and counts its calls.
struct Expansion {
  core::detail::RobotSteps steps;
  int finished = 0;
};
Expansion expand(const std::string& dir, const json& robot) {
  const json doc = {{"robots", {robot}}};
  const std::string scene_file = dir + "/scene.json";
  const core::JsonNode node(doc["robots"][0], scene_file, "/robots/0");
  Expansion out;
  out.steps = core::detail::expand_robot(
      node, dir, scene_file,
      [&](core::TriangleMesh& mesh, const std::string& entry, const std::string&) {
        ++out.finished;
        core::detail::validate_and_orient(mesh, scene_file, entry);
      });
  return out;
}

// Expects expand_robot to throw one InputError naming `file` (relative to dir; "" for the
// scene), `entry` and a reason containing each of `reasons`.
void expect_error(const std::string& dir, const json& robot, const std::string& file,
                  const std::string& entry, const std::vector<std::string>& reasons) {
  try {
    expand(dir, robot);
    ADD_FAILURE() << "accepted (expected: " << entry << ")";
  } catch (const core::InputError& e) {
    if (std::getenv("CAMPLACE_PRINT_ERRORS")) std::printf("%s\n", e.what());
    EXPECT_EQ(e.file(), dir + "/" + (file.empty() ? "scene.json" : file)) << e.what();
    EXPECT_EQ(e.entry(), entry) << e.what();
    for (const auto& r : reasons)
      EXPECT_NE(e.reason().find(r), std::string::npos) << "missing \"" << r << "\" in " << e.what();
  }
}

TEST(RobotKinematics, PlanarTwoLinkChainMatchesClosedForm) {
  const std::string dir = temp_dir("robot-planar");
  write_file(dir + "/planar.urdf", kPlanarUrdf);
  const std::vector<std::array<double, 2>> qs = {{0, 0}, {0.7, -1.2}, {-2.5, 3.1}};
  json traj = json::array();
  for (std::size_t r = 0; r < qs.size(); ++r)
    traj.push_back({{"t", r}, {"joints", {{"j1", qs[r][0]}, {"j2", qs[r][1]}}}});
  const Expansion e = expand(dir, {{"name", "arm"}, {"urdf", "planar.urdf"}, {"trajectory", traj}});
  ASSERT_EQ(e.steps.times, (std::vector<double>{0, 1, 2}));
  ASSERT_EQ(e.steps.links.size(), 3u);
  EXPECT_EQ(e.finished, 2);  // each link mesh finished once, not once per sample
  for (std::size_t r = 0; r < qs.size(); ++r) {
    const double q1 = qs[r][0], q12 = qs[r][0] + qs[r][1];
    const auto& objects = e.steps.links[r];
    ASSERT_EQ(objects.size(), 2u);  // "base" has no geometry
    EXPECT_EQ(objects[0].name, "arm/l1");
    EXPECT_EQ(objects[1].name, "arm/l2");
    EXPECT_EQ(objects[0].entry, "/robots/0 (link \"l1\", collision 0)");
    std::vector<Vec3> l1, l2;
    for (double x : {0.0, 1.0}) {
      for (double y : {-0.05, 0.05}) {
        for (double z : {-0.05, 0.05}) {
          l1.emplace_back(x * std::cos(q1) - y * std::sin(q1), x * std::sin(q1) + y * std::cos(q1),
                          z);
          const double x2 = 0.5 * x;
          l2.emplace_back(std::cos(q1) + x2 * std::cos(q12) - y * std::sin(q12),
                          std::sin(q1) + x2 * std::sin(q12) + y * std::cos(q12), z);
        }
      }
    }
    expect_vertices(objects[0].mesh, l1, "l1 row " + std::to_string(r));
    expect_vertices(objects[1].mesh, l2, "l2 row " + std::to_string(r));
    const core::Box3 b = core::bounding_box(objects[1].mesh);
    EXPECT_LT((objects[1].bounds.min - b.min).norm(), kTol);
    EXPECT_LT((objects[1].bounds.max - b.max).norm(), kTol);
  }
}

TEST(RobotKinematics, BaseRotatesThenTranslatesTheRootLink) {
  const std::string dir = temp_dir("robot-base");
  write_file(dir + "/planar.urdf", kPlanarUrdf);
  const double q1 = 0.4, q2 = 0.9;
  const Expansion e =
      expand(dir, {{"urdf", "planar.urdf"},
                   {"base", {{"rotate_deg", {0, 0, 90}}, {"translate", {1, 2, 0.5}}}},
                   {"trajectory", {{{"t", 0}, {"joints", {{"j1", q1}, {"j2", q2}}}}}}});
  ASSERT_EQ(e.steps.links.size(), 1u);
  EXPECT_EQ(e.steps.name, "robot");
  EXPECT_EQ(e.steps.links[0][1].name, "robot/l2");
  // The tip of l2 (x = 0.5, y = z = 0.05 in l2) in the URDF frame, then (x, y, z) → (−y, x, z)
  // (90° about z) and + (1, 2, 0.5).
  const double x = std::cos(q1) + 0.5 * std::cos(q1 + q2) - 0.05 * std::sin(q1 + q2);
  const double y = std::sin(q1) + 0.5 * std::sin(q1 + q2) + 0.05 * std::cos(q1 + q2);
  const Vec3 tip(-y + 1, x + 2, 0.05 + 0.5);
  double best = 1e300;
  for (const Vec3& v : e.steps.links[0][1].mesh.vertices) best = std::min(best, (v - tip).norm());
  EXPECT_LT(best, kTol);
}

// base → a (revolute z, at z = 0.5) → l1 → b (prismatic along x, origin x = 0.2 and yaw 90°)
// → l2 → c (revolute about (1, 1, 0)/√2, origin z = 0.3 and rpy (0.3, 0.2, 0.1)) → l3, whose
// box 0.2 × 0.1 × 0.4 sits at x = 0.1 pitched by 0.3.
const std::string kThreeJointUrdf = R"(<robot name="three">
  <link name="base"/>
  <link name="l1"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="l2"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="l3"><collision><origin xyz="0.1 0 0" rpy="0 0.3 0"/>
    <geometry><box size="0.2 0.1 0.4"/></geometry></collision></link>
  <joint name="a" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.5"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="b" type="prismatic"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.2 0 0" rpy="0 0 1.5707963267948966"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="0.5" effort="1" velocity="1"/></joint>
  <joint name="c" type="revolute"><parent link="l2"/><child link="l3"/>
    <origin xyz="0 0 0.3" rpy="0.3 0.2 0.1"/><axis xyz="1 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
</robot>
)";

// l3's box corners in the world for joint values (a, b, c), by hand:
// world = Rz(a)·(Rz(π/2)·(Rrpy·Rk(c)·(Ry(0.3)·p + (0.1, 0, 0)) + (0, 0, 0.3)) + b·x + (0.2, 0, 0))
//         + (0, 0, 0.5), with Rrpy = Rz(0.1)·Ry(0.2)·Rx(0.3).
std::vector<Vec3> three_joint_l3_corners(double qa, double qb, double qc) {
  const Mat3 rpy = rot_z(0.1) * rot_y(0.2) * rot_x(0.3);
  std::vector<Vec3> l3;
  for (const Vec3& p : box_corners(Vec3(0.2, 0.1, 0.4))) {
    const Vec3 in_l3 = rot_y(0.3) * p + Vec3(0.1, 0, 0);
    const Vec3 in_l2 = rpy * (rot_diagonal_xy(qc) * in_l3) + Vec3(0, 0, 0.3);
    const Vec3 in_l1 = rot_z(kPi / 2) * (in_l2 + Vec3(qb, 0, 0)) + Vec3(0.2, 0, 0);
    l3.push_back(rot_z(qa) * in_l1 + Vec3(0, 0, 0.5));
  }
  return l3;
}

TEST(RobotKinematics, PrismaticRpyAndSkewAxisChainMatchesHandComputedPoses) {
  const std::string dir = temp_dir("robot-three");
  write_file(dir + "/three.urdf", kThreeJointUrdf);
  const std::vector<std::array<double, 3>> qs = {{0, 0, 0}, {0.8, 0.3, -1.1}, {-2.2, 0.5, 1.7}};
  std::string csv = "# t, a, b, c\n t , c, a ,b\n";
  for (std::size_t r = 0; r < qs.size(); ++r) {
    csv += std::to_string(r) + "," + std::to_string(qs[r][2]) + ", " + std::to_string(qs[r][0]) +
           "," + std::to_string(qs[r][1]) + "\n";
  }
  write_file(dir + "/three.csv", csv);
  const Expansion e = expand(dir, {{"urdf", "three.urdf"}, {"trajectory", "three.csv"}});
  ASSERT_EQ(e.steps.links.size(), 3u);
  EXPECT_EQ(e.steps.files, (std::vector<std::string>{dir + "/three.urdf", dir + "/three.csv"}));
  for (std::size_t r = 0; r < qs.size(); ++r) {
    // std::to_string keeps 6 decimals; the values above have at most 2.
    const double qa = qs[r][0], qb = qs[r][1], qc = qs[r][2];
    const auto& objects = e.steps.links[r];
    ASSERT_EQ(objects.size(), 3u);
    // l2's origin, by hand: (0.2 cos a − b sin a, 0.2 sin a + b cos a, 0.5) — the prismatic
    // axis is l1's x turned by 90°, i.e. (−sin a, cos a, 0).
    const Vec3 l2_origin(0.2 * std::cos(qa) - qb * std::sin(qa),
                         0.2 * std::sin(qa) + qb * std::cos(qa), 0.5);
    EXPECT_LT((objects[1].bounds.center() - l2_origin).norm(), kTol) << "row " << r;
    const std::vector<Vec3> l3 = three_joint_l3_corners(qa, qb, qc);
    expect_vertices(objects[2].mesh, l3, "l3 row " + std::to_string(r));
  }
}

// A mimic joint m follows j: value 2·j + 0.1.
TEST(RobotKinematics, MimicJointFollowsMultiplierAndOffset) {
  const std::string dir = temp_dir("robot-mimic");
  write_file(dir + "/mimic.urdf", R"(<robot name="m">
  <link name="base"/>
  <link name="a"/>
  <link name="b"><collision><origin xyz="1 0 0"/><geometry><box size="0.2 0.2 0.2"/></geometry>
  </collision></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="m" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
    <mimic joint="j" multiplier="2" offset="0.1"/></joint>
</robot>)");
  const double q = 0.3, angle = q + (2 * q + 0.1);  // b turns by j + m about the same axis
  const Expansion e =
      expand(dir, {{"urdf", "mimic.urdf"}, {"trajectory", {{{"t", 0}, {"joints", {{"j", q}}}}}}});
  EXPECT_LT(
      (e.steps.links[0][0].bounds.center() - Vec3(std::cos(angle), std::sin(angle), 0)).norm(),
      kTol);
  // Giving the mimic joint a value is refused: it follows j.
  expect_error(
      dir, {{"urdf", "mimic.urdf"}, {"trajectory", {{{"t", 0}, {"joints", {{"j", q}, {"m", 0}}}}}}},
      "", "/robots/0/trajectory/0/joints/m", {"joint \"m\" mimics \"j\""});
}

// The angle of the one-joint robot's link at each sample.
std::vector<double> angles(const Expansion& e) {
  std::vector<double> out;
  for (const auto& objects : e.steps.links) {
    const Vec3 c = objects[0].bounds.center();
    out.push_back(std::atan2(c.y(), c.x()));
  }
  return out;
}

void expect_near_all(const std::vector<double>& got, const std::vector<double>& want,
                     const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], want[i], kTol) << what << i;
}

TEST(RobotTrajectory, StepsAndEverySecondsSampleAndInterpolateLinearly) {
  const std::string dir = temp_dir("robot-sample");
  write_file(dir + "/one.urdf", kOneJointUrdf);
  // q: 0 at t = 0, 1 at t = 2, −1 at t = 3.
  write_file(dir + "/one.csv", "t,j\n0,0\n2,1\n3,-1\n");
  const json robot = {{"urdf", "one.urdf"}, {"trajectory", "one.csv"}};

  Expansion rows = expand(dir, robot);
  expect_near_all(rows.steps.times, {0, 2, 3}, "rows t");
  expect_near_all(angles(rows), {0, 1, -1}, "rows q");

  json steps = robot;
  steps["sample"] = {{"steps", 5}};  // t = 0, 0.75, 1.5, 2.25, 3
  Expansion s = expand(dir, steps);
  expect_near_all(s.steps.times, {0, 0.75, 1.5, 2.25, 3}, "steps t");
  expect_near_all(angles(s), {0, 0.375, 0.75, 1 - 0.25 * 2, -1}, "steps q");

  steps["sample"] = {{"steps", 1}};
  expect_near_all(expand(dir, steps).steps.times, {0}, "one step");

  json every = robot;
  every["sample"] = {{"every_s", 0.8}};  // 0, 0.8, 1.6, 2.4, then the last row's 3
  Expansion ev = expand(dir, every);
  expect_near_all(ev.steps.times, {0, 0.8, 1.6, 2.4, 3}, "every_s t");
  expect_near_all(angles(ev), {0, 0.4, 0.8, 1 - 0.4 * 2, -1}, "every_s q");

  every["sample"] = {{"every_s", 1}};  // lands on the last row: no sample twice
  expect_near_all(expand(dir, every).steps.times, {0, 1, 2, 3}, "every_s 1");
}

TEST(RobotTrajectory, ContinuousJointInterpolatesPlainlyWithoutWrapping) {
  const std::string dir = temp_dir("robot-continuous");
  write_file(dir + "/c.urdf", R"(<robot name="c">
  <link name="base"/>
  <link name="arm"><collision><origin xyz="1 0 0"/><geometry><box size="0.2 0.2 0.2"/>
  </geometry></collision></link>
  <joint name="j" type="continuous"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
  </joint>
</robot>)");
  // From 3 to −3 rad: halfway is 0 (the long way round), not ±π.
  const Expansion e = expand(
      dir,
      {{"urdf", "c.urdf"},
       {"trajectory", {{{"t", 0}, {"joints", {{"j", 3}}}}, {{"t", 1}, {"joints", {{"j", -3}}}}}},
       {"sample", {{"steps", 3}}}});
  expect_near_all(angles(e), {3, 0, -3}, "continuous");
}

// Writes an OFF box [0, 1]³ scaled by `s` along x.
std::string off_box(double s) {
  std::string t = "OFF\n8 6 0\n";
  for (int i = 0; i < 8; ++i) {
    t += std::to_string(i & 1 ? s : 0.0) + " " + std::to_string(i & 2 ? 1 : 0) + " " +
         std::to_string(i & 4 ? 1 : 0) + "\n";
  }
  // Outward quads: −x, +x, −y, +y, −z, +z.
  t += "4 0 4 6 2\n4 1 3 7 5\n4 0 1 5 4\n4 2 6 7 3\n4 0 2 3 1\n4 4 5 7 6\n";
  return t;
}

TEST(RobotMeshes, PackageRelativeAndFileUrisResolveAndVisualLinksAreSelectable) {
  const std::string dir = temp_dir("robot-meshes");
  write_file(dir + "/pkgs/my_robot/meshes/unit.off", off_box(1));
  write_file(dir + "/urdf/meshes/long.off", off_box(3));
  write_file(dir + "/abs/wide.off", off_box(2));
  write_file(dir + "/urdf/r.urdf", R"(<robot name="r">
  <link name="base">
    <collision><geometry><mesh filename="package://my_robot/meshes/unit.off" scale="2 1 0.5"/>
    </geometry></collision>
    <collision><origin xyz="0 0 1"/><geometry><mesh filename="meshes/long.off"/></geometry>
    </collision>
    <visual><geometry><mesh filename="file://)" +
                                       dir + R"(/abs/wide.off"/></geometry></visual>
  </link>
</robot>)");
  const json traj = {{{"t", 0}, {"joints", json::object()}}};
  const json robot = {{"name", "r"},
                      {"urdf", "urdf/r.urdf"},
                      {"package_paths", {{"my_robot", "pkgs/my_robot"}}},
                      {"trajectory", traj}};
  const Expansion c = expand(dir, robot);
  ASSERT_EQ(c.steps.links.at(0).size(), 2u);
  const auto& objects = c.steps.links[0];
  EXPECT_EQ(objects[0].name, "r/base");
  EXPECT_EQ(objects[1].name, "r/base/1");
  EXPECT_EQ(objects[1].entry, "/robots/0 (link \"base\", collision 1)");
  EXPECT_LT((objects[0].bounds.max - Vec3(2, 1, 0.5)).norm(), kTol);  // scale 2 1 0.5
  EXPECT_LT((objects[1].bounds.min - Vec3(0, 0, 1)).norm(), kTol);
  EXPECT_LT((objects[1].bounds.max - Vec3(3, 1, 2)).norm(), kTol);
  EXPECT_EQ(c.steps.files,
            (std::vector<std::string>{dir + "/urdf/r.urdf", dir + "/pkgs/my_robot/meshes/unit.off",
                                      dir + "/urdf/meshes/long.off"}));

  json visual = robot;
  visual["links"] = "visual";
  const Expansion v = expand(dir, visual);
  ASSERT_EQ(v.steps.links.at(0).size(), 1u);
  EXPECT_EQ(v.steps.links[0][0].entry, "/robots/0 (link \"base\", visual 0)");
  EXPECT_LT((v.steps.links[0][0].bounds.max - Vec3(2, 1, 1)).norm(), kTol);
}

// Points of the primitive's surface, all inside (or on) the convex mesh: on the inner side of
// every face plane.
void expect_convex_contains(const core::TriangleMesh& m, const std::vector<Vec3>& points) {
  for (const Vec3& p : points) {
    for (const auto& t : m.triangles) {
      const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
      const Vec3 n = (b - a).cross(c - a).normalized();
      ASSERT_LE(n.dot(p - a), 1e-12) << "point " << p.transpose() << " outside a face";
    }
  }
}

TEST(RobotPrimitives, CylinderAndSphereMeshesContainThePrimitiveAndAreClosed) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  const double r = 0.3, len = 0.8;
  core::TriangleMesh cyl = core::detail::cylinder_mesh(r, len);
  EXPECT_EQ(cyl.vertices.size(), 2u * core::detail::kCylinderSides + 2);
  EXPECT_EQ(cyl.triangles.size(), 4u * core::detail::kCylinderSides);
  std::vector<Vec3> rim;
  for (int i = 0; i < 2000; ++i) {
    const double phi = 2 * kPi * u(rng);
    rim.emplace_back(r * std::cos(phi), r * std::sin(phi), (u(rng) < 0.5 ? -0.5 : 0.5) * len);
  }
  expect_convex_contains(cyl, rim);
  // Tight: the vertices lie at r / cos(π/k), the edges' midpoints on the circle.
  for (const Vec3& v : cyl.vertices) {
    const double rv = std::hypot(v.x(), v.y());
    if (rv > 0) {
      EXPECT_NEAR(rv, r / std::cos(kPi / core::detail::kCylinderSides), 1e-12);
    }
  }
  const double before = core::signed_volume(cyl);
  core::detail::validate_and_orient(cyl, "test", "cylinder");
  EXPECT_NEAR(core::signed_volume(cyl), before, 1e-12);  // already outward
  EXPECT_GT(before, kPi * r * r * len);

  core::TriangleMesh sph = core::detail::sphere_mesh(r);
  EXPECT_EQ(sph.vertices.size(),
            std::size_t((core::detail::kSphereBands - 1) * core::detail::kSphereSectors + 2));
  EXPECT_EQ(sph.triangles.size(),
            std::size_t(2 * (core::detail::kSphereBands - 1) * core::detail::kSphereSectors));
  std::normal_distribution<double> g;
  std::vector<Vec3> surface;
  for (int i = 0; i < 5000; ++i) surface.push_back(r * Vec3(g(rng), g(rng), g(rng)).normalized());
  for (const Vec3& axis : std::array<Vec3, 3>{Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()}) {
    surface.push_back(r * axis);
    surface.push_back(-r * axis);
  }
  expect_convex_contains(sph, surface);
  const double sphere_before = core::signed_volume(sph);
  core::detail::validate_and_orient(sph, "test", "sphere");
  EXPECT_NEAR(core::signed_volume(sph), sphere_before, 1e-12);
  EXPECT_GT(sphere_before, 4.0 / 3.0 * kPi * r * r * r);
  EXPECT_LT(sphere_before, 1.2 * 4.0 / 3.0 * kPi * r * r * r);  // and not grossly larger
}

// ---- swept volumes ----

// The planar chain's l2 corners at (q1, q2), by hand.
std::vector<Vec3> planar_l2_corners(double q1, double q2) {
  std::vector<Vec3> out;
  const double q12 = q1 + q2;
  for (double x : {0.0, 0.5}) {
    for (double y : {-0.05, 0.05}) {
      for (double z : {-0.05, 0.05}) {
        out.emplace_back(std::cos(q1) + x * std::cos(q12) - y * std::sin(q12),
                         std::sin(q1) + x * std::sin(q12) + y * std::cos(q12), z);
      }
    }
  }
  return out;
}

// True when p lies in the convex mesh (on the inner side of every face plane, within tol).
bool in_convex(const core::TriangleMesh& m, const Vec3& p, double tol = 1e-9) {
  for (const auto& t : m.triangles) {
    const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    if ((b - a).cross(c - a).normalized().dot(p - a) > tol) return false;
  }
  return true;
}

// Random points of the solid box with these 8 corners (convex combinations).
std::vector<Vec3> points_of(const std::vector<Vec3>& corners, std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> out = corners;
  for (int i = 0; i < n; ++i) {
    const double x = u(rng), y = u(rng), z = u(rng);
    Vec3 p = Vec3::Zero();
    for (int c = 0; c < 8; ++c)
      p += corners[c] * ((c & 4 ? x : 1 - x) * (c & 2 ? y : 1 - y) * (c & 1 ? z : 1 - z));
    out.push_back(p);
  }
  return out;
}

TEST(RobotSwept, EnclosureHoldsTheLinkAtRandomIntermediatePoses) {
  const std::string dir = temp_dir("robot-swept");
  write_file(dir + "/planar.urdf", kPlanarUrdf);
  // Rows at t = 0, 1, 2, sampled at t = 0 and 2: sample 0 must enclose the motion through the
  // row at t = 1, where the path turns.
  const std::vector<std::array<double, 3>> rows = {{0, 0, 0}, {1, 1.5, -2.0}, {2, -0.5, 2.5}};
  json traj = json::array();
  for (const auto& r : rows)
    traj.push_back({{"t", r[0]}, {"joints", {{"j1", r[1]}, {"j2", r[2]}}}});
  const Expansion e = expand(
      dir,
      {{"urdf", "planar.urdf"}, {"trajectory", traj}, {"sample", {{"steps", 2}}}, {"swept", true}});
  ASSERT_EQ(e.steps.links.size(), 2u);
  core::TriangleMesh hull = e.steps.links[0][1].mesh;
  EXPECT_NO_THROW(core::detail::validate_and_orient(hull, "test", "swept l2"));
  EXPECT_GT(core::signed_volume(e.steps.links[0][1].mesh), 0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 2);
  for (int i = 0; i < 300; ++i) {
    const double t = u(rng);
    const auto& a = rows[t < 1 ? 0 : 1];
    const auto& b = rows[t < 1 ? 1 : 2];
    const double s = t - a[0];  // rows 1 s apart
    const double q1 = (1 - s) * a[1] + s * b[1], q2 = (1 - s) * a[2] + s * b[2];
    for (const Vec3& p : points_of(planar_l2_corners(q1, q2), rng, 20))
      ASSERT_TRUE(in_convex(e.steps.links[0][1].mesh, p)) << "t = " << t << ": " << p.transpose();
  }
  // The last sample is the pose alone.
  expect_vertices(e.steps.links[1][1].mesh, planar_l2_corners(-0.5, 2.5), "last sample");
}

TEST(RobotSwept, EnclosureHoldsAPrismaticAndSkewAxisChain) {
  const std::string dir = temp_dir("robot-swept3");
  write_file(dir + "/three.urdf", kThreeJointUrdf);
  const std::array<double, 3> q0 = {-1.0, 0.0, -1.5}, q1 = {1.2, 0.5, 1.8};
  const json traj = {{{"t", 0}, {"joints", {{"a", q0[0]}, {"b", q0[1]}, {"c", q0[2]}}}},
                     {{"t", 4}, {"joints", {{"a", q1[0]}, {"b", q1[1]}, {"c", q1[2]}}}}};
  const Expansion e = expand(dir, {{"urdf", "three.urdf"}, {"trajectory", traj}, {"swept", true}});
  ASSERT_EQ(e.steps.links.size(), 2u);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 300; ++i) {
    const double s = u(rng);
    const auto l3 = three_joint_l3_corners((1 - s) * q0[0] + s * q1[0], (1 - s) * q0[1] + s * q1[1],
                                           (1 - s) * q0[2] + s * q1[2]);
    for (const Vec3& p : points_of(l3, rng, 20))
      ASSERT_TRUE(in_convex(e.steps.links[0][2].mesh, p)) << "s = " << s << ": " << p.transpose();
  }
}

TEST(RobotSwept, MotionThroughARowBetweenSamplesIsEnclosed) {
  const std::string dir = temp_dir("robot-swept-knot");
  write_file(dir + "/one.urdf", kOneJointUrdf);
  // Out to 1.5 rad and back between the samples at t = 0 and t = 2: equal end poses, yet the link
  // sweeps a quarter circle.
  write_file(dir + "/one.csv", "t,j\n0,0\n1,1.5\n2,0\n");
  const Expansion e = expand(dir, {{"urdf", "one.urdf"},
                                   {"trajectory", "one.csv"},
                                   {"sample", {{"steps", 2}}},
                                   {"swept", true}});
  for (double q = 0; q <= 1.5; q += 0.05) {
    const Vec3 centre(std::cos(q), std::sin(q), 0);  // the cube's centre, by hand
    EXPECT_TRUE(in_convex(e.steps.links[0][0].mesh, centre)) << "q = " << q;
  }
}

TEST(RobotSwept, LinkAtRestKeepsItsOwnMesh) {
  const std::string dir = temp_dir("robot-swept-rest");
  write_file(dir + "/planar.urdf", kPlanarUrdf);
  // A robot standing still over an interval sweeps nothing: each link keeps its own mesh.
  const json still = {{{"t", 0}, {"joints", {{"j1", 0.3}, {"j2", 0.2}}}},
                      {{"t", 1}, {"joints", {{"j1", 0.3}, {"j2", 0.2}}}}};
  const Expansion e =
      expand(dir, {{"urdf", "planar.urdf"}, {"trajectory", still}, {"swept", true}});
  expect_vertices(e.steps.links[0][1].mesh, planar_l2_corners(0.3, 0.2), "at rest");
}

// ---- bad input: one InputError each, naming the file and the entry ----

class RobotErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = temp_dir(std::string("robot-errors-") +
                    ::testing::UnitTest::GetInstance()->current_test_info()->name());
    write_file(dir_ + "/planar.urdf", kPlanarUrdf);
  }
  json robot(const json& trajectory) const {
    return {{"urdf", "planar.urdf"}, {"trajectory", trajectory}};
  }
  json row(double t, double j1, double j2) const {
    return {{"t", t}, {"joints", {{"j1", j1}, {"j2", j2}}}};
  }
  json csv(const std::string& text) const {
    write_file(dir_ + "/traj.csv", text);
    return robot("traj.csv");
  }
  std::string dir_;
};

TEST_F(RobotErrors, UrdfThatDoesNotParseNamesTheFileAndUrdfdomsReason) {
  write_file(dir_ + "/bad.urdf", "<robot name=\"x\"><link name=\"a\"></robot>");
  expect_error(dir_, {{"urdf", "bad.urdf"}, {"trajectory", "t.csv"}}, "", "/robots/0/urdf",
               {"URDF file " + dir_ + "/bad.urdf cannot be parsed: "});
  // Not XML-malformed but not a robot: a joint names a link that does not exist.
  write_file(dir_ + "/bad2.urdf", R"(<robot name="x"><link name="a"/>
    <joint name="j" type="fixed"><parent link="a"/><child link="nowhere"/></joint></robot>)");
  expect_error(dir_, {{"urdf", "bad2.urdf"}, {"trajectory", "t.csv"}}, "", "/robots/0/urdf",
               {"cannot be parsed: ", "nowhere"});
}

TEST_F(RobotErrors, XacroFileMustBeExpandedFirst) {
  write_file(dir_ + "/r.urdf.xacro", R"(<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="arm"><link name="a"/></xacro:macro><link name="base"/></robot>)");
  expect_error(dir_, {{"urdf", "r.urdf.xacro"}, {"trajectory", "t.csv"}}, "", "/robots/0/urdf",
               {"contains xacro macros", "xacro robot.urdf.xacro > robot.urdf"});
}

TEST_F(RobotErrors, MissingUrdfFile) {
  expect_error(dir_, {{"urdf", "none.urdf"}, {"trajectory", "t.csv"}}, "", "/robots/0/urdf",
               {"URDF file " + dir_ + "/none.urdf does not exist"});
}

TEST_F(RobotErrors, MissingMeshFileNamesTheLinkElement) {
  write_file(dir_ + "/m.urdf", R"(<robot name="m"><link name="body"><collision><geometry>
    <mesh filename="meshes/gone.stl"/></geometry></collision></link></robot>)");
  expect_error(dir_, {{"urdf", "m.urdf"}, {"trajectory", {{{"t", 0}, {"joints", json::object()}}}}},
               "", "/robots/0 (link \"body\", collision 0)",
               {"mesh file " + dir_ + "/meshes/gone.stl does not exist"});
}

TEST_F(RobotErrors, UnlistedPackageNamesTheUriAndTheKeyToAdd) {
  write_file(dir_ + "/p.urdf", R"(<robot name="p"><link name="body"><collision><geometry>
    <mesh filename="package://ur_description/meshes/base.stl"/></geometry></collision></link>
    </robot>)");
  expect_error(
      dir_, {{"urdf", "p.urdf"}, {"trajectory", {{{"t", 0}, {"joints", json::object()}}}}}, "",
      "/robots/0 (link \"body\", collision 0)",
      {"package://ur_description/meshes/base.stl", "\"package_paths\"", "\"ur_description\""});
}

TEST_F(RobotErrors, UnknownJointInTrajectoryListsTheMovableJoints) {
  expect_error(dir_, robot({{{"t", 0}, {"joints", {{"j1", 0}, {"j2", 0}, {"elbow", 0}}}}}), "",
               "/robots/0/trajectory/0/joints/elbow",
               {"unknown joint \"elbow\"", "movable joints are: j1, j2"});
  expect_error(dir_, csv("t,j1,elbow,j2\n0,0,0,0\n"), "traj.csv", "line 1, column 3",
               {"unknown joint \"elbow\"", "movable joints are: j1, j2"});
}

TEST_F(RobotErrors, MissingJointIsListed) {
  expect_error(dir_, robot({row(0, 0, 0), {{"t", 1}, {"joints", {{"j1", 0}}}}}), "",
               "/robots/0/trajectory/1/joints", {"row 1 gives no value", "j2"});
  expect_error(dir_, csv("t, j2\n0, 0\n"), "traj.csv", "line 1", {"no column", "j1"});
}

TEST_F(RobotErrors, ValueOutOfLimitsNamesJointRowValueAndLimits) {
  expect_error(dir_, robot({row(0, 0, 0), row(1, 0, 3.5)}), "", "/robots/0/trajectory/1/joints/j2",
               {"joint \"j2\" value 3.5 rad at row 1 is outside its limits [-3.2, 3.2] rad"});
  // Line numbers count comment and blank lines.
  expect_error(dir_, csv("# comment\nt,j1,j2\n\n0,0,0\n1,-3.3,0\n"), "traj.csv",
               "line 5, column \"j1\"",
               {"joint \"j1\" value -3.3 rad at line 5 is outside its limits [-3.2, 3.2] rad"});
  // Within the 1e-9 slack: accepted.
  EXPECT_NO_THROW(expand(dir_, robot(json::array({row(0, 3.2 + 5e-10, 0)}))));
}

TEST_F(RobotErrors, TimesMustIncreaseStrictly) {
  expect_error(dir_, robot({row(0, 0, 0), row(1, 0, 0), row(1, 0, 0)}), "",
               "/robots/0/trajectory/2/t", {"time 1 s is not after the previous row's 1 s"});
  expect_error(dir_, csv("t,j1,j2\n0,0,0\n-1,0,0\n"), "traj.csv", "line 3, column \"t\"",
               {"times must increase strictly"});
}

TEST_F(RobotErrors, EmptyTrajectory) {
  expect_error(dir_, robot(json::array()), "", "/robots/0/trajectory", {"at least one row"});
  expect_error(dir_, csv("# nothing\n"), "traj.csv", "", {"the trajectory is empty"});
  expect_error(dir_, csv("t,j1,j2\n"), "traj.csv", "", {"no rows"});
}

TEST_F(RobotErrors, FloatingJointIsRefused) {
  write_file(dir_ + "/f.urdf", R"(<robot name="f"><link name="world"/><link name="body"/>
    <joint name="free" type="floating"><parent link="world"/><child link="body"/></joint>
    </robot>)");
  expect_error(dir_, {{"urdf", "f.urdf"}, {"trajectory", "t.csv"}}, "",
               "/robots/0/urdf (joint \"free\")", {"\"floating\" is not supported"});
}

TEST_F(RobotErrors, BadCsvRows) {
  expect_error(dir_, csv("t,j1,j2\n0,0,0\n1,0\n"), "traj.csv", "line 3",
               {"the row has 2 values, the header 3 columns"});
  expect_error(dir_, csv("t,j1,j2\n0,0,zero\n"), "traj.csv", "line 2, column \"j2\"",
               {"\"zero\" is not a finite number"});
  expect_error(dir_, csv("time,j1,j2\n0,0,0\n"), "traj.csv", "line 1",
               {"first column must be \"t\""});
  expect_error(dir_, csv("t,j1,j2,j1\n0,0,0,0\n"), "traj.csv", "line 1, column 4", {"given twice"});
  expect_error(dir_, robot("none.csv"), "", "/robots/0/trajectory",
               {"trajectory file " + dir_ + "/none.csv does not exist"});
}

TEST_F(RobotErrors, BadRobotKeys) {
  json r = robot(json::array({row(0, 0, 0)}));
  r["link"] = "visual";
  expect_error(dir_, r, "", "/robots/0/link", {"unknown field \"link\""});
  r = robot(json::array({row(0, 0, 0)}));
  r["links"] = "inertial";
  expect_error(dir_, r, "", "/robots/0/links", {"expected \"collision\" or \"visual\""});
  r = robot(json::array({row(0, 0, 0)}));
  r["sample"] = {{"steps", 2}, {"every_s", 1}};
  expect_error(dir_, r, "", "/robots/0/sample", {"exactly one of"});
  r["sample"] = {{"every_s", 0}};
  expect_error(dir_, r, "", "/robots/0/sample/every_s", {"must be positive"});
  r["sample"] = {{"steps", 0}};
  expect_error(dir_, r, "", "/robots/0/sample/steps", {"out of range"});
  r = robot(json::array({row(0, 0, 0)}));
  r["base"] = {{"scale", 2}};
  expect_error(dir_, r, "", "/robots/0/base/scale", {"unknown field \"scale\""});
}

}  // namespace
}  // namespace camplace::testing

namespace camplace::testing {
namespace {

TEST_F(RobotErrors, TimesBeyondABillionSecondsAreRefused) {
  expect_error(dir_, robot({row(-1e308, 0, 0), row(1e308, 0, 0)}), "", "/robots/0/trajectory/0/t",
               {"is beyond ±1e+09 s"});
  expect_error(dir_, csv("t,j1,j2\n0,0,0\n2e9,0,0\n"), "traj.csv", "line 3, column \"t\"",
               {"is beyond ±1e+09 s"});
}

TEST_F(RobotErrors, ARobotWithoutGeometryOfTheChosenKindIsRefused) {
  write_file(dir_ + "/v.urdf", R"(<robot name="v"><link name="body"><visual><geometry>
    <box size="0.1 0.1 0.1"/></geometry></visual></link></robot>)");
  expect_error(dir_, {{"urdf", "v.urdf"}, {"trajectory", {{{"t", 0}, {"joints", json::object()}}}}},
               "", "/robots/0", {"no collision geometry", "\"links\": \"visual\""});
}

TEST_F(RobotErrors, AMimicThatThrowsALinkFarAwayIsRefused) {
  write_file(dir_ + "/mm.urdf", R"(<robot name="mm"><link name="base"/>
    <link name="a"/><link name="b"><collision><geometry><box size="0.1 0.1 0.1"/></geometry>
    </collision></link>
    <joint name="j" type="continuous"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/></joint>
    <joint name="p" type="prismatic"><parent link="a"/><child link="b"/><axis xyz="1 0 0"/>
      <limit lower="-1e300" upper="1e300" effort="1" velocity="1"/><mimic joint="j" multiplier="1e300"/></joint>
    </robot>)");
  expect_error(dir_, {{"urdf", "mm.urdf"}, {"trajectory", {{{"t", 0}, {"joints", {{"j", 2.0}}}}}}},
               "", "/robots/0 (link \"b\", collision 0)", {"the link lies beyond ±1e+06 m"});
}

}  // namespace
}  // namespace camplace::testing
