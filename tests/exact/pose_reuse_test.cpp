// The targets' silhouette cones shared between states of the same pose (ExactOptions::reuse_poses,
// the default) against every state building its own: every state's d_model², model volume and
// component counts are the same exact fractions. The scenes repeat the person's poses across time
// steps while the robot moves, in both dynamic modes: in `modelled` mode the robot occludes, so
// the person's cone of a step where the robot stands in front of him differs from that of a step
// where it does not, and a cache keyed on the targets alone would give other models.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "../core/fine_meshes.hpp"
#include "camplace/core/camera.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/exact/evaluator.hpp"
#include "scene_builder.hpp"

namespace camplace {
namespace {

using core::Vec3;
using testing::mesh_object;

/// A person of two ellipsoids (torso, head) standing at (x, y).
std::vector<core::SceneObject> person(double x, double y) {
  return {mesh_object("torso", testing::ellipsoid(Vec3(x, y, 0.8), Vec3(0.22, 0.15, 0.75), 8, 5,
                                                  Eigen::Matrix3d::Identity())),
          mesh_object("head", testing::ellipsoid(Vec3(x, y, 1.65), Vec3(0.12, 0.12, 0.15), 6, 4,
                                                 Eigen::Matrix3d::Identity()))};
}

/// 4×3×3 m; camera 0 on the west wall looks east along y = 1.5 at the person at (3, 1.5); the
/// robot (a column) stands between them at step 0 and step 2 and aside at step 1; a second
/// person at (1, 0.6) in the second event of each step; camera 1 looks down from a corner.
core::Scene repeated_pose_scene(core::DynamicMode mode) {
  const core::Box3 area{Vec3(0, 0, 0), Vec3(4, 3, 3)};
  core::Scene scene = testing::simple_scene(area, {8, 6, 6}, 2, 30.0, {}, {});
  core::use_exact_models(scene.cameras);
  scene.dynamic_mode = mode;
  scene.plausibility = {};
  scene.static_obstacles.push_back(
      mesh_object("shelf", testing::subdivided_box(Vec3(0.3, 2.3, 0), Vec3(0.8, 2.8, 1.2), 3)));
  scene.time_steps.clear();
  const double robot_y[3] = {1.5, 0.5, 1.45};
  for (int h = 0; h < 3; ++h) {
    core::TimeStep step;
    step.dynamic_obstacles.push_back(
        mesh_object("robot", testing::ellipsoid(Vec3(2.0, robot_y[h], 1.0), Vec3(0.12, 0.12, 0.6),
                                                8, 4, Eigen::Matrix3d::Identity())));
    step.critical = step.dynamic_obstacles;
    for (int l = 0; l < 2; ++l) {
      core::Event e;
      e.weight = 0.5;
      e.targets = l == 0 ? person(3.0, 1.5) : person(1.0, 0.6);
      step.events.push_back(std::move(e));
    }
    scene.time_steps.push_back(std::move(step));
  }
  return scene;
}

TEST(PoseReuse, StatesOfTheSamePoseGiveTheSameFractionsAsComputingEachState) {
  const core::CameraConfig config{testing::camera_at(Vec3(0.05, 1.5, 1.2), 0.0, -5.0),
                                  testing::camera_at(Vec3(3.9, 2.9, 2.9), -140.0, -35.0)};
  // Both dynamic modes with one thread (a thread visits every step), `modelled` also with two.
  for (const auto mode : {core::DynamicMode::modelled, core::DynamicMode::masked}) {
    for (const int threads : {1, 2}) {
      if (mode == core::DynamicMode::masked && threads == 2) continue;
      SCOPED_TRACE(std::string(mode == core::DynamicMode::modelled ? "modelled" : "masked") +
                   ", threads " + std::to_string(threads));
      const core::Scene scene = repeated_pose_scene(mode);
      exact::ExactOptions reuse;
      reuse.threads = threads;
      exact::ExactOptions each = reuse;
      each.reuse_poses = false;
      long last_done = -1, total = 0;
      reuse.on_progress = [&](long done, long of) {
        EXPECT_EQ(done, last_done + 1);
        last_done = done;
        total = of;
      };
      const auto a = exact::evaluate_exact(scene, config, reuse);
      const auto b = exact::evaluate_exact(scene, config, each);
      EXPECT_EQ(total, 6 * 2);
      EXPECT_EQ(last_done, total);
      ASSERT_EQ(a.states.size(), b.states.size());
      for (std::size_t s = 0; s < a.states.size(); ++s) {
        EXPECT_EQ(a.states[s].d_model_sq_exact, b.states[s].d_model_sq_exact) << "state " << s;
        EXPECT_EQ(a.states[s].model_volume_exact, b.states[s].model_volume_exact) << "state " << s;
        EXPECT_EQ(a.states[s].components, b.states[s].components) << "state " << s;
        EXPECT_EQ(a.states[s].components_removed, b.states[s].components_removed) << "state " << s;
      }
      EXPECT_EQ(a.err, b.err);
    }
  }
}

}  // namespace
}  // namespace camplace
