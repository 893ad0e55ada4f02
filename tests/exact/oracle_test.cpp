// The exact model against the brute-force sensor model of tests/support (an independent
// implementation of SPEC §3): at random points away from every boundary, p ∈ M exactly when no
// camera reports it free and it lies inside no obstacle (SPEC §4, filter off).
#include "oracle.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <random>

#include "camplace/core/camera.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/exact/evaluator.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "camplace/voxel/grid.hpp"
#include "environment.hpp"
#include "scene_builder.hpp"

namespace camplace {
namespace {

using core::Vec3;
using testing::compare_with_oracle;

// Random scenes whose cameras mix frusta (with roll), pyramids and cones (the exact
// pipeline's inscribed pyramids), with near and far planes. The exact model agrees with the
// brute-force reference, and the conservative voxel model contains it (d_voxel ≤ d_exact, every
// sampled exact model point in a model voxel). One exact evaluation per scene (Nef booleans are
// slow).
TEST(ExactOracle, RandomFrustumScenesWithRollAgreeAndTheConservativeVoxelModelContainsThem) {
  std::mt19937 rng(1414);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 4; ++trial) {
    SCOPED_TRACE(trial);
    core::Scene scene = testing::random_scene(rng, {8, 6, 6});
    testing::randomize_camera_models(rng, scene);
    core::use_exact_models(scene.cameras);  // the reference sees what the exact pipeline sees
    scene.plausibility = {};
    scene.time_steps.resize(1);  // 2 states per trial
    core::CameraConfig config = testing::random_config(rng, scene);
    testing::randomize_rolls(rng, config);
    exact::ExactOptions options;
    options.keep_models = true;
    const auto exact_eval = exact::evaluate_exact(scene, config, options);
    const auto a = compare_with_oracle(scene, config, exact_eval, 300, rng);
    EXPECT_GT(a.checked, 250);
    EXPECT_EQ(a.mismatches, 0);

    const voxel::VoxelEvaluator voxels(scene, {});
    const auto voxel_eval = voxels.evaluate(config);
    const auto& grid = voxels.grid();
    int in_exact = 0;
    for (std::size_t s = 0; s < exact_eval.states.size(); ++s) {
      EXPECT_LE(voxel_eval.states[s].d_model, exact_eval.states[s].d_model + 1e-9) << "state " << s;
      const auto model = voxels.model(config, int(s));
      for (int i = 0; i < 300; ++i) {
        const Vec3 p =
            scene.area.min +
            Vec3(unit(rng), unit(rng), unit(rng)).cwiseProduct(scene.area.max - scene.area.min);
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
    EXPECT_GT(in_exact, 20);  // the containment check is not vacuous
  }
}

// A wide frustum (179° × 150°, rolled 30°) reaches beyond the far end of the area in
// the exact pipeline as in the reference; with a near plane the space before it is not seen.
TEST(ExactOracle, WideFrustumReachesTheFarEndOfTheArea) {
  using testing::box_object;
  const core::Box3 area{Vec3(0, 0, 0), Vec3(4, 1, 1)};
  auto scene = testing::simple_scene(area, {8, 2, 2}, 1, 30.0,
                                     {box_object("c", Vec3(0, 0.875, 0.375), Vec3(0.25, 1, 0.625))},
                                     {box_object("target", Vec3(1, 0, 0), Vec3(1.25, 0.2, 0.2))});
  core::CameraModel& m = scene.cameras.models[0];
  m.fov = core::FovShape::frustum;
  m.horizontal = 179.0 * core::kDegree;
  m.vertical = 150.0 * core::kDegree;
  m.near = 1.5;
  core::CameraConfig config{testing::camera_at(Vec3(-1, 0.5, 0.5), 0.0, 0.0)};
  config[0].roll = 30.0 * core::kDegree;
  std::mt19937 rng(3);
  const auto a = compare_with_oracle(scene, config, 1000, rng);
  EXPECT_GT(a.checked, 900);
  EXPECT_EQ(a.mismatches, 0);
}

TEST(ExactOracle, RandomScenesAgreeWithTheBruteForceSensorModel) {
  std::mt19937 rng(20240611);
  for (int trial = 0; trial < 10; ++trial) {
    core::Scene scene = testing::random_scene(rng, {8, 6, 6});
    core::use_exact_models(scene.cameras);  // the exact pipeline's FOV
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
  auto scene = testing::simple_scene(
      area, {8, 6, 6}, 3, 30.0, {testing::box_object("c", Vec3(3.5, 0.2, 0), Vec3(3.8, 0.5, 1))},
      {l_prism("person", Vec3(1.8, 1.2, 0), 0.3, 1.7)});
  core::use_exact_models(scene.cameras);
  for (auto& m : scene.cameras.models) m.sides = 7;
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
  core::use_exact_models(scene.cameras);
  scene.plausibility = {};
  const auto config = core::load_camera_config(
      std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic_corners.json", scene);
  std::mt19937 rng(7);
  const auto a = compare_with_oracle(scene, config, 500, rng);
  EXPECT_GT(a.inside, 0);
  EXPECT_EQ(a.mismatches, 0);
}

// Regression: an unlimited pyramid of half angle α ≥ 60° was cut at axial distance t·cos α with
// t ≈ 2·reach, short of S's far end (here x > 3.2 was outside the FOV). The target sits in a
// corner, so most of the far end is seen free.
TEST(ExactOracle, WidePyramidReachesTheFarEndOfTheArea) {
  using testing::box_object;
  const core::Box3 area{Vec3(0, 0, 0), Vec3(4, 1, 1)};
  auto scene = testing::simple_scene(area, {8, 2, 2}, 1, 75.0,
                                     {box_object("c", Vec3(0, 0.875, 0.375), Vec3(0.25, 1, 0.625))},
                                     {box_object("target", Vec3(1, 0, 0), Vec3(1.25, 0.2, 0.2))});
  core::use_exact_models(scene.cameras);
  for (auto& m : scene.cameras.models) m.sides = 4;
  const core::CameraConfig config{testing::camera_at(Vec3(-1, 0.5, 0.5), 0.0, 0.0)};
  std::mt19937 rng(3);
  const auto a = compare_with_oracle(scene, config, 1000, rng);
  EXPECT_GT(a.checked, 900);
  EXPECT_EQ(a.mismatches, 0);
}

// Voxel and exact disagreed near 90° (a 4-sided pyramid at 89.999999999° gave an exact
// model of nearly all of S), and the exact pyramid stopped short of S above 60°. One camera high
// in a corner of paper_basic's area, 8-sided pyramids from 30° to 89.999999999°: the exact model
// agrees with the brute-force sensor model at random points, and the conservative voxel model
// contains it (d_voxel ≤ d_exact, and every sampled exact model point lies in a model voxel).
TEST(ExactOracle, WideAnglesAgreeWithTheBruteForceSensorModelAndTheVoxelPipeline) {
  using testing::box_object;
  std::mt19937 rng(16);
  for (const double angle : {30.0, 60.0, 75.0, 85.0, 89.0, 89.999999999}) {
    SCOPED_TRACE(angle);
    const core::Box3 area{Vec3(0, 0, 0), Vec3(4, 3, 3)};
    auto scene =
        testing::simple_scene(area, {16, 12, 12}, 1, angle,
                              {box_object("cabinet", Vec3(2.6, 0.5, 0.0), Vec3(3.1, 1.0, 0.7))},
                              {box_object("person", Vec3(1.0, 1.5, 0.0), Vec3(1.4, 1.8, 1.75))});
    core::use_exact_models(scene.cameras);
    for (auto& m : scene.cameras.models) m.sides = 8;
    const core::CameraConfig config{testing::camera_at(Vec3(0, 0, 3), 36.87, -35.0)};
    const auto a = compare_with_oracle(scene, config, 400, rng);
    EXPECT_GT(a.checked, 350);
    EXPECT_EQ(a.mismatches, 0);

    exact::ExactOptions options;
    options.keep_models = true;
    const auto exact_eval = exact::evaluate_exact(scene, config, options);
    const voxel::VoxelEvaluator voxels(scene, {});
    const auto voxel_eval = voxels.evaluate(config);
    ASSERT_EQ(voxel_eval.states.size(), exact_eval.states.size());
    for (std::size_t s = 0; s < exact_eval.states.size(); ++s) {
      EXPECT_LE(voxel_eval.states[s].d_model, exact_eval.states[s].d_model + 1e-9) << "state " << s;
      EXPECT_GE(voxel_eval.states[s].model_volume, exact_eval.states[s].model_volume - 1e-9)
          << "state " << s;
      const auto model = voxels.model(config, int(s));
      const auto& grid = voxels.grid();
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      int in_exact = 0;
      for (int i = 0; i < 400; ++i) {
        const Vec3 p =
            area.min + Vec3(unit(rng), unit(rng), unit(rng)).cwiseProduct(area.max - area.min);
        if (!exact_eval.models[s].contains(p)) continue;
        ++in_exact;
        std::array<int, 3> ijk{};
        for (int k = 0; k < 3; ++k)
          ijk[k] =
              std::clamp(int(std::floor((p[k] - area.min[k]) / grid.step[k])), 0, grid.n[k] - 1);
        const int index = ijk[0] + grid.n[0] * (ijk[1] + grid.n[1] * ijk[2]);
        EXPECT_TRUE(model[index]) << "state " << s << " point " << p.transpose();
      }
      EXPECT_GT(in_exact, 0) << "state " << s;
    }
  }
}

// A camera exactly on an object's surface was blind in the exact pipeline (closed
// containment) and saw in the voxel pipeline (winding number), so the conservative voxel model
// no longer contained the exact one. One convention now (SPEC §3.3: on the surface = inside,
// blind): cameras on a face, an edge and a vertex of a static box, and on a face, an edge and
// the apex of the target, with a second camera seeing normally.
TEST(ExactOracle, CamerasOnAnObjectsSurfaceAreBlindInBothPipelines) {
  using testing::box_object;
  const core::Box3 area{Vec3(0, 0, 0), Vec3(4, 3, 3)};
  core::SceneObject person = box_object("person", Vec3(2.5, 1.0, 0.0), Vec3(2.9, 1.4, 1.7));
  auto scene = testing::simple_scene(area, {16, 12, 12}, 2, 40.0,
                                     {box_object("box", Vec3(1, 1, 0), Vec3(2, 2, 1))}, {person});
  core::use_exact_models(scene.cameras);
  for (auto& m : scene.cameras.models) m.sides = 8;
  const auto other = testing::camera_at(Vec3(4, 3, 3), -140.0, -35.0);
  const std::vector<std::pair<const char*, Vec3>> on_surface{
      {"box face", Vec3(1.5, 1.5, 1.0)},    {"box edge", Vec3(2.0, 1.5, 1.0)},
      {"box vertex", Vec3(2.0, 2.0, 1.0)},  {"person face", Vec3(2.5, 1.2, 0.8)},
      {"person edge", Vec3(2.5, 1.0, 0.8)}, {"person apex", Vec3(2.9, 1.4, 1.7)}};
  for (const auto& [where, position] : on_surface) {
    SCOPED_TRACE(where);
    const core::CameraConfig config{testing::camera_at(position, 180.0, -30.0), other};
    // The blind camera changes nothing: the model is the one the other camera alone leaves.
    // (A camera in the ceiling's corner looking straight up sees nothing of S.)
    const core::CameraConfig alone{testing::camera_at(Vec3(0, 0, 3), 0.0, 89.0), other};
    const auto exact_eval = exact::evaluate_exact(scene, config);
    const auto exact_alone = exact::evaluate_exact(scene, alone);
    const voxel::VoxelEvaluator voxels(scene, {});
    const auto voxel_eval = voxels.evaluate(config);
    const auto voxel_alone = voxels.evaluate(alone);
    ASSERT_EQ(exact_eval.states.size(), 1u);
    EXPECT_EQ(exact_eval.states[0].model_volume_exact, exact_alone.states[0].model_volume_exact);
    EXPECT_EQ(voxel_eval.states[0].model_volume, voxel_alone.states[0].model_volume);
    EXPECT_LE(voxel_eval.states[0].d_model, exact_eval.states[0].d_model + 1e-9);
    EXPECT_GE(voxel_eval.states[0].model_volume, exact_eval.states[0].model_volume - 1e-9);
  }
}

// Regression (a crash): cameras on S's boundary — (0,0,2) on an edge of the ceiling, (2,0.1,1.8)
// on the face x = 2. The apex of such a camera's free pyramid touches the model's facet on S's
// face in a single point, a vertex isolated in that facet (a Nef facet cycle that is an
// SHalfloop), on which CGAL 5.5's Nef → polygon-mesh conversion dereferenced an empty polygon.
TEST(ExactModel, CamerasOnTheBoundaryOfTheArea) {
  using testing::box_object;
  const core::Box3 area{Vec3(0, 0, 0), Vec3(2, 2, 2)};
  auto scene = testing::simple_scene(
      area, {4, 4, 4}, 2, 35.0, {}, {box_object("person", Vec3(0.3, 0.3, 0), Vec3(0.7, 0.6, 1.6))});
  core::use_exact_models(scene.cameras);
  for (auto& m : scene.cameras.models) m.sides = 4;
  scene.dynamic_mode = core::DynamicMode::modelled;
  auto& step = scene.time_steps[0];
  step.dynamic_obstacles = {box_object("robot", Vec3(1.5, 1.5, 0), Vec3(1.9, 1.9, 0.6))};
  step.critical = step.dynamic_obstacles;
  step.events[0].weight = 0.7;
  core::Event second;
  second.weight = 0.3;
  second.targets = {box_object("person", Vec3(0.2, 1.2, 0), Vec3(0.5, 1.5, 1.6))};
  step.events.push_back(second);
  const core::CameraConfig config{testing::camera_at(Vec3(0, 0, 2), 45, -40),
                                  testing::camera_at(Vec3(2, 0.1, 1.8), 135, -30)};

  exact::ExactOptions options;
  options.keep_models = true;
  const auto eval = exact::evaluate_exact(scene, config, options);
  ASSERT_EQ(eval.states.size(), 2u);
  for (std::size_t s = 0; s < eval.states.size(); ++s) {
    const auto& r = eval.states[s];
    EXPECT_GT(r.model_volume, 0.0) << "state " << s;
    EXPECT_LE(r.model_volume, 8.0) << "state " << s;
    EXPECT_GE(r.components, 1) << "state " << s;
    EXPECT_LE(r.d_model, r.d_true + 1e-12) << "state " << s;
    // The boundary is a closed outward mesh enclosing the exact volume.
    EXPECT_NEAR(core::signed_volume(eval.models[s].boundary_mesh()), r.model_volume, 1e-9)
        << "state " << s;
  }
  std::mt19937 rng(5);
  const auto a = compare_with_oracle(scene, config, 2000, rng);
  EXPECT_GT(a.inside, 200);
  EXPECT_EQ(a.mismatches, 0);
}

// A camera position on S's boundary: on a corner, an edge, a face (the ceiling z = S.max.z
// often, as in the `ceiling` preset) or inside; coordinates often on a 1/4 grid so that they
// line up with object coordinates. Directions sometimes axis-aligned (pyramid faces parallel to
// S's faces) or vertical.
core::CameraSetting boundary_camera(std::mt19937& rng, const core::Box3& area) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int fixed = std::uniform_int_distribution<int>(0, 3)(rng);  // coordinates on the boundary
  std::array<int, 3> axes{0, 1, 2};
  std::shuffle(axes.begin(), axes.end(), rng);
  if (fixed == 1 && unit(rng) < 0.5) axes = {2, 0, 1};  // the ceiling (or floor)
  Vec3 p;
  for (int k = 0; k < 3; ++k) {
    const int i = axes[k];
    const double lo = area.min[i], hi = area.max[i];
    if (k < fixed) {
      p[i] = (i == 2 || unit(rng) < 0.5) ? hi : lo;
    } else if (unit(rng) < 0.4) {
      p[i] = lo + (hi - lo) * std::uniform_int_distribution<int>(1, 3)(rng) / 4.0;
    } else {
      p[i] = lo + (hi - lo) * unit(rng);
    }
  }
  double yaw = -180 + 360 * unit(rng), pitch = -90 + 90 * unit(rng);
  if (unit(rng) < 0.5) {
    // Aimed into S: the pyramid then touches S's boundary only at its apex (an isolated vertex
    // of the model's facet there), the case that used to crash.
    const Vec3 aim = area.min + (Vec3::Constant(0.25) + 0.5 * Vec3(unit(rng), unit(rng), unit(rng)))
                                    .cwiseProduct(area.max - area.min);
    const Vec3 d = (aim - p).normalized();
    constexpr double kToDeg = 180.0 / 3.14159265358979323846;
    yaw = std::atan2(d.y(), d.x()) * kToDeg;
    pitch = std::asin(std::clamp(d.z(), -1.0, 1.0)) * kToDeg;
  } else {
    if (unit(rng) < 0.3) yaw = 45.0 * std::uniform_int_distribution<int>(-4, 4)(rng);
    if (unit(rng) < 0.2) pitch = std::array<double, 3>{-90.0, -45.0, 0.0}[rng() % 3];
  }
  return testing::camera_at(p, yaw, pitch);
}

// A small room S = [0,2]³ with boxes standing on the floor, one per quadrant of the floor (so
// targets never meet obstacles), often flush with a wall: a static box, a robot and one target
// per event; 2 events.
core::Scene small_room_scene(std::mt19937& rng) {
  using testing::box_object;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::array<int, 4> quadrants{0, 1, 2, 3};
  std::shuffle(quadrants.begin(), quadrants.end(), rng);
  auto box_in = [&](const std::string& name, int q, double height) {
    const Vec3 lo(q % 2, q / 2, 0.0);
    Vec3 a(lo.x() + 0.8 * unit(rng), lo.y() + 0.8 * unit(rng), 0.0);
    Vec3 b(a.x() + 0.1 + (lo.x() + 1 - a.x() - 0.1) * unit(rng),
           a.y() + 0.1 + (lo.y() + 1 - a.y() - 0.1) * unit(rng), height);
    if (unit(rng) < 0.3) a.x() = lo.x();  // flush with the wall x = 0 or with the neighbour
    if (unit(rng) < 0.3) b.y() = lo.y() + 1;
    return box_object(name, a, b);
  };
  const core::Box3 area{Vec3(0, 0, 0), Vec3(2, 2, 2)};
  auto scene = testing::simple_scene(area, {4, 4, 4}, 2 + int(rng() % 2), 25 + 20 * unit(rng), {},
                                     {box_in("person", quadrants[0], 1.6)});
  core::use_exact_models(scene.cameras);
  const int sides = 3 + int(rng() % 6);
  for (auto& m : scene.cameras.models) m.sides = sides;
  scene.dynamic_mode = unit(rng) < 0.5 ? core::DynamicMode::masked : core::DynamicMode::modelled;
  scene.static_obstacles.push_back(box_in("shelf", quadrants[3], 0.5 + unit(rng)));
  auto& step = scene.time_steps[0];
  step.dynamic_obstacles = {box_in("robot", quadrants[1], 0.3 + 0.5 * unit(rng))};
  step.critical = step.dynamic_obstacles;
  core::Event second;
  second.weight = 0.5;
  second.targets = {box_in("person", quadrants[2], 1.6)};
  step.events.push_back(second);
  return scene;
}

TEST(ExactOracle, CamerasOnTheBoundaryOfTheAreaAgreeWithTheBruteForceSensorModel) {
  // CAMPLACE_EXACT_FUZZ_TRIALS=N runs N trials (longer fuzzing by hand); default 20 (~6 s).
  const int trials = int(testing::env_number("CAMPLACE_EXACT_FUZZ_TRIALS", 20));
  std::mt19937 rng(unsigned(testing::env_number("CAMPLACE_EXACT_FUZZ_SEED", 20240612u)));
  for (int trial = 0; trial < trials; ++trial) {
    core::Scene scene;
    if (trial % 2 == 0) {
      scene = small_room_scene(rng);
    } else {
      scene = testing::random_scene(rng, {8, 6, 6});
      core::use_exact_models(scene.cameras);
      scene.plausibility = {};
      scene.time_steps.resize(1);  // 2 states per trial
    }
    core::CameraConfig config;
    for (int c = 0; c < scene.cameras.count; ++c)
      config.push_back(boundary_camera(rng, scene.area));
    const auto a = compare_with_oracle(scene, config, 200, rng);
    EXPECT_GT(a.checked, 0);
    EXPECT_EQ(a.mismatches, 0) << "trial " << trial;
  }
}

}  // namespace
}  // namespace camplace
