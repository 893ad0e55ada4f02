// The exact pipeline (SPEC §6) with obstacles and critical objects that extend beyond the area
// S (SPEC §2): a wall crossing S whose part outside S hides a region, by hand, and random
// scenes with an object crossing each face of S against the brute-force sensor model
// (tests/support/reference.cpp) and the conservative voxel model (which must contain the exact
// model: d_voxel_conservative ≤ d_exact ≤ d_true without a filter). Nef booleans: label `slow`.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "camplace/core/camera.hpp"
#include "camplace/exact/evaluator.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "crossing_scene.hpp"
#include "reference.hpp"
#include "scene_builder.hpp"

namespace camplace {
namespace {

using core::Vec3;
using testing::box_object;
using testing::camera_at;

/// The conservative voxel model of `scene` holds every point of the exact models that a sample
/// of `samples` points per state finds, and d_voxel ≤ d_exact ≤ d_true; returns the number of
/// exact model points found.
int expect_voxel_model_contains_exact(const core::Scene& scene, const core::CameraConfig& config,
                                      const exact::ExactEvaluation& exact_eval, int samples,
                                      std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const voxel::VoxelEvaluator voxels(scene, {voxel::LabelMode::conservative, {0, 0, 0}});
  const auto voxel_eval = voxels.evaluate(config);
  const voxel::Grid& grid = voxels.grid();
  int in_exact = 0;
  for (std::size_t s = 0; s < exact_eval.states.size(); ++s) {
    EXPECT_LE(voxel_eval.states[s].d_model, exact_eval.states[s].d_model + 1e-9) << "state " << s;
    EXPECT_LE(exact_eval.states[s].d_model, exact_eval.states[s].d_true + 1e-12) << "state " << s;
    EXPECT_NEAR(voxel_eval.states[s].d_true, exact_eval.states[s].d_true, 1e-12) << "state " << s;
    const auto model = voxels.model(config, static_cast<int>(s));
    for (int i = 0; i < samples; ++i) {
      const Vec3 p =
          scene.area.min + Vec3(unit(rng), unit(rng), unit(rng)).cwiseProduct(scene.area.size());
      if (!exact_eval.models[s].contains(p)) continue;
      ++in_exact;
      std::array<int, 3> ijk{};
      for (int k = 0; k < 3; ++k) {
        ijk[k] = std::clamp(int(std::floor((p[k] - scene.area.min[k]) / grid.step[k])), 0,
                            grid.n[k] - 1);
      }
      EXPECT_TRUE(model[ijk[0] + grid.n[0] * (ijk[1] + grid.n[1] * ijk[2])])
          << "state " << s << " point " << p.transpose();
    }
  }
  return in_exact;
}

// S = [0,4]×[0,1]×[0,1]; a camera outside S at c = (−2, 1.5, 0.5) looking along +x (4-sided
// pyramid of half angle 60°: at x ≥ 0 its section |y − 1.5| + |z − 0.5| ≤ √3·(x + 2) holds all of
// S); a wall x ∈ [−0.5, 0.5], y ∈ [−1, 1.2], z ∈ [−1, 2] crossing S's faces x = 0, y = 0, y = 1,
// z = 0 and z = 1. Rays from c to S descend in y and stay within the wall's z range, so in the
// (x, y) plane: p with x ≥ 0.5 lies in the shadow when the ray's height at the wall's back face
// x = 0.5 is ≤ 1.2 — an edge outside S (y = 1.2 > 1) —, i.e. y ≤ 1.5 − 0.12·(x + 2) =
// 1.26 − 0.12·x; that is all of y ∈ [0, 1] for x ≤ 13/6. S ∩ wall (x ≤ 0.5) is removed as
// interior. The target and the critical object lie in the shadow (the wall hides their
// silhouettes) and a critical object is no obstacle, so
//   vol M = (13/6 − 1/2) + ∫_{13/6}^{4} (1.26 − 0.12 x) dx = 5/3 + 1.35 + 169/600 = 1979/600 m³,
// for a static wall and for a dynamic one in either mode (the masked wall's cone adds only points
// before it, at x < −0.5, outside S). The wall clipped to S would give
// ∫_{0.5}^{4} (1.1 − 0.2 x) dx = 2.275 m³: the part outside S decides.
TEST(ExactBeyondArea, WallCrossingSHidesARegionOfHandComputedVolume) {
  const core::Box3 area{Vec3(0, 0, 0), Vec3(4, 1, 1)};
  const auto target = box_object("person", Vec3(1, 0.3, 0.2), Vec3(1.5, 0.6, 0.8));
  const auto critical = box_object("robot", Vec3(1.7, 0.1, 0.1), Vec3(2.0, 0.3, 0.4));
  const auto wall = box_object("wall", Vec3(-0.5, -1, -1), Vec3(0.5, 1.2, 2));
  const core::CameraConfig config{camera_at(Vec3(-2, 1.5, 0.5), 0.0, 0.0)};
  std::mt19937 rng(17);
  for (int kind = 0; kind < 3; ++kind) {
    SCOPED_TRACE(kind);
    core::Scene scene = testing::simple_scene(area, {16, 4, 4}, 1, 60.0, {critical}, {target});
    core::use_exact_models(scene.cameras);
    for (auto& m : scene.cameras.models) m.sides = 4;
    if (kind == 0) {
      scene.static_obstacles.push_back(wall);
    } else {
      scene.time_steps[0].dynamic_obstacles.push_back(wall);
      scene.dynamic_mode = kind == 1 ? core::DynamicMode::masked : core::DynamicMode::modelled;
    }
    exact::ExactOptions options;
    options.keep_models = true;
    const auto eval = exact::evaluate_exact(scene, config, options);
    ASSERT_EQ(eval.states.size(), 1u);
    EXPECT_NEAR(eval.states[0].model_volume, 1979.0 / 600.0, 1e-9);
    EXPECT_EQ(eval.states[0].components, 1);
    const exact::ExactModel& m = eval.models[0];
    EXPECT_FALSE(m.contains(Vec3(0.25, 0.5, 0.5)));  // inside the wall (interior)
    EXPECT_TRUE(m.contains(Vec3(2.0, 0.95, 0.5)));   // x ≤ 13/6: the whole section hidden
    EXPECT_TRUE(m.contains(Vec3(3.5, 0.8, 0.5)));    // 0.8 < 1.26 − 0.42 = 0.84
    EXPECT_FALSE(m.contains(Vec3(3.5, 0.88, 0.5)));  // above the shadow: free
    EXPECT_TRUE(m.contains(Vec3(1.8, 0.2, 0.2)));    // in the robot: a critical object, no obstacle
    // d(C, M) = 0: the robot lies in the hidden region. d_true: x gap 0.2, y gap 0, z overlap.
    EXPECT_EQ(eval.states[0].d_model, 0.0);
    EXPECT_NEAR(eval.states[0].d_true, 0.2, 1e-12);
    EXPECT_GT(expect_voxel_model_contains_exact(scene, config, eval, 400, rng), 100);
  }
}

// Random scenes with an object crossing each face of S (tests/support/crossing_scene.hpp; the
// three kinds on each face): at random points of S away from every boundary,
// p ∈ M exactly when no camera reports it free (brute force, the exact pipeline's pyramids) and
// it lies inside no obstacle; the conservative voxel model contains the exact model. The cameras:
// in S aimed at the object, outside S behind its outside part, and inside that part or outside S
// elsewhere.
TEST(ExactBeyondArea, ObjectsCrossingEachFaceAgreeWithTheBruteForceSensorModel) {
  std::mt19937 rng(20261206);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int n = 0; n < 18; ++n) {
    const int face = n / 3;
    const testing::beyond::Kind kind = testing::beyond::kKinds[n % 3];
    SCOPED_TRACE(std::string("face ") + std::to_string(face) + " " +
                 testing::beyond::kind_name(kind));
    testing::beyond::Crossing c = testing::beyond::crossing_scene(rng, face, kind);
    core::Scene& scene = c.scene;
    core::use_exact_models(scene.cameras);  // the reference sees what the exact pipeline sees
    scene.voxels = {8, 6, 6};
    exact::ExactOptions options;
    options.keep_models = true;
    const auto eval = exact::evaluate_exact(scene, c.config, options);
    int checked = 0, inside = 0;
    for (std::size_t s = 0; s < eval.states.size(); ++s) {
      const auto& step = scene.time_steps[0];
      for (int i = 0; i < 300; ++i) {
        const Vec3 p =
            scene.area.min + Vec3(unit(rng), unit(rng), unit(rng)).cwiseProduct(scene.area.size());
        bool ambiguous = false, non_free = true;
        for (int cam = 0; cam < scene.cameras.count; ++cam) {
          const auto label =
              testing::reference_label(scene, 0, static_cast<int>(s), c.config[cam], p, 1e-6, cam);
          ambiguous |= label.ambiguous;
          non_free = non_free && label.label != voxel::Label::free;
        }
        bool in_obstacle = false;
        for (const auto& o : scene.static_obstacles)
          in_obstacle |= testing::reference_inside(o.mesh, p);
        for (const auto& o : step.dynamic_obstacles)
          in_obstacle |= testing::reference_inside(o.mesh, p);
        if (ambiguous) continue;
        const bool expected = non_free && !in_obstacle;
        ++checked;
        inside += expected;
        EXPECT_EQ(eval.models[s].contains(p), expected)
            << "state " << s << " point " << p.transpose();
      }
    }
    EXPECT_GT(checked, 250);
    EXPECT_GT(inside, 10);
    EXPECT_GT(expect_voxel_model_contains_exact(scene, c.config, eval, 300, rng), 10);
  }
}

}  // namespace
}  // namespace camplace
