// Obstacles and critical objects that extend beyond the area S (SPEC §2: they occlude and,
// masked, change pixels wherever they are; the model is always inside S): the voxel labels of
// both modes against the brute-force references (tests/support/reference.cpp, which know
// nothing of S) with an object crossing each face of S, for each kind of obstacle, with cameras
// inside S, outside it behind the object's outside part, and inside that outside part (blind);
// the model (interiors subtracted) and the distances against values computed independently. The
// random sweeps against the references are in beyond_area_sweep_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>

#include "camplace/core/distance.hpp"
#include "camplace/core/err.hpp"
#include "crossing_scene.hpp"
#include "lower_bound_reference.hpp"
#include "reference.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using core::Box3;
using core::Vec3;
using voxel::Label;
using voxel::LabelMode;
using namespace beyond;  // crossing scenes (tests/support/crossing_scene.hpp)

/// Camera 2 inside the crossing box's outside part sees nothing in either mode, and a camera
/// outside S sees voxels of S free.
TEST(BeyondArea, CameraInsideAnOutsidePartIsBlindAndCamerasOutsideSSee) {
  for (LabelMode mode : {LabelMode::center, LabelMode::conservative}) {
    core::Scene s = simple_scene(kArea, {8, 6, 6}, 2, 40.0, {}, {});
    s.dynamic_mode = core::DynamicMode::modelled;  // the conveyor occludes (below the voxel)
    s.time_steps.front().dynamic_obstacles.push_back(
        box_object("conveyor", Vec3(-2, 1, 0), Vec3(6, 2, 0.5)));
    s.time_steps.front().critical = s.time_steps.front().dynamic_obstacles;
    s.time_steps.front().events.front().targets.push_back(
        box_object("person", Vec3(1.5, 2.2, 0.2), Vec3(1.9, 2.6, 1.8)));
    const voxel::VoxelEvaluator evaluator(s, {mode, {0, 0, 0}});
    // Inside the conveyor at x = −1.5 (outside S), looking along +x into S.
    const auto blind = evaluator.labels(camera_at(Vec3(-1.5, 1.5, 0.25), 0, 0), 0, 0);
    EXPECT_EQ(std::count(blind.begin(), blind.end(), Label::undetectable),
              static_cast<long>(blind.size()))
        << "mode " << static_cast<int>(mode);
    // Above S at (2, 1.5, 5), looking down: the voxels just below the top of S at the centre
    // are free.
    const auto above = evaluator.labels(camera_at(Vec3(2, 1.5, 5), 0, -90), 0, 0);
    const voxel::Grid& g = evaluator.grid();
    const int v = 4 + g.n[0] * (2 + g.n[1] * (g.n[2] - 1));  // centre (2.25, 1.25, 2.75)
    EXPECT_EQ(above[v], Label::free) << "mode " << static_cast<int>(mode);
  }
}

/// Voxels of S wholly inside an obstacle that reaches beyond S are removed from M (centre inside
/// in center mode, the whole voxel inside in conservative mode); by hand for a box crossing each
/// face: one camera looks away from S, so every voxel is undetectable and M is S less the removed
/// voxels. Voxels of 0.5 m; the wall reaches 0.85 m into S along the face's axis and 2 m beyond
/// it, and across from −1 m to 1.15 m (crossing the low faces of the other axes too): whole
/// voxels inside, 1 deep × 2 × 2 = 4 (conservative); centres inside (0.25 and 0.75 m from the
/// face, 0.25 and 0.75 m across), 2 × 2 × 2 = 8 (center). No centre or voxel face lies on the
/// wall's faces (no ties).
TEST(BeyondArea, InteriorsOfObstaclesCrossingEachFaceAreSubtractedFromTheModel) {
  for (int face = 0; face < 6; ++face) {
    const Face f = face_of(face);
    Box3 b;
    for (int a = 0; a < 3; ++a) {
      if (a == f.axis) {
        b.min[a] = f.side ? kArea.max[a] - 0.85 : kArea.min[a] - 2.0;
        b.max[a] = f.side ? kArea.max[a] + 2.0 : kArea.min[a] + 0.85;
      } else {
        b.min[a] = -1.0;
        b.max[a] = 1.15;
      }
    }
    for (Kind kind : kKinds) {
      for (LabelMode mode : {LabelMode::center, LabelMode::conservative}) {
        core::Scene s = simple_scene(kArea, {8, 6, 6}, 1, 30.0, {}, {});
        core::TimeStep& step = s.time_steps.front();
        const core::SceneObject wall = box_object("wall", b.min, b.max);
        if (kind == Kind::static_obstacle) {
          s.static_obstacles.push_back(wall);
          // Smaller than a voxel and clear of every centre: removes nothing.
          step.dynamic_obstacles.push_back(
              box_object("robot", Vec3(3.0, 2.0, 2.0), Vec3(3.2, 2.2, 2.2)));
        } else {
          step.dynamic_obstacles.push_back(wall);
        }
        s.dynamic_mode = kind == Kind::modelled_dynamic ? core::DynamicMode::modelled
                                                        : core::DynamicMode::masked;
        step.critical = step.dynamic_obstacles;
        step.events.front().targets.push_back(
            box_object("person", Vec3(2.6, 1.6, 1.6), Vec3(2.9, 1.9, 1.9)));
        const voxel::VoxelEvaluator evaluator(s, {mode, {0, 0, 0}});
        const core::CameraConfig config{camera_at(Vec3(10, 10, 10), 45, 45)};
        const auto model = evaluator.model(config, 0);
        const voxel::Grid& g = evaluator.grid();
        int removed = 0;
        for (int v = 0; v < g.count(); ++v) {
          const Box3 box = g.voxel_box(v);
          bool inside = true;
          for (int a = 0; a < 3; ++a) {
            if (mode == LabelMode::conservative) {
              inside = inside && box.min[a] >= b.min[a] && box.max[a] <= b.max[a];
            } else {
              inside = inside && box.center()[a] > b.min[a] && box.center()[a] < b.max[a];
            }
          }
          removed += inside;
          EXPECT_EQ(model[v], inside ? 0 : 1)
              << "face " << face << " " << kind_name(kind) << " mode " << static_cast<int>(mode)
              << " voxel " << v;
        }
        EXPECT_EQ(removed, mode == LabelMode::conservative ? 4 : 8) << "face " << face;
      }
    }
  }
}

/// d(C, M) and the true distance with a critical object partly outside S come from its mesh: a
/// conveyor from x = −3 m to x = 1 m, a target at x ∈ [3, 3.5]: d_true = 2 m by hand; d(C, M)
/// equals the minimum over the model's voxels of the box-to-box gap (by hand, per axis) from the
/// conveyor to the voxel's box (conservative) or centre (center), and in conservative mode it
/// is at most d_true (M ⊇ the target).
TEST(BeyondArea, DistancesOfACriticalObjectPartlyOutsideSComeFromItsMesh) {
  core::Scene s = simple_scene(kArea, {8, 6, 6}, 1, 60.0, {}, {});
  core::TimeStep& step = s.time_steps.front();
  step.dynamic_obstacles.push_back(box_object("conveyor", Vec3(-3, 1, 0), Vec3(1, 2, 0.5)));
  step.critical = step.dynamic_obstacles;
  step.events.front().targets.push_back(
      box_object("person", Vec3(3, 1.2, 0.2), Vec3(3.5, 1.8, 1.8)));
  EXPECT_NEAR(std::sqrt(core::true_squared_distance(s, {0, 0}).value), 2.0, 1e-12);
  for (LabelMode mode : {LabelMode::center, LabelMode::conservative}) {
    for (core::DynamicMode dyn : {core::DynamicMode::masked, core::DynamicMode::modelled}) {
      s.dynamic_mode = dyn;
      const voxel::VoxelEvaluator evaluator(s, {mode, {0, 0, 0}});
      // Outside S at x = 6 m, looking along −x into S.
      const core::CameraConfig config{camera_at(Vec3(6, 1.5, 1.5), 180, 0)};
      const auto e = evaluator.evaluate(config);
      ASSERT_EQ(e.states.size(), 1u);
      EXPECT_NEAR(e.states[0].d_true, 2.0, 1e-12);
      if (mode == LabelMode::conservative) {
        EXPECT_LE(e.states[0].d_model, 2.0 + 1e-12);
      }
      // Independent check of d(C, M): the minimum over the model's voxels of the distance from
      // the conveyor box (by hand: per-axis gaps) to the voxel's box (conservative) or centre.
      const auto model = evaluator.model(config, 0);
      const Box3 conveyor{Vec3(-3, 1, 0), Vec3(1, 2, 0.5)};
      double best = std::numeric_limits<double>::infinity();
      for (int v = 0; v < evaluator.grid().count(); ++v) {
        if (!model[v]) continue;
        const Box3 box = evaluator.grid().voxel_box(v);
        const Box3 probe = mode == LabelMode::center ? Box3{box.center(), box.center()} : box;
        double sq = 0;
        for (int a = 0; a < 3; ++a) {
          const double gap =
              std::max({0.0, probe.min[a] - conveyor.max[a], conveyor.min[a] - probe.max[a]});
          sq += gap * gap;
        }
        best = std::min(best, sq);
      }
      ASSERT_TRUE(std::isfinite(best));
      EXPECT_NEAR(e.states[0].d_model, std::sqrt(best), 1e-9)
          << "mode " << static_cast<int>(mode) << " dynamic " << static_cast<int>(dyn);
    }
  }
}

}  // namespace
}  // namespace camplace::testing
