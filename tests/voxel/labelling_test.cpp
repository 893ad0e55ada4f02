// Labels of SPEC §3 in hand-computed planar cases (see planar_fixture.hpp).
#include <gtest/gtest.h>

#include "planar_fixture.hpp"

namespace camplace::testing {
namespace {

using voxel::Label;
using voxel::LabelMode;
const double kTan30 = std::tan(30.0 * 3.14159265358979323846 / 180.0);

std::vector<Label> center_labels(const core::Scene& scene) {
  voxel::VoxelEvaluator evaluator(scene, {LabelMode::center, {0, 0, 0}});
  return evaluator.labels(planar_camera(), 0);
}

TEST(Labelling, OneCameraNoObstacleSeesItsConeFree) {
  const auto labels = center_labels(planar_scene());
  for (int j = 0; j < 16; ++j) {
    for (int i = 0; i < 16; ++i) {
      const Label expected = slope(i, j) <= kTan30 ? Label::free : Label::undetectable;
      EXPECT_EQ(labels[i + 16 * j], expected) << "voxel " << i << "," << j;
    }
  }
}

TEST(Labelling, ConservativeFreeOnlyWhenAllCornersInCone) {
  const core::Scene scene = planar_scene();
  voxel::VoxelEvaluator evaluator(scene, {LabelMode::conservative, {0, 0, 0}});
  const auto labels = evaluator.labels(planar_camera(), 0);
  for (int j = 0; j < 16; ++j) {
    for (int i = 0; i < 16; ++i) {
      // Corners at x ∈ {0.25i, 0.25i+0.25}, y likewise, z ∈ {0, 0.25}: inside the cone when the
      // distance from the axis (y = 2, z = 0.125) is at most x·tan 30°.
      bool all_in = true;
      for (double x : {0.25 * i, 0.25 * i + 0.25}) {
        for (double y : {0.25 * j, 0.25 * j + 0.25}) {
          all_in = all_in && std::hypot(y - 2.0, 0.125) <= x * kTan30;
        }
      }
      const Label expected = all_in ? Label::free : Label::undetectable;
      EXPECT_EQ(labels[i + 16 * j], expected) << "voxel " << i << "," << j;
    }
  }
}

TEST(Labelling, BoxTargetCastsSilhouetteCone) {
  // Target [2.5,3]×[1.75,2.25]: rays with slope ≤ 0.25/2.5 = 0.1 meet its front face.
  const auto labels =
      center_labels(planar_scene({box_object("target", {2.5, 1.75, 0}, {3, 2.25, 0.25})}));
  int occupied = 0;
  for (int j = 0; j < 16; ++j) {
    for (int i = 0; i < 16; ++i) {
      const double s = slope(i, j);
      const Label expected = s <= 0.1      ? Label::occupied
                             : s <= kTan30 ? Label::free
                                           : Label::undetectable;
      EXPECT_EQ(labels[i + 16 * j], expected) << "voxel " << i << "," << j;
      occupied += expected == Label::occupied;
    }
  }
  EXPECT_EQ(occupied, 24);  // rows j = 7, 8 from x = 1.375 (11 each) and j = 6, 9 at x = 3.875
}

TEST(Labelling, StaticObstacleShadowIsUndetectableAndFrontStaysFree) {
  core::Scene scene = planar_scene();
  // Front face at x = 1.5, |y − 2| ≤ 0.5: rays with slope ≤ 1/3 meet it.
  scene.static_obstacles.push_back(box_object("wall", {1.5, 1.5, 0}, {2.0, 2.5, 0.25}));
  const auto labels = center_labels(scene);
  int shadowed = 0;
  for (int j = 0; j < 16; ++j) {
    for (int i = 0; i < 16; ++i) {
      const double s = slope(i, j);
      if (near(s, 1.0 / 3.0)) continue;  // the ray grazes the wall's corner: a tie
      Label expected = s <= kTan30 ? Label::free : Label::undetectable;
      if (s < 1.0 / 3.0 && cx(i) > 1.5) expected = Label::undetectable;
      EXPECT_EQ(labels[i + 16 * j], expected) << "voxel " << i << "," << j;
      shadowed += s < 1.0 / 3.0 && cx(i) > 1.5;
    }
  }
  EXPECT_GT(shadowed, 20);
}

TEST(Labelling, StaticObstacleInFrontOfTargetLeavesFrontFree) {
  // Wall [1.5,2]×[1.5,2.5] hides the target [2.5,3]×[1.75,2.25] completely (slopes ≤ 0.1 <
  // 1/3): in front of the wall every point is free, behind it undetectable, nothing occupied.
  core::Scene scene = planar_scene({box_object("target", {2.5, 1.75, 0}, {3, 2.25, 0.25})});
  scene.static_obstacles.push_back(box_object("wall", {1.5, 1.5, 0}, {2.0, 2.5, 0.25}));
  const auto labels = center_labels(scene);
  for (int j = 0; j < 16; ++j) {
    for (int i = 0; i < 16; ++i) {
      const double s = slope(i, j);
      if (near(s, 1.0 / 3.0)) continue;
      Label expected = s <= kTan30 ? Label::free : Label::undetectable;
      if (s < 1.0 / 3.0 && cx(i) > 1.5) expected = Label::undetectable;
      EXPECT_EQ(labels[i + 16 * j], expected) << "voxel " << i << "," << j;
    }
  }
}

TEST(Labelling, ConservativeSeparatesBoxesFromThinTriangleCones) {
  // A flat target (1 cm thick) in the camera's own horizontal plane: its triangles' cones are
  // thin wedges. Rays of slope ≤ 0.1 meet it; the voxels [3, 3.25]×[2.5, 2.75] and
  // [3, 3.25]×[1.25, 1.5] are wholly in the FOV and all their rays have slope ≥ 0.16: free.
  const core::Scene scene = planar_scene({tetra_object("flat", {2.5, 1.75, 0.12}, {2.5, 2.25, 0.12},
                                                       {3.0, 2.0, 0.12}, {2.75, 2.0, 0.13})});
  voxel::VoxelEvaluator evaluator(scene, {LabelMode::conservative, {0, 0, 0}});
  const auto labels = evaluator.labels(planar_camera(), 0);
  EXPECT_EQ(labels[12 + 16 * 10], Label::free);
  EXPECT_EQ(labels[12 + 16 * 5], Label::free);
  EXPECT_EQ(labels[11 + 16 * 8], Label::occupied);  // on the axis, behind the target
  // Every voxel wholly in the FOV is free exactly when no point of it has |y − 2| ≤ 0.1·x (the
  // fan of rays through the target's front edge; the voxel's z-range always holds the plane).
  const auto empty = voxel::VoxelEvaluator(planar_scene(), {LabelMode::conservative, {0, 0, 0}})
                         .labels(planar_camera(), 0);
  int checked = 0;
  for (int j = 0; j < 16; ++j) {
    for (int i = 0; i < 16; ++i) {
      if (empty[i + 16 * j] != Label::free) continue;
      const double y0 = 0.25 * j, y1 = y0 + 0.25, x_max = 0.25 * i + 0.25;
      const double gap = (y0 > 2 ? y0 - 2 : y1 < 2 ? 2 - y1 : 0.0) - 0.1 * x_max;
      if (std::abs(gap) < 1e-9) continue;  // touches the fan's boundary: a tie
      EXPECT_EQ(labels[i + 16 * j] == Label::free, gap > 0) << "voxel " << i << "," << j;
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(Labelling, MaskedDynamicObstacleOccupiesModelledOneOccludes) {
  core::Scene scene = planar_scene();
  scene.time_steps[0].dynamic_obstacles.push_back(
      box_object("robot", {2.5, 1.75, 0}, {3, 2.25, 0.25}));
  scene.dynamic_mode = core::DynamicMode::masked;
  const auto masked = center_labels(scene);
  scene.dynamic_mode = core::DynamicMode::modelled;
  const auto modelled = center_labels(scene);
  for (int j = 0; j < 16; ++j) {
    for (int i = 0; i < 16; ++i) {
      const double s = slope(i, j);
      const Label outside = s <= kTan30 ? Label::free : Label::undetectable;
      EXPECT_EQ(masked[i + 16 * j], s <= 0.1 ? Label::occupied : outside) << i << "," << j;
      const Label behind = cx(i) > 2.5 ? Label::undetectable : Label::free;
      EXPECT_EQ(modelled[i + 16 * j], s <= 0.1 ? behind : outside) << i << "," << j;
    }
  }
}

TEST(Labelling, CameraInsideObstacleSeesNothing) {
  core::Scene scene = planar_scene();
  scene.static_obstacles.push_back(box_object("pillar", {0.25, 1.75, 0}, {0.75, 2.25, 0.25}));
  voxel::VoxelEvaluator evaluator(scene, {LabelMode::center, {0, 0, 0}});
  const auto labels = evaluator.labels(camera_at({0.5, 2.0, 0.125}, 0, 0), 0);
  for (Label l : labels) EXPECT_EQ(l, Label::undetectable);
  // A camera outside the pillar does see free space.
  const auto outside = evaluator.labels(camera_at({0.1, 2.0, 0.125}, 90, 0), 0);
  EXPECT_NE(std::count(outside.begin(), outside.end(), Label::free), 0);
}

TEST(Labelling, InscribedTriangularPyramidIsNarrowerThanCone) {
  // k = 3, first vertex on the up axis (world z): at depth 1 the pyramid's section is the
  // triangle inscribed in the circle of radius r = tan 30°; its chord through the centre,
  // perpendicular to up, has half-width r/√3 = 1/3. So in the horizontal plane: slope < 1/3.
  core::Scene scene = planar_scene();
  core::use_exact_models(scene.cameras);
  for (auto& m : scene.cameras.models) m.sides = 3;
  const auto pyramid = center_labels(scene);
  for (auto& m : scene.cameras.models) m.fov = core::FovShape::cone;
  const auto cone = center_labels(scene);
  int narrower = 0;
  for (int j = 0; j < 16; ++j) {
    for (int i = 0; i < 16; ++i) {
      const double s = slope(i, j);
      if (near(s, 1.0 / 3.0)) continue;
      EXPECT_EQ(pyramid[i + 16 * j], s < 1.0 / 3.0 ? Label::free : Label::undetectable)
          << i << "," << j;
      if (pyramid[i + 16 * j] == Label::free) {
        EXPECT_EQ(cone[i + 16 * j], Label::free);
      }
      narrower += cone[i + 16 * j] == Label::free && pyramid[i + 16 * j] != Label::free;
    }
  }
  EXPECT_GT(narrower, 0);
}

TEST(Labelling, RangeCutsTheFovAtAxialDepth) {
  core::Scene scene = planar_scene();
  for (auto& m : scene.cameras.models) m.range = 2.0;
  const auto labels = center_labels(scene);
  for (int j = 0; j < 16; ++j) {
    for (int i = 0; i < 16; ++i) {
      const Label expected =
          slope(i, j) <= kTan30 && cx(i) <= 2.0 ? Label::free : Label::undetectable;
      EXPECT_EQ(labels[i + 16 * j], expected) << i << "," << j;
    }
  }
}

}  // namespace
}  // namespace camplace::testing
