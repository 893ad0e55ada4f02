// The exact pipeline (SPEC §3–4, §6) against cases computed by hand. All scenes use a box
// S = [0,4]×[0,1]×[0,1] seen by cameras on its long axis from outside (x = −1 looking +x,
// x = 5 looking −x) with a 4-sided pyramid of half angle 60°, which contains all of S, so the
// model is decided by shadows and silhouette cones only and has closed forms: a camera at
// x = −1 on the axis of a target whose front face is the square |y−½|, |z−½| ≤ w at x = a sees
// the square cone of half width w·(x+1)/(a+1).
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "camplace/core/distance.hpp"
#include "camplace/core/error.hpp"
#include "camplace/exact/evaluator.hpp"
#include "scene_builder.hpp"

namespace camplace {
namespace {

using core::Vec3;
using testing::box_object;
using testing::camera_at;

constexpr double kTol = 1e-12;

core::Scene axis_scene(int cameras, std::vector<core::SceneObject> critical,
                       std::vector<core::SceneObject> targets) {
  core::Box3 area{Vec3(0, 0, 0), Vec3(4, 1, 1)};
  core::Scene s = testing::simple_scene(area, {16, 4, 4}, cameras, 60.0, std::move(critical),
                                        std::move(targets));
  core::use_exact_models(s.cameras);
  for (auto& m : s.cameras.models) m.sides = 4;
  return s;
}

const core::CameraSetting kFromLeft = camera_at(Vec3(-1, 0.5, 0.5), 0.0, 0.0);
const core::CameraSetting kFromRight = camera_at(Vec3(5, 0.5, 0.5), 180.0, 0.0);

// Target with front face x = 1, half width 1/4: cone half width (x+1)/8, clipped by S for
// x ≥ 3. Model volume ∫₀³ (x+1)²/16 dx + 1 = 111/48.
core::SceneObject axis_target() {
  return box_object("target", Vec3(1, 0.25, 0.25), Vec3(2, 0.75, 0.75));
}

TEST(ExactModel, OneCameraOneBoxTargetHasClosedFormVolumeAndDistance) {
  // Critical box near the wall y = 1; nearest point (0.625, 0.875) to the cone face
  // 8y − x = 5: d = (7 − 0.625 − 5)/√65, d² = (11/8)²/65 = 121/4160.
  auto scene = axis_scene(1, {box_object("c", Vec3(0.5, 0.875, 0.375), Vec3(0.625, 1, 0.625))},
                          {axis_target()});
  const auto eval = exact::evaluate_exact(scene, {kFromLeft});
  ASSERT_EQ(eval.states.size(), 1u);
  const auto& r = eval.states[0];
  EXPECT_NEAR(r.model_volume, 111.0 / 48.0, kTol);
  EXPECT_EQ(r.components, 1);
  EXPECT_EQ(r.components_removed, 0);
  EXPECT_EQ(r.d_model_sq_exact, "121/4160");
  EXPECT_NEAR(r.d_model, std::sqrt(121.0 / 4160.0), kTol);
  // d_true: gaps 3/8 in x and 1/8 in y → 10/64 = 5/32.
  EXPECT_EQ(r.d_true_sq_exact, "5/32");
  EXPECT_NEAR(eval.err, std::pow(std::sqrt(5.0 / 32) - std::sqrt(121.0 / 4160), 2), kTol);
  EXPECT_LE(r.d_model, r.d_true);
}

TEST(ExactModel, TwoOpposedCamerasGiveTheDoubleConeHull) {
  // Target [1.5,2.5]×[¼,¾]²: left cone half width (x+1)/10, right (5−x)/10; the hull is their
  // intersection, 2·∫₀² (x+1)²/25 dx = 52/75 (one camera alone: ∫₀⁴ (x+1)²/25 dx = 124/75).
  const auto target = box_object("target", Vec3(1.5, 0.25, 0.25), Vec3(2.5, 0.75, 0.75));
  const auto critical = box_object("c", Vec3(0, 0.875, 0.375), Vec3(0.25, 1, 0.625));
  auto one = axis_scene(1, {critical}, {target});
  EXPECT_NEAR(exact::evaluate_exact(one, {kFromLeft}).states[0].model_volume, 124.0 / 75.0, kTol);
  auto two = axis_scene(2, {critical}, {target});
  const auto model = exact::build_exact_model(two, {kFromLeft, kFromRight}, {0, 0});
  EXPECT_NEAR(model.volume(), 52.0 / 75.0, kTol);
  EXPECT_EQ(model.components(), 1);
  EXPECT_TRUE(model.contains(Vec3(0.5, 0.64, 0.5)));  // both half widths ≥ 0.15
  EXPECT_TRUE(model.contains(Vec3(3.5, 0.36, 0.5)));
  EXPECT_FALSE(model.contains(Vec3(0.2, 0.7, 0.5)));   // left half width 0.12 < 0.2
  EXPECT_FALSE(model.contains(Vec3(3.8, 0.5, 0.63)));  // right half width 0.12 < 0.13
  EXPECT_TRUE(model.contains(Vec3(2.0, 0.79, 0.79)));  // near the corner of the widest section
  EXPECT_FALSE(model.contains(Vec3(2.0, 0.81, 0.5)));
}

// One camera, a critical box c near x = 0 and the target [2.5,3]×[¼,¾]² (seen from kFromLeft).
core::Scene target_behind_pole_scene() {
  return axis_scene(1, {box_object("c", Vec3(0, 0.875, 0.375), Vec3(0.25, 1, 0.625))},
                    {box_object("target", Vec3(2.5, 0.25, 0.25), Vec3(3, 0.75, 0.75))});
}

// A pole x ∈ [1, 1.25], |y−½| ≤ 1/16, full height, between the camera and the target.
core::SceneObject pole(const std::string& name) {
  return box_object(name, Vec3(1, 0.4375, 0), Vec3(1.25, 0.5625, 1));
}

TEST(ExactModel, StaticObstacleBetweenCameraAndTargetLeavesTheSpaceInFrontFree) {
  auto scene = target_behind_pole_scene();
  scene.static_obstacles.push_back(pole("pole"));
  const auto model = exact::build_exact_model(scene, {kFromLeft}, {0, 0});
  // On the axis in front of the pole: the ray hits the pole first → free.
  EXPECT_FALSE(model.contains(Vec3(0.5, 0.5, 0.5)));
  EXPECT_FALSE(model.contains(Vec3(0.5, 0.5, 0.55)));
  // A ray passing beside the pole (offset 0.12 > 1/16 at x = 1) onto the target (0.21 ≤ ¼).
  EXPECT_TRUE(model.contains(Vec3(0.5, 0.59, 0.5)));
  // Behind the pole (shadow), and inside it (obstacle interiors are removed).
  EXPECT_TRUE(model.contains(Vec3(1.5, 0.5, 0.5)));
  EXPECT_TRUE(model.contains(Vec3(1.5, 0.5, 0.95)));
  EXPECT_FALSE(model.contains(Vec3(1.1, 0.5, 0.5)));
  // The target itself stays in the model (it is hidden behind the pole on the axis).
  EXPECT_TRUE(model.contains(Vec3(2.75, 0.5, 0.5)));
  EXPECT_TRUE(model.contains(Vec3(2.75, 0.3, 0.3)));
  // Free space beside everything.
  EXPECT_FALSE(model.contains(Vec3(0.5, 0.9, 0.1)));
}

TEST(ExactModel, MaskedDynamicObstacleOccupiesItsConeModelledOneOccludes) {
  auto scene = target_behind_pole_scene();
  scene.time_steps[0].dynamic_obstacles.push_back(pole("robot"));
  scene.dynamic_mode = core::DynamicMode::masked;
  const auto masked = exact::build_exact_model(scene, {kFromLeft}, {0, 0});
  scene.dynamic_mode = core::DynamicMode::modelled;
  const auto modelled = exact::build_exact_model(scene, {kFromLeft}, {0, 0});
  // In front of the robot on the axis: occupied when masked, free when modelled.
  EXPECT_TRUE(masked.contains(Vec3(0.5, 0.5, 0.5)));
  EXPECT_FALSE(modelled.contains(Vec3(0.5, 0.5, 0.5)));
  // A ray that meets only the robot (z = 0.8 at x = 0.5 → 0.9 at x = 1 inside the robot's
  // height, above the target's cone): masked occupied, modelled free in front, hidden behind.
  EXPECT_TRUE(masked.contains(Vec3(0.5, 0.5, 0.8)));
  EXPECT_FALSE(modelled.contains(Vec3(0.5, 0.5, 0.8)));
  EXPECT_TRUE(modelled.contains(Vec3(1.5, 0.5, 0.9)));
  // Beside the robot both see the target's cone.
  EXPECT_TRUE(masked.contains(Vec3(0.5, 0.59, 0.5)));
  EXPECT_TRUE(modelled.contains(Vec3(0.5, 0.59, 0.5)));
  EXPECT_FALSE(masked.contains(Vec3(1.1, 0.5, 0.5)));  // robot interior removed
  EXPECT_GT(masked.volume(), modelled.volume());
}

TEST(ExactModel, CameraInsideAnObstacleSeesNothing) {
  // The left camera sits inside the static box [0,½]×[¼,¾]²; only the right camera sees. Its
  // cone through the target's face x = 3 (half width ¼ at distance 2) is (5−x)/8, the full
  // section for x ≤ 1: volume 1 + ∫₁⁴ ((5−x)/4)² dx − ⅛ (the obstacle) = 111/48 − 6/48.
  auto scene = axis_scene(2, {box_object("c", Vec3(3.75, 0.875, 0.375), Vec3(4, 1, 0.625))},
                          {box_object("target", Vec3(2.5, 0.25, 0.25), Vec3(3, 0.75, 0.75))});
  scene.static_obstacles.push_back(box_object("box", Vec3(0, 0.25, 0.25), Vec3(0.5, 0.75, 0.75)));
  const auto inside = camera_at(Vec3(0.25, 0.5, 0.5), 0.0, 0.0);
  const auto eval = exact::evaluate_exact(scene, {inside, kFromRight});
  EXPECT_NEAR(eval.states[0].model_volume, 105.0 / 48.0, kTol);
  // A camera on the obstacle's surface sees nothing either (its rays start on the object).
  const auto on_surface = camera_at(Vec3(0.5, 0.5, 0.5), 0.0, 0.0);
  EXPECT_NEAR(exact::evaluate_exact(scene, {on_surface, kFromRight}).states[0].model_volume,
              105.0 / 48.0, kTol);
}

// S ∖ a full wall at x ∈ [2, 2.25] seen from the left with the target [1,1.5]×[¼,¾]²: the cone
// piece x ∈ [0, 2] of volume ∫₀² (x+1)²/16 dx = 13/24 and the hidden block [2.25,4]×[0,1]² of
// volume 7/4 are two components separated by the wall.
core::Scene wall_scene() {
  auto scene = axis_scene(1, {box_object("c", Vec3(0, 0.875, 0.375), Vec3(0.25, 1, 0.625))},
                          {box_object("target", Vec3(1, 0.25, 0.25), Vec3(1.5, 0.75, 0.75))});
  scene.static_obstacles.push_back(box_object("wall", Vec3(2, 0, 0), Vec3(2.25, 1, 1)));
  return scene;
}

TEST(ExactModel, FilterRemovesTheComponentOfKnownVolume) {
  auto scene = wall_scene();
  auto eval = exact::evaluate_exact(scene, {kFromLeft});
  EXPECT_EQ(eval.states[0].components, 2);
  EXPECT_NEAR(eval.states[0].model_volume, 13.0 / 24.0 + 7.0 / 4.0, kTol);
  // Nearest point of the critical box (0.25, 0.875) to the cone face 8y − x = 5:
  // d² = (7/4)²/65 = 49/1040.
  EXPECT_EQ(eval.states[0].d_model_sq_exact, "49/1040");

  scene.plausibility.min_volume = 1.0;  // removes the cone piece (13/24 m³)
  eval = exact::evaluate_exact(scene, {kFromLeft});
  EXPECT_EQ(eval.states[0].components, 1);
  EXPECT_EQ(eval.states[0].components_removed, 1);
  EXPECT_NEAR(eval.states[0].model_volume, 7.0 / 4.0, kTol);
  EXPECT_EQ(eval.states[0].d_model_sq_exact, "4/1");  // to the block at x = 2.25
  const auto filtered = exact::build_exact_model(scene, {kFromLeft}, {0, 0});
  EXPECT_FALSE(filtered.contains(Vec3(1.25, 0.5, 0.5)));  // in the removed cone piece
  EXPECT_TRUE(filtered.contains(Vec3(3, 0.5, 0.5)));
  EXPECT_TRUE(filtered.contains(Vec3(2.25, 0.5, 0.5)));  // on the kept block's boundary
  ASSERT_EQ(filtered.component_info().size(), 2u);

  // min_volume = the double nearest 13/24: removed exactly when that double exceeds 13/24.
  const double v = 13.0 / 24.0;
  scene.plausibility.min_volume = v;
  eval = exact::evaluate_exact(scene, {kFromLeft});
  EXPECT_EQ(eval.states[0].components_removed, std::fma(v, 24.0, -13.0) > 0.0 ? 1 : 0);

  // Heights: the cone piece's z-extent is that of its section at x = 2, 2·3/8 = 3/4;
  // the block spans 1. min_height 3/4 keeps both (not below), 0.75 + 2⁻²⁰ removes the cone.
  scene.plausibility.min_volume = 0.0;
  scene.plausibility.min_height = 0.75;
  eval = exact::evaluate_exact(scene, {kFromLeft});
  EXPECT_EQ(eval.states[0].components, 2);
  scene.plausibility.min_height = 0.75 + std::ldexp(1.0, -20);
  eval = exact::evaluate_exact(scene, {kFromLeft});
  EXPECT_EQ(eval.states[0].components, 1);
  EXPECT_NEAR(eval.states[0].model_volume, 7.0 / 4.0, kTol);
}

TEST(ExactModel, EmptyModelGivesTheDiagonal) {
  auto scene = wall_scene();
  scene.plausibility.min_volume = 10.0;  // removes both components
  const auto eval = exact::evaluate_exact(scene, {kFromLeft});
  EXPECT_EQ(eval.states[0].components, 0);
  EXPECT_EQ(eval.states[0].components_removed, 2);
  EXPECT_EQ(eval.states[0].model_volume, 0.0);
  EXPECT_EQ(eval.states[0].d_model_sq_exact, "18/1");  // 4² + 1² + 1²
  EXPECT_NEAR(eval.states[0].d_model, std::sqrt(18.0), kTol);
}

TEST(ExactModel, TouchingAndOverlappingSetsHaveDistanceZero) {
  // The critical box's edge x = 0.625, y = 0.703125 lies on the cone face 8y − x = 5.
  auto touching = axis_scene(
      1, {box_object("c", Vec3(0.5, 0.703125, 0.375), Vec3(0.625, 1, 0.625))}, {axis_target()});
  auto r = exact::evaluate_exact(touching, {kFromLeft}).states[0];
  EXPECT_EQ(r.d_model_sq_exact, "0/1");
  EXPECT_EQ(r.d_model, 0.0);
  // Just outside: moved by 2⁻¹⁰ in y → d² = (8·2⁻¹⁰)²/65.
  auto apart = axis_scene(
      1,
      {box_object("c", Vec3(0.5, 0.703125 + std::ldexp(1.0, -10), 0.375), Vec3(0.625, 1, 0.625))},
      {axis_target()});
  r = exact::evaluate_exact(apart, {kFromLeft}).states[0];
  EXPECT_EQ(r.d_model_sq_exact, "1/1064960");  // 2⁻¹⁴/65
  // Critical object wholly inside the model (no boundary contact).
  auto inside = axis_scene(1, {box_object("c", Vec3(3.25, 0.25, 0.25), Vec3(3.5, 0.5, 0.5))},
                           {axis_target()});
  EXPECT_EQ(exact::evaluate_exact(inside, {kFromLeft}).states[0].d_model_sq_exact, "0/1");
  // The model wholly inside the critical object: a critical box containing all of S.
  auto around = axis_scene(1, {box_object("c", Vec3(0, 0, 0), Vec3(4, 1, 1))}, {axis_target()});
  EXPECT_EQ(exact::evaluate_exact(around, {kFromLeft}).states[0].d_model_sq_exact, "0/1");
}

TEST(ExactModel, ThreadCountChangesNoResult) {
  // 2 time steps × 2 events: one thread, a thread per step, and steps split between threads.
  std::mt19937 rng(42);
  core::Scene scene = testing::random_scene(rng, {8, 6, 6});
  const auto config = testing::random_config(rng, scene);
  exact::ExactOptions options;
  options.threads = 1;
  const auto one = exact::evaluate_exact(scene, config, options);
  ASSERT_EQ(one.states.size(), 4u);
  for (int threads : {2, 3, 4}) {
    options.threads = threads;
    const auto many = exact::evaluate_exact(scene, config, options);
    ASSERT_EQ(many.states.size(), one.states.size());
    EXPECT_EQ(many.err, one.err) << threads << " threads";
    for (std::size_t s = 0; s < one.states.size(); ++s) {
      const auto &a = one.states[s], &b = many.states[s];
      EXPECT_EQ(b.time_step, a.time_step);
      EXPECT_EQ(b.event, a.event);
      EXPECT_EQ(b.d_true_sq_exact, a.d_true_sq_exact) << threads << " threads, state " << s;
      EXPECT_EQ(b.d_model_sq_exact, a.d_model_sq_exact) << threads << " threads, state " << s;
      EXPECT_EQ(b.model_volume_exact, a.model_volume_exact) << threads << " threads, state " << s;
      EXPECT_EQ(b.components, a.components);
      EXPECT_EQ(b.components_removed, a.components_removed);
    }
  }
}

TEST(ExactModel, ConfigurationOfTheWrongSizeIsRejected) {
  auto scene = axis_scene(2, {box_object("c", Vec3(0.5, 0.875, 0.375), Vec3(0.625, 1, 0.625))},
                          {axis_target()});
  EXPECT_THROW(exact::evaluate_exact(scene, {kFromLeft}), core::InputError);
}

TEST(ExactModel, ExportWritesModelAndPyramidMeshes) {
  auto scene = axis_scene(1, {box_object("c", Vec3(0.5, 0.875, 0.375), Vec3(0.625, 1, 0.625))},
                          {axis_target()});
  const std::string dir = testing::temp_dir("exact_export");
  exact::ExactOptions options;
  options.export_dir = dir;
  options.keep_models = true;
  const auto eval = exact::evaluate_exact(scene, {kFromLeft}, options);
  EXPECT_TRUE(std::filesystem::exists(dir + "/state-h0-e0-model.off"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/camera-0-pyramid.off"));
  ASSERT_EQ(eval.models.size(), 1u);
  const auto mesh = eval.models[0].boundary_mesh();
  EXPECT_NEAR(core::signed_volume(mesh), 111.0 / 48.0, 1e-9);
}

}  // namespace
}  // namespace camplace
