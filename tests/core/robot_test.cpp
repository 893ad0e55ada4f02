// Robots from URDF on a joint trajectory (detail::expand_robot): link poses against forward
// kinematics written out by hand, trajectory sampling and interpolation, mesh paths and the
// primitive meshes. Swept volumes: robot_swept_test.cpp; bad input: robot_errors_test.cpp.
#include "../../core/src/robot.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "../../core/src/mesh_checks.hpp"
#include "robot_fixtures.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using namespace robot_fixtures;  // the robot tests' helpers (robot_fixtures.hpp)

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

}  // namespace
}  // namespace camplace::testing
