// The fast labeller against the labeller it replaced (tests/support/
// legacy_labeller.cpp, a verbatim copy): every label and every model over random scenes and
// configurations, both modes. Center mode must agree everywhere (ties at exact boundaries aside:
// the brute-force reference flags them); conservative mode may only turn a voxel the old
// labeller proved free into a non-free one, never the reverse.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "camplace/core/distance.hpp"
#include "camplace/core/err.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/sensor_model.hpp"
#include "camplace/voxel/components.hpp"
#include "legacy_labeller.hpp"
#include "lower_bound_reference.hpp"
#include "reference.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using voxel::Label;
using voxel::LabelMode;

struct Tally {
  long compared = 0, differing = 0;
};

// Compares labels and filtered models of one scene and configuration, adding to `tally`
// (void: gtest's ASSERT_* return from it.)
void compare_all(const core::Scene& scene, const core::CameraConfig& config, LabelMode mode,
                 std::array<int, 3> resolution, const std::string& what, Tally& tally) {
  const voxel::VoxelEvaluator fast(scene, {mode, resolution});
  const LegacyLabeller old(scene, {mode, resolution});
  const auto all_states = core::states(scene);
  for (std::size_t st = 0; st < all_states.size(); ++st) {
    for (const auto& camera : config) {
      const auto a = old.labels(camera, static_cast<int>(st));
      const auto b = fast.labels(camera, static_cast<int>(st));
      EXPECT_EQ(a.size(), b.size());
      for (std::size_t v = 0; v < a.size(); ++v) {
        ++tally.compared;
        if (a[v] == b[v]) continue;
        ++tally.differing;
        if (mode == LabelMode::conservative) {
          // Toward non-free only.
          ASSERT_EQ(a[v], Label::free) << what << " state " << st << " voxel " << v;
          continue;
        }
        // Center mode: only at a tie of the voxel centre (the reference says where).
        const ReferenceLabel ref =
            reference_label(scene, all_states[st].time_step, all_states[st].event, camera,
                            fast.grid().voxel_center(static_cast<int>(v)));
        ASSERT_TRUE(ref.ambiguous) << what << " state " << st << " voxel " << v << " old "
                                   << static_cast<int>(a[v]) << " new " << static_cast<int>(b[v]);
      }
    }
  }
  const auto raw = old.raw_models(config);
  for (std::size_t st = 0; st < all_states.size(); ++st) {
    std::vector<std::uint8_t> expected = raw[st];
    voxel::filter_components(expected, old.grid(), scene.plausibility);
    const auto got = fast.model(config, static_cast<int>(st));
    ASSERT_EQ(expected.size(), got.size());
    for (std::size_t v = 0; v < got.size(); ++v) {
      if (expected[v] == got[v]) continue;
      ++tally.differing;
      if (mode == LabelMode::conservative) {
        ASSERT_EQ(got[v], 1) << what << " state " << st << " model voxel " << v;
      }
    }
  }
}

TEST(LegacyEquivalence, EveryLabelAndModelOnRandomScenesMatchesTheOldLabeller) {
  std::mt19937 rng(11);
  for (LabelMode mode : {LabelMode::center, LabelMode::conservative}) {
    Tally total;
    for (int s = 0; s < 10 && !HasFatalFailure(); ++s) {
      const core::Scene scene = random_scene(rng, {12, 9, 9});
      const core::CameraConfig config = random_config(rng, scene);
      const std::array<int, 3> resolution{10 + s % 3 * 3, 8 + s % 2 * 3, 7 + s % 4};
      compare_all(scene, config, mode, resolution,
                  std::string(core::name_of(mode)) + " scene " + std::to_string(s), total);
    }
    EXPECT_GT(total.compared, 100000);
    // The fast labeller runs the same exact tests on fewer candidates: differences would come
    // only from rounding at exact boundaries, so they must be (nearly) absent.
    EXPECT_LE(total.differing * 10000, total.compared) << core::name_of(mode);
  }
}

TEST(LegacyEquivalence, PaperSceneCornersAndRandomConfigurations) {
  const core::Scene scene =
      core::load_scene(std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic.json");
  std::vector<core::CameraConfig> configs{core::load_camera_config(
      std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic_corners.json", scene)};
  std::mt19937 rng(5);
  configs.push_back(random_config(rng, scene));
  for (LabelMode mode : {LabelMode::center, LabelMode::conservative}) {
    for (const auto& config : configs) {
      Tally t;
      compare_all(scene, config, mode, {16, 12, 12}, "paper_basic", t);
      EXPECT_EQ(t.differing, 0) << core::name_of(mode);
    }
  }
}

// d(C, M) and the conservative lower bound of Err by the formulas of the previous evaluator
// (core::box_solid_sq_distance / point_solid_sq_distance on every voxel): the same doubles.
TEST(LegacyEquivalence, DistancesAndLowerBoundEqualTheCoreFormulas) {
  std::mt19937 rng(17);
  for (int s = 0; s < 6; ++s) {
    const core::Scene scene = random_scene(rng, {12, 9, 9});
    const core::CameraConfig config = random_config(rng, scene);
    const auto all_states = core::states(scene);
    for (LabelMode mode : {LabelMode::center, LabelMode::conservative}) {
      const voxel::VoxelEvaluator evaluator(scene, {mode, {0, 0, 0}});
      const voxel::Grid& grid = evaluator.grid();
      const bool conservative = mode == LabelMode::conservative;
      const auto result = evaluator.evaluate(config);
      for (std::size_t st = 0; st < all_states.size(); ++st) {
        const core::TimeStep& step = scene.time_steps[all_states[st].time_step];
        std::vector<double> critical(grid.count(), std::numeric_limits<double>::infinity());
        for (int v = 0; v < grid.count(); ++v) {
          for (const core::SceneObject& c : step.critical) {
            critical[v] = std::min(
                critical[v], conservative
                                 ? core::box_solid_sq_distance(c.mesh, grid.voxel_box(v))
                                 : core::point_solid_sq_distance(c.mesh, grid.voxel_center(v)));
          }
        }
        const auto model = evaluator.model(config, static_cast<int>(st));
        double best = std::numeric_limits<double>::infinity();
        for (int v = 0; v < grid.count(); ++v) {
          if (model[v]) best = std::min(best, critical[v]);
        }
        const double expected =
            std::isinf(best) ? core::empty_model_distance(scene.area) : std::sqrt(best);
        EXPECT_EQ(result.states[st].d_model, expected) << "scene " << s << " state " << st;
      }
      // The lower bound: the brute-force reference (lower_bound_reference.hpp).
      EXPECT_EQ(evaluator.err_lower_bound(),
                conservative ? reference_lower_bound(scene, grid) : 0.0)
          << "scene " << s;
    }
  }
}

TEST(LegacyEquivalence, MoreThan64StatesAreHandledInChunks) {
  // States are processed 64 at a time (bit masks): 2 steps × 35 events, the events' targets
  // cycling through the random scene's.
  std::mt19937 rng(31);
  core::Scene scene = random_scene(rng, {10, 8, 8});
  for (core::TimeStep& step : scene.time_steps) {
    const std::vector<core::Event> events = step.events;
    step.events.clear();
    for (int l = 0; l < 35; ++l) step.events.push_back(events[l % events.size()]);
  }
  ASSERT_EQ(core::states(scene).size(), 70u);
  const core::CameraConfig config = random_config(rng, scene);
  for (LabelMode mode : {LabelMode::center, LabelMode::conservative}) {
    Tally t;
    compare_all(scene, config, mode, {10, 8, 8}, "70 states", t);
    EXPECT_EQ(t.differing, 0) << core::name_of(mode);
  }
}

TEST(LegacyEquivalence, EqualObjectsOfSeveralStatesKeepEachStatesLabels) {
  // Conservative mode tests an object that several states hold (the same role, equal meshes)
  // once for all of them (voxel/src/setup.cpp): here the events repeat in both time steps, and
  // step 0's dynamic obstacle, occluding (modelled mode), comes back as a target (occupying) in
  // step 1, which must not be shared.
  std::mt19937 rng(41);
  for (int s = 0; s < 3; ++s) {
    core::Scene scene = random_scene(rng, {12, 9, 9});
    scene.dynamic_mode = core::DynamicMode::modelled;
    ASSERT_EQ(scene.time_steps.size(), 2u);
    core::TimeStep& second = scene.time_steps[1];
    second.events = scene.time_steps[0].events;
    second.events[0].targets.push_back(scene.time_steps[0].dynamic_obstacles.at(0));
    const core::CameraConfig config = random_config(rng, scene);
    for (LabelMode mode : {LabelMode::center, LabelMode::conservative}) {
      Tally t;
      compare_all(scene, config, mode, {12, 9, 9}, "scene " + std::to_string(s), t);
      EXPECT_EQ(t.differing, 0) << core::name_of(mode) << " scene " << s;
    }
  }
}

/// `scene` with `steps` time steps that repeat its first ones in turn, each step's dynamic
/// obstacles, critical objects and targets moved by their own random offsets (up to `reach` in x
/// and y, half of it in z): copies of a mesh moved a little between time steps. With `keep_first`,
/// the first time steps stay as they are and the copies follow them.
core::Scene with_moved_copies(std::mt19937& rng, core::Scene scene, int steps, double reach,
                              bool keep_first) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  auto move = [&](core::SceneObject& object) {
    const core::Vec3 offset(reach * unit(rng), reach * unit(rng), 0.5 * reach * unit(rng));
    for (core::Vec3& v : object.mesh.vertices) v += offset;
    object.bounds.min += offset;
    object.bounds.max += offset;
  };
  const std::vector<core::TimeStep> first = scene.time_steps;
  if (!keep_first) scene.time_steps.clear();
  for (int h = static_cast<int>(scene.time_steps.size()); h < steps; ++h) {
    core::TimeStep step = first[h % first.size()];
    step.t = h;
    for (core::SceneObject& o : step.dynamic_obstacles) move(o);
    for (core::SceneObject& o : step.critical) move(o);
    for (core::Event& event : step.events) {
      for (core::SceneObject& o : event.targets) move(o);
    }
    scene.time_steps.push_back(std::move(step));
  }
  return scene;
}

TEST(LegacyEquivalence, CopiesMovedBetweenTimeStepsKeepEachStatesLabels) {
  // Conservative mode tests the slot groups of copies of a mesh moved a little from one time
  // step to the next in bundles, by the bundle's bounds first (voxel/src/camera_setup.cpp): here
  // 36 time steps repeat the random scene's two with their dynamic obstacles, critical objects
  // and targets each moved by its own offset (up to 0.12 m, about a third of a voxel), in both
  // dynamic modes (occupying and occluding copies), more than 64 states (two chunks).
  std::mt19937 rng(43);
  for (int s = 0; s < 2; ++s) {
    core::Scene scene = random_scene(rng, {12, 9, 9});
    scene.dynamic_mode = s == 0 ? core::DynamicMode::masked : core::DynamicMode::modelled;
    ASSERT_EQ(scene.time_steps.size(), 2u);
    scene = with_moved_copies(rng, std::move(scene), 36, 0.12, true);
    ASSERT_GT(core::states(scene).size(), 64u);
    const core::CameraConfig config = random_config(rng, scene);
    Tally t;
    compare_all(scene, config, LabelMode::conservative, {12, 9, 9}, "scene " + std::to_string(s),
                t);
    EXPECT_EQ(t.differing, 0) << "scene " << s;
  }
}

/// What compare_with_each_state_alone counted over one scene.
struct AloneTally {
  long differing = 0;        ///< labels that differ from the state's own scene's
  long model_differing = 0;  ///< model voxels that differ
  long free = 0;             ///< free labels of the states' own scenes
  long in_model = 0, out_of_model = 0;
};

/// Every label of every state of `scene`, and every model of each camera alone (the scene's
/// cameras all at its setting; they share one model) and of all cameras, labelled with all states
/// at once, against those of the state's own scene (its time step and event only: no other
/// copies, no bundles). labels() asks for one state at a time, the models for all at once.
AloneTally compare_with_each_state_alone(const core::Scene& scene, const core::CameraConfig& config,
                                         LabelMode mode, const std::array<int, 3>& resolution) {
  AloneTally t;
  const voxel::VoxelEvaluator all(scene, {mode, resolution});
  const auto states = core::states(scene);
  std::vector<core::CameraConfig> configs;
  for (const core::CameraSetting& camera : config) configs.emplace_back(config.size(), camera);
  configs.push_back(config);
  for (std::size_t st = 0; st < states.size(); ++st) {
    core::Scene alone = scene;
    alone.time_steps = {scene.time_steps[states[st].time_step]};
    alone.time_steps[0].events = {scene.time_steps[states[st].time_step].events[states[st].event]};
    const voxel::VoxelEvaluator one(alone, {mode, resolution});
    for (const core::CameraSetting& camera : config) {
      const auto expected = one.labels(camera, 0);
      const auto got = all.labels(camera, static_cast<int>(st));
      EXPECT_EQ(expected.size(), got.size());
      for (std::size_t v = 0; v < std::min(got.size(), expected.size()); ++v) {
        t.differing += expected[v] != got[v];
        t.free += expected[v] == Label::free;
      }
    }
    for (const core::CameraConfig& cams : configs) {
      const auto expected = one.model(cams, 0);
      const auto got = all.model(cams, static_cast<int>(st));
      EXPECT_EQ(expected.size(), got.size());
      for (std::size_t v = 0; v < std::min(got.size(), expected.size()); ++v) {
        t.model_differing += expected[v] != got[v];
        (expected[v] ? t.in_model : t.out_of_model) += 1;
      }
    }
  }
  return t;
}

TEST(LegacyEquivalence, CopiesInBundlesGiveTheModelsOfEachStateAlone) {
  // Conservative mode tests copies of a mesh moved a little between time steps in bundles, for
  // all their states at once (voxel/src/camera_setup.cpp), and block clearing leaves all of a
  // bundle's states to the per-voxel tests once one copy may decide a block
  // (docs/design/labelling.md L4 step 4). A state labelled wrongly non-free passes the comparison
  // with the old labeller (culling may free voxels it did not): here every label, and every
  // camera's model of all states at once, must equal those of the state labelled alone.
  // Objects of up to 0.8 × 0.8 × 1.3 m, each moved by up to 0.08 m in each of 32 time steps,
  // occupying and occluding copies (both dynamic modes), 64 states, 4 scenes.
  std::mt19937 rng(91);
  const std::array<int, 3> resolution{12, 9, 9};
  for (int s = 0; s < 4 && !HasFailure(); ++s) {
    core::Scene scene = random_scene(rng, resolution);
    scene.dynamic_mode = s % 2 == 0 ? core::DynamicMode::masked : core::DynamicMode::modelled;
    scene.plausibility = {};
    scene = with_moved_copies(rng, std::move(scene), 32, 0.08, false);
    ASSERT_EQ(core::states(scene).size(), 64u);
    const core::CameraConfig config = random_config(rng, scene);
    const AloneTally t =
        compare_with_each_state_alone(scene, config, LabelMode::conservative, resolution);
    EXPECT_EQ(t.differing, 0) << "scene " << s;
    EXPECT_EQ(t.model_differing, 0) << "scene " << s;
    EXPECT_GT(t.free, 0) << "scene " << s;
  }
}

TEST(LegacyEquivalence, CenterLabelsAndModelsOfCopiesEqualThoseOfEachStateAlone) {
  // Center mode lists the slot groups of copies moved a little between time steps in bundles
  // (docs/design/labelling.md L1 step 7), for labels and models; and for the models of all
  // states at once (judge_center with free_only) the hits of an object whose states of interest
  // are all blocked are not tested, and a voxel is left as soon as every state is blocked (L8).
  // Each hit claims only its own object's states, so every state keeps the labels and the model
  // it has alone. Here 64 states of copies moved a little between 32 time steps (so each voxel
  // and camera has many objects, some of whose states are blocked before others), occupying and
  // occluding copies (both dynamic modes). A skipped hit that decides an open state (a state
  // free where it is occupied alone, or the reverse) makes a model differ.
  std::mt19937 rng(57);
  const std::array<int, 3> resolution{12, 9, 9};
  for (int s = 0; s < 4 && !HasFailure(); ++s) {
    core::Scene scene = random_scene(rng, resolution);
    scene.dynamic_mode = s % 2 == 0 ? core::DynamicMode::masked : core::DynamicMode::modelled;
    scene.plausibility = {};
    scene = with_moved_copies(rng, std::move(scene), 32, 0.08, false);
    ASSERT_EQ(core::states(scene).size(), 64u);
    const core::CameraConfig config = random_config(rng, scene);
    const AloneTally t =
        compare_with_each_state_alone(scene, config, LabelMode::center, resolution);
    EXPECT_EQ(t.differing, 0) << "scene " << s;
    EXPECT_EQ(t.model_differing, 0) << "scene " << s;
    EXPECT_GT(t.in_model, 0) << "scene " << s;
    EXPECT_GT(t.out_of_model, 0) << "scene " << s;
  }
}

TEST(LegacyEquivalence, BlocksCutShortKeepVoxelsWhoseBallHoldsTheCamera) {
  // A 2×2×1 block of 1 m voxels, [2, 4]² × [0, 1] (the grid has one layer: blocks are cut short
  // in z), and a 170° × 170° frustum camera 1.53 m from the block's centre toward its corner
  // (2, 2): outside the block's bounding ball (radius 1.5 m), which lies in the frustum, but
  // within 0.87 m (a voxel's radius) of voxel (2, 2, 0)'s centre. Per voxel, a camera in or at a
  // voxel's bounding ball never proves it free (in_fov); a whole-block test must not either.
  const double pi = 3.14159265358979323846;
  core::Scene scene = simple_scene({core::Vec3(0, 0, 0), core::Vec3(8, 8, 1)}, {8, 8, 1}, 1, 30,
                                   {box_object("critical", {7, 7, 0}, {8, 8, 1})},
                                   {box_object("target", {0, 6, 0}, {1, 7, 1})});
  scene.plausibility = {};
  core::CameraModel& model = scene.cameras.models.at(0);
  model.fov = core::FovShape::frustum;
  model.horizontal = model.vertical = 170.0 * pi / 180.0;
  const core::Vec3 corner_dir = core::Vec3(-1, -1, 0).normalized();
  const core::Vec3 position = core::Vec3(3, 3, 0.5) + 1.53 * corner_dir;
  const core::CameraConfig config{camera_at(position, 45, 0)};
  ASSERT_LT((position - core::Vec3(2.5, 2.5, 0.5)).norm(), std::sqrt(0.75));
  const voxel::VoxelEvaluator evaluator(scene, {LabelMode::conservative, {8, 8, 1}});
  const int v = 2 + 8 * 2;
  EXPECT_EQ(evaluator.model(config, 0)[v], 1);
  // The box reference agrees: a camera within the voxel's ball never sees it free.
  EXPECT_EQ(reference_box_label(scene, 0, 0, config[0], evaluator.grid().voxel_box(v)).label,
            Label::undetectable);
  // Its neighbours in the block are seen free, here and by the old labeller.
  for (const int u : {3 + 8 * 2, 2 + 8 * 3, 3 + 8 * 3}) EXPECT_EQ(evaluator.model(config, 0)[u], 0);
  Tally t;
  compare_all(scene, config, LabelMode::conservative, {8, 8, 1}, "block cut short", t);
  EXPECT_EQ(t.differing, 0);
}

// The models (blocks cleared per state, voxels occupying objects reach into kept untested) against
// the per-voxel path: a voxel is in M exactly when none of the cameras' labels() calls it free,
// apart from voxels wholly inside an obstacle, which M leaves out (here: the centre and the 8
// corners inside one obstacle). Filter off.
void expect_models_equal_per_voxel_labels(const core::Scene& scene,
                                          const core::CameraConfig& config,
                                          std::array<int, 3> resolution, int threads,
                                          const std::string& what) {
  voxel::VoxelOptions options{LabelMode::conservative, resolution};
  options.threads = threads;
  const voxel::VoxelEvaluator evaluator(scene, options);
  const voxel::Grid& grid = evaluator.grid();
  const auto all_states = core::states(scene);
  for (std::size_t st = 0; st < all_states.size(); ++st) {
    std::vector<std::uint8_t> expected(grid.count(), 1);
    for (int c = 0; c < scene.cameras.count; ++c) {
      const auto labels = evaluator.labels(config[c], static_cast<int>(st), c);
      for (int v = 0; v < grid.count(); ++v) expected[v] &= labels[v] != Label::free;
    }
    const auto model = evaluator.model(config, static_cast<int>(st));
    const core::TimeStep& step = scene.time_steps[all_states[st].time_step];
    std::vector<const core::TriangleMesh*> obstacles;
    for (const auto& o : scene.static_obstacles) obstacles.push_back(&o.mesh);
    for (const auto& o : step.dynamic_obstacles) obstacles.push_back(&o.mesh);
    for (int v = 0; v < grid.count(); ++v) {
      if (model[v] == expected[v]) continue;
      const core::Box3 box = grid.voxel_box(v);
      bool removed = false;
      for (const core::TriangleMesh* mesh : obstacles) {
        bool inside = reference_inside(*mesh, box.center());
        for (int q = 0; q < 8 && inside; ++q) {
          inside = reference_inside(*mesh, core::Vec3((q & 1) ? box.max.x() : box.min.x(),
                                                      (q & 2) ? box.max.y() : box.min.y(),
                                                      (q & 4) ? box.max.z() : box.min.z()));
        }
        removed = removed || inside;
      }
      ASSERT_TRUE(model[v] == 0 && removed)
          << what << " state " << st << " voxel " << v << ": model " << int(model[v])
          << ", per-voxel labels " << int(expected[v]);
    }
  }
}

TEST(LegacyEquivalence, ModelsEqualThePerVoxelLabelsOfTheirCameras) {
  // Uneven resolutions (blocks cut short at the grid's end and at the threads' slices), mixed
  // camera models with roll, wide frusta (175° × 170°), cameras moved onto voxel centres and
  // corners and near 2³ and 4³ block corners, 1 to 3 threads.
  const double pi = 3.14159265358979323846;
  std::mt19937 rng(777);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int s = 0; s < 60 && !HasFatalFailure(); ++s) {
    const std::array<int, 3> resolution{9 + s % 7, 7 + s % 5, 5 + s % 4};
    core::Scene scene = random_scene(rng, resolution);
    scene.plausibility = {};
    if (s % 2) randomize_camera_models(rng, scene);
    if (s % 4 == 3) {
      for (core::CameraModel& m : scene.cameras.models) {
        m.fov = core::FovShape::frustum;
        m.horizontal = 175.0 * pi / 180.0;
        m.vertical = 170.0 * pi / 180.0;
      }
    }
    core::CameraConfig config = random_config(rng, scene);
    if (s % 2) randomize_rolls(rng, config);
    const voxel::Grid grid = voxel::make_grid(scene.area, resolution);
    for (core::CameraSetting& camera : config) {
      const double u = unit(rng);
      if (u >= 0.6) continue;
      for (int a = 0; a < 3; ++a) {
        const double f = (camera.position[a] - grid.area.min[a]) / grid.step[a];
        double q = u < 0.2    ? std::floor(f) + 0.5           // a voxel centre
                   : u < 0.3  ? std::round(f / 2) * 2 + 1e-7  // near a 2³ block corner
                   : u < 0.45 ? std::round(f / 4) * 4 - 1e-9  // near a 4³ block corner
                              : std::round(f);                // a voxel corner
        camera.position[a] = grid.area.min[a] + std::clamp(q, 0.5, grid.n[a] - 0.5) * grid.step[a];
      }
    }
    expect_models_equal_per_voxel_labels(scene, config, resolution, 1 + s % 3,
                                         "scene " + std::to_string(s));
  }
  // Fine meshes: the bins get finer than the grid's resolution gives (camera_setup).
  for (int s = 0; s < 3 && !HasFatalFailure(); ++s) {
    core::Scene fine = with_fine_meshes(random_scene(rng, {9, 7, 6}), 400);
    fine.plausibility = {};
    expect_models_equal_per_voxel_labels(fine, random_config(rng, fine), {9, 7, 6}, 1 + s % 2,
                                         "fine scene " + std::to_string(s));
  }
  // More than 64 states: several chunks.
  core::Scene scene = random_scene(rng, {10, 8, 8});
  scene.plausibility = {};
  while (core::states(scene).size() < 70) scene.time_steps.push_back(scene.time_steps[0]);
  expect_models_equal_per_voxel_labels(scene, random_config(rng, scene), {10, 8, 8}, 2,
                                       "70 states");
}

TEST(LegacyEquivalence, ThreadsDoNotChangeTheResult) {
  std::mt19937 rng(23);
  for (int s = 0; s < 4; ++s) {
    const core::Scene scene = random_scene(rng, {12, 9, 9});
    const core::CameraConfig config = random_config(rng, scene);
    for (LabelMode mode : {LabelMode::center, LabelMode::conservative}) {
      voxel::VoxelOptions options{mode, {14, 10, 9}};
      const auto one = voxel::VoxelEvaluator(scene, options).evaluate(config);
      options.threads = 3;
      const voxel::VoxelEvaluator threaded(scene, options);
      const auto three = threaded.evaluate(config);
      EXPECT_EQ(one.err, three.err);
      ASSERT_EQ(one.states.size(), three.states.size());
      for (std::size_t st = 0; st < one.states.size(); ++st) {
        EXPECT_EQ(one.states[st].d_model, three.states[st].d_model);
        EXPECT_EQ(one.states[st].model_volume, three.states[st].model_volume);
        EXPECT_EQ(one.states[st].components, three.states[st].components);
      }
    }
  }
  const core::Scene scene = random_scene(rng, {12, 9, 9});
  for (int bad : {0, -1, voxel::kMaxThreads + 1}) {
    voxel::VoxelOptions options;
    options.threads = bad;
    EXPECT_THROW(voxel::VoxelEvaluator(scene, options), core::InputError) << bad;
  }
}

}  // namespace
}  // namespace camplace::testing
