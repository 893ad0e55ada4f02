// The silhouette cones built from outlines in each camera's image plane (the default) against the
// former construction, the union of one cone per visible face (ExactOptions::face_cones, an
// independent construction of the same sets): every state's d_model², model volume and component
// counts are the same exact fractions, on random scenes of fine meshes (50–800 triangles per
// object) and on hand-made outlines with holes and touching pieces; the models also agree with
// the brute-force sensor model of tests/support.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "../core/fine_meshes.hpp"
#include "camplace/core/camera.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/exact/evaluator.hpp"
#include "environment.hpp"
#include "oracle.hpp"
#include "same_results.hpp"
#include "scene_builder.hpp"

namespace camplace {
namespace {

using core::Vec3;

/// An ellipsoid of 50–800 triangles with semi-axes `radii` (at most 0.4 m), randomly turned.
core::TriangleMesh random_ellipsoid(std::mt19937& rng, const Vec3& center, const Vec3& radii) {
  int slices = 0, stacks = 0;
  do {
    slices = 5 + int(rng() % 24);
    stacks = 3 + int(rng() % 14);
  } while (2 * slices * (stacks - 1) < 50 || 2 * slices * (stacks - 1) > 800);
  return testing::ellipsoid(center, radii, slices, stacks, testing::random_rotation(rng));
}

/// A 4×3×3 m room cut into 4×3×2 cells of 1×1×1.5 m, one object group per cell (so that targets
/// never meet obstacles): a finely cut static box, a robot of one or two turned ellipsoids, and
/// per event a person of two overlapping ellipsoids (torso and head) and sometimes a turned
/// finely cut box; 1 time step, 1–2 events, 2–3 cameras of mixed models, either dynamic mode,
/// the plausibility filter on in some scenes.
core::Scene fine_mesh_scene(std::mt19937& rng, bool filter) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  testing::CellRoom room = testing::cell_room(rng);
  core::Scene scene = std::move(room.scene);
  auto cell_center = [&] { return room.next_cell(); };
  scene.dynamic_mode = unit(rng) < 0.5 ? core::DynamicMode::masked : core::DynamicMode::modelled;
  scene.plausibility = {};
  if (filter) scene.plausibility = {0.002 + 0.01 * unit(rng), 0.2 * unit(rng)};
  {
    const Vec3 c = cell_center(), h(0.2 + 0.2 * unit(rng), 0.2 + 0.2 * unit(rng), 0.4);
    scene.static_obstacles.push_back(
        testing::mesh_object("shelf", testing::subdivided_box(c - h, c + h, 2 + int(rng() % 5))));
  }
  core::TimeStep& step = scene.time_steps[0];
  step.events.clear();
  const Vec3 robot = cell_center();
  step.dynamic_obstacles.push_back(testing::mesh_object(
      "robot base", random_ellipsoid(rng, robot, Vec3(0.15 + 0.2 * unit(rng), 0.15, 0.35))));
  if (unit(rng) < 0.5)
    step.dynamic_obstacles.push_back(testing::mesh_object(
        "robot arm", random_ellipsoid(rng, robot + Vec3(0.1, 0, 0.2), Vec3(0.3, 0.08, 0.08))));
  step.critical = step.dynamic_obstacles;
  const int events = 1 + int(rng() % 2);
  for (int l = 0; l < events; ++l) {
    core::Event e;
    e.weight = 1.0 / events;
    const Vec3 c = cell_center();
    e.targets.push_back(
        testing::mesh_object("torso", random_ellipsoid(rng, c, Vec3(0.25, 0.15, 0.4))));
    e.targets.push_back(testing::mesh_object(
        "head", random_ellipsoid(rng, c + Vec3(0, 0, 0.45), Vec3(0.12, 0.12, 0.15))));
    if (unit(rng) < 0.5) {
      const Vec3 b = cell_center(), h(0.15, 0.15, 0.25);
      e.targets.push_back(testing::mesh_object(
          "bag", testing::moved(testing::subdivided_box(-h, h, 2 + int(rng() % 4)),
                                testing::random_rotation(rng), b)));
    }
    step.events.push_back(std::move(e));
  }
  return scene;
}

/// Evaluates `config` both ways and expects the same exact results in every state.
exact::ExactEvaluation expect_same_as_face_cones(const core::Scene& scene,
                                                 const core::CameraConfig& config) {
  exact::ExactOptions options;
  options.keep_models = true;
  exact::ExactOptions reference = options;
  reference.face_cones = true;
  const auto fast = exact::evaluate_exact(scene, config, options);
  testing::expect_same_exact_results(fast, exact::evaluate_exact(scene, config, reference));
  return fast;
}

TEST(OutlineCones, RandomFineMeshScenesEqualTheFaceConesExactlyAndTheBruteForceModel) {
  // CAMPLACE_EXACT_OUTLINE_TRIALS=N runs N scenes (longer checks by hand); default 4 (the
  // per-face reference takes seconds per scene).
  const int trials = int(testing::env_number("CAMPLACE_EXACT_OUTLINE_TRIALS", 4));
  std::mt19937 rng(unsigned(testing::env_number("CAMPLACE_EXACT_OUTLINE_SEED", 20261203u)));
  for (int trial = 0; trial < trials; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const bool filter = trial % 3 == 2;
    const core::Scene scene = fine_mesh_scene(rng, filter);
    core::CameraConfig config = testing::random_config(rng, scene);
    testing::randomize_rolls(rng, config);
    const auto eval = expect_same_as_face_cones(scene, config);
    if (!filter) {
      const auto a = testing::compare_with_oracle(scene, config, eval, 100, rng);
      EXPECT_GT(a.checked, 0);
      EXPECT_EQ(a.mismatches, 0);
    }
  }
}

/// A square frame of four bars around the line of sight of a camera looking through it: the
/// occupied outline is a ring (a region with a hole); with `touching` the bars meet only at their
/// corners' edges, so the outline's pieces touch at single points.
TEST(OutlineCones, FramesSeenThroughTheirOpeningEqualTheFaceCones) {
  using testing::box_object;
  const core::Box3 area{Vec3(0, 0, 0), Vec3(4, 3, 3)};
  for (const bool touching : {false, true}) {
    SCOPED_TRACE(touching ? "touching" : "overlapping");
    const double o = touching ? 0.0 : 0.05;  // overlap of the bars at the corners
    const double x0 = 2.0, x1 = 2.2, lo = 1.0, hi = 2.0, w = 0.2;
    std::vector<core::SceneObject> bars{
        box_object("bottom", Vec3(x0, lo, lo), Vec3(x1, hi, lo + w)),
        box_object("top", Vec3(x0, lo, hi - w), Vec3(x1, hi, hi)),
        box_object("left", Vec3(x0, lo, lo + w - o), Vec3(x1, lo + w, hi - w + o)),
        box_object("right", Vec3(x0, hi - w, lo + w - o), Vec3(x1, hi, hi - w + o))};
    if (touching) {
      // Diagonal neighbours that meet along one edge only.
      bars.push_back(box_object("corner a", Vec3(x0, 0.4, 0.4), Vec3(x1, 0.6, 0.6)));
      bars.push_back(box_object("corner b", Vec3(x0, 0.6, 0.6), Vec3(x1, 0.8, 0.8)));
    }
    auto scene =
        testing::simple_scene(area, {8, 6, 6}, 2, 40.0,
                              {box_object("robot", Vec3(3.5, 0.2, 0), Vec3(3.8, 0.5, 1))}, bars);
    core::use_exact_models(scene.cameras);
    for (auto& m : scene.cameras.models) m.sides = 6;
    scene.static_obstacles.push_back(
        box_object("post", Vec3(1.0, 1.45, 0.0), Vec3(1.1, 1.55, 1.6)));
    const core::CameraConfig config{testing::camera_at(Vec3(0.0, 1.5, 1.5), 0.0, 0.0),
                                    testing::camera_at(Vec3(4.0, 3.0, 2.5), -140.0, -25.0)};
    const auto eval = expect_same_as_face_cones(scene, config);
    std::mt19937 rng(26);
    const auto a = testing::compare_with_oracle(scene, config, eval, 1500, rng);
    EXPECT_GT(a.inside, 50);
    EXPECT_EQ(a.mismatches, 0);
  }
}

}  // namespace
}  // namespace camplace
