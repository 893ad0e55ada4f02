#pragma once
// Shared by the robot tests (robot_test.cpp, robot_swept_test.cpp, robot_errors_test.cpp): the
// test's own rotations, the URDFs of the chains they pose, and expand_robot run on one robot
// entry with its error check.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../../core/src/mesh_checks.hpp"
#include "../../core/src/robot.hpp"
#include "camplace/core/error.hpp"

namespace camplace::testing::robot_fixtures {

using core::kPi;
using core::Vec3;
using nlohmann::json;
using Mat3 = Eigen::Matrix3d;

constexpr double kTol = 1e-9;

// ---- rotations written out entry by entry (the test's own kinematics) ----
inline Mat3 rot_x(double a) {
  Mat3 m;
  m << 1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a);
  return m;
}
inline Mat3 rot_y(double a) {
  Mat3 m;
  m << std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a);
  return m;
}
inline Mat3 rot_z(double a) {
  Mat3 m;
  m << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  return m;
}
// Rotation by a about the unit axis (1, 1, 0)/√2 (Rodrigues: cI + s[k]× + (1 − c)kkᵀ, written
// out).
inline Mat3 rot_diagonal_xy(double a) {
  const double c = std::cos(a), s = std::sin(a), h = std::sqrt(0.5);
  Mat3 m;
  m << c + (1 - c) * 0.5, (1 - c) * 0.5, s * h,  //
      (1 - c) * 0.5, c + (1 - c) * 0.5, -s * h,  //
      -s * h, s * h, c;
  return m;
}

// The 8 corners of a box of `size` centred at the origin.
inline std::vector<Vec3> box_corners(const Vec3& size) {
  std::vector<Vec3> out;
  for (int i = 0; i < 8; ++i) {
    out.emplace_back((i & 1 ? 0.5 : -0.5) * size.x(), (i & 2 ? 0.5 : -0.5) * size.y(),
                     (i & 4 ? 0.5 : -0.5) * size.z());
  }
  return out;
}

// Every expected point is a vertex of the mesh (within kTol), and the counts agree.
inline void expect_vertices(const core::TriangleMesh& mesh, const std::vector<Vec3>& expected,
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
inline const std::string kPlanarUrdf = R"(<robot name="planar">
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
inline const std::string kOneJointUrdf = R"(<robot name="one">
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
inline Expansion expand(const std::string& dir, const json& robot) {
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
inline void expect_error(const std::string& dir, const json& robot, const std::string& file,
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

// base → a (revolute z, at z = 0.5) → l1 → b (prismatic along x, origin x = 0.2 and yaw 90°)
// → l2 → c (revolute about (1, 1, 0)/√2, origin z = 0.3 and rpy (0.3, 0.2, 0.1)) → l3, whose
// box 0.2 × 0.1 × 0.4 sits at x = 0.1 pitched by 0.3.
inline const std::string kThreeJointUrdf = R"(<robot name="three">
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
inline std::vector<Vec3> three_joint_l3_corners(double qa, double qb, double qc) {
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

}  // namespace camplace::testing::robot_fixtures
