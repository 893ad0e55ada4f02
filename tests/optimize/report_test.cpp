#include "camplace/optimize/report.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>

#include "camplace/core/camera.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/json_reader.hpp"
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

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(Report, RunFileReadsBackToTheSameRunAndContext) {
  const core::Scene scene = testing::small_scene();
  const VoxelObjective objective(scene, voxel::VoxelOptions{});
  OptimizeOptions o;
  o.max_evaluations = 300;
  o.seed = 4;
  o.threads = 1;
  const RunResult run = optimize(scene, objective, o);
  ASSERT_GE(run.history.size(), 1u);
  RunContext context;
  context.scene_file = "a dir/it's scene.json";
  context.mode = "conservative";
  context.resolution = {9, 9, 8};
  context.start = "corners";
  context.time_limit = 12.5;
  context.max_evaluations = 300;
  const std::string text = run_json(run, context).dump(2);
  EXPECT_EQ(nlohmann::json::parse(text).at("format_version"), kRunFileFormat);

  const RunFile back = run_from_json(nlohmann::json::parse(text), "run-4.json");
  // The writer applied to what was read gives the same text, byte for byte.
  EXPECT_EQ(run_json(back.run, back.context).dump(2), text);
  // Spot checks against the values the optimizer returned, field by field.
  EXPECT_EQ(back.run.err, run.err);
  EXPECT_EQ(back.run.evaluations, 300u);
  EXPECT_EQ(back.run.stop_reason, run.stop_reason);
  EXPECT_EQ(back.run.seed, 4u);
  EXPECT_EQ(back.run.history.size(), run.history.size());
  EXPECT_EQ(back.run.memory.vm_peak_kb, run.memory.vm_peak_kb);
  EXPECT_EQ(back.run.mean_timing.clustering_ms, run.mean_timing.clustering_ms);
  EXPECT_EQ(back.context.scene_file, context.scene_file);
  EXPECT_EQ(back.context.resolution, context.resolution);
  EXPECT_EQ(back.context.time_limit, 12.5);
  // The cameras are the ones `camplace evaluate --cameras` reads from the file.
  const fs::path dir = fresh_dir("round-trip");
  core::write_file_atomically((dir / "run-4.json").string(), text);
  const core::CameraConfig evaluate_reads =
      core::load_camera_config((dir / "run-4.json").string(), scene);
  ASSERT_EQ(back.run.best.size(), evaluate_reads.size());
  for (std::size_t i = 0; i < evaluate_reads.size(); ++i) {
    EXPECT_EQ(back.run.best[i].position, evaluate_reads[i].position) << i;
    EXPECT_EQ(back.run.best[i].yaw, evaluate_reads[i].yaw) << i;
    EXPECT_EQ(back.run.best[i].pitch, evaluate_reads[i].pitch) << i;
  }
  EXPECT_EQ(read_run_file((dir / "run-4.json").string()).run.err, run.err);
  fs::remove_all(dir);
}

TEST(Report, RunFilesWithoutAFormatVersionAreFormatOneAndReadBackUnchanged) {
  // The study's run files in docs/reports were written before "format_version" existed.
  const fs::path runs = fs::path(CAMPLACE_SOURCE_DIR) / "docs/reports/study_cameras/runs";
  int files = 0;
  for (const auto& group : fs::directory_iterator(runs)) {
    for (const char* name : {"run-1.json", "run-2.json"}) {
      const fs::path file = group.path() / name;
      if (!fs::exists(file)) continue;
      ++files;
      const std::string text = read_text(file);
      const nlohmann::json j = nlohmann::json::parse(text);
      ASSERT_FALSE(j.contains("format_version")) << file;
      const RunFile back = read_run_file(file.string());
      nlohmann::ordered_json again = run_json(back.run, back.context);
      EXPECT_EQ(again.at("format_version"), kRunFileFormat);
      again.erase("format_version");
      EXPECT_EQ(again.dump(2) + "\n", text) << file;  // `camplace optimize` ends it with "\n"
    }
  }
  EXPECT_GE(files, 14);
}

/// The InputError run_from_json throws for `j`, or none.
std::optional<core::InputError> read_error(const nlohmann::json& j) {
  try {
    run_from_json(j, "dir/run-7.json");
  } catch (const core::InputError& e) {
    return e;
  }
  return std::nullopt;
}

TEST(Report, UnknownFormatVersionsAndDamagedRunFilesAreErrorsNamingFileAndEntry) {
  RunResult run;
  run.best = core::CameraConfig(2);
  run.stop_reason = StopReason::tolerance;
  const nlohmann::json good = nlohmann::json::parse(run_json(run, RunContext{}).dump());
  ASSERT_FALSE(read_error(good));

  struct Case {
    std::string what, pointer, value, entry, reason_part;
  };
  const std::vector<Case> cases = {
      {"newer format", "/format_version", "99", "/format_version", "unknown run file format 99"},
      {"format 0", "/format_version", "0", "/format_version", "unknown run file format 0"},
      {"format as text", "/format_version", "\"2\"", "/format_version", "unknown run file format"},
      {"err as text", "/err", "\"small\"", "/err", "expected a number"},
      {"negative count", "/evaluations", "-1", "/evaluations", "non-negative integer"},
      {"unknown stop", "/stop_reason", "\"bored\"", "/stop_reason", "unknown stop reason"},
      {"extra key", "/colour", "1", "/colour", "unknown field"},
      {"bad camera", "/cameras/1/yaw_deg", "200", "/cameras/1/yaw_deg", "out of range"},
      {"bad timing", "/time_per_evaluation_ms/total", "null", "/time_per_evaluation_ms/total",
       "expected a number"},
  };
  for (const Case& c : cases) {
    nlohmann::json j = good;
    j[nlohmann::json::json_pointer(c.pointer)] = nlohmann::json::parse(c.value);
    const std::optional<core::InputError> e = read_error(j);
    ASSERT_TRUE(e) << c.what;
    EXPECT_EQ(e->file(), "dir/run-7.json") << c.what;
    EXPECT_EQ(e->entry(), c.entry) << c.what;
    EXPECT_NE(e->reason().find(c.reason_part), std::string::npos) << c.what << ": " << e->what();
  }
  nlohmann::json missing = good;
  missing.erase("memory_kb");
  const std::optional<core::InputError> e = read_error(missing);
  ASSERT_TRUE(e);
  EXPECT_NE(e->reason().find("missing required field \"memory_kb\""), std::string::npos);
  // Files that are not JSON at all.
  const fs::path dir = fresh_dir("damaged");
  core::write_file_atomically((dir / "run-1.json").string(), "{\"cameras\": [");
  EXPECT_THROW(read_run_file((dir / "run-1.json").string()), core::InputError);
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
