// The shadows of non-convex occluding solids built from patches of their front faces found in
// each camera's image plane (the default) against the former construction, the union of one
// shadow per front face (ExactOptions::face_shadows, an independent construction of the same
// sets): the two are the same point set within the camera's FOV on random dented and bumped
// ellipsoids (50–800 triangles, cameras at random places outside, looking at the solid, sideways
// from close by, or grazing along one of its faces); and every state's d_model², model volume and
// component counts are the same exact fractions on random scenes in modelled mode (the robot, two
// interpenetrating non-convex solids, occludes) with a non-convex static obstacle; the models also
// agree with the brute-force sensor model of tests/support.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "../core/fine_meshes.hpp"
#include "camplace/core/camera.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/exact/evaluator.hpp"
#include "environment.hpp"
#include "internal/shadow_check.hpp"
#include "oracle.hpp"
#include "same_results.hpp"
#include "scene_builder.hpp"

namespace camplace {
namespace {

using core::Vec3;

/// An ellipsoid of 50–800 triangles with semi-axes `radii`, randomly turned, each vertex moved
/// along its ray from the centre by a sum of random dents and bumps (a star-shaped closed mesh,
/// still outward: every triangle keeps its vertices' rays, hence its orientation about the
/// centre). Returns the largest distance from the centre to a vertex in `reach`.
core::TriangleMesh dented_ellipsoid(std::mt19937& rng, const Vec3& center, const Vec3& radii,
                                    double* reach = nullptr) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int slices = 0, stacks = 0;
  do {
    slices = 5 + int(rng() % 24);
    stacks = 3 + int(rng() % 14);
  } while (2 * slices * (stacks - 1) < 50 || 2 * slices * (stacks - 1) > 800);
  core::TriangleMesh m =
      testing::ellipsoid(center, radii, slices, stacks, testing::random_rotation(rng));
  struct Bump {
    Vec3 direction;
    double amplitude, width;
  };
  std::vector<Bump> bumps(2 + rng() % 5);
  for (auto& b : bumps) {
    b.direction = Vec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5).normalized();
    b.amplitude = -0.45 + 1.0 * unit(rng);  // dents down to 0.55 of the radius, bumps to 1.55
    b.width = 0.25 + 0.5 * unit(rng);
  }
  double far = 0.0;
  for (Vec3& v : m.vertices) {
    const Vec3 r = v - center;
    const Vec3 dir = r.normalized();
    double f = 1.0;
    for (const auto& b : bumps)
      f += b.amplitude * std::exp(-(dir - b.direction).squaredNorm() / (b.width * b.width));
    v = center + std::max(f, 0.3) * r;
    far = std::max(far, (v - center).norm());
  }
  if (reach) *reach = far;
  return m;
}

/// The setting of a camera at `position` looking along `direction`.
core::CameraSetting looking(const Vec3& position, const Vec3& direction) {
  const Vec3 d = direction.normalized();
  core::CameraSetting s;
  s.position = position;
  s.yaw = std::atan2(d.y(), d.x());
  s.pitch = std::asin(std::clamp(d.z(), -1.0, 1.0));
  return s;
}

TEST(ShadowPatches, EqualThePerFaceShadowsOnRandomDentedMeshes) {
  // CAMPLACE_EXACT_SHADOW_TRIALS=N runs N solids, 3 views each (longer checks by hand); default
  // 8 (the per-face reference takes seconds per view).
  const int trials = int(testing::env_number("CAMPLACE_EXACT_SHADOW_TRIALS", 8));
  const unsigned default_seed = 20261204u;
  const auto seed = unsigned(testing::env_number("CAMPLACE_EXACT_SHADOW_SEED", default_seed));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const core::Box3 box{Vec3(-3, -3, -3), Vec3(3, 3, 3)};
  int checked = 0, grazing = 0, split = 0, crossing = 0;
  for (int trial = 0; trial < trials; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    double reach = 0.0;
    const Vec3 radii(0.3 + 0.3 * unit(rng), 0.3 + 0.3 * unit(rng), 0.3 + 0.3 * unit(rng));
    const core::TriangleMesh mesh = dented_ellipsoid(rng, Vec3::Zero(), radii, &reach);
    core::Scene scene = testing::simple_scene(box, {8, 8, 8}, 1, 30.0, {}, {});
    testing::randomize_camera_models(rng, scene);
    core::use_exact_models(scene.cameras);
    const core::CameraModel& model = scene.cameras.models[0];
    for (int view = 0; view < 3; ++view) {
      SCOPED_TRACE("view " + std::to_string(view));
      core::CameraSetting setting;
      const bool graze = view == 2;
      if (graze) {
        // In the plane of a random face (up to rounding), looking along it at its centroid.
        const auto& t = mesh.triangles[rng() % mesh.triangles.size()];
        const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
        const Vec3 centroid = (a + b + c) / 3.0;
        const Vec3 n = (b - a).cross(c - a).normalized();
        Vec3 along = (b - a).normalized();
        const double turn = 6.2831853 * unit(rng);
        along = std::cos(turn) * along + std::sin(turn) * n.cross(along);
        const Vec3 position = centroid + (reach * (1.2 + unit(rng))) * along;
        setting = looking(position, centroid - position);
      } else {
        const Vec3 dir = Vec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5).normalized();
        const Vec3 position = (reach * (1.05 + 1.5 * unit(rng))) * dir;
        const Vec3 off = Vec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5);
        if (view == 0) {
          // At the solid, up to ~50° off.
          setting = looking(position, -dir + 1.5 * unit(rng) * off);
        } else {
          // Sideways, close by: the camera's plane (x − c)·d = 0 cuts the solid, so faces cross
          // it (built one by one) and others lie behind it (left out).
          const Vec3 side = off.cross(dir).normalized();
          setting = looking((reach * (1.02 + 0.2 * unit(rng))) * dir, side - 0.3 * unit(rng) * dir);
        }
      }
      setting.roll = 6.2831853 * unit(rng);
      const auto check = exact::internal::check_shadow(mesh, setting, model, box);
      if (check.camera_inside) continue;
      EXPECT_TRUE(check.same) << check.front_faces << " front faces, " << check.patches
                              << " patches, " << check.single << " crossing faces";
      ++checked;
      grazing += graze;
      split += check.patches > 1;
      crossing += check.single > 0;
    }
  }
  std::printf("%d views checked: %d grazing, %d with several patches, %d with crossing faces\n",
              checked, grazing, split, crossing);
  if (trials >= 8 && seed == default_seed) {
    EXPECT_GT(grazing, 0);
    EXPECT_GT(split, 0);
    EXPECT_GT(crossing, 0);
  }
}

/// A 4×3×3 m room cut into 4×3×2 cells of 1×1×1.5 m, one object group per cell: a dented static
/// solid, a robot of two interpenetrating dented solids (modelled: it occludes), per event a
/// person of two overlapping ellipsoids; 1 time step, 1–2 events, 2–3 cameras of mixed models.
core::Scene dented_scene(std::mt19937& rng, bool filter) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  testing::CellRoom room = testing::cell_room(rng);
  core::Scene scene = std::move(room.scene);
  auto cell_center = [&] { return room.next_cell(); };
  scene.dynamic_mode = core::DynamicMode::modelled;
  scene.plausibility = {};
  if (filter) scene.plausibility = {0.002 + 0.01 * unit(rng), 0.2 * unit(rng)};
  scene.static_obstacles.push_back(
      testing::mesh_object("shelf", dented_ellipsoid(rng, cell_center(), Vec3(0.25, 0.25, 0.35))));
  core::TimeStep& step = scene.time_steps[0];
  step.events.clear();
  const Vec3 robot = cell_center();
  step.dynamic_obstacles.push_back(testing::mesh_object(
      "robot base", dented_ellipsoid(rng, robot, Vec3(0.1 + 0.15 * unit(rng), 0.15, 0.3))));
  step.dynamic_obstacles.push_back(testing::mesh_object(
      "robot arm", dented_ellipsoid(rng, robot + Vec3(0.1, 0, 0.2), Vec3(0.28, 0.08, 0.1))));
  step.critical = step.dynamic_obstacles;
  const int events = 1 + int(rng() % 2);
  for (int l = 0; l < events; ++l) {
    core::Event e;
    e.weight = 1.0 / events;
    const Vec3 c = cell_center();
    e.targets.push_back(
        testing::mesh_object("torso", testing::ellipsoid(c, Vec3(0.25, 0.15, 0.35), 8, 5)));
    e.targets.push_back(testing::mesh_object(
        "head", testing::ellipsoid(c + Vec3(0, 0, 0.4), Vec3(0.12, 0.12, 0.15), 6, 4)));
    step.events.push_back(std::move(e));
  }
  return scene;
}

TEST(ShadowPatches, RandomModelledScenesEqualThePerFaceShadowsExactlyAndTheBruteForceModel) {
  // CAMPLACE_EXACT_SHADOW_SCENES=N runs N scenes (longer checks by hand); default 4.
  const int trials = int(testing::env_number("CAMPLACE_EXACT_SHADOW_SCENES", 4));
  const unsigned default_seed = 20261205u;
  const auto seed = unsigned(testing::env_number("CAMPLACE_EXACT_SHADOW_SEED", default_seed));
  std::mt19937 rng(seed);
  int nonempty = 0;
  for (int trial = 0; trial < trials; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const bool filter = trial % 3 == 2;
    const core::Scene scene = dented_scene(rng, filter);
    core::CameraConfig config = testing::random_config(rng, scene);
    testing::randomize_rolls(rng, config);
    exact::ExactOptions options;
    options.keep_models = true;
    options.threads = 1;
    exact::ExactOptions reference = options;
    reference.face_shadows = true;
    const auto fast = exact::evaluate_exact(scene, config, options);
    testing::expect_same_exact_results(fast, exact::evaluate_exact(scene, config, reference));
    for (const auto& r : fast.states) nonempty += r.components > 0;
    if (!filter) {
      const auto agreement = testing::compare_with_oracle(scene, config, fast, 100, rng);
      EXPECT_GT(agreement.checked, 0);
      EXPECT_EQ(agreement.mismatches, 0);
    }
  }
  if (trials >= 4 && seed == default_seed) {
    EXPECT_GT(nonempty, 0);
  }
}

}  // namespace
}  // namespace camplace
