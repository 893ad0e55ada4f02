// Two `camplace optimize` processes writing into one --out folder at the same time (a
// Slurm study runs several into one folder on purpose): the summary each writes covers every run
// file in the folder, so the last one lists both processes' seeds.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

namespace {

namespace fs = std::filesystem;

const std::string kBinary = CAMPLACE_BINARY;
const std::string kScene = std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic.json";

pid_t start_optimize(const fs::path& dir, const char* seed, const std::string& log) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::freopen(log.c_str(), "w", stdout);
    std::freopen(log.c_str(), "a", stderr);
    ::execl(kBinary.c_str(), kBinary.c_str(), "optimize", kScene.c_str(), "--out", dir.c_str(),
            "--seed", seed, "--runs", "1", "--max-evals", "300", "--threads", "1", "--quiet",
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

TEST(ConcurrentOptimize, TheSummaryListsTheRunsOfBothProcesses) {
  const fs::path dir =
      fs::temp_directory_path() / ("camplace-concurrent-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  // Several rounds: which process writes its summary last varies; it must list both each time.
  for (int round = 0; round < 3; ++round) {
    fs::remove_all(dir);
    const std::string log = dir.string() + ".log";
    const pid_t a = start_optimize(dir, "1", log + "1");
    const pid_t b = start_optimize(dir, "2", log + "2");
    ASSERT_GT(a, 0);
    ASSERT_GT(b, 0);
    int status_a = 0, status_b = 0;
    ::waitpid(a, &status_a, 0);
    ::waitpid(b, &status_b, 0);
    ASSERT_TRUE(WIFEXITED(status_a) && WEXITSTATUS(status_a) == 0) << round;
    ASSERT_TRUE(WIFEXITED(status_b) && WEXITSTATUS(status_b) == 0) << round;
    const nlohmann::json summary = nlohmann::json::parse(std::ifstream(dir / "summary.json"));
    EXPECT_EQ(summary.at("runs"), 2) << round;
    std::set<unsigned> seeds;
    for (const auto& row : summary.at("per_run")) seeds.insert(row.at("seed").get<unsigned>());
    EXPECT_EQ(seeds, (std::set<unsigned>{1, 2})) << round;
    // summary.csv: a header and one line per run.
    std::ifstream csv(dir / "summary.csv");
    int lines = 0;
    for (std::string line; std::getline(csv, line);) ++lines;
    EXPECT_EQ(lines, 3) << round;
    // No lock file or temporary file joins the folder.
    std::set<std::string> files;
    for (const auto& entry : fs::directory_iterator(dir)) {
      files.insert(entry.path().filename().string());
    }
    EXPECT_EQ(files,
              (std::set<std::string>{"run-1.json", "run-2.json", "summary.csv", "summary.json"}));
    // The printed table says which time each column is ("ms/eval" was read as wall
    // time): wall/eval is the run's seconds per evaluation, as summary.csv has it.
    if (round == 0) {
      std::ifstream printed(log + "1");
      std::string text((std::istreambuf_iterator<char>(printed)), std::istreambuf_iterator<char>());
      EXPECT_NE(text.find("ms/eval wall/eval"), std::string::npos) << text;
      EXPECT_NE(text.find("ms/eval: mean duration of one evaluation (wall clock on the thread "
                          "running it); wall/eval: the run's wall-clock time per evaluation"),
                std::string::npos)
          << text;
      const nlohmann::json run1 = nlohmann::json::parse(std::ifstream(dir / "run-1.json"));
      const double wall = run1.at("time_per_evaluation_ms").at("wall_clock").get<double>();
      EXPECT_NEAR(wall, run1.at("seconds").get<double>() * 1000.0 / 300.0, 1e-9);
      char cell[32];
      std::snprintf(cell, sizeof cell, "%.2f", wall);
      EXPECT_NE(text.find(cell), std::string::npos) << cell << "\n" << text;
    }
    fs::remove(log + "1");
    fs::remove(log + "2");
  }
  fs::remove_all(dir);
}

}  // namespace
