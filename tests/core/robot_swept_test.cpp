// Robots' swept volumes ("swept": true, detail::expand_robot): every sample's object encloses
// the link at random intermediate poses computed by hand; a link at rest keeps its own mesh.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "../../core/src/mesh_checks.hpp"
#include "robot_fixtures.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using namespace robot_fixtures;  // the robot tests' helpers (robot_fixtures.hpp)

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

}  // namespace
}  // namespace camplace::testing
