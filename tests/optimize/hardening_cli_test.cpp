// `camplace optimize` bounded and safe with others: --max-seconds bounds the whole command, a
// signal ends the scene's loading at once, a process whose folder was filled with runs of other
// settings while it ran writes nothing, the summary describes the run files on disk when
// processes of overlapping seeds share a folder, and a damaged run file is named.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "command.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const std::string kBinary = CAMPLACE_BINARY;
const std::string kScene = std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic.json";

CommandResult camplace(const std::string& args) { return run_camplace(kBinary, args); }

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Starts `camplace ARGS...` with stdout and stderr into `log`.
pid_t start(const std::vector<std::string>& args, const std::string& log) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::freopen(log.c_str(), "w", stdout);
    std::freopen(log.c_str(), "a", stderr);
    std::vector<char*> argv{const_cast<char*>(kBinary.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(kBinary.c_str(), argv.data());
    ::_exit(127);
  }
  return pid;
}

/// Waits until the process `pid` has a handler for SIGTERM (/proc/PID/status, SigCgt); false
/// after `seconds` or when it ended.
bool wait_until_catches_sigterm(pid_t pid, double seconds) {
  const auto begin = std::chrono::steady_clock::now();
  while (seconds_since(begin) < seconds) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(status, line);) {
      if (line.rfind("SigCgt:", 0) != 0) continue;
      const unsigned long long caught = std::stoull(line.substr(7), nullptr, 16);
      if ((caught >> (SIGTERM - 1)) & 1ULL) return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

json read_json(const fs::path& path) {
  std::ifstream in(path);
  return json::parse(in);
}

std::vector<fs::path> run_files(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("run-", 0) == 0 && e.path().extension() == ".json") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// Every row of summary.json's per_run is the run file of its seed (Err and evaluations), and
/// every run file has its row.
void expect_summary_matches_files(const fs::path& dir) {
  const json summary = read_json(dir / "summary.json");
  const std::vector<fs::path> files = run_files(dir);
  ASSERT_EQ(summary.at("per_run").size(), files.size()) << summary.dump(1);
  for (const json& row : summary.at("per_run")) {
    const fs::path file = dir / ("run-" + std::to_string(row.at("seed").get<unsigned>()) + ".json");
    ASSERT_TRUE(fs::exists(file)) << file;
    const json run = read_json(file);
    EXPECT_EQ(row.at("err").dump(), run.at("err").dump()) << file;
    EXPECT_EQ(row.at("evaluations"), run.at("evaluations")) << file;
  }
}

TEST(OptimizeHardening, MaxSecondsBoundsTheWholeCommandAndKeepsTheRunsMade) {
  const std::string out = temp_dir("max-seconds");
  const auto begin = std::chrono::steady_clock::now();
  const CommandResult r = camplace("optimize " + kScene + " --out " + out +
                                   " --runs 3 --time-limit 0 --tolerance 0 --max-seconds 1.5 "
                                   "--threads 1 --quiet");
  const double took = seconds_since(begin);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("error: optimize stopped: --max-seconds 1.5 exceeded; "),
            std::string::npos)
      << r.output;
  EXPECT_LT(took, 6.0) << r.output;
  // The runs made are written and summarised; the cut one stopped at the time limit.
  const std::vector<fs::path> files = run_files(out);
  ASSERT_FALSE(files.empty());
  EXPECT_EQ(read_json(files.back()).at("stop_reason"), "time_limit");
  EXPECT_EQ(read_json(fs::path(out) / "summary.json").at("runs"), files.size());
  expect_summary_matches_files(out);
  const CommandResult bad = camplace("optimize " + kScene + " --out " + out + " --max-seconds -1");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_EQ(bad.output.rfind("error: command line: --max-seconds", 0), 0u) << bad.output;
}

TEST(OptimizeHardening, ExportAndCompareHaveMaxSecondsToo) {
  // The exact pipeline over paper_basic's 6 states takes over a second: cut at 0.3 s.
  const std::string out = temp_dir("export-max-seconds");
  const std::string cameras = std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic_corners.json";
  for (const std::string command : {"export", "compare"}) {
    const auto begin = std::chrono::steady_clock::now();
    const CommandResult r =
        camplace(command + " " + kScene + " --cameras " + cameras + " --out " + out + "/" +
                 command + (command == "export" ? " --pipeline exact" : "") + " --max-seconds 0.3");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("error: " + command + " stopped: --max-seconds 0.3 exceeded; "),
              std::string::npos)
        << r.output;
    EXPECT_LT(seconds_since(begin), 3.0) << r.output;
  }
}

TEST(OptimizeHardening, TheOtherLongCommandsHaveMaxSecondsToo) {
  // Each is cut well before its work would end (an exact check of paper_basic takes most of a
  // second; the runs have no budget but a 600 s time limit), within a second of its deadline.
  const std::string dir = temp_dir("long-commands-max-seconds");
  const std::string cameras = std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic_corners.json";
  ASSERT_EQ(camplace("optimize " + kScene + " --out " + dir + "/opt --runs 1 --max-evals 20 " +
                     "--threads 1 --quiet")
                .exit_code,
            0);
  // 36x27x27 voxels: a run cannot reach its tolerance or lower bound within the second.
  const json study = {
      {"algorithm", "gaco"},
      {"mode", "conservative"},
      {"runs_per_group", 1},
      {"threads", 1},
      {"first_seed", 1},
      {"scene_seed", 1},
      {"time_limit_s", 600},
      {"max_evaluations", 2000000000},
      {"examinations",
       json::array({{{"name", "resolution"}, {"family", "resolution"}, {"params", {5}}}})}};
  const std::string study_file = write_file(dir + "/study.json", study.dump(1));
  struct Case {
    std::string command, args, kept;
    std::string seconds = "1";
  };
  const std::vector<Case> cases = {
      {"validate", dir + "/opt",
       "the exact checks finished so far are in " + dir +
           "/opt/validation-cache; rerun the same command to resume",
       "0.2"},
      {"compare-optimizer", kScene + " --runs " + dir + "/opt --out " + dir + "/co", ""},
      {"robustness",
       kScene + " --cameras " + cameras +
           " --position-tol 0.03 --angle-tol 2 --pipeline exact --out " + dir + "/rb",
       "nothing was written"},
      {"study", study_file + " --out " + dir + "/study",
       "the finished runs are in " + dir + "/study/runs"},
      {"plan",
       kScene + " --counts 2..3 --runs 1 --max-evals 0 --time-limit 600 --resolution " +
           "36x27x27 --threads 1 --out " + dir + "/plan",
       "the finished runs are in " + dir + "/plan/runs"}};
  for (const Case& c : cases) {
    const auto begin = std::chrono::steady_clock::now();
    const CommandResult r = camplace(c.command + " " + c.args + " --max-seconds " + c.seconds);
    const double took = seconds_since(begin);
    EXPECT_EQ(r.exit_code, 1) << c.command << ": " << r.output;
    EXPECT_NE(r.output.find("error: " + c.command + " stopped: --max-seconds " + c.seconds +
                            " exceeded; " + c.kept),
              std::string::npos)
        << c.command << ": " << r.output;
    EXPECT_LT(took, 4.0) << c.command << ": " << r.output;
  }
  // The study's and the plan's run under way got SIGTERM: it wrote its best so far as
  // "interrupted" (a rerun repeats it) instead of running on for 600 s.
  for (const std::string& file :
       {dir + "/study/runs/resolution-5/run-1.json", dir + "/plan/runs/2/run-1.json"}) {
    const auto begin = std::chrono::steady_clock::now();
    while (!fs::exists(file) && seconds_since(begin) < 10.0) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    ASSERT_TRUE(fs::exists(file)) << file;
    EXPECT_EQ(read_json(file).at("stop_reason"), "interrupted") << file;
  }
  // Without the bound, validate resumes from the cache and finishes.
  EXPECT_EQ(camplace("validate " + dir + "/opt").exit_code, 0);
}

TEST(OptimizeHardening, ASignalEndsTheScenesLoadingAtOnce) {
  // A scene whose static obstacle is a sphere of 360,000 triangles: its loading (reading,
  // checking) takes seconds. SIGTERM while it loads ends the process within a second, with
  // the status of the signal; it used to wait for the loading to end.
  const std::string dir = temp_dir("load-signal");
  {
    std::ofstream off(dir + "/ball.off");
    const int n = 300, m = 600;
    off << "OFF\n" << 2 + (n - 1) * m << " " << 2 * m * (n - 1) << " 0\n0 0 0.3\n";
    char line[96];
    for (int i = 1; i < n; ++i) {
      for (int j = 0; j < m; ++j) {
        const double th = M_PI * i / n, ph = 2 * M_PI * j / m;
        std::snprintf(line, sizeof line, "%.9f %.9f %.9f\n", 0.3 * std::sin(th) * std::cos(ph),
                      0.3 * std::sin(th) * std::sin(ph), 0.3 * std::cos(th));
        off << line;
      }
    }
    off << "0 0 -0.3\n";
    const auto idx = [&](int i, int j) { return 1 + (i - 1) * m + (j % m); };
    for (int j = 0; j < m; ++j) off << "3 0 " << idx(1, j) << " " << idx(1, j + 1) << "\n";
    for (int i = 1; i < n - 1; ++i) {
      for (int j = 0; j < m; ++j) {
        off << "3 " << idx(i, j) << " " << idx(i + 1, j) << " " << idx(i + 1, j + 1) << "\n3 "
            << idx(i, j) << " " << idx(i + 1, j + 1) << " " << idx(i, j + 1) << "\n";
      }
    }
    const int last = 1 + (n - 1) * m;
    for (int j = 0; j < m; ++j)
      off << "3 " << last << " " << idx(n - 1, j + 1) << " " << idx(n - 1, j) << "\n";
  }
  json scene = read_json(kScene);
  scene["static_obstacles"].push_back(
      {{"name", "ball"}, {"file", "ball.off"}, {"transform", {{"translate", {2, 1.5, 1.5}}}}});
  write_file(dir + "/scene.json", scene.dump());
  const pid_t pid =
      start({"optimize", dir + "/scene.json", "--out", dir + "/out", "--quiet"}, dir + "/log");
  // Signalled once its handlers are in place (they are installed just before the loading,
  // which then takes seconds): not after a guessed delay, which a loaded machine can outlast.
  ASSERT_TRUE(wait_until_catches_sigterm(pid, 20.0)) << read_text(dir + "/log");
  const auto signalled = std::chrono::steady_clock::now();
  ::kill(pid, SIGTERM);
  const int status = wait_for(pid, 10.0);
  const double took = seconds_since(signalled);
  ASSERT_TRUE(status != -1 && WIFEXITED(status)) << read_text(dir + "/log");
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM) << read_text(dir + "/log");
  // Within a second (the watcher looks every 50 ms); the loading takes 3-4 s.
  EXPECT_LT(took, 1.0) << read_text(dir + "/log");
  EXPECT_NE(read_text(dir + "/log").find("interrupted: nothing was written"), std::string::npos)
      << read_text(dir + "/log");
}

TEST(OptimizeHardening, RunsOfOtherSettingsWrittenMeanwhileStopTheProcessBeforeItWrites) {
  // A (center mode) runs for 6 s; B (conservative) starts after A's check of the empty folder
  // and writes its run first. A finds it under the folder's lock and writes nothing: the folder
  // holds only conservative runs and a summary of them.
  const std::string out = temp_dir("concurrent-settings") + "/out";
  const std::string logs = temp_dir("concurrent-settings-logs");
  const pid_t a = start({"optimize", kScene, "--out", out, "--seed", "1", "--mode", "center",
                         "--time-limit", "6", "--tolerance", "0", "--threads", "1", "--quiet"},
                        logs + "/a.log");
  // A makes its folder right after its check of the runs there: B starts then, not after a
  // guessed delay.
  const auto started = std::chrono::steady_clock::now();
  while (!fs::exists(out) && seconds_since(started) < 20.0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(fs::exists(out)) << read_text(logs + "/a.log");
  const CommandResult b = camplace("optimize " + kScene + " --out " + out +
                                   " --seed 5 --max-evals 30 --threads 1 --quiet");
  ASSERT_EQ(b.exit_code, 0) << b.output;
  const int status = wait_for(a, 30.0);
  const std::string log = read_text(logs + "/a.log");
  ASSERT_TRUE(status != -1 && WIFEXITED(status)) << log;
  EXPECT_EQ(WEXITSTATUS(status), 1) << log;
  EXPECT_NE(log.find("mode: conservative → center"), std::string::npos) << log;
  EXPECT_NE(log.find("the run of seed 1 was not written"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(fs::path(out) / "run-1.json"));
  for (const fs::path& file : run_files(out)) {
    EXPECT_EQ(read_json(file).at("context").at("mode"), "conservative") << file;
  }
  expect_summary_matches_files(out);
}

TEST(OptimizeHardening, TheSummaryDescribesTheRunFilesWhenSeedsOverlap) {
  // A makes seeds 1 and 2, B (started 0.5 s later) seeds 2 and 3, each run 1 s: B writes its
  // run 2 first, A overwrites it, B writes the last summary. It used to describe B's own run 2.
  const std::string out = temp_dir("concurrent-seeds");
  const std::string logs = temp_dir("concurrent-seeds-logs");
  const std::vector<std::string> common{"--runs",    "2", "--time-limit", "1", "--tolerance", "0",
                                        "--threads", "1", "--quiet"};
  std::vector<std::string> args_a{"optimize", kScene, "--out", out, "--seed", "1"};
  std::vector<std::string> args_b{"optimize", kScene, "--out", out, "--seed", "2"};
  args_a.insert(args_a.end(), common.begin(), common.end());
  args_b.insert(args_b.end(), common.begin(), common.end());
  const pid_t a = start(args_a, logs + "/a.log");
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const pid_t b = start(args_b, logs + "/b.log");
  const int status_a = wait_for(a, 30.0), status_b = wait_for(b, 30.0);
  ASSERT_TRUE(WIFEXITED(status_a) && WEXITSTATUS(status_a) == 0) << read_text(logs + "/a.log");
  ASSERT_TRUE(WIFEXITED(status_b) && WEXITSTATUS(status_b) == 0) << read_text(logs + "/b.log");
  EXPECT_EQ(run_files(out).size(), 3u);
  expect_summary_matches_files(out);
}

TEST(OptimizeHardening, ADamagedRunFileIsNamedBeforeAnyRun) {
  const std::string out = temp_dir("damaged-run");
  ASSERT_EQ(camplace("optimize " + kScene + " --out " + out + " --max-evals 20 --quiet").exit_code,
            0);
  json run = read_json(fs::path(out) / "run-1.json");
  run["cameras"].erase(run["cameras"].size() - 1);
  write_file(out + "/run-1.json", run.dump(1));
  const CommandResult r =
      camplace("optimize " + kScene + " --out " + out + " --seed 2 --max-evals 20 --quiet");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("error: " + out + "/run-1.json: /cameras: holds 5 cameras, the scene"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(fs::path(out) / "run-2.json"));
}

}  // namespace
}  // namespace camplace::testing
