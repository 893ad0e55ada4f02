// The conservative voxel models of one solid cut into different coplanar triangles against the
// exact model of SPEC §6 (docs/design/labelling.md L9): each version's model contains the exact
// model, which does not depend on how a face is cut. Small scenes: the Nef pipeline is slow.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "camplace/core/geometry.hpp"
#include "camplace/exact/evaluator.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "retriangulate.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using core::Vec3;

/// Voxels outside `voxel_model` that hold points of the exact model: a boundary triangle of the
/// exact model reaching into the voxel's interior (shrunk by 1e-9 m), or the voxel's centre in
/// the exact model. Brute force over all voxels.
int exact_points_outside(const exact::ExactModel& model, const voxel::Grid& grid,
                         const std::vector<std::uint8_t>& voxel_model) {
  if (model.empty()) return 0;
  const core::TriangleMesh boundary = model.boundary_mesh();
  int outside = 0;
  for (int v = 0; v < grid.count(); ++v) {
    if (voxel_model[v]) continue;
    core::Box3 box = grid.voxel_box(v);
    box.min += Vec3::Constant(1e-9);
    box.max -= Vec3::Constant(1e-9);
    bool holds = model.contains(grid.voxel_center(v));
    for (std::size_t t = 0; t < boundary.triangles.size() && !holds; ++t) {
      const auto& tri = boundary.triangles[t];
      holds = core::triangle_box_overlap(boundary.vertices[tri[0]], boundary.vertices[tri[1]],
                                         boundary.vertices[tri[2]], box);
    }
    outside += holds;
  }
  return outside;
}

/// For every state: the exact model of `scene`, and the conservative voxel models of `scene`
/// and of each of `cuts` (the same solids cut otherwise); none may leave out an exact point.
/// Cone cameras become their inscribed pyramids in every pipeline (SPEC §1). Returns the number
/// of voxels where some cut's model differs from the uncut one's.
int expect_models_hold_exact(core::Scene scene, std::vector<core::Scene> cuts,
                             const core::CameraConfig& config, const char* what) {
  core::use_exact_models(scene.cameras);
  for (core::Scene& cut : cuts) core::use_exact_models(cut.cameras);
  const voxel::VoxelEvaluator whole(scene, {voxel::LabelMode::conservative, {0, 0, 0}});
  std::vector<voxel::VoxelEvaluator> finer;
  for (const core::Scene& cut : cuts) {
    finer.emplace_back(cut, voxel::VoxelOptions{voxel::LabelMode::conservative, {0, 0, 0}});
  }
  const auto states = core::states(scene);
  int differ = 0;
  for (std::size_t st = 0; st < states.size(); ++st) {
    const exact::ExactModel model = exact::build_exact_model(scene, config, states[st]);
    const auto model_whole = whole.model(config, static_cast<int>(st));
    EXPECT_EQ(exact_points_outside(model, whole.grid(), model_whole), 0)
        << what << " uncut, state " << st;
    for (std::size_t k = 0; k < finer.size(); ++k) {
      const auto model_cut = finer[k].model(config, static_cast<int>(st));
      EXPECT_EQ(exact_points_outside(model, whole.grid(), model_cut), 0)
          << what << " cut " << k << ", state " << st;
      for (std::size_t v = 0; v < model_cut.size(); ++v) differ += model_cut[v] != model_whole[v];
    }
  }
  return differ;
}

// The hand cases of triangulation_test.cpp: the slab below the voxel with its
// faces cut 4 × 4 (the cut frees voxels the uncut faces block), the prism with one sliver (no
// culling: back faces block voxels the culled prism leaves free). Both models hold the exact one.
TEST(TriangulationExact, HandCasesBothModelsHoldTheExactModel) {
  const core::CameraConfig config{camera_at(Vec3(0, 0, 0), 0, 0)};
  const core::Scene slab = slab_scene();
  const core::Scene slab_cut =
      cut_every_object(slab, [](const core::TriangleMesh& m) { return subdivide(m, 4); });
  EXPECT_GT(expect_models_hold_exact(slab, {slab_cut}, config, "slab"), 0);
  const core::Scene prism = prism_scene();
  core::Scene sliver = prism;
  split_inside(sliver.static_obstacles[0].mesh, 0, {1e-11, 0.5, 0.5 - 1e-11});
  expect_models_hold_exact(prism, {sliver}, config, "prism");
}

// Two random scenes (boxes and tetrahedra; static, dynamic and target solids; 4 states; 6
// cameras looking at targets, which leave 2–35 % of the 12 × 9 × 9 voxels outside the model)
// with every face of every solid cut regularly (3 × 3), by random splits and by sliver splits.
TEST(TriangulationExact, RandomScenesCutThreeWaysHoldTheExactModel) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int differ = 0;
  for (int s = 0; s < 2; ++s) {
    core::Scene scene = random_scene(rng, {12, 9, 9});
    scene.cameras.resize(6);
    core::CameraConfig config = random_config(rng, scene);
    for (core::CameraSetting& camera : config) {
      const auto& targets = scene.time_steps[0].events[0].targets;
      const Vec3 d = targets[static_cast<int>(2 * unit(rng))].bounds.center() - camera.position;
      camera.yaw = std::atan2(d.y(), d.x());
      camera.pitch = std::atan2(d.z(), std::hypot(d.x(), d.y()));
    }
    std::vector<core::Scene> cuts;
    cuts.push_back(
        cut_every_object(scene, [](const core::TriangleMesh& m) { return subdivide(m, 3); }));
    for (bool slivers : {false, true}) {
      cuts.push_back(cut_every_object(
          scene, [&](const core::TriangleMesh& m) { return random_splits(m, rng, 40, slivers); }));
    }
    const std::string what = "random scene " + std::to_string(s);
    differ += expect_models_hold_exact(scene, cuts, config, what.c_str());
  }
  std::printf("model voxels where a cut version differs: %d\n", differ);
}

}  // namespace
}  // namespace camplace::testing
