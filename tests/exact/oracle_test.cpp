// The exact model against the brute-force sensor model of tests/support (an independent
// implementation of SPEC §3): at random points away from every boundary, p ∈ M exactly when no
// camera reports it free and it lies inside no obstacle (SPEC §4, filter off).
#include <gtest/gtest.h>

#include <random>

#include "camplace/core/camera.hpp"
#include "camplace/exact/evaluator.hpp"
#include "reference.hpp"
#include "scene_builder.hpp"

namespace camplace {
namespace {

using core::Vec3;

struct Agreement {
  int checked = 0, inside = 0, mismatches = 0;
};

// Compares the kept models of every state at `samples` random points per state.
Agreement compare_with_oracle(const core::Scene& scene, const core::CameraConfig& config,
                              int samples, std::mt19937& rng) {
  exact::ExactOptions options;
  options.keep_models = true;
  const auto eval = exact::evaluate_exact(scene, config, options);
  const auto states = core::states(scene);
  Agreement a;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::size_t s = 0; s < states.size(); ++s) {
    // Without the filter M ⊇ targets (SPEC §4), so the model never over-estimates.
    EXPECT_LE(eval.states[s].d_model, eval.states[s].d_true + 1e-12) << "state " << s;
    const auto& step = scene.time_steps[states[s].time_step];
    for (int i = 0; i < samples; ++i) {
      const Vec3 p = scene.area.min + Vec3(unit(rng), unit(rng), unit(rng))
                                          .cwiseProduct(scene.area.max - scene.area.min);
      bool ambiguous = false, non_free = true;
      for (const auto& cam : config) {
        const auto label = testing::reference_label(scene, states[s].time_step, states[s].event,
                                                    cam, p, 1e-6);
        ambiguous |= label.ambiguous;
        if (label.label == voxel::Label::free) non_free = false;
      }
      bool in_obstacle = false;
      for (const auto& o : scene.static_obstacles)
        in_obstacle |= testing::reference_inside(o.mesh, p);
      for (const auto& o : step.dynamic_obstacles)
        in_obstacle |= testing::reference_inside(o.mesh, p);
      if (ambiguous) continue;
      const bool expected = non_free && !in_obstacle;
      ++a.checked;
      a.inside += expected;
      if (eval.models[s].contains(p) != expected) {
        ++a.mismatches;
        ADD_FAILURE() << "state " << s << " point (" << p.transpose() << "): exact "
                      << eval.models[s].contains(p) << ", oracle " << expected;
      }
    }
  }
  return a;
}

TEST(ExactOracle, RandomScenesAgreeWithTheBruteForceSensorModel) {
  std::mt19937 rng(20240611);
  for (int trial = 0; trial < 10; ++trial) {
    core::Scene scene = testing::random_scene(rng, {8, 6, 6});
    scene.cameras.fov = core::FovShape::pyramid;  // the exact pipeline's FOV
    scene.plausibility = {};
    const auto config = testing::random_config(rng, scene);
    const auto a = compare_with_oracle(scene, config, 300, rng);
    EXPECT_GT(a.checked, 0);
    EXPECT_EQ(a.mismatches, 0) << "trial " << trial;
  }
}

// A closed L-shaped prism: the L = [0,2]×[0,1] ∪ [0,1]×[0,2] (scaled by s, moved to lo) extruded
// over height h. Non-convex: exercises the per-face shadows and cones and the Nef containment.
core::SceneObject l_prism(const std::string& name, const Vec3& lo, double s, double h) {
  const double xy[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};  // CCW from +z
  core::SceneObject o;
  o.name = o.entry = name;
  for (int top = 0; top < 2; ++top)
    for (const auto& v : xy) o.mesh.vertices.push_back(lo + Vec3(s * v[0], s * v[1], top * h));
  const int fan[4][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}};  // star-shaped from 0
  for (const auto& t : fan) {
    o.mesh.triangles.push_back({6 + t[0], 6 + t[1], 6 + t[2]});  // top, normal +z
    o.mesh.triangles.push_back({t[0], t[2], t[1]});              // bottom, normal −z
  }
  for (int i = 0; i < 6; ++i) {
    const int j = (i + 1) % 6;
    o.mesh.triangles.push_back({i, j, 6 + j});
    o.mesh.triangles.push_back({i, 6 + j, 6 + i});
  }
  o.bounds = core::bounding_box(o.mesh);
  return o;
}

TEST(ExactOracle, NonConvexObjectsAgreeWithTheBruteForceSensorModel) {
  const core::Box3 area{Vec3(0, 0, 0), Vec3(4, 3, 3)};
  auto scene = testing::simple_scene(area, {8, 6, 6}, 3, 30.0,
                                     {testing::box_object("c", Vec3(3.5, 0.2, 0), Vec3(3.8, 0.5, 1))},
                                     {l_prism("person", Vec3(1.8, 1.2, 0), 0.3, 1.7)});
  scene.cameras.fov = core::FovShape::pyramid;
  scene.cameras.sides = 7;
  ASSERT_GT(core::signed_volume(scene.time_steps[0].events[0].targets[0].mesh), 0.0);
  scene.static_obstacles.push_back(l_prism("shelf", Vec3(0.9, 0.6, 0), 0.35, 1.2));
  scene.time_steps[0].dynamic_obstacles.push_back(l_prism("arm", Vec3(2.6, 1.9, 0.5), 0.2, 0.6));
  const core::CameraConfig config{testing::camera_at(Vec3(0, 0, 2.5), 35, -25),
                                  testing::camera_at(Vec3(4, 3, 2.8), -140, -30),
                                  testing::camera_at(Vec3(0.2, 2.9, 1.0), -40, -5)};
  for (auto mode : {core::DynamicMode::masked, core::DynamicMode::modelled}) {
    scene.dynamic_mode = mode;
    std::mt19937 rng(11);
    const auto a = compare_with_oracle(scene, config, 1500, rng);
    EXPECT_GT(a.inside, 50);
    EXPECT_EQ(a.mismatches, 0);
  }
}

TEST(ExactOracle, PaperBasicAgreesWithTheBruteForceSensorModel) {
  core::Scene scene = core::load_scene(std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic.json");
  scene.cameras.fov = core::FovShape::pyramid;
  scene.plausibility = {};
  const auto config = core::load_camera_config(
      std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic_corners.json", scene);
  std::mt19937 rng(7);
  const auto a = compare_with_oracle(scene, config, 500, rng);
  EXPECT_GT(a.inside, 0);
  EXPECT_EQ(a.mismatches, 0);

}

}  // namespace
}  // namespace camplace
