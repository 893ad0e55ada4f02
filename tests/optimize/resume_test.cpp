// `camplace optimize` into a folder that already holds runs: every setting that
// determines a run's result, the scene file's content and a mesh file's content, when changed,
// make the command fail naming the change and leave the folder as it was; settings that do not
// change results (threads, seeds, progress output) do not; --restart discards the folder's runs
// (and nothing else) and starts afresh.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "command.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

namespace fs = std::filesystem;

// A small cell (8x6x6 voxels, 2 cameras: a run of 30 evaluations takes milliseconds) with a
// static obstacle read from a mesh file, so that the mesh file's hash is recorded too.
const char* kScene = R"({
  "description": "resume test cell",
  "area": {"min": [0, 0, 0], "max": [4, 3, 3]},
  "voxels": [8, 6, 6],
  "cameras": {"count": 2, "half_angle_deg": 35, "fov": "pyramid", "sides": 4},
  "static_obstacles": [{"name": "crate", "file": "crate.off"}],
  "time_steps": [{
    "dynamic_obstacles": [{"name": "robot", "box": {"min": [0.5, 0.5, 0], "max": [1.0, 1.0, 1.5]}}],
    "events": [{"weight": 1, "targets": [
      {"name": "person", "box": {"min": [2.5, 1.5, 0], "max": [3.0, 2.0, 1.8]}}]}]}]
})";

/// A tetrahedron in the free corner of the cell (OFF, outward faces); `top` is its apex height.
std::string crate_off(const std::string& top) {
  return "OFF\n4 4 0\n3.2 0.2 0\n3.8 0.2 0\n3.2 0.8 0\n3.4 0.4 " + top +
         "\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
}

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

TEST(OptimizeResume, EachChangedSettingIsRefusedNamingItAndRestartStartsAfresh) {
  const std::string dir = temp_dir("optimize-resume");
  const std::string scene = write_file(dir + "/cell.json", kScene);
  write_file(dir + "/crate.off", crate_off("0.5"));
  const std::string out = dir + "/out";
  // `optimize` with the base settings, some replaced or added.
  auto optimize = [&](std::map<std::string, std::string> options) {
    std::map<std::string, std::string> all = {
        {"--mode", "center"}, {"--max-evals", "30"}, {"--threads", "1"}, {"--out", out}};
    for (auto& [key, value] : options) all[key] = value;
    std::string args = "optimize " + scene + " --quiet";
    for (const auto& [key, value] : all) args += " " + key + (value.empty() ? "" : " " + value);
    return camplace(args);
  };
  CommandResult r = optimize({{"--runs", "2"}});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json run1 = nlohmann::json::parse(read(out + "/run-1.json"));
  const std::string tolerance = run1.at("tolerance").dump();
  const std::string population = run1.at("population").dump();
  ASSERT_NE(population, "40");
  const auto before = snapshot(out);

  // Each setting that determines a run's result, in run-file terms: old → new.
  const struct {
    std::string option, value, expect;
  } changed[] = {
      {"--algorithm", "cmaes", "algorithm: gaco → cmaes"},
      {"--objective", "err+volume", "objective: err → err+volume"},
      {"--mode", "conservative", "mode: center → conservative"},
      {"--resolution", "4x3x3", "resolution: 8x6x6 → 4x3x3"},
      {"--start", "corners", "start: random → corners"},
      {"--time-limit", "100", "time_limit_s: 300 → 100"},
      {"--max-evals", "31", "max_evaluations: 30 → 31"},
      {"--tolerance", "0.5", "tolerance: " + tolerance + " → 0.5"},
      {"--population", "40", "population: " + population + " → 40"},
  };
  for (const auto& c : changed) {
    r = optimize({{c.option, c.value}});
    EXPECT_EQ(r.exit_code, 1) << c.option << "\n" << r.output;
    EXPECT_EQ(r.output.rfind("error: " + out + ": holds runs made with other settings", 0), 0u)
        << c.option << "\n"
        << r.output;
    // Alone on the line of the runs, or listed below it with what follows from it (the default
    // population of another solver, the default tolerance at another resolution).
    EXPECT_TRUE(r.output.find("  run-1.json (and 1 more run): " + c.expect + "\n") !=
                    std::string::npos ||
                (r.output.find("  run-1.json (and 1 more run):\n") != std::string::npos &&
                 r.output.find("\n    " + c.expect + "\n") != std::string::npos))
        << c.option << "\n"
        << r.output;
    EXPECT_NE(r.output.find("rerun with --restart"), std::string::npos) << r.output;
    EXPECT_EQ(snapshot(out), before) << c.option << ": the folder changed";
  }
  // Several at once: each named, under the runs that show them.
  r = optimize({{"--start", "corners"}, {"--max-evals", "31"}});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("run-1.json (and 1 more run):\n    start: random → corners\n"
                          "    max_evaluations: 30 → 31\n"),
            std::string::npos)
      << r.output;

  // The scene file's content (the description only: the bytes are what counts).
  const std::string scene_text = read(scene);
  std::string edited = scene_text;
  edited.replace(edited.find("resume test cell"), 16, "resume test cell, edited");
  write_file(scene, edited);
  r = optimize({});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("run-1.json (and 1 more run): scene " + scene + " changed (sha256 "),
            std::string::npos)
      << r.output;
  write_file(scene, scene_text);
  // A mesh file's content.
  write_file(dir + "/crate.off", crate_off("0.6"));
  r = optimize({});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("run-1.json (and 1 more run): mesh file " + dir +
                          "/crate.off changed (sha256 "),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("scene " + scene + " changed"), std::string::npos) << r.output;
  write_file(dir + "/crate.off", crate_off("0.5"));
  EXPECT_EQ(snapshot(out), before);

  // What does not change a run's Err resumes: the thread count, other seeds, progress output,
  // the same scene content at another path.
  fs::copy_file(scene, dir + "/cell-copy.json");
  r = camplace("optimize " + dir + "/cell-copy.json --mode center --max-evals 30 --out " + out +
               " --threads 2 --seed 5 --runs 1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out + "/run-5.json"));
  // An identical rerun reproduces the run (an evaluation budget, the same seed).
  r = optimize({});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(nlohmann::json::parse(read(out + "/run-1.json")).at("cameras"), run1.at("cameras"));

  // --restart: the run files, the summaries and validate's files go, files of the user stay.
  write_file(out + "/notes.txt", "mine");
  write_file(out + "/run-1 copy.json", "mine too");
  write_file(out + "/validation.csv", "run,scene\n");
  write_file(out + "/validation-cache/" + std::string(64, 'a') + ".json", "{}");
  r = optimize({{"--algorithm", "cmaes"}, {"--restart", ""}});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::set<std::string> files;
  for (const auto& e : fs::directory_iterator(out)) files.insert(e.path().filename().string());
  EXPECT_EQ(files, (std::set<std::string>{"notes.txt", "run-1 copy.json", "run-1.json",
                                          "summary.csv", "summary.json"}));
  EXPECT_EQ(read(out + "/notes.txt"), "mine");
  EXPECT_EQ(nlohmann::json::parse(read(out + "/run-1.json")).at("algorithm"), "cmaes");
  // The folder now holds cmaes runs: resuming with them works, gaco is refused.
  r = optimize({{"--algorithm", "cmaes"}, {"--seed", "2"}});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = optimize({});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("run-1.json (and 1 more run):\n    algorithm: cmaes → gaco\n"),
            std::string::npos)
      << r.output;
}

TEST(OptimizeResume, RestartOfAFolderWithoutRunsRemovesNothing) {
  // A folder that is not an optimize folder: --restart must not take anything from it.
  const std::string dir = temp_dir("optimize-restart-foreign");
  const std::string scene = write_file(dir + "/cell.json", kScene);
  write_file(dir + "/crate.off", crate_off("0.5"));
  write_file(dir + "/out/summary.txt", "mine");
  write_file(dir + "/out/data/run-1.json", "mine");  // not in the folder itself
  const CommandResult r = camplace("optimize " + scene + " --mode center --max-evals 20 --quiet" +
                                   " --restart --out " + dir + "/out");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read(dir + "/out/summary.txt"), "mine");
  EXPECT_EQ(read(dir + "/out/data/run-1.json"), "mine");
  EXPECT_TRUE(fs::exists(dir + "/out/run-1.json"));
}

}  // namespace
}  // namespace camplace::testing
