// Robots' bad input (detail::expand_robot): one InputError for every kind, naming the file (scene,
// URDF or trajectory CSV), the entry and the reason.
#include <gtest/gtest.h>

#include <string>

#include "robot_fixtures.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using namespace robot_fixtures;  // the robot tests' helpers (robot_fixtures.hpp)

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
