// Model, components, filter, distances and Err (SPEC §4–5) in hand-computed planar cases.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>

#include "camplace/core/err.hpp"
#include "planar_fixture.hpp"

namespace camplace::testing {
namespace {

using voxel::LabelMode;
const double kTan30 = std::tan(30.0 * 3.14159265358979323846 / 180.0);
const double kVoxelVolume = 0.25 * 0.25 * 0.25;

voxel::Evaluation evaluate(const core::Scene& scene, LabelMode mode) {
  return voxel::VoxelEvaluator(scene, {mode, {0, 0, 0}}).evaluate({planar_camera()});
}

// Distance from the critical box [1.0,1.1]×[1.9,2.1]×[0,0.25] to a point of the plane z=0.125.
double distance_to_critical(double x, double y) {
  const double dx = std::max({1.0 - x, 0.0, x - 1.1});
  const double dy = std::max({1.9 - y, 0.0, y - 2.1});
  return std::hypot(dx, dy);
}

TEST(Model, OneCameraModelIsAreaMinusFov) {
  const auto e = evaluate(planar_scene(), LabelMode::center);
  int count = 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (int j = 0; j < 16; ++j) {
    for (int i = 0; i < 16; ++i) {
      if (slope(i, j) <= kTan30) continue;
      ++count;
      nearest = std::min(nearest, distance_to_critical(cx(i), cy(j)));
    }
  }
  ASSERT_EQ(e.states.size(), 1u);
  EXPECT_NEAR(e.states[0].model_volume, count * kVoxelVolume, 1e-12);
  EXPECT_NEAR(e.states[0].d_model, nearest, 1e-12);
  // The wedges above and below the cone join in column i = 0, where the cone's half-width
  // 0.125·tan 30° = 0.072 m is below the 0.125 m from the axis to the nearest centres.
  EXPECT_EQ(e.states[0].components, 1);
}

TEST(Model, BoxTargetSilhouetteDistanceByHand) {
  const auto e = evaluate(planar_scene({box_object("target", {2.5, 1.75, 0}, {3, 2.25, 0.25})}),
                          LabelMode::center);
  // Nearest model voxel: silhouette voxel centre (1.375, 2.125): dx = 0.275, dy = 0.025.
  EXPECT_NEAR(e.states[0].d_model, std::hypot(0.275, 0.025), 1e-12);
  EXPECT_NEAR(e.states[0].d_true, 1.4, 1e-12);  // gap between x = 1.1 and x = 2.5
  EXPECT_EQ(e.states[0].components, 2);         // silhouette and the joined wedges
  EXPECT_NEAR(e.err, std::pow(1.4 - std::hypot(0.275, 0.025), 2), 1e-12);
}

TEST(Model, ConservativeModelHoldsEveryVoxelARayToTheTargetCrosses) {
  // Rows j = 7, 8 touch the line y = 2, whose rays (slope 0) meet the target: no voxel of them
  // is wholly free, so all 32 are in the conservative model, including [1,1.25]×[1.75,2.25]
  // which overlaps the critical box: d_model = 0.
  const core::Scene scene = planar_scene({box_object("target", {2.5, 1.75, 0}, {3, 2.25, 0.25})});
  const voxel::VoxelEvaluator conservative(scene, {LabelMode::conservative, {0, 0, 0}});
  const auto model = conservative.model({planar_camera()}, 0);
  for (int i = 0; i < 16; ++i) {
    EXPECT_EQ(model[i + 16 * 7], 1) << i;
    EXPECT_EQ(model[i + 16 * 8], 1) << i;
  }
  const auto e = conservative.evaluate({planar_camera()});
  const auto center = evaluate(scene, LabelMode::center);
  EXPECT_EQ(e.states[0].d_model, 0.0);
  EXPECT_GE(e.states[0].model_volume, center.states[0].model_volume);
}

TEST(Model, FilterRemovesTheSmallestComponent) {
  core::Scene scene = planar_scene({box_object("target", {2.5, 1.75, 0}, {3, 2.25, 0.25})});
  // Components by hand: silhouette (slope ≤ 0.1) and the wedges outside the cone.
  int silhouette = 0, wedges = 0;
  for (int j = 0; j < 16; ++j) {
    for (int i = 0; i < 16; ++i) {
      const double s = slope(i, j);
      silhouette += s <= 0.1;
      wedges += s > kTan30;
    }
  }
  ASSERT_LT(silhouette, wedges);
  scene.plausibility.min_volume = (silhouette + 0.5) * kVoxelVolume;
  const auto e = evaluate(scene, LabelMode::center);
  EXPECT_EQ(e.states[0].components, 1);
  EXPECT_EQ(e.states[0].components_removed, 1);
  EXPECT_NEAR(e.states[0].model_volume, wedges * kVoxelVolume, 1e-12);
}

TEST(Model, HeightFilterCanEmptyTheModelThenDistanceIsDiagonal) {
  core::Scene scene = planar_scene();
  scene.plausibility.min_height = 0.3;  // every component is one voxel (0.25 m) high
  const auto e = evaluate(scene, LabelMode::conservative);
  EXPECT_EQ(e.states[0].components, 0);
  EXPECT_EQ(e.states[0].components_removed, 1);
  EXPECT_EQ(e.states[0].model_volume, 0.0);
  EXPECT_NEAR(e.states[0].d_model, std::sqrt(16.0 + 16.0 + 0.0625), 1e-12);
}

TEST(Model, DistanceToAFarModelIsTheMinimumOverItsVoxels) {
  // A wide camera (75°) at one end of a 4 × 4 × 1 m room sees all of it but the wedges beside
  // itself; the critical box lies at the other end. The model (the wedges, a few hundred voxels)
  // is farther from C than most of the room, so the distance scan walks the model's own voxels
  // (docs/design/distance.md D1, 4). Brute force: the least distance over every model voxel.
  const core::Box3 area{core::Vec3(0, 0, 0), core::Vec3(4, 4, 1)};
  const core::Scene scene = simple_scene(area, {32, 32, 4}, 1, 75.0,
                                         {box_object("critical", {3.7, 1.9, 0.4}, {3.8, 2.1, 0.6})},
                                         {box_object("target", {0, 3.875, 0}, {0.125, 4, 0.25})});
  const core::CameraSetting camera = camera_at({0.01, 2, 0.5}, 0, 0);
  for (const LabelMode mode : {LabelMode::conservative, LabelMode::center}) {
    const voxel::VoxelEvaluator evaluator(scene, {mode, {0, 0, 0}});
    const voxel::Evaluation e = evaluator.evaluate({camera});
    const auto model = evaluator.model({camera}, 0);
    const core::TriangleMesh& critical = scene.time_steps[0].critical[0].mesh;
    double best = std::numeric_limits<double>::infinity();
    int count = 0;
    for (int v = 0; v < evaluator.grid().count(); ++v) {
      if (!model[v]) continue;
      ++count;
      best = std::min(
          best, mode == LabelMode::conservative
                    ? core::box_solid_sq_distance(critical, evaluator.grid().voxel_box(v))
                    : core::point_solid_sq_distance(critical, evaluator.grid().voxel_center(v)));
    }
    EXPECT_GT(count, 128);   // not the few-voxel path
    EXPECT_LT(count, 1024);  // fewer voxels than the shells nearer than the model hold
    EXPECT_GT(best, 3.0 * 3.0);
    EXPECT_NEAR(e.states[0].d_model, std::sqrt(best), 1e-12);
  }
}

TEST(Model, ObstacleInteriorIsRemoved) {
  core::Scene scene = planar_scene();
  // The pillar covers voxels i = 1, 2 and j = 7, 8 exactly; the camera stands in it (blind),
  // so the model is everything but the pillar, in both modes.
  scene.static_obstacles.push_back(box_object("pillar", {0.25, 1.75, 0}, {0.75, 2.25, 0.25}));
  for (LabelMode mode : {LabelMode::center, LabelMode::conservative}) {
    const auto e = voxel::VoxelEvaluator(scene, {mode, {0, 0, 0}})
                       .evaluate({camera_at({0.5, 2, 0.125}, 0, 0)});
    EXPECT_NEAR(e.states[0].model_volume, (256 - 4) * kVoxelVolume, 1e-12);
    // Nearest model voxel (1.125, 1.875): its centre is 0.025 m off the critical box in x and y;
    // its box overlaps it.
    EXPECT_NEAR(e.states[0].d_model, mode == LabelMode::center ? std::hypot(0.025, 0.025) : 0.0,
                1e-12);
  }
}

TEST(Model, ErrIsWeightedSumOfSquaredDifferences) {
  const std::vector<core::ErrTerm> terms = {{0.5, 1.0, 0.25}, {0.25, 2.0, 2.0}, {0.25, 1.5, 0.5}};
  EXPECT_DOUBLE_EQ(core::error_functional(terms), 0.5 * 0.5625 + 0.0 + 0.25 * 1.0);
  EXPECT_NEAR(core::default_tolerance({core::Vec3(0, 0, 0), core::Vec3(4, 3, 3)}, {16, 12, 12}),
              0.046875, 1e-12);  // (½·√(3·0.25²))² = 3/64, the paper's 0.046 m²
}

}  // namespace
}  // namespace camplace::testing

namespace camplace::testing {
namespace {

TEST(Model, ConservativeErrLowerBoundByHandAndNeverBeaten) {
  // Target [2.45,3]×[1.75,2.25]: the voxel it reaches into nearest to the critical box is
  // [2.25,2.5]×[1.75,2]×[0,0.25] at 2.25 − 1.1 = 1.15 m, while d_true = 1.35 m: the bound is
  // (1.35 − 1.15)² = 0.04 m². (Voxels the target only touches do not count:
  // lower_bound_test.cpp.)
  const core::Scene scene = planar_scene({box_object("target", {2.45, 1.75, 0}, {3, 2.25, 0.25})});
  const voxel::VoxelEvaluator evaluator(scene, {voxel::LabelMode::conservative, {0, 0, 0}});
  EXPECT_NEAR(evaluator.err_lower_bound(), 0.04, 1e-12);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 200; ++i) {
    const auto camera =
        camera_at({4 * u(rng), 4 * u(rng), 0.25 * u(rng)}, -180 + 360 * u(rng), -10 + 20 * u(rng));
    EXPECT_GE(evaluator.err({camera}), evaluator.err_lower_bound() - 1e-12);
  }
  EXPECT_EQ(voxel::VoxelEvaluator(scene, {voxel::LabelMode::center, {0, 0, 0}}).err_lower_bound(),
            0.0);
}

}  // namespace
}  // namespace camplace::testing
