// Resuming a study folder: every change of the study file that changes its runs'
// results, or drops runs from the study, is refused naming it and leaves the folder as it was;
// a study that grows keeps its runs; --restart discards the folder's runs, report and checks
// (nothing else) and runs afresh. `compare-optimizer` and `validate` refuse run files of
// another scene (by content hash). Tiny runs: the whole program takes a few seconds.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "command.hpp"
#include "report_header.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

namespace fs = std::filesystem;

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Every file below `dir` with its content.
std::map<std::string, std::string> snapshot(const std::string& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) files[e.path().string()] = read(e.path().string());
  }
  return files;
}

CommandResult camplace(const std::string& args) { return run_camplace(CAMPLACE_BINARY, args); }

/// A study of two groups (dynamic_objects-1, whose placement depends on scene_seed, and
/// cameras-3), 2 runs each of at most 40 evaluations, with some keys replaced.
std::string study_json(const std::map<std::string, std::string>& changes = {}) {
  std::map<std::string, std::string> keys = {
      {"description", "\"resume test\""},
      {"algorithm", "\"gaco\""},
      {"mode", "\"center\""},
      {"runs_per_group", "2"},
      {"threads", "1"},
      {"first_seed", "1"},
      {"scene_seed", "1"},
      {"time_limit_s", "60"},
      {"max_evaluations", "40"},
      {"examinations",
       R"([{"name": "objects", "family": "dynamic_objects", "params": [1]},
           {"name": "cameras", "family": "cameras", "params": [3]}])"}};
  for (const auto& [key, value] : changes) keys[key] = value;
  std::string text = "{";
  for (const auto& [key, value] : keys) {
    text += (text.size() > 1 ? ",\n \"" : "\n \"") + key + "\": " + value;
  }
  return text + "\n}\n";
}

TEST(StudyResume, EachChangedStudySettingIsRefusedNamingItAndRestartStartsAfresh) {
  const std::string dir = temp_dir("study-resume");
  const std::string study = dir + "/study.json";
  const std::string out = dir + "/out";
  write_file(study, study_json());
  CommandResult r = camplace("study " + study + " --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("runs: 4 (0 found, 4 run now)"), std::string::npos) << r.output;
  const auto before = snapshot(out);

  const struct {
    std::string key, value, expect;
  } changed[] = {
      {"algorithm", "\"cmaes\"",
       "runs/dynamic_objects-1/run-1.json (and 3 more runs): algorithm: gaco → cmaes"},
      {"mode", "\"conservative\"", "(and 3 more runs): mode: center → conservative"},
      {"max_evaluations", "41", "(and 3 more runs): max_evaluations: 40 → 41"},
      {"time_limit_s", "30", "(and 3 more runs): time_limit_s: 60 → 30"},
      {"threads", "2", "(and 3 more runs): threads: 1 → 2"},
      // The generated scenes' content (the placement of dynamic_objects-1 is random).
      {"scene_seed", "2",
       "runs/dynamic_objects-1/run-1.json (and 1 more run): scene " + out +
           "/scenes/dynamic_objects-1.json changed (sha256 "},
      {"runs_per_group", "1",
       "runs/dynamic_objects-1/run-2.json (and 1 more run): seed 2 is not the study's seed 1 "
       "(runs_per_group or first_seed changed)"},
      {"first_seed", "2",
       "runs/dynamic_objects-1/run-1.json (and 1 more run): seed 1 is outside the study's seeds "
       "2–3 "
       "(runs_per_group or first_seed changed)"},
      {"examinations", R"([{"name": "objects", "family": "dynamic_objects", "params": [1]}])",
       "runs/cameras-3/run-1.json (and 1 more run): group cameras-3 is not in the study "
       "(examinations changed)"},
  };
  for (const auto& c : changed) {
    write_file(study, study_json({{c.key, c.value}}));
    r = camplace("study " + study + " --out " + out);
    EXPECT_EQ(r.exit_code, 1) << c.key << "\n" << r.output;
    EXPECT_EQ(r.output.rfind("error: " + out + ": holds runs made with other settings", 0), 0u)
        << c.key << "\n"
        << r.output;
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.key << "\n" << r.output;
    EXPECT_NE(r.output.find("rerun with --restart"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("study: "), std::string::npos) << "a run started\n" << r.output;
    EXPECT_EQ(snapshot(out), before) << c.key << ": the folder changed";
  }

  // A study that grows keeps its runs: more runs per group, another group; a new description.
  write_file(study,
             study_json({{"runs_per_group", "3"},
                         {"description", "\"grown\""},
                         {"examinations",
                          R"([{"name": "objects", "family": "dynamic_objects", "params": [1]},
                              {"name": "cameras", "family": "cameras", "params": [3, 4]}])"}}));
  r = camplace("study " + study + " --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("runs: 9 (4 found, 5 run now)"), std::string::npos) << r.output;
  EXPECT_EQ(read(out + "/runs/cameras-3/run-1.json"),
            before.at(out + "/runs/cameras-3/run-1.json"));

  // --restart with another solver: the study's files go, the user's stay.
  write_file(out + "/notes.txt", "mine");
  write_file(out + "/runs/cameras-3/notes.txt", "mine too");
  write_file(out + "/validation.csv", "stale");
  write_file(out + "/validation.md", "stale");
  write_file(out + "/validation-cache/" + std::string(64, 'b') + ".json", "{}");
  write_file(out + "/iterations_vs_resolution.png", "a plot of another study");
  write_file(study, study_json({{"algorithm", "\"de\""}}));
  r = camplace("study " + study + " --out " + out + " --restart");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("restart: discarded 9 run files\nruns: 4 (0 found, 4 run now)"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(read(out + "/notes.txt"), "mine");
  EXPECT_EQ(read(out + "/runs/cameras-3/notes.txt"), "mine too");
  for (const char* gone :
       {"/validation.csv", "/validation.md", "/validation-cache", "/iterations_vs_resolution.png",
        "/runs/cameras-4", "/scenes/cameras-4.json", "/runs/cameras-3/run-3.json"}) {
    EXPECT_FALSE(fs::exists(out + gone)) << gone;
  }
  EXPECT_EQ(nlohmann::json::parse(read(out + "/runs/cameras-3/run-1.json")).at("algorithm"), "de");
  EXPECT_EQ(read(out + "/report.md").find("grown"), std::string::npos);
  // The folder is now the restarted study's: resuming it finds every run.
  r = camplace("study " + study + " --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("runs: 4 (4 found, 0 run now)"), std::string::npos) << r.output;
}

TEST(StudyResume, RunFilesWithoutProvenanceAreComparedWithTheFoldersSceneCopy) {
  // Run files of formats 1 and 2 record no scene hashes; they were made on the scene the study
  // wrote into its folder, so that copy stands in for them.
  const std::string dir = temp_dir("study-resume-legacy");
  const std::string study = dir + "/study.json";
  const std::string out = dir + "/out";
  const std::string examinations =
      R"([{"name": "objects", "family": "dynamic_objects", "params": [1]}])";
  write_file(study, study_json({{"examinations", examinations}}));
  CommandResult r = camplace("study " + study + " --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* name :
       {"/runs/dynamic_objects-1/run-1.json", "/runs/dynamic_objects-1/run-2.json"}) {
    nlohmann::ordered_json run = nlohmann::ordered_json::parse(read(out + name));
    run.erase("format_version");
    run.erase("provenance");
    write_file(out + name, run.dump(2) + "\n");
  }
  r = camplace("study " + study + " --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("runs: 2 (2 found, 0 run now)"), std::string::npos) << r.output;
  write_file(study, study_json({{"examinations", examinations}, {"scene_seed", "3"}}));
  r = camplace("study " + study + " --out " + out);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("runs/dynamic_objects-1/run-1.json (and 1 more run): scene " + out +
                          "/scenes/dynamic_objects-1.json changed (sha256 "),
            std::string::npos)
      << r.output;
}

TEST(StudyResume, RunsMadeWhenCeilingCamerasCouldLookUpAreRefused) {
  // Before run file format 4 the ceiling preset let cameras look up: such runs of a
  // ceiling group are not runs of the study as it is now, though the scene's text is the same.
  // (The test above resumes format-1 runs of a room-domain group.)
  const std::string dir = temp_dir("study-resume-ceiling");
  const std::string study = dir + "/study.json";
  const std::string out = dir + "/out";
  write_file(
      study,
      study_json({{"examinations", R"([{"name": "ceiling", "family": "domain_ceiling"}])"}}));
  CommandResult r = camplace("study " + study + " --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = camplace("study " + study + " --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("runs: 2 (2 found, 0 run now)"), std::string::npos) << r.output;
  const std::string run_file = out + "/runs/domain_ceiling/run-2.json";
  nlohmann::ordered_json run = nlohmann::ordered_json::parse(read(run_file));
  run["format_version"] = 3;
  run.erase("objective");  // format 3 had neither
  run.erase("tie_breaker");
  write_file(run_file, run.dump(2) + "\n");
  r = camplace("study " + study + " --out " + out);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("runs/domain_ceiling/run-2.json: cameras.domain \"ceiling\": now pitch "
                          "−90°…0° (looking down or level); this run file (format 3"),
            std::string::npos)
      << r.output;
  r = camplace("study " + study + " --out " + out + " --restart");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("runs: 2 (0 found, 2 run now)"), std::string::npos) << r.output;
}

// A small cell (as in validation_test.cpp): exact evaluations take a few milliseconds.
const char* kCell = R"({
  "area": {"min": [0, 0, 0], "max": [4, 3, 3]},
  "voxels": [8, 6, 6],
  "cameras": {"count": 2, "half_angle_deg": 35, "fov": "pyramid", "sides": 4},
  "dynamic_mode": "modelled",
  "time_steps": [{
    "dynamic_obstacles": [{"name": "robot", "box": {"min": [0.5, 0.5, 0], "max": [1.0, 1.0, 1.5]}}],
    "events": [{"weight": 1, "targets": [
      {"name": "person", "box": {"min": [2.5, 1.5, 0], "max": [3.0, 2.0, 1.8]}}]}]}]
})";

TEST(SceneCheck, CompareOptimizerAndValidateRefuseRunFilesOfAnotherScene) {
  const std::string dir = temp_dir("scene-check");
  const std::string scene = write_file(dir + "/cell.json", kCell);
  const std::string runs = dir + "/runs";
  CommandResult r = camplace("optimize " + scene + " --mode center --max-evals 20 --runs 2" +
                             " --threads 1 --quiet --out " + runs);
  ASSERT_EQ(r.exit_code, 0) << r.output;

  // The same content at another path is the same scene.
  const std::string copy = write_file(dir + "/copy/cell.json", kCell);
  r = camplace("compare-optimizer " + copy + " --runs " + runs + " --samples 2 --out " + dir +
               "/same");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  expect_provenance_header(read(dir + "/same/report.md"),
                           "# Optimizer results against the exact pipeline", copy, copy,
                           "samples 2, seed 1");
  // Another scene (here: the same cell with a description) is refused, naming the run file.
  std::string other_text = kCell;
  other_text.insert(1, "\n  \"description\": \"another cell\",");
  const std::string other = write_file(dir + "/other.json", other_text);
  r = camplace("compare-optimizer " + other + " --runs " + runs + " --samples 2 --out " + dir +
               "/other-out");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output.rfind("error: " + runs +
                               "/run-1.json: /provenance/scene_sha256: made for another scene (or "
                               "the scene changed since): scene " +
                               other + " changed (sha256 ",
                           0),
            0u)
      << r.output;
  EXPECT_FALSE(fs::exists(dir + "/other-out/report.md"));

  // validate: each run whose scene changed since is an error row naming it (by the same rule).
  write_file(scene, other_text);
  r = camplace("validate " + runs);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  for (const char* run : {"/run-1.json", "/run-2.json"}) {
    EXPECT_NE(r.output.find("error: " + runs + run +
                            ": /provenance/scene_sha256: made for another scene (or the scene "
                            "changed since): scene " +
                            scene + " changed (sha256 "),
              std::string::npos)
        << r.output;
  }
  EXPECT_NE(r.output.find("2 could not be checked"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace camplace::testing
