// The voxel labeller against the brute-force reference (tests/support/reference.cpp) on random
// scenes and configurations: every object kind, FOV shape, range and dynamic mode.
#include <gtest/gtest.h>

#include <random>

#include "reference.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using voxel::Label;
using voxel::LabelMode;
constexpr int kScenes = 12;

TEST(Oracle, CenterLabelsEqualReferenceAtVoxelCentres) {
  std::mt19937 rng(20261123);
  long compared = 0, ties = 0;
  for (int s = 0; s < kScenes; ++s) {
    const core::Scene scene = random_scene(rng, {12, 9, 9});
    const voxel::VoxelEvaluator evaluator(scene, {LabelMode::center, {0, 0, 0}});
    const core::CameraConfig config = random_config(rng, scene);
    const auto all_states = core::states(scene);
    for (std::size_t st = 0; st < all_states.size(); ++st) {
      for (const auto& camera : config) {
        const auto labels = evaluator.labels(camera, static_cast<int>(st));
        for (int v = 0; v < evaluator.grid().count(); ++v) {
          const ReferenceLabel ref =
              reference_label(scene, all_states[st].time_step, all_states[st].event, camera,
                              evaluator.grid().voxel_center(v));
          if (ref.ambiguous) {
            ++ties;
            continue;
          }
          ++compared;
          ASSERT_EQ(labels[v], ref.label) << "scene " << s << " state " << st << " voxel " << v;
        }
      }
    }
  }
  EXPECT_GT(compared, 100 * ties);  // ties are rare; the comparison is not vacuous
}

TEST(Oracle, ConservativeFreeVoxelsAreFreeAtSampledPoints) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  long free_voxels = 0;
  for (int s = 0; s < kScenes; ++s) {
    const core::Scene scene = random_scene(rng, {12, 9, 9});
    const voxel::VoxelEvaluator evaluator(scene, {LabelMode::conservative, {0, 0, 0}});
    const core::CameraConfig config = random_config(rng, scene);
    const auto all_states = core::states(scene);
    for (std::size_t st = 0; st < all_states.size(); ++st) {
      for (const auto& camera : config) {
        const auto labels = evaluator.labels(camera, static_cast<int>(st));
        for (int v = 0; v < evaluator.grid().count(); ++v) {
          if (labels[v] != Label::free) continue;
          ++free_voxels;
          const core::Box3 box = evaluator.grid().voxel_box(v);
          // The 27 points of a 3×3×3 lattice (corners, edge and face centres) and 8 random ones.
          std::vector<core::Vec3> points;
          for (int a = 0; a < 27; ++a) {
            points.push_back(box.min +
                             box.size().cwiseProduct(core::Vec3(a % 3, (a / 3) % 3, a / 9) / 2.0));
          }
          for (int r = 0; r < 8; ++r) {
            points.push_back(box.min +
                             box.size().cwiseProduct(core::Vec3(unit(rng), unit(rng), unit(rng))));
          }
          for (const core::Vec3& p : points) {
            const ReferenceLabel ref =
                reference_label(scene, all_states[st].time_step, all_states[st].event, camera, p);
            ASSERT_TRUE(ref.ambiguous || ref.label == Label::free)
                << "scene " << s << " state " << st << " voxel " << v << " point " << p.transpose();
          }
        }
      }
    }
  }
  EXPECT_GT(free_voxels, 1000);  // the check is not vacuous
}

TEST(Oracle, ConservativeModelContainsCenterModel) {
  std::mt19937 rng(99);
  for (int s = 0; s < kScenes; ++s) {
    core::Scene scene = random_scene(rng, {12, 9, 9});
    scene.plausibility = {0.05, 0.5};
    const voxel::VoxelEvaluator center(scene, {LabelMode::center, {0, 0, 0}});
    const voxel::VoxelEvaluator conservative(scene, {LabelMode::conservative, {0, 0, 0}});
    const core::CameraConfig config = random_config(rng, scene);
    for (int st = 0; st < static_cast<int>(core::states(scene).size()); ++st) {
      const auto a = center.model(config, st), b = conservative.model(config, st);
      for (std::size_t v = 0; v < a.size(); ++v) {
        ASSERT_LE(a[v], b[v]) << "scene " << s << " state " << st << " voxel " << v;
      }
    }
    const auto ea = center.evaluate(config), eb = conservative.evaluate(config);
    for (std::size_t st = 0; st < ea.states.size(); ++st) {
      EXPECT_LE(eb.states[st].d_model, ea.states[st].d_model + 1e-12);
    }
  }
}

}  // namespace
}  // namespace camplace::testing
