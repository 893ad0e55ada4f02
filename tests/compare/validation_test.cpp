// `camplace validate`: every run's exact check equals what `camplace evaluate` says
// for the same run file, reruns come from the cache, bad folders and files are errors that keep
// the other runs, and Ctrl-C mid-way resumes.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "command.hpp"
#include "report_header.hpp"
#include "scene_builder.hpp"

namespace camplace {
namespace {

namespace fs = std::filesystem;
using testing::CommandResult;
using testing::expect_provenance_header;
using testing::run_camplace;
using testing::temp_dir;
using testing::write_file;

// A small cell (exact evaluations take well under a second): a robot box and a person box,
// the robot modelled (so d(C, M) is not 0 by the robot's own silhouette), 2 pyramid cameras.
const char* kScene = R"({
  "area": {"min": [0, 0, 0], "max": [4, 3, 3]},
  "voxels": [8, 6, 6],
  "cameras": {"count": 2, "half_angle_deg": 35, "fov": "pyramid", "sides": 4},
  "dynamic_mode": "modelled",
  "time_steps": [{
    "dynamic_obstacles": [{"name": "robot", "box": {"min": [0.5, 0.5, 0], "max": [1.0, 1.0, 1.5]}}],
    "events": [{"weight": 1, "targets": [
      {"name": "person", "box": {"min": [2.5, 1.5, 0], "max": [3.0, 2.0, 1.8]}}]}]}]
})";

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

using CsvRow = std::map<std::string, std::string>;

/// validation.csv as rows of column → value (its fields hold no commas in these tests).
std::vector<CsvRow> read_csv(const std::string& path) {
  std::stringstream in(read(path));
  auto split = [](const std::string& line) {
    std::vector<std::string> cells;
    std::string cell;
    std::stringstream s(line);
    while (std::getline(s, cell, ',')) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    return cells;
  };
  std::string line;
  std::getline(in, line);
  const auto header = split(line);
  std::vector<CsvRow> rows;
  while (std::getline(in, line)) {
    const auto cells = split(line);
    CsvRow row;
    for (std::size_t i = 0; i < header.size() && i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

CommandResult camplace(const std::string& args) { return run_camplace(CAMPLACE_BINARY, args); }

/// An optimize folder with `runs` center-mode runs on the small cell.
std::string optimize_folder(const std::string& dir, int runs) {
  const std::string scene = write_file(dir + "/cell.json", kScene);
  const std::string out = dir + "/opt";
  const CommandResult r = camplace("optimize " + scene + " --mode center --max-evals 80 --runs " +
                                   std::to_string(runs) + " --quiet --out " + out);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return out;
}

TEST(Validate, ExactErrEqualsEvaluateOnTheRunFileAndRerunsComeFromTheCache) {
  const std::string dir = temp_dir("validate-basic");
  const std::string out = optimize_folder(dir, 2);
  const CommandResult first = camplace("validate " + out + " --threads 2");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_NE(first.output.find("checked 2 runs (0 from the cache)"), std::string::npos)
      << first.output;
  const std::string csv = read(out + "/validation.csv");
  const auto rows = read_csv(out + "/validation.csv");
  ASSERT_EQ(rows.size(), 2u);
  for (const CsvRow& row : rows) {
    const std::string run = out + "/" + row.at("run");
    const nlohmann::json run_file = nlohmann::json::parse(read(run));
    // The voxel Err as the run recorded it.
    EXPECT_EQ(std::stod(row.at("voxel_err")), run_file.at("err").get<double>());
    // The exact Err and the same-FOV voxel results, through `camplace evaluate` on the file.
    const CommandResult both = camplace("evaluate " + dir + "/cell.json --cameras " + run +
                                        " --pipeline both --mode center --resolution 8x6x6 --json");
    ASSERT_EQ(both.exit_code, 0) << both.output;
    const nlohmann::json j = nlohmann::json::parse(both.output);
    EXPECT_EQ(std::stod(row.at("exact_err")), j.at("exact").at("err").get<double>());
    EXPECT_EQ(std::stod(row.at("voxel_err_same_fov")), j.at("voxel").at("err").get<double>());
    double over = -1e300;
    for (std::size_t s = 0; s < j.at("exact").at("states").size(); ++s) {
      over = std::max(over, j["voxel"]["states"][s]["d_model"].get<double>() -
                                j["exact"]["states"][s]["d_model"].get<double>());
    }
    EXPECT_EQ(std::stod(row.at("max_overestimate")), over);
    const double target = std::stod(row.at("target"));
    EXPECT_EQ(target, run_file.at("tolerance").get<double>());  // center mode
    EXPECT_EQ(row.at("reached_exact"), std::stod(row.at("exact_err")) <= target ? "true" : "false");
    EXPECT_EQ(row.at("error"), "");
  }
  const CommandResult again = camplace("validate " + out);
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("checked 2 runs (2 from the cache)"), std::string::npos)
      << again.output;
  EXPECT_EQ(read(out + "/validation.csv"), csv);
  EXPECT_NE(read(out + "/validation.md").find("| 2 | 2 | 0 | 2 |"), std::string::npos);
  // The header names the runs' scene as they recorded it, with its SHA-256.
  const std::string scene =
      nlohmann::json::parse(read(out + "/run-1.json")).at("context").at("scene");
  expect_provenance_header(read(out + "/validation.md"),
                           "# Exact check of the optimizer results in " + out, scene, scene,
                           "folder `" + out + "`, threads ");
  EXPECT_EQ(read(out + "/validation.md").find("none could be read"), std::string::npos);
}

// A lone run's check gets every thread (its exact evaluation runs on them); of two runs on two
// threads the first gets one; the exact memory check sees those threads and refuses before the work
// (the run becomes a row with the reason); progress counts the exact (state, camera) steps.
TEST(Validate, ALoneRunsCheckGetsEveryThreadAndTheExactMemoryCheck) {
  const std::string dir = temp_dir("validate-threads");
  // Two time steps, so that the exact pipeline can use two threads.
  nlohmann::json scene = nlohmann::json::parse(kScene);
  scene["time_steps"].push_back(scene["time_steps"][0]);
  scene["time_steps"][1]["dynamic_obstacles"][0]["box"]["min"] = {0.5, 2.0, 0};
  scene["time_steps"][1]["dynamic_obstacles"][0]["box"]["max"] = {1.0, 2.5, 1.5};
  const std::string scene_file = write_file(dir + "/cell.json", scene.dump());
  auto folder = [&](const std::string& name, int runs) {
    const std::string out = dir + "/" + name;
    const CommandResult r =
        camplace("optimize " + scene_file + " --mode center --max-evals 40 --runs " +
                 std::to_string(runs) + " --quiet --out " + out);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return out;
  };
  const std::string one = folder("one", 1), two = folder("two", 2);
  const std::string tiny = "CAMPLACE_MEM_AVAILABLE_KB=1000 " + std::string(CAMPLACE_BINARY);
  const CommandResult lone = run_camplace(tiny, "validate " + one + " --threads 2");
  EXPECT_NE(lone.exit_code, 0);
  EXPECT_NE(lone.output.find("the exact pipeline with 2 cameras, 2 threads"), std::string::npos)
      << lone.output;
  const CommandResult pair = run_camplace(tiny, "validate " + two + " --threads 2");
  EXPECT_NE(pair.exit_code, 0);
  // The first run starts with the second still to come: one thread. (The second gets the
  // threads idle when it starts: two if the first has already been refused.)
  EXPECT_NE(pair.output.find("run-1.json: the exact pipeline with 2 cameras, 1 thread and"),
            std::string::npos)
      << pair.output;
  // With the memory there: checked, and the first progress line counts the steps (2 states ×
  // 2 cameras).
  const CommandResult ok = camplace("validate " + one + " --threads 2 --progress");
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(ok.output.find("exact (state, camera) steps of the checks under way 0/4"),
            std::string::npos)
      << ok.output;
  EXPECT_NE(ok.output.find("checked 1 runs (0 from the cache)"), std::string::npos) << ok.output;
}

TEST(Validate, BadFoldersAndFilesAreErrorsThatKeepTheOtherRuns) {
  const std::string dir = temp_dir("validate-bad");
  fs::create_directories(dir + "/empty");
  CommandResult r = camplace("validate " + dir + "/empty");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("error: " + dir + "/empty: holds no run file"), std::string::npos)
      << r.output;
  r = camplace("validate " + dir + "/nothing-here");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("not a folder"), std::string::npos) << r.output;

  const std::string out = optimize_folder(dir, 2);
  write_file(out + "/run-9.json", "{\"cameras\": [");
  r = camplace("validate " + out);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("error: " + out + "/run-9.json: not valid JSON"), std::string::npos)
      << r.output;
  auto rows = read_csv(out + "/validation.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].at("error"), "");
  EXPECT_EQ(rows[1].at("error"), "");
  EXPECT_NE(rows[2].at("error").find("not valid JSON"), std::string::npos);
  fs::remove(out + "/run-9.json");

  // The scene changed since the runs: its recorded SHA-256 no longer matches.
  write_file(dir + "/cell.json", std::string(kScene) + "\n");
  r = camplace("validate " + out);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("/provenance/scene_sha256: made for another scene (or the scene "
                          "changed since): scene " +
                          dir + "/cell.json changed (sha256 "),
            std::string::npos)
      << r.output;
  // The scene is gone.
  fs::remove(dir + "/cell.json");
  r = camplace("validate " + out);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(
      r.output.find("/context/scene: the scene file \"" + dir + "/cell.json\" does not exist"),
      std::string::npos)
      << r.output;
}

TEST(Validate, StudyFoldersAndCtrlCMidwayResume) {
  const std::string dir = temp_dir("validate-study");
  const std::string study = write_file(dir + "/study.json", R"({"description": "tiny",
    "algorithm": "gaco", "mode": "conservative", "runs_per_group": 3, "threads": 1,
    "time_limit_s": 60, "max_evaluations": 40,
    "examinations": [{"name": "cameras", "family": "cameras", "params": [3]}]})");
  const std::string out = dir + "/out";
  CommandResult r = camplace("study " + study + " --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;

  // Ctrl-C after the first finished run (one thread, so the others are still to come).
  int pipe_fd[2];
  ASSERT_EQ(pipe(pipe_fd), 0);
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(pipe_fd[1], STDERR_FILENO);
    dup2(pipe_fd[1], STDOUT_FILENO);
    close(pipe_fd[0]);
    close(pipe_fd[1]);
    execl(CAMPLACE_BINARY, CAMPLACE_BINARY, "validate", out.c_str(), "--threads", "1", "--progress",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  close(pipe_fd[1]);
  std::string seen;
  char buffer[256];
  ssize_t n = 0;
  bool sent = false;
  while ((n = ::read(pipe_fd[0], buffer, sizeof buffer)) > 0) {
    seen.append(buffer, n);
    if (!sent && seen.find("validate: 1/3 runs") != std::string::npos) {
      kill(pid, SIGINT);
      sent = true;
    }
  }
  close(pipe_fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(sent) << seen;
  ASSERT_TRUE(WIFEXITED(status)) << seen;
  EXPECT_EQ(WEXITSTATUS(status), 130) << seen;  // 128 + SIGINT
  EXPECT_NE(seen.find("interrupted: validate interrupted; rerun the same command to resume"),
            std::string::npos)
      << seen;
  const auto partial = read_csv(out + "/validation.csv");
  EXPECT_GE(partial.size(), 1u);
  EXPECT_LT(partial.size(), 3u);

  r = camplace("validate " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("checked 3 runs (" + std::to_string(partial.size()) + " from the cache)"),
            std::string::npos)
      << r.output;
  const auto rows = read_csv(out + "/validation.csv");
  ASSERT_EQ(rows.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(rows[i].at("run"), "runs/cameras-3/run-" + std::to_string(i + 1) + ".json");
    EXPECT_EQ(rows[i].at("mode"), "conservative");
    // Conservative mode: the target is max(tolerance, the run's lower bound L), SPEC §4, with
    // L read as reached within 1e-12 relative (Err and L sum in different orders).
    const double lower_bound = std::stod(rows[i].at("err_lower_bound"));
    EXPECT_EQ(std::stod(rows[i].at("target")),
              std::max(std::stod(rows[i].at("tolerance")), lower_bound * (1.0 + 1e-12)));
  }
}

}  // namespace
}  // namespace camplace
