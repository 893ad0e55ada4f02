// Obstacles and critical objects that extend beyond the area S, the random sweeps: the voxel
// labels of both modes against the brute-force references (tests/support/reference.cpp, which
// know nothing of S) with an object crossing each face of S, for each kind of obstacle, with
// cameras inside S, outside it behind the object's outside part, and inside that outside part
// (blind); the free voxels at sampled points, the lower bound and the refined model against
// their references. The hand cases are in beyond_area_test.cpp. These sweeps take seconds in a
// Release build and minutes under ASan: they are in reference_sweep_tests (label slow).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>

#include "camplace/core/distance.hpp"
#include "camplace/core/err.hpp"
#include "crossing_scene.hpp"
#include "lower_bound_reference.hpp"
#include "reference.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using core::Box3;
using core::Vec3;
using voxel::Label;
using voxel::LabelMode;
using namespace beyond;  // crossing scenes (tests/support/crossing_scene.hpp)

struct Tally {
  long compared = 0, ties = 0, decided_outside = 0;
  std::array<long, 3> by_label{};
};

/// Every voxel label of `mode` for every face × kind × `per_face` scenes against the reference
/// of that mode; also counts the labels that the parts outside S decide (the reference on the
/// scene clipped to S differs).
void compare_crossing_labels(LabelMode mode, unsigned seed, int per_face, Tally& tally) {
  std::mt19937 rng(seed);
  for (int face = 0; face < 6; ++face) {
    for (Kind kind : kKinds) {
      for (int n = 0; n < per_face; ++n) {
        const Crossing c = crossing_scene(rng, face, kind);
        const core::Scene clipped = clipped_to_area(c);
        const voxel::VoxelEvaluator evaluator(c.scene, {mode, {0, 0, 0}});
        const voxel::Grid& grid = evaluator.grid();
        const auto all_states = core::states(c.scene);
        for (std::size_t st = 0; st < all_states.size(); ++st) {
          const int h = all_states[st].time_step, l = all_states[st].event;
          for (int cam = 0; cam < c.scene.cameras.count; ++cam) {
            const auto labels = evaluator.labels(c.config[cam], static_cast<int>(st), cam);
            for (int v = 0; v < grid.count(); ++v) {
              auto reference = [&](const core::Scene& scene) {
                return mode == LabelMode::center
                           ? reference_label(scene, h, l, c.config[cam], grid.voxel_center(v), 1e-7,
                                             cam)
                           : reference_box_label(scene, h, l, c.config[cam], grid.voxel_box(v),
                                                 1e-7, cam);
              };
              const ReferenceLabel ref = reference(c.scene);
              if (ref.ambiguous) {
                ++tally.ties;
                continue;
              }
              ++tally.compared;
              ++tally.by_label[static_cast<int>(ref.label)];
              const ReferenceLabel inside_only = reference(clipped);
              if (!inside_only.ambiguous && inside_only.label != ref.label) {
                ++tally.decided_outside;
              }
              ASSERT_EQ(labels[v], ref.label)
                  << "face " << face << " " << kind_name(kind) << " scene " << n << " state " << st
                  << " camera " << cam << " at " << c.config[cam].position.transpose() << " voxel "
                  << v;
            }
          }
        }
      }
    }
  }
}

TEST(BeyondArea, CenterLabelsEqualReferenceWithObstaclesCrossingEachFace) {
  Tally t;
  compare_crossing_labels(LabelMode::center, 20261201, 3, t);
  EXPECT_GT(t.compared, 100 * t.ties);
  for (long n : t.by_label) EXPECT_GT(n, 1000);
  // The parts outside S decide many labels: clipping the obstacles to S would fail this test.
  EXPECT_GT(t.decided_outside, 1000);
}

TEST(BeyondArea, ConservativeLabelsEqualBoxReferenceWithObstaclesCrossingEachFace) {
  Tally t;
  compare_crossing_labels(LabelMode::conservative, 20261202, 3, t);
  EXPECT_GT(t.compared, 100 * t.ties);
  for (long n : t.by_label) EXPECT_GT(n, 1000);
  EXPECT_GT(t.decided_outside, 1000);
}

/// Conservative mode's free voxels are free at 35 points each (the 3×3×3 lattice and 8 random
/// points) by the point reference, which needs no culling rule: soundness on crossing scenes
/// with the scenes' cameras and random ones inside and outside S.
TEST(BeyondArea, ConservativeFreeVoxelsAreFreeAtSampledPointsWithObstaclesCrossingEachFace) {
  std::mt19937 rng(20261203);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  long free_voxels = 0;
  for (int face = 0; face < 6; ++face) {
    for (Kind kind : kKinds) {
      const Crossing c = crossing_scene(rng, face, kind);
      const voxel::VoxelEvaluator evaluator(c.scene, {LabelMode::conservative, {0, 0, 0}});
      for (const core::CameraConfig& config : {c.config, random_wide_config(rng, c.scene)}) {
        const auto all_states = core::states(c.scene);
        for (std::size_t st = 0; st < all_states.size(); ++st) {
          for (int cam = 0; cam < c.scene.cameras.count; ++cam) {
            const auto labels = evaluator.labels(config[cam], static_cast<int>(st), cam);
            for (int v = 0; v < evaluator.grid().count(); ++v) {
              if (labels[v] != Label::free) continue;
              ++free_voxels;
              const Box3 box = evaluator.grid().voxel_box(v);
              for (int a = 0; a < 35; ++a) {
                const Vec3 f = a < 27 ? Vec3(a % 3, (a / 3) % 3, a / 9) / 2.0
                                      : Vec3(unit(rng), unit(rng), unit(rng));
                const Vec3 p = box.min + box.size().cwiseProduct(f);
                const ReferenceLabel ref =
                    reference_label(c.scene, all_states[st].time_step, all_states[st].event,
                                    config[cam], p, 1e-7, cam);
                ASSERT_TRUE(ref.ambiguous || ref.label == Label::free)
                    << "face " << face << " " << kind_name(kind) << " state " << st << " camera "
                    << cam << " voxel " << v << " point " << p.transpose();
              }
            }
          }
        }
      }
    }
  }
  EXPECT_GT(free_voxels, 2000);
}

/// The conservative lower bound with occupying objects (masked dynamic obstacles) crossing S:
/// equal to the brute-force reference (tests/voxel/lower_bound_reference.hpp, every voxel, no
/// index ranges), its proven voxels in every model and no Err below it, for the scene's cameras
/// and random ones inside and outside S; also with a plausibility filter.
TEST(BeyondArea, LowerBoundEqualsReferenceAndHoldsWithObjectsCrossingEachFace) {
  std::mt19937 rng(20261204);
  long proven_total = 0;
  for (int face = 0; face < 6; ++face) {
    for (Kind kind : kKinds) {
      Crossing c = crossing_scene(rng, face, kind);
      if (face % 2 == 1) c.scene.plausibility = {0.02, 0.3};
      const voxel::VoxelEvaluator evaluator(c.scene, {LabelMode::conservative, {0, 0, 0}});
      const double bound = evaluator.err_lower_bound();
      const std::string what = "face " + std::to_string(face) + " " + kind_name(kind);
      EXPECT_EQ(bound, reference_lower_bound(c.scene, evaluator.grid())) << what;
      const auto proven = reference_proven_voxels(c.scene, evaluator.grid());
      std::vector<core::CameraConfig> configs{c.config};
      for (int n = 0; n < 4; ++n) configs.push_back(random_wide_config(rng, c.scene));
      for (const core::CameraConfig& config : configs) {
        EXPECT_GE(core::lower_bound_threshold(evaluator.err(config)), bound) << what;
        for (std::size_t s = 0; s < proven.size(); ++s) {
          const auto model = evaluator.model(config, static_cast<int>(s));
          for (int v = 0; v < evaluator.grid().count(); ++v) {
            if (!proven[s][v]) continue;
            ++proven_total;
            ASSERT_EQ(model[v], 1) << what << " state " << s << " voxel " << v;
          }
        }
      }
    }
  }
  EXPECT_GT(proven_total, 1000);
}

/// Refinement (2 levels) with obstacles crossing each face: every point of S that no camera sees
/// free by the point reference and that lies in no obstacle is in a finest cell of the refined
/// model (no plausibility filter), and the refined model lies in the unrefined one.
TEST(BeyondArea, RefinedModelHoldsEveryReferenceModelPointWithObstaclesCrossingEachFace) {
  std::mt19937 rng(20261205);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  long in_model = 0;
  for (int face = 0; face < 6; ++face) {
    for (Kind kind : kKinds) {
      const Crossing c = crossing_scene(rng, face, kind);
      voxel::VoxelOptions options{LabelMode::conservative, {0, 0, 0}};
      options.refine = 2;
      const voxel::VoxelEvaluator refined(c.scene, options);
      const voxel::VoxelEvaluator base(c.scene, {LabelMode::conservative, {0, 0, 0}});
      const voxel::Grid cells = refined.leaf_grid();
      const auto all_states = core::states(c.scene);
      for (const core::CameraConfig& config : {c.config, random_wide_config(rng, c.scene)}) {
        for (std::size_t st = 0; st < all_states.size(); ++st) {
          const auto model = refined.leaf_model(config, static_cast<int>(st));
          const auto coarse = base.model(config, static_cast<int>(st));
          const auto refined_base = refined.model(config, static_cast<int>(st));
          for (std::size_t v = 0; v < coarse.size(); ++v) {
            ASSERT_LE(refined_base[v], coarse[v]) << "face " << face << " voxel " << v;
          }
          const auto& step = c.scene.time_steps[all_states[st].time_step];
          for (int i = 0; i < 150; ++i) {
            const Vec3 p =
                kArea.min + Vec3(unit(rng), unit(rng), unit(rng)).cwiseProduct(kArea.size());
            bool ambiguous = false, non_free = true;
            for (int cam = 0; cam < c.scene.cameras.count; ++cam) {
              const ReferenceLabel ref =
                  reference_label(c.scene, all_states[st].time_step, all_states[st].event,
                                  config[cam], p, 1e-7, cam);
              ambiguous |= ref.ambiguous;
              non_free = non_free && ref.label != Label::free;
            }
            bool in_obstacle = false;
            for (const auto& o : c.scene.static_obstacles)
              in_obstacle |= reference_inside(o.mesh, p);
            for (const auto& o : step.dynamic_obstacles) in_obstacle |= reference_inside(o.mesh, p);
            if (ambiguous || !non_free || in_obstacle) continue;
            ++in_model;
            std::array<int, 3> ijk{};
            for (int k = 0; k < 3; ++k) {
              ijk[k] = std::clamp(int(std::floor((p[k] - kArea.min[k]) / cells.step[k])), 0,
                                  cells.n[k] - 1);
            }
            EXPECT_TRUE(model[ijk[0] + cells.n[0] * (ijk[1] + cells.n[1] * ijk[2])])
                << "face " << face << " " << kind_name(kind) << " state " << st << " point "
                << p.transpose();
          }
        }
      }
    }
  }
  EXPECT_GT(in_model, 500);
}

}  // namespace
}  // namespace camplace::testing
