#include "camplace/optimize/report.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <optional>
#include <sstream>

#include "camplace/core/camera.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/provenance.hpp"
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

// A frustum scene with roll free in the domain. Roll is in the decision vector (one
// per camera), the run file carries roll_deg and the model names, and `evaluate --cameras RUNFILE`
// (core::load_camera_config) reads the same poses back and reproduces Err exactly.
TEST(Report, CameraPosesWithRollSurviveTheRunFileRoundTrip) {
  const core::Scene scene =
      core::load_scene(std::string(CAMPLACE_SOURCE_DIR) + "/tests/data/frustum_small.json");
  ASSERT_EQ(scene.cameras.count, 3);
  voxel::VoxelOptions center;
  center.mode = voxel::LabelMode::center;
  const VoxelObjective objective(scene, center);
  OptimizeOptions o;
  o.max_evaluations = 300;
  o.seed = 14;
  const RunResult run = optimize(scene, objective, o);
  int rolled = 0;
  for (const core::CameraSetting& c : run.best) {
    EXPECT_LE(std::abs(c.roll), 45.0 * core::kDegree + 1e-12);
    rolled += c.roll != 0.0;
  }
  EXPECT_GT(rolled, 0);  // roll is a decision variable here

  const fs::path dir = fresh_dir("roll");
  const fs::path file = dir / "run-14.json";
  RunContext context;
  context.camera_models = camera_models(scene);
  EXPECT_EQ(context.camera_models, (std::vector<std::string>{"rgb", "rgb", "depth"}));
  core::write_file_atomically(file.string(), run_json(run, context).dump(2));
  std::ifstream in(file);
  const nlohmann::json j = nlohmann::json::parse(in);
  ASSERT_EQ(j.at("cameras").size(), 3u);
  EXPECT_EQ(j.at("cameras")[2].at("model"), "depth");
  EXPECT_EQ(read_run_file(file.string()).context.camera_models, context.camera_models);
  const core::CameraConfig config = core::load_camera_config(file.string(), scene);
  ASSERT_EQ(config.size(), run.best.size());
  for (std::size_t i = 0; i < config.size(); ++i) {
    EXPECT_EQ(config[i].position, run.best[i].position) << i;
    EXPECT_EQ(config[i].yaw, run.best[i].yaw) << i;
    EXPECT_EQ(config[i].pitch, run.best[i].pitch) << i;
    EXPECT_EQ(config[i].roll, run.best[i].roll) << i;
  }
  voxel::Timing timing;
  EXPECT_EQ(objective.evaluate(config, timing), j.at("err").get<double>());
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
  EXPECT_EQ(back.run.objective, "err");  // the default
  EXPECT_EQ(back.run.tie_breaker, run.tie_breaker);
  // The model touches the robot in every state (this coarse conservative scene stays on the
  // plateau) and fills part of S: the weighted model volumes over S's volume, summed here from
  // evaluate's per-state figures.
  EXPECT_GT(run.tie_breaker, 0.0);
  EXPECT_LT(run.tie_breaker, 1.0);
  double weighted = 0.0, weights = 0.0;
  for (const core::StateResult& state : objective.evaluator().evaluate(run.best).states) {
    EXPECT_EQ(state.d_model, 0.0);
    weighted += state.weight * state.model_volume;
    weights += state.weight;
  }
  const core::Vec3 size = scene.area.size();
  EXPECT_NEAR(run.tie_breaker, weighted / (weights * size.x() * size.y() * size.z()), 1e-15);
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
      // Made before the tie-breaker: they minimised Err alone.
      EXPECT_EQ(back.run.objective, "err") << file;
      EXPECT_EQ(again.at("objective"), "err") << file;
      EXPECT_EQ(again.at("tie_breaker"), 0.0) << file;
      again.erase("objective");
      again.erase("tie_breaker");
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
      {"unknown objective", "/objective", "\"volume\"", "/objective", "unknown objective"},
      {"tie-breaker above 1", "/tie_breaker", "1.5", "/tie_breaker", "out of range"},
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
  // A refinement the voxel evaluator refuses is named as the run file's entry (validate used
  // to say only "option: refine: ...", naming no file).
  for (const auto& [mode, refine, reason] :
       {std::tuple<std::string, int, std::string>{"conservative", 99, "out of range [1, 10]"},
        {"center", 2, "refinement needs mode conservative, the run's mode is \"center\""}}) {
    nlohmann::json j = good;
    j["context"]["mode"] = mode;
    j["context"]["refine"] = refine;
    const std::optional<core::InputError> e = read_error(j);
    ASSERT_TRUE(e) << mode << " " << refine;
    EXPECT_EQ(e->file(), "dir/run-7.json");
    EXPECT_EQ(e->entry(), "/context/refine");
    EXPECT_NE(e->reason().find(reason), std::string::npos) << e->what();
  }
  nlohmann::json refined = good;
  refined["context"]["mode"] = "conservative";
  refined["context"]["refine"] = 10;
  EXPECT_FALSE(read_error(refined));
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
  EXPECT_EQ(j.at("median_evaluations_reached"), 200.0);
  // No run reached the tolerance: the medians over those runs are null, not 0.
  std::vector<RunResult> failed = runs;
  for (auto& r : failed) r.reached_tolerance = false;
  const auto none = summary_json(failed, RunContext{}, false);
  EXPECT_TRUE(none.at("median_evaluations_reached").is_null());
  EXPECT_TRUE(none.at("median_seconds_reached").is_null());
  std::ostringstream table;
  print_summary(table, runs);
  EXPECT_NE(table.str().find("2/3"), std::string::npos) << table.str();
}

TEST(Resume, RunFileSeedReadsOnlyTheNamesCamplaceWrites) {
  EXPECT_EQ(run_file_seed("run-1.json"), 1u);
  EXPECT_EQ(run_file_seed("run-0.json"), 0u);
  EXPECT_EQ(run_file_seed("run-4294967295.json"), 4294967295u);
  for (const char* name :
       {"run-4294967296.json", "run-01.json", "run-1 copy.json", "run-.json", "run--1.json",
        "run-+1.json", "run-1.json.tmp123", "summary.json", "Run-1.json", "run-1.JSON"}) {
    EXPECT_FALSE(run_file_seed(name)) << name;
  }
}

/// Settings with every member set, as recorded_settings gives them.
RunSettings full_settings() {
  RunSettings s;
  s.scene_file = "cell.json";
  s.scene = core::combine_scene_hashes(core::sha256_hex("scene"), {});
  s.mode = "center";
  s.resolution = std::array<int, 3>{8, 6, 6};
  s.algorithm = "gaco";
  s.objective = "err";
  s.start = "random";
  s.time_limit = 60.0;
  s.max_evaluations = 3000;
  s.tolerance = 0.1875;
  s.population = 32;
  s.seed = 1;
  s.threads = 2;
  return s;
}

TEST(Resume, SettingsChangesNameEachDifferingSettingOldToNew) {
  const RunSettings recorded = full_settings();
  EXPECT_TRUE(settings_changes(recorded, recorded).empty());
  const struct {
    std::function<void(RunSettings&)> change;
    std::string expect;
  } cases[] = {
      {[](RunSettings& s) { s.mode = "conservative"; }, "mode: center → conservative"},
      {[](RunSettings& s) {
         s.resolution = std::array<int, 3>{16, 12, 12};
       },
       "resolution: 8x6x6 → 16x12x12"},
      {[](RunSettings& s) { s.algorithm = "cmaes"; }, "algorithm: gaco → cmaes"},
      {[](RunSettings& s) { s.objective = "err+volume"; }, "objective: err → err+volume"},
      {[](RunSettings& s) { s.start = "corners"; }, "start: random → corners"},
      {[](RunSettings& s) { s.time_limit = 0.5; }, "time_limit_s: 60 → 0.5"},
      {[](RunSettings& s) { s.max_evaluations = 200; }, "max_evaluations: 3000 → 200"},
      {[](RunSettings& s) { s.tolerance = 0.1; }, "tolerance: 0.1875 → 0.1"},
      {[](RunSettings& s) { s.population = 20; }, "population: 32 → 20"},
      {[](RunSettings& s) { s.seed = 7; }, "seed: 1 → 7"},
      {[](RunSettings& s) { s.threads = 4; }, "threads: 2 → 4"},
      {[](RunSettings& s) { s.scene = core::combine_scene_hashes(core::sha256_hex("other"), {}); },
       "scene cell.json changed (sha256 " + core::sha256_hex("scene").substr(0, 12) + "… → " +
           core::sha256_hex("other").substr(0, 12) + "…)"},
  };
  for (const auto& c : cases) {
    RunSettings now = recorded;
    c.change(now);
    EXPECT_EQ(settings_changes(recorded, now), std::vector<std::string>{c.expect}) << c.expect;
  }
  // Unset on either side: not compared (a run file without provenance has no scene hashes;
  // `optimize` leaves the seed and the threads out).
  RunSettings now = recorded;
  now.scene = core::combine_scene_hashes(core::sha256_hex("other"), {});
  now.seed = 7;
  now.threads = 4;
  now.tolerance = 0.1;
  RunSettings unrecorded = recorded;
  unrecorded.scene.reset();
  unrecorded.tolerance.reset();
  now.seed.reset();
  now.threads.reset();
  EXPECT_TRUE(settings_changes(unrecorded, now).empty());
  // The scene path alone is no change: the same content at another path is the same scene.
  now = recorded;
  now.scene_file = "elsewhere/cell.json";
  EXPECT_TRUE(settings_changes(recorded, now).empty());
}

// Run files of formats 1–3 were made when the ceiling preset let cameras look up: with a
// ceiling domain now, they are not runs of the same problem; other domains are unchanged.
TEST(Resume, RunsOfTheOldCeilingPresetAreAChange) {
  RunSettings recorded = full_settings();
  RunSettings now = recorded;
  now.ceiling_pitch = true;
  for (int format : {1, 2, 3}) {
    recorded.format = format;
    const auto changes = settings_changes(recorded, now);
    ASSERT_EQ(changes.size(), 1u) << format;
    EXPECT_NE(changes[0].find("cameras.domain \"ceiling\""), std::string::npos) << changes[0];
    EXPECT_NE(changes[0].find("format " + std::to_string(format)), std::string::npos);
    now.ceiling_pitch = false;
    EXPECT_TRUE(settings_changes(recorded, now).empty()) << format;
    now.ceiling_pitch = true;
  }
  recorded.format = kRunFileFormat;
  EXPECT_TRUE(settings_changes(recorded, now).empty());
}

TEST(Resume, RecordedSettingsAreWhatTheRunFileSays) {
  RunResult run;
  run.best = core::CameraConfig(2);
  run.algorithm = "sade";
  run.objective = "err+volume";
  run.seed = 9;
  run.threads = 3;
  run.population = 24;
  run.tolerance = 0.25;
  RunContext context;
  context.scene_file = "a.json";
  context.mode = "conservative";
  context.resolution = {4, 5, 6};
  context.start = "corners";
  context.time_limit = 7.5;
  context.max_evaluations = 77;
  const RunSettings without =
      recorded_settings(run_from_json(run_json(run, context), "run-9.json"));
  EXPECT_FALSE(without.scene);
  context.provenance = core::Provenance{};
  context.provenance->scene = core::combine_scene_hashes(core::sha256_hex("a"), {});
  const RunSettings s = recorded_settings(run_from_json(run_json(run, context), "run-9.json"));
  EXPECT_EQ(s.scene_file, "a.json");
  ASSERT_TRUE(s.scene);
  EXPECT_EQ(s.scene->combined, context.provenance->scene.combined);
  EXPECT_EQ(s.mode, "conservative");
  EXPECT_EQ(s.resolution, (std::array<int, 3>{4, 5, 6}));
  EXPECT_EQ(s.algorithm, "sade");
  EXPECT_EQ(s.objective, "err+volume");
  EXPECT_EQ(s.start, "corners");
  EXPECT_EQ(s.time_limit, 7.5);
  EXPECT_EQ(s.max_evaluations, 77u);
  EXPECT_EQ(s.tolerance, 0.25);
  EXPECT_EQ(s.population, 24);
  EXPECT_EQ(s.seed, 9u);
  EXPECT_EQ(s.threads, 3);
  EXPECT_EQ(s.format, kRunFileFormat);
  // The format the file says; 1 without the key.
  nlohmann::ordered_json old = run_json(run, context);
  old["format_version"] = 3;
  EXPECT_EQ(recorded_settings(run_from_json(old, "run-9.json")).format, 3);
  old.erase("format_version");
  EXPECT_EQ(recorded_settings(run_from_json(old, "run-9.json")).format, 1);
}

TEST(Resume, CheckResumeListsEachChangeOnceAndDiscardRunsRemovesOnlyCamplaceFiles) {
  const fs::path dir = fresh_dir("resume");
  RunResult run;
  run.best = core::CameraConfig(2);
  run.algorithm = "gaco";
  run.population = 32;
  run.tolerance = 0.1875;
  run.threads = 2;
  RunContext context;
  context.scene_file = "cell.json";
  context.mode = "center";
  context.resolution = {8, 6, 6};
  context.start = "random";
  context.time_limit = 60.0;
  context.max_evaluations = 3000;
  context.provenance = core::Provenance{};
  context.provenance->scene = core::combine_scene_hashes(core::sha256_hex("scene"), {});
  for (unsigned seed : {1u, 2u, 10u}) {
    run.seed = seed;
    core::write_file_atomically((dir / ("run-" + std::to_string(seed) + ".json")).string(),
                                run_json(run, context).dump(2));
  }
  core::write_file_atomically((dir / "summary.json").string(), "{}");
  core::write_file_atomically((dir / "summary.csv").string(), "seed\n");
  core::write_file_atomically((dir / "notes.txt").string(), "mine");
  core::write_file_atomically((dir / "run-1 copy.json").string(), "not a run file");

  RunSettings now = full_settings();
  now.seed.reset();
  now.threads.reset();
  EXPECT_NO_THROW(check_resume(dir.string(), now));  // every seed, any thread count
  EXPECT_NO_THROW(check_resume((dir / "missing").string(), now));
  now.algorithm = "cmaes";
  now.max_evaluations = 200;
  try {
    check_resume(dir.string(), now);
    ADD_FAILURE() << "no error";
  } catch (const SettingsChanged& e) {
    EXPECT_EQ(std::string(e.what()),
              dir.string() +
                  ": holds runs made with other settings than this command:\n"
                  "  run-1.json (and 2 more runs):\n"
                  "    algorithm: gaco → cmaes\n"
                  "    max_evaluations: 3000 → 200");
  }

  EXPECT_EQ(discard_runs(dir.string()), 3);
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir)) left.push_back(e.path().filename().string());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"notes.txt", "run-1 copy.json"}));
  EXPECT_EQ(discard_runs((dir / "missing").string()), 0);
  fs::remove_all(dir);
}

TEST(Resume, SettingsChangedListsAtMostTwentyDifferencesAndGroupsTheirRuns) {
  std::vector<SettingsConflict> conflicts;
  for (int i = 0; i < 25; ++i) {
    conflicts.push_back({"runs/g" + std::to_string(i) + "/run-1.json",
                         {"scene g" + std::to_string(i) + " changed", "algorithm: gaco → de"}});
  }
  const std::string text = SettingsChanged("DIR", conflicts).what();
  const std::string expect_start =
      "DIR: holds runs made with other settings than this command:\n"
      "  runs/g0/run-1.json: scene g0 changed\n"
      "  runs/g0/run-1.json (and 24 more runs): algorithm: gaco → de\n"
      "  runs/g1/run-1.json: scene g1 changed\n";
  EXPECT_EQ(text.substr(0, expect_start.size()), expect_start) << text;
  const std::string expect_end =
      "  runs/g18/run-1.json: scene g18 changed\n"
      "  ... and 6 more differences";
  ASSERT_GE(text.size(), expect_end.size());
  EXPECT_EQ(text.substr(text.size() - expect_end.size()), expect_end) << text;

  // The limit falls inside the changes of one run: 19 single ones, then a run with 5.
  conflicts.clear();
  for (int i = 0; i < 19; ++i) conflicts.push_back({"r" + std::to_string(i), {std::to_string(i)}});
  conflicts.push_back({"last", {"a", "b", "c", "d", "e"}});
  const std::string capped = SettingsChanged("DIR", conflicts).what();
  const std::string capped_end = "  r18: 18\n  last:\n    a\n  ... and 4 more differences";
  ASSERT_GE(capped.size(), capped_end.size());
  EXPECT_EQ(capped.substr(capped.size() - capped_end.size()), capped_end) << capped;
}

}  // namespace
}  // namespace camplace::optimize
