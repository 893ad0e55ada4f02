// Runs the real `camplace` binary: SIGINT during `camplace optimize` must leave a complete run
// file whose configuration `camplace evaluate` accepts and whose Err it reproduces.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <thread>

#include "command.hpp"

namespace {

using camplace::testing::capture;

using camplace::testing::wait_for;

namespace fs = std::filesystem;

const std::string kBinary = CAMPLACE_BINARY;
const std::string kScene = std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic.json";

/// Sends `sig` to a running `camplace optimize` and checks what it leaves (SIGINT,
/// SIGTERM and SIGHUP alike, exit status 128 + the signal).
void signal_leaves_a_complete_run_file(int sig) {
  const fs::path dir =
      fs::temp_directory_path() /
      ("camplace-cli-test-" + std::to_string(::getpid()) + "-" + std::to_string(sig));
  fs::remove_all(dir);
  const std::string log = (dir.string() + ".log");

  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    std::freopen(log.c_str(), "w", stdout);
    std::freopen((log + ".err").c_str(), "w", stderr);
    ::execl(kBinary.c_str(), kBinary.c_str(), "optimize", kScene.c_str(), "--out", dir.c_str(),
            "--seed", "3", "--runs", "5", "--time-limit", "60", "--threads", "2",
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  ASSERT_EQ(::kill(pid, sig), 0);
  const int status = wait_for(pid, 20.0);
  ASSERT_NE(status, -1) << "camplace optimize did not stop after signal " << sig;
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 128 + sig);

  // The run file is complete JSON (written through a temporary file and a rename).
  const fs::path run_file = dir / "run-3.json";
  ASSERT_TRUE(fs::exists(run_file));
  // Nothing else: no temporary file left, and Ctrl-C ended the whole job (no run-4.json).
  std::set<std::string> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    files.insert(entry.path().filename().string());
  }
  EXPECT_EQ(files, (std::set<std::string>{"run-3.json", "summary.csv", "summary.json"}));
  std::ifstream in(run_file);
  const nlohmann::json run = nlohmann::json::parse(in);  // throws on a truncated file
  EXPECT_EQ(run.at("stop_reason"), "interrupted");
  EXPECT_GT(run.at("evaluations").get<int>(), 0);
  EXPECT_EQ(run.at("cameras").size(), 6u);
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(dir / "summary.json"));
  EXPECT_TRUE(summary.at("interrupted").get<bool>());
  EXPECT_EQ(summary.at("runs"), 1);
  EXPECT_TRUE(fs::exists(dir / "summary.csv"));

  // `camplace evaluate` accepts the run file and reproduces its Err.
  const std::string output = capture("'" + kBinary + "' evaluate '" + kScene + "' --cameras '" +
                                     run_file.string() + "' --json");
  const nlohmann::json evaluated = nlohmann::json::parse(output);
  EXPECT_EQ(evaluated.at("err").get<double>(), run.at("err").get<double>());

  fs::remove_all(dir);
  fs::remove(log);
  fs::remove(log + ".err");
}

TEST(Cli, SigintLeavesACompleteRunFileThatEvaluateReproduces) {
  signal_leaves_a_complete_run_file(SIGINT);
}

TEST(Cli, SigtermAndSighupLeaveACompleteRunFileToo) {
  signal_leaves_a_complete_run_file(SIGTERM);
  signal_leaves_a_complete_run_file(SIGHUP);
}

TEST(Cli, HelpListsTheObjectiveOptionWithItsDefault) {
  const std::string text = capture(kBinary + " optimize --help 2>&1");
  const std::size_t option = text.find("--objective");
  ASSERT_NE(option, std::string::npos) << text;
  const std::string line = text.substr(option, text.find('\n', option) - option);
  EXPECT_NE(line.find("}=err"), std::string::npos) << text;  // the default, shown
  EXPECT_NE(line.find("err+volume"), std::string::npos) << text;
  EXPECT_NE(text.find("Objectives (--objective):"), std::string::npos) << text;
}

TEST(Cli, BadOptionValuesExitOneNamingTheOption) {
  const std::string out =
      (fs::temp_directory_path() / ("camplace-cli-bad-" + std::to_string(::getpid()))).string();
  const struct {
    std::string options, expect;
  } cases[] = {
      {"--population 100000000", "--population: must lie in [0, 100000]"},
      {"--time-limit nan", "--time-limit: must be a number of seconds"},
      {"--time-limit inf", "--time-limit: must be a number of seconds"},
      {"--max-evals -1", "--max-evals: must lie in [0, 1e12]"},
      {"--threads 100000", "--threads: must lie in [0, 256]"},
      {"--runs 0", "--runs: must lie in [1, 100000]"},
      {"--tolerance nan", "--tolerance: must be a finite number"},
      {"--algorithm foo", "error: command line: --algorithm"},
      {"--objective volume", "error: command line: --objective"},
      {"--objective ERR", "error: command line: --objective"},
      {"--seed -1", "error: command line: "},
  };
  for (const auto& c : cases) {
    const std::string text = capture(kBinary + " optimize " + kScene + " --quiet --out " + out +
                                     " " + c.options + " 2>&1; echo rc=$?");
    EXPECT_NE(text.find(c.expect), std::string::npos) << c.options << "\n" << text;
    EXPECT_EQ(text.rfind("error: ", 0), 0u) << c.options << "\n" << text;
    EXPECT_NE(text.find("rc=1\n"), std::string::npos) << c.options << "\n" << text;
  }
  fs::remove_all(out);
}

}  // namespace
