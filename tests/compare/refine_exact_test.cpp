// Adaptive refinement (VoxelOptions::refine) against the exact pipeline, an
// independent implementation (CGAL Nef polyhedra): the refined conservative model contains the
// exact model (compare::compare_voxel_exact checks it on the finest cells) and never
// over-estimates d(C, M), and on paper_basic's corners configuration it is within one finest
// cell's diagonal of the exact distance in every state. Nef-heavy: label `slow`.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <string>

#include "camplace/compare/voxel_vs_exact.hpp"
#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/exact/evaluator.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "model_containment.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

const std::string kPaperBasic = std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic.json";
const std::string kCorners = std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic_corners.json";

TEST(RefineExact, PaperBasicCornersWithinOneCellDiagonalAndConservative) {
  const core::Scene scene = core::load_scene(kPaperBasic);
  const core::CameraConfig config = core::load_camera_config(kCorners, scene);
  compare::CompareOptions options;
  options.refine_levels = {1, 3};
  const compare::CompareResult result = compare::compare_voxel_exact(scene, config, options);
  EXPECT_EQ(result.conservative_violations, 0);
  int refined_rows = 0;
  for (const compare::CompareRow& row : result.rows) {
    if (row.refine == 0) continue;
    ++refined_rows;
    const std::string where = "refine " + std::to_string(row.refine) + " state (" +
                              std::to_string(row.time_step) + ", " + std::to_string(row.event) +
                              ")";
    EXPECT_EQ(row.exact_outside, 0) << where;
    EXPECT_LE(row.d_voxel, row.d_exact + 1e-9) << where;
    EXPECT_NEAR(row.cell_diagonal, row.voxel_diagonal / (1 << row.refine), 1e-12) << where;
    if (row.refine == 3) {
      EXPECT_LE(std::abs(row.d_voxel - row.d_exact), row.cell_diagonal) << where;
    }
  }
  EXPECT_EQ(refined_rows, 12);  // 6 states × 2 levels
}

// Random scenes (boxes and tetrahedra, masked or modelled dynamic obstacles, cone or pyramid,
// with or without a far plane; 6 cameras, and as critical object a small box apart from the
// obstacles, so that d(C, M) is not 0) and random configurations: no conservative violation at
// 2 levels.
TEST(RefineExact, RandomScenesStayConservative) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int moved = 0;  // rows where refinement changed d(C, M): the check is not vacuous
  for (int n = 0; n < 4; ++n) {
    core::Scene scene = random_scene(rng, {8, 6, 6});
    scene.cameras.resize(6);
    for (core::TimeStep& step : scene.time_steps) {
      const core::Vec3 lo(0.2 + 3.4 * unit(rng), 0.2 + 2.4 * unit(rng), 0.2 + 2.4 * unit(rng));
      step.critical = {box_object("critical", lo, lo + core::Vec3::Constant(0.2))};
    }
    // Cameras at random places looking at random targets' centres (so that they carve the
    // model near the targets).
    core::CameraConfig config = random_config(rng, scene);
    for (core::CameraSetting& camera : config) {
      const auto& events = scene.time_steps[static_cast<int>(2 * unit(rng))].events;
      const auto& targets = events[static_cast<int>(2 * unit(rng))].targets;
      const core::Vec3 d =
          targets[static_cast<int>(2 * unit(rng))].bounds.center() - camera.position;
      camera.yaw = std::atan2(d.y(), d.x());
      camera.pitch = std::atan2(d.z(), std::hypot(d.x(), d.y()));
    }
    compare::CompareOptions options;
    options.refine_levels = {0, 2};
    const compare::CompareResult result = compare::compare_voxel_exact(scene, config, options);
    EXPECT_EQ(result.conservative_violations, 0) << "scene " << n;
    for (std::size_t r = 0; r < result.rows.size(); ++r) {
      const compare::CompareRow& row = result.rows[r];
      if (row.mode != "conservative") continue;
      EXPECT_EQ(row.exact_outside, 0) << "scene " << n;
      EXPECT_LE(row.d_voxel, row.d_exact + 1e-9) << "scene " << n;
      if (row.refine == 2) {
        // The unrefined row of the same state came one block of states earlier.
        const std::size_t states = result.rows.size() / 3;
        moved += result.rows[r - states].d_voxel != row.d_voxel;
      }
    }
  }
  EXPECT_GT(moved, 0);
}

// The containment check locates one centre per connected set of centres (joined by grid segments
// no boundary triangle meets) instead of every centre. Against the reference that locates every
// centre, on the voxel models of both modes (refined too) and on voxel models that lack random
// voxels or everything, where most counted voxels are found by their centres alone.
TEST(RefineExact, ContainmentByConnectedSetsEqualsLocatingEveryCentre) {
  using compare::detail::CentreLocation;
  using compare::detail::exact_outside_voxel_model;
  std::mt19937 rng(5);
  std::vector<std::pair<core::Scene, core::CameraConfig>> cases;
  {
    const core::Scene scene = core::load_scene(kPaperBasic);
    cases.emplace_back(scene, core::load_camera_config(kCorners, scene));
  }
  for (int n = 0; n < 3; ++n) {
    core::Scene scene = random_scene(rng, {8, 6, 6});
    core::CameraConfig config = random_config(rng, scene);
    cases.emplace_back(std::move(scene), std::move(config));
  }
  // Counts compared, and the voxels counted against empty voxel models (most lie wholly inside
  // the exact model and are found by their centres alone).
  int compared = 0, by_centre = 0;
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const core::Scene scene = compare::with_pyramid_fov(cases[c].first);
    const core::CameraConfig& config = cases[c].second;
    exact::ExactOptions exact_options;
    exact_options.keep_models = true;
    const exact::ExactEvaluation ex = exact::evaluate_exact(scene, config, exact_options);
    for (const auto& [mode, level] :
         std::vector<std::pair<voxel::LabelMode, int>>{{voxel::LabelMode::center, 0},
                                                       {voxel::LabelMode::conservative, 0},
                                                       {voxel::LabelMode::conservative, 2}}) {
      voxel::VoxelOptions options;
      options.mode = mode;
      options.refine = level;
      const voxel::VoxelEvaluator evaluator(scene, options);
      const voxel::Grid grid = evaluator.leaf_grid();
      const auto models = evaluator.leaf_models(config);
      for (std::size_t s = 0; s < models.size(); ++s) {
        std::vector<std::uint8_t> thinned = models[s];
        for (auto& in : thinned) in = in && rng() % 4 != 0;
        const std::vector<std::uint8_t> none(models[s].size(), 0);
        for (const std::vector<std::uint8_t>* voxel_model :
             std::array<const std::vector<std::uint8_t>*, 3>{&models[s], &thinned, &none}) {
          const int fast = exact_outside_voxel_model(ex.models[s], grid, *voxel_model);
          const int reference = exact_outside_voxel_model(ex.models[s], grid, *voxel_model,
                                                          CentreLocation::every_centre);
          EXPECT_EQ(fast, reference) << "case " << c << ", mode " << core::name_of(mode)
                                     << ", refine " << level << ", state " << s;
          ++compared;
          by_centre += voxel_model == &none ? reference : 0;
        }
      }
    }
  }
  EXPECT_GT(compared, 100);
  EXPECT_GT(by_centre, 1000);
}

}  // namespace
}  // namespace camplace::testing
