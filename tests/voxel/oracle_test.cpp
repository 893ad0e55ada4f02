// The voxel labeller against the brute-force reference (tests/support/reference.cpp) on random
// scenes and configurations: every object kind, FOV shape, range and dynamic mode.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "reference.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using voxel::Label;
using voxel::LabelMode;
constexpr int kScenes = 12;

struct LabelTally {
  long compared = 0, ties = 0;
  std::array<long, 3> by_label{};  ///< compared labels by the reference's label
};

// Every label of `mode` against the brute-force reference of that mode: center mode the ray
// through the voxel centre (reference_label), conservative mode every triangle's cone against
// the whole voxel box by LP duality, the FOV on the 8 corners (reference_box_label); no culling,
// bins or blocks. `make_scene` and `make_config` draw each scene and configuration; ties (the
// reference's margin) are skipped and counted.
template <class MakeScene, class MakeConfig>
void compare_labels_with_reference(std::mt19937& rng, int scenes, LabelMode mode,
                                   const MakeScene& make_scene, const MakeConfig& make_config,
                                   LabelTally& tally) {
  for (int s = 0; s < scenes; ++s) {
    const core::Scene scene = make_scene(rng);
    const voxel::VoxelEvaluator evaluator(scene, {mode, {0, 0, 0}});
    const core::CameraConfig config = make_config(rng, scene);
    const auto all_states = core::states(scene);
    for (std::size_t st = 0; st < all_states.size(); ++st) {
      const int h = all_states[st].time_step, l = all_states[st].event;
      for (int c = 0; c < scene.cameras.count; ++c) {
        const auto labels = evaluator.labels(config[c], static_cast<int>(st), c);
        for (int v = 0; v < evaluator.grid().count(); ++v) {
          const voxel::Grid& grid = evaluator.grid();
          const ReferenceLabel ref =
              mode == LabelMode::center
                  ? reference_label(scene, h, l, config[c], grid.voxel_center(v), 1e-7, c)
                  : reference_box_label(scene, h, l, config[c], grid.voxel_box(v), 1e-7, c);
          if (ref.ambiguous) {
            ++tally.ties;
            continue;
          }
          ++tally.compared;
          ++tally.by_label[static_cast<int>(ref.label)];
          ASSERT_EQ(labels[v], ref.label)
              << "scene " << s << " state " << st << " camera " << c << " voxel " << v;
        }
      }
    }
  }
}

core::Scene small_random_scene(std::mt19937& rng) { return random_scene(rng, {12, 9, 9}); }

TEST(Oracle, CenterLabelsEqualReferenceAtVoxelCentres) {
  std::mt19937 rng(20261123);
  LabelTally t;
  compare_labels_with_reference(rng, kScenes, LabelMode::center, small_random_scene, random_config,
                                t);
  EXPECT_GT(t.compared, 100 * t.ties);  // ties are rare; the comparison is not vacuous
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

TEST(Oracle, ConservativeLabelsEqualBoxReference) {
  std::mt19937 rng(20261129);
  LabelTally t;
  compare_labels_with_reference(rng, kScenes, LabelMode::conservative, small_random_scene,
                                random_config, t);
  EXPECT_GT(t.compared, 100 * t.ties);
  for (long n : t.by_label) EXPECT_GT(n, 500);  // every label occurs often: not vacuous
}

// Fine meshes: a chunk of states holds far more slots than a few per bin of the grid's
// resolution (at most 8 × 8 bins here, 12 objects of 400 triangles), so the labeller's bins get
// finer (camera_setup); every label still equals the reference's. One scene per mode: the
// reference is slow on 4,800 triangles under the sanitizers.
core::Scene fine_random_scene(std::mt19937& rng) {
  return with_fine_meshes(random_scene(rng, {8, 6, 6}), 400);
}

TEST(Oracle, FineMeshLabelsEqualReferenceInBothModes) {
  for (LabelMode mode : {LabelMode::center, LabelMode::conservative}) {
    std::mt19937 rng(20261203);
    LabelTally t;
    compare_labels_with_reference(rng, 1, mode, fine_random_scene, random_config, t);
    EXPECT_GT(t.compared, 100 * t.ties);
    EXPECT_GT(t.by_label[static_cast<int>(Label::free)], 50);  // not vacuous
    EXPECT_GT(t.by_label[static_cast<int>(Label::undetectable)], 50);
  }
}

// Cameras near the objects of fine meshes: just outside a surface looking at it, along it
// (grazing) or away, and inside objects; mixed camera models with near planes and rolls. The
// labeller rules out or accepts whole clusters of triangles per camera (back-facing, facing and
// in front, beyond a box, outside a box's or ray's projection, projected on first use); here the
// clusters straddle the FOV's edges, the near plane and the camera's plane.
core::CameraConfig cameras_near_objects(std::mt19937& rng, const core::Scene& scene) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<const core::SceneObject*> objects;
  for (const auto& o : scene.static_obstacles) objects.push_back(&o);
  for (const auto& step : scene.time_steps) {
    for (const auto& o : step.dynamic_obstacles) objects.push_back(&o);
    for (const auto& event : step.events) {
      for (const auto& o : event.targets) objects.push_back(&o);
    }
  }
  core::CameraConfig config;
  for (int i = 0; i < scene.cameras.count; ++i) {
    const core::SceneObject& o = *objects[static_cast<std::size_t>(unit(rng) * objects.size())];
    const auto& vertices = o.mesh.vertices;
    const core::Vec3 v = vertices[static_cast<std::size_t>(unit(rng) * vertices.size())];
    const core::Vec3 center = o.bounds.center();
    core::Vec3 out = (v - center).normalized();
    // Inside, just outside (a camera within rounding of the surface is blind: SPEC §3.3), farther
    // out.
    const double offsets[] = {-0.05, 1e-4, 0.003, 0.05, 0.4};
    core::Vec3 p = v + offsets[static_cast<int>(unit(rng) * 5)] * out;
    if (i % 2 == 1) {
      // Anywhere, looking at the object (its silhouette's clusters face the camera both ways).
      p = scene.area.min +
          scene.area.size().cwiseProduct(core::Vec3(unit(rng), unit(rng), unit(rng)));
      out = (p - center).normalized();
    }
    p = p.cwiseMax(scene.area.min).cwiseMin(scene.area.max);
    // Toward the object's centre, along its surface, or away, each turned a little.
    core::Vec3 d = -out;
    const double kind = unit(rng);
    if (kind > 0.6) d = out.cross(core::Vec3(unit(rng), unit(rng), unit(rng))).normalized();
    if (kind > 0.9) d = out;
    d = (d + 0.2 * core::Vec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5)).normalized();
    constexpr double kToDeg = 180.0 / core::kPi;
    config.push_back(camera_at(p, std::atan2(d.y(), d.x()) * kToDeg,
                               std::asin(std::clamp(d.z(), -1.0, 1.0)) * kToDeg));
  }
  randomize_rolls(rng, config);
  return config;
}

core::Scene fine_scene_mixed_cameras(std::mt19937& rng) {
  core::Scene scene = with_fine_meshes(random_scene(rng, {8, 6, 6}), 300);
  randomize_camera_models(rng, scene);
  return scene;
}

TEST(Oracle, FineMeshLabelsFromCamerasNearObjectsEqualReference) {
  for (LabelMode mode : {LabelMode::center, LabelMode::conservative}) {
    std::mt19937 rng(20261204);
    LabelTally t;
    compare_labels_with_reference(rng, 2, mode, fine_scene_mixed_cameras, cameras_near_objects, t);
    EXPECT_GT(t.compared, 100 * t.ties);
    EXPECT_GT(t.by_label[static_cast<int>(Label::free)], 50);  // not vacuous
    EXPECT_GT(t.by_label[static_cast<int>(Label::undetectable)], 50);
    EXPECT_GT(t.by_label[static_cast<int>(Label::occupied)], 20);
  }
}

// Two large solids of fine meshes (deep trees over their clusters: camera set-up rules out whole
// subtrees as back faces, or as facing the camera and projecting outside the FOV) and cameras on,
// just above and along their surfaces, inside them and looking at them from anywhere, with wide
// frusta: subtrees straddle the camera's plane, the FOV's edges and the near plane, and patches
// of the surface in front of the camera are seen at grazing angles just ahead of it. Every label
// of both modes equals the brute-force reference's, which tests every triangle.
core::Scene two_large_solids(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const core::Box3 area{core::Vec3(0, 0, 0), core::Vec3(4, 3, 3)};
  // A flat table-like target and an upright obstacle beside it.
  const core::Vec3 lo(0.4 + 0.4 * unit(rng), 0.3 + 0.3 * unit(rng), 0.5 + 0.4 * unit(rng));
  const core::Box3 table{lo, lo + core::Vec3(2.2, 1.8, 0.25 + 0.2 * unit(rng))};
  const core::Box3 post{core::Vec3(3.1, 0.8, 0.0), core::Vec3(3.7, 2.2, 2.6)};
  const core::SceneObject robot =
      box_object("robot", core::Vec3(0.2, 2.5, 0.0), core::Vec3(0.6, 2.9, 1.2));
  core::Scene scene =
      simple_scene(area, {12, 9, 9}, 4, 45.0, {robot}, {ellipsoid_object("table", table, 1800)});
  scene.time_steps[0].dynamic_obstacles.push_back(robot);
  scene.static_obstacles.push_back(ellipsoid_object("post", post, 1200));
  randomize_camera_models(rng, scene);
  for (core::CameraModel& m : scene.cameras.models) {
    // Wide frusta see the surface just ahead of a camera on it.
    m.fov = core::FovShape::frustum;
    m.horizontal = (120.0 + 50.0 * unit(rng)) * core::kPi / 180.0;
    m.vertical = (100.0 + 60.0 * unit(rng)) * core::kPi / 180.0;
  }
  return scene;
}

core::CameraConfig cameras_on_surfaces(std::mt19937& rng, const core::Scene& scene) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const core::SceneObject& table = scene.time_steps[0].events[0].targets[0];
  const core::SceneObject& post = scene.static_obstacles[0];
  core::CameraConfig config;
  constexpr double kToDeg = 180.0 / core::kPi;
  for (int i = 0; i < scene.cameras.count; ++i) {
    const double kind = unit(rng);
    const core::SceneObject& o = kind < 0.7 ? table : post;
    const auto& vertices = o.mesh.vertices;
    const core::Vec3 v = vertices[static_cast<std::size_t>(unit(rng) * vertices.size())];
    // The outward normal of the ellipsoid at v.
    const core::Vec3 half = 0.5 * o.bounds.size();
    const core::Vec3 n =
        (v - o.bounds.center()).cwiseQuotient(half.cwiseProduct(half)).normalized();
    const double offsets[] = {-0.03, 3e-3, 0.05, 0.15, 0.3};
    const core::Vec3 p = v + offsets[static_cast<int>(unit(rng) * 5)] * n;
    // Along the surface (turned a little toward or away from it), or at it.
    core::Vec3 d =
        n.cross(core::Vec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5)).normalized();
    d = (d - 0.8 * unit(rng) * n).normalized();
    if (unit(rng) < 0.2) d = -n;
    config.push_back(camera_at(p.cwiseMax(scene.area.min).cwiseMin(scene.area.max),
                               std::atan2(d.y(), d.x()) * kToDeg,
                               std::asin(std::clamp(d.z(), -1.0, 1.0)) * kToDeg));
  }
  randomize_rolls(rng, config);
  return config;
}

TEST(Oracle, LargeSolidsLabelsFromCamerasOnTheirSurfacesEqualReference) {
  for (LabelMode mode : {LabelMode::center, LabelMode::conservative}) {
    std::mt19937 rng(20261205);
    LabelTally t;
    compare_labels_with_reference(rng, 3, mode, two_large_solids, cameras_on_surfaces, t);
    // Conservative mode: ~3 % of the boxes touch a surface within the reference's margin.
    EXPECT_GT(t.compared, 20 * t.ties);
    EXPECT_GT(t.by_label[static_cast<int>(Label::free)], 100);  // not vacuous
    EXPECT_GT(t.by_label[static_cast<int>(Label::undetectable)], 100);
    EXPECT_GT(t.by_label[static_cast<int>(Label::occupied)], 100);
  }
}

// A thread's per-camera tables serve every evaluator it runs, of either mode: fine meshes, so
// that center mode tests rays against groups before projecting them, evaluated after and
// between conservative evaluations on the same thread give what they give alone.
TEST(Oracle, EvaluatorsOfBothModesOnOneThreadGiveTheirOwnResults) {
  std::mt19937 rng(20261206);
  const core::Scene scene = with_fine_meshes(random_scene(rng, {8, 6, 6}), 600);
  const core::CameraConfig config = random_config(rng, scene);
  const voxel::VoxelEvaluator conservative(scene, {LabelMode::conservative, {0, 0, 0}});
  const voxel::VoxelEvaluator center(scene, {LabelMode::center, {0, 0, 0}});
  const double conservative_err = conservative.evaluate(config).err;
  const double center_err = center.evaluate(config).err;
  for (int round = 0; round < 2; ++round) {
    EXPECT_EQ(conservative.evaluate(config).err, conservative_err);
    EXPECT_EQ(center.evaluate(config).err, center_err);
  }
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

// Mixed camera models (frusta, pyramids, cones, near and far planes) with random roll.
// Center mode labels every voxel centre as the reference does; conservative mode's free voxels
// are free at sampled points (conservative stays conservative); with refinement the model still
// holds every sampled point the reference finds in M.
core::Scene frustum_scene(std::mt19937& rng) {
  core::Scene scene = random_scene(rng, {12, 9, 9});
  randomize_camera_models(rng, scene);
  return scene;
}

core::CameraConfig rolled_config(std::mt19937& rng, const core::Scene& scene) {
  core::CameraConfig config = random_config(rng, scene);
  randomize_rolls(rng, config);
  return config;
}

TEST(Oracle, FrustaWithRollCenterLabelsEqualReference) {
  std::mt19937 rng(1414);
  LabelTally t;
  compare_labels_with_reference(rng, 8, LabelMode::center, frustum_scene, rolled_config, t);
  EXPECT_GT(t.compared, 100 * t.ties);
  // The frusta see something: not vacuous.
  EXPECT_GT(
      t.by_label[static_cast<int>(Label::free)] + t.by_label[static_cast<int>(Label::occupied)],
      1000);
}

TEST(Oracle, FrustaWithRollConservativeFreeVoxelsAreFree) {
  std::mt19937 rng(1415);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  long free_voxels = 0;
  for (int s = 0; s < 8; ++s) {
    const core::Scene scene = frustum_scene(rng);
    const voxel::VoxelEvaluator evaluator(scene, {LabelMode::conservative, {0, 0, 0}});
    const core::CameraConfig config = rolled_config(rng, scene);
    const auto all_states = core::states(scene);
    for (std::size_t st = 0; st < all_states.size(); ++st) {
      for (int c = 0; c < scene.cameras.count; ++c) {
        const auto labels = evaluator.labels(config[c], static_cast<int>(st), c);
        for (int v = 0; v < evaluator.grid().count(); ++v) {
          if (labels[v] != Label::free) continue;
          ++free_voxels;
          const core::Box3 box = evaluator.grid().voxel_box(v);
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
            const ReferenceLabel ref = reference_label(scene, all_states[st].time_step,
                                                       all_states[st].event, config[c], p, 1e-7, c);
            ASSERT_TRUE(ref.ambiguous || ref.label == Label::free)
                << "scene " << s << " state " << st << " camera " << c << " voxel " << v
                << " point " << p.transpose();
          }
        }
      }
    }
  }
  EXPECT_GT(free_voxels, 500);
}

TEST(Oracle, FrustaWithRollConservativeLabelsEqualBoxReference) {
  std::mt19937 rng(1417);
  LabelTally t;
  compare_labels_with_reference(rng, 8, LabelMode::conservative, frustum_scene, rolled_config, t);
  EXPECT_GT(t.compared, 100 * t.ties);
  for (long n : t.by_label) EXPECT_GT(n, 500);
}

TEST(Oracle, FrustaWithRollRefinedModelHoldsEveryReferenceModelPoint) {
  std::mt19937 rng(1416);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  long in_model = 0;
  for (int s = 0; s < 4; ++s) {
    core::Scene scene = frustum_scene(rng);
    scene.plausibility = {};
    voxel::VoxelOptions options{LabelMode::conservative, {0, 0, 0}};
    options.refine = 2;
    const voxel::VoxelEvaluator evaluator(scene, options);
    const core::CameraConfig config = rolled_config(rng, scene);
    const auto all_states = core::states(scene);
    const voxel::Grid cells = evaluator.leaf_grid();
    for (std::size_t st = 0; st < all_states.size(); ++st) {
      const auto model = evaluator.leaf_model(config, static_cast<int>(st));
      const auto& step = scene.time_steps[all_states[st].time_step];
      for (int i = 0; i < 300; ++i) {
        const core::Vec3 p =
            scene.area.min +
            core::Vec3(unit(rng), unit(rng), unit(rng)).cwiseProduct(scene.area.size());
        bool ambiguous = false, non_free = true;
        for (int c = 0; c < scene.cameras.count; ++c) {
          const ReferenceLabel ref = reference_label(scene, all_states[st].time_step,
                                                     all_states[st].event, config[c], p, 1e-7, c);
          ambiguous |= ref.ambiguous;
          non_free = non_free && ref.label != Label::free;
        }
        bool in_obstacle = false;
        for (const auto& o : scene.static_obstacles) in_obstacle |= reference_inside(o.mesh, p);
        for (const auto& o : step.dynamic_obstacles) in_obstacle |= reference_inside(o.mesh, p);
        if (ambiguous || !non_free || in_obstacle) continue;
        ++in_model;
        std::array<int, 3> ijk{};
        for (int k = 0; k < 3; ++k) {
          ijk[k] = std::clamp(int(std::floor((p[k] - scene.area.min[k]) / cells.step[k])), 0,
                              cells.n[k] - 1);
        }
        EXPECT_TRUE(model[ijk[0] + cells.n[0] * (ijk[1] + cells.n[1] * ijk[2])])
            << "scene " << s << " state " << st << " point " << p.transpose();
      }
    }
  }
  EXPECT_GT(in_model, 100);
}

}  // namespace
}  // namespace camplace::testing
