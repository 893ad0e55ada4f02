#include "camplace/optimize/report.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "camplace/core/camera.hpp"
#include "camplace/core/files.hpp"
#include "camplace/optimize/voxel_objective.hpp"
#include "test_scene.hpp"

namespace camplace::optimize {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() /
                       ("camplace-report-test-" + std::to_string(::getpid()) + "-" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(Report, RunFileCamerasAreReadByTheEvaluateReaderAndReproduceErr) {
  const core::Scene scene = testing::small_scene();
  voxel::VoxelOptions center;
  center.mode = voxel::LabelMode::center;
  const VoxelObjective objective(scene, center);
  OptimizeOptions o;
  o.max_evaluations = 500;
  o.seed = 9;
  const RunResult run = optimize(scene, objective, o);

  const fs::path dir = fresh_dir("run");
  const fs::path file = dir / "run-9.json";
  core::write_file_atomically(file.string(), run_json(run, RunContext{}).dump(2));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1);

  // `camplace evaluate --cameras` reads the file with core::load_camera_config.
  const core::CameraConfig config = core::load_camera_config(file.string(), scene);
  voxel::Timing timing;
  std::ifstream in(file);
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(objective.evaluate(config, timing), j.at("err").get<double>());
  for (const char* key : {"cameras", "err", "evaluations", "reached_tolerance", "seconds",
                          "stop_reason", "history", "time_per_evaluation_ms", "memory_kb"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j.at("evaluations").get<std::uint64_t>(), 500u);
  EXPECT_EQ(j.at("stop_reason"), "max_evaluations");
  EXPECT_EQ(j.at("err_lower_bound").get<double>(), 0.0);  // center mode: no bound
  fs::remove_all(dir);
}

TEST(Report, SummaryCountsSuccessesAndTakesMedians) {
  std::vector<RunResult> runs(3);
  const double errs[] = {0.04, 0.2, 0.03};
  const std::uint64_t evals[] = {100, 900, 300};
  for (int i = 0; i < 3; ++i) {
    runs[i].seed = i + 1;
    runs[i].err = errs[i];
    runs[i].evaluations = evals[i];
    runs[i].seconds = 10.0 * (i + 1);
    runs[i].tolerance = 0.05;
    runs[i].reached_tolerance = errs[i] <= 0.05;
    runs[i].best = core::CameraConfig(2);
  }
  const Summary s = summarize(runs);
  EXPECT_EQ(s.runs, 3);
  EXPECT_EQ(s.reached, 2);
  EXPECT_EQ(s.median_evaluations, 300.0);
  EXPECT_EQ(s.median_seconds, 20.0);
  EXPECT_EQ(s.median_evaluations_reached, 200.0);  // median of 100 and 300
  EXPECT_EQ(s.best_run, 2);

  const std::string csv = summary_csv(runs);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4);
  const auto j = summary_json(runs, RunContext{}, false);
  EXPECT_EQ(j.at("reached_tolerance"), 2);
  EXPECT_EQ(j.at("best").at("seed"), 3);
  std::ostringstream table;
  print_summary(table, runs);
  EXPECT_NE(table.str().find("2/3"), std::string::npos) << table.str();
}

}  // namespace
}  // namespace camplace::optimize
