// `optimize --snap`: the snapped cameras lie on the grid, in their domains and
// out of the keep-out boxes, and their Err is the one an independent evaluation of the re-read
// camera file gives.
#include "../../optimize/src/snap.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "camplace/core/camera.hpp"
#include "camplace/optimize/encoding.hpp"
#include "camplace/optimize/optimizer.hpp"
#include "camplace/optimize/report.hpp"
#include "camplace/optimize/voxel_objective.hpp"
#include "test_scene.hpp"

namespace camplace::optimize {
namespace {

using nlohmann::json;
constexpr double kDeg = M_PI / 180.0;

using testing::temp_path;

/// The small scene with a ceiling mount (camera 0), a wall mount (camera 1), a box domain
/// (camera 2) and a keep-out box over the robot.
core::Scene snap_scene() {
  return testing::small_scene_with(json::parse(R"({
    "mounts": [
      {"name": "ceiling", "corner": [0, 0, 2.5], "edges": [[0, 3, 0], [3, 0, 0]],
       "pitch_deg": [-40, 40], "yaw_deg": [-40, 40]},
      {"name": "wall", "corner": [0, 3, 1.25], "edges": [[3, 0, 0], [0, 0, 1.25]]}
    ],
    "keep_out": [{"name": "reach", "min": [0, 0, 0], "max": [1.3, 1.3, 2.6]}],
    "camera_domains": [{"mount": "ceiling"}, {"mount": "wall"},
                       {"x": [0.05, 2.95], "y": [0.05, 2.95], "z": [1.0, 2.45]}]
  })"));
}

/// True when v is a multiple of step (relative rounding 1e-9) or one of the bounds.
bool on_grid(double v, double step, double lo, double hi) {
  const double k = std::round(v / step);
  return std::abs(v - k * step) <= 1e-9 * std::max(1.0, std::abs(v)) || std::abs(v - lo) <= 1e-12 ||
         std::abs(v - hi) <= 1e-12;
}

TEST(Snap, RoundToGridRoundsClampsAndAvoidsKeepOut) {
  const core::Scene scene = snap_scene();
  const Encoding encoding(scene);
  const SnapGrid grid{0.1, 5 * kDeg};
  std::vector<double> x = encoding.encode(corner_start(scene));
  // Camera 2 (box domain, variables 8..12): x = 0.234 → 0.2, y = 0.03 → 0.05 (clamped to the
  // bound; 0.0 lies outside), z = 2.44 → 2.4, yaw 12.6° → 15°.
  x[8] = 0.234;
  x[9] = 0.03;
  x[10] = 2.44;
  x[11] = 12.6 * kDeg;
  const std::vector<double> r = detail::round_to_grid(encoding, x, grid);
  EXPECT_NEAR(r[8], 0.2, 1e-12);
  EXPECT_NEAR(r[9], 0.05, 1e-12);
  EXPECT_NEAR(r[10], 2.4, 1e-12);
  EXPECT_NEAR(r[11], 15 * kDeg, 1e-12);
  // Camera 2 at (1.21, 1.0, 2.0) rounds to (1.2, 1.0, 2.0), inside the keep-out box: it moves to
  // the nearest free grid position, (1.3, 1.0, 2.0) (0.09 m from the continuous one).
  x[8] = 1.21;
  x[9] = 1.0;
  x[10] = 2.0;
  const std::vector<double> moved = detail::round_to_grid(encoding, x, grid);
  EXPECT_NEAR(moved[8], 1.3, 1e-12);
  EXPECT_NEAR(moved[9], 1.0, 1e-12);
  EXPECT_NEAR(moved[10], 2.0, 1e-12);
  EXPECT_TRUE(encoding.keeps_out(moved));
}

TEST(Snap, SnappedCamerasLieOnTheGridAndTheirErrIsIndependentlyRecomputed) {
  const core::Scene scene = snap_scene();
  voxel::VoxelOptions voxel_options;
  voxel_options.mode = voxel::LabelMode::center;
  const VoxelObjective objective(scene, voxel_options);
  OptimizeOptions o;
  o.algorithm = "pso";
  o.max_evaluations = 300;
  o.seed = 4;
  o.threads = 2;
  o.tolerance = 0.0;
  o.snap = SnapGrid{0.1, 5 * kDeg};
  const RunResult r = optimize(scene, objective, o);
  ASSERT_TRUE(r.snapped);
  const SnappedResult& snap = *r.snapped;
  EXPECT_GT(snap.evaluations, 0u);
  EXPECT_LE(snap.err, snap.rounded_err + 1e-12);
  const Encoding encoding(scene);
  const std::vector<double> x = encoding.encode(snap.cameras);
  const std::vector<double> steps = encoding.steps(0.1, 5 * kDeg);
  ASSERT_EQ(steps.size(), x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    const Variable& v = encoding.variables()[k];
    EXPECT_TRUE(on_grid(x[k], steps[k], v.lo, v.hi))
        << "variable " << k << " = " << x[k] << " step " << steps[k];
    EXPECT_GE(x[k], v.lo - 1e-9);
    EXPECT_LE(x[k], v.hi + 1e-9);
  }
  // On their mounts and out of the keep-out box.
  EXPECT_NEAR(snap.cameras[0].position.z(), 2.5, 1e-12);
  EXPECT_NEAR(snap.cameras[1].position.y(), 3.0, 1e-12);
  for (const core::CameraSetting& c : snap.cameras) {
    EXPECT_FALSE(scene.cameras.keep_out[0].contains(c.position)) << c.position.transpose();
  }
  // Independent recomputation: the cameras written as a camera file, re-read and evaluated by a
  // fresh objective.
  const std::string file = temp_path("snapped.json");
  std::ofstream(file) << core::camera_config_json(snap.cameras);
  const core::CameraConfig reread = core::load_camera_config(file, scene);
  std::filesystem::remove(file);
  const VoxelObjective fresh(scene, voxel_options);
  core::Timing timing;
  EXPECT_EQ(fresh.evaluate(reread, timing), snap.err);

  // The run file carries the snapped result and reads it back.
  RunContext context;
  context.scene_file = scene.file;
  context.mode = "center";
  context.resolution = scene.voxels;
  context.start = "random";
  const RunFile back = run_from_json(json::parse(run_json(r, context).dump()), "run.json");
  ASSERT_TRUE(back.run.snapped);
  EXPECT_EQ(back.run.snapped->err, snap.err);
  EXPECT_EQ(back.run.snapped->evaluations, snap.evaluations);
  EXPECT_NEAR(back.run.snapped->grid.angle, 5 * kDeg, 1e-15);
  EXPECT_EQ(back.run.snapped->cameras.size(), snap.cameras.size());
}

TEST(Snap, TheGridSearchStopsOnASignalOrAtTheRunsTimeLimit) {
  // The interrupt raised before the run: the run makes its one evaluation, and snapping only
  // rounds (one evaluation on the grid) instead of searching the grid for up to 50 evaluations
  // per variable past the run's end.
  const core::Scene scene = snap_scene();
  voxel::VoxelOptions voxel_options;
  voxel_options.mode = voxel::LabelMode::center;
  const VoxelObjective objective(scene, voxel_options);
  std::atomic<bool> stop{true};
  OptimizeOptions o;
  o.algorithm = "pso";
  o.seed = 4;
  o.threads = 1;
  o.tolerance = 0.0;
  o.interrupt = &stop;
  o.snap = SnapGrid{0.1, 5 * kDeg};
  const RunResult interrupted = optimize(scene, objective, o);
  EXPECT_EQ(interrupted.stop_reason, StopReason::interrupted);
  ASSERT_TRUE(interrupted.snapped);
  EXPECT_EQ(interrupted.snapped->evaluations, 1u);
  EXPECT_EQ(interrupted.snapped->err, interrupted.snapped->rounded_err);
  // A time limit that has passed when the search ends: the same.
  o.interrupt = nullptr;
  o.time_limit = 1e-9;
  const RunResult timed = optimize(scene, objective, o);
  EXPECT_EQ(timed.stop_reason, StopReason::time_limit);
  ASSERT_TRUE(timed.snapped);
  EXPECT_EQ(timed.snapped->evaluations, 1u);
}

}  // namespace
}  // namespace camplace::optimize
