// `camplace study`: a study finishes, reruns identically, and an interrupted or damaged study
// resumes without repeating or losing runs.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "command.hpp"
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

int count_lines(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }

std::string study_json(int max_evaluations) {
  return R"({"description": "test study", "algorithm": "gaco", "mode": "conservative",
    "runs_per_group": 2, "threads": 1, "first_seed": 1, "scene_seed": 1,
    "time_limit_s": 120, "max_evaluations": )" + std::to_string(max_evaluations) + R"(,
    "examinations": [{"name": "cameras", "family": "cameras", "params": [3, 4]},
                     {"name": "ceiling", "family": "domain_ceiling"}]})";
}

// Columns before the timing ones (vm_peak_kb, seconds, *_ms) of runs.csv.
std::string without_timing(const std::string& csv) {
  std::stringstream in(csv), out;
  std::string line;
  while (std::getline(in, line)) {
    std::size_t pos = 0;
    for (int i = 0; i < 20; ++i) pos = line.find(',', pos) + 1;  // keep the first 20 columns
    out << line.substr(0, pos) << "\n";
  }
  return out.str();
}

TEST(Study, FinishesRerunsIdenticallyAndRedoesOnlyMissingRuns) {
  const std::string dir = temp_dir("study");
  const std::string study = write_file(dir + "/study.json", study_json(300));
  const std::string args = "study " + study + " --out " + dir + "/out";
  const CommandResult first = run_camplace(CAMPLACE_BINARY, args);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_NE(first.output.find("runs: 6 (0 found, 6 run now)"), std::string::npos) << first.output;
  const std::string csv = read(dir + "/out/runs.csv");
  EXPECT_EQ(count_lines(csv), 1 + 6);
  const std::string report = read(dir + "/out/report.md");
  EXPECT_NE(report.find("## Budget"), std::string::npos);
  EXPECT_TRUE(fs::exists(dir + "/out/success_vs_cameras.png"));
  EXPECT_TRUE(fs::exists(dir + "/out/time_vs_cameras.png"));

  // Delete one run: only that one is run again; the others keep their files untouched.
  const std::string gone = dir + "/out/runs/cameras-4/run-2.json";
  const std::string kept = dir + "/out/runs/cameras-3/run-1.json";
  const auto kept_time = fs::last_write_time(kept);
  ASSERT_TRUE(fs::remove(gone));
  const CommandResult second = run_camplace(CAMPLACE_BINARY, args);
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_NE(second.output.find("runs: 6 (5 found, 1 run now)"), std::string::npos) << second.output;
  EXPECT_TRUE(fs::exists(gone));
  EXPECT_EQ(fs::last_write_time(kept), kept_time);
  // With an evaluation budget the rows are the same apart from timing, and the report too.
  EXPECT_EQ(without_timing(read(dir + "/out/runs.csv")), without_timing(csv));
  const std::string report2 = read(dir + "/out/report.md");
  EXPECT_EQ(report2.substr(0, report2.find("## Time and memory")), report.substr(0, report.find("## Time and memory")));
}

TEST(Study, InterruptedStudyResumesWithoutRepeatingOrLosingRuns) {
  const std::string dir = temp_dir("study-int");
  const std::string study = write_file(dir + "/study.json", study_json(4000));
  // Start the study in its own process group and press Ctrl-C (SIGINT to the group) after a
  // while, as a terminal does.
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    setpgid(0, 0);
    const std::string out = dir + "/out";
    execl(CAMPLACE_BINARY, CAMPLACE_BINARY, "study", study.c_str(), "--out", out.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  setpgid(pid, pid);
  // Wait until at least one run is finished, then interrupt.
  const auto start = std::chrono::steady_clock::now();
  while (!fs::exists(dir + "/out/runs/cameras-3/run-1.json") &&
         std::chrono::steady_clock::now() - start < std::chrono::seconds(120)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  kill(-pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  // Finished runs before the interrupt.
  int finished_before = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir + "/out/runs")) {
    if (e.path().filename().string().rfind("run-", 0) == 0 && read(e.path().string()).find("\"interrupted\"") == std::string::npos) {
      ++finished_before;
    }
  }
  ASSERT_GE(finished_before, 1);
  ASSERT_LT(finished_before, 6) << "the study finished before the interrupt; the test proves nothing";
  const CommandResult resumed = run_camplace(CAMPLACE_BINARY, "study " + study + " --out " + dir + "/out");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("runs: 6 (" + std::to_string(finished_before) + " found, " +
                                std::to_string(6 - finished_before) + " run now)"),
            std::string::npos)
      << resumed.output;
  const std::string csv = read(dir + "/out/runs.csv");
  EXPECT_EQ(count_lines(csv), 1 + 6);
  // Every (group, seed) exactly once.
  for (const char* key : {"cameras,3,1,", "cameras,3,2,", "cameras,4,1,", "cameras,4,2,", "domain_ceiling,0,1,", "domain_ceiling,0,2,"}) {
    const std::size_t first = csv.find(key);
    EXPECT_NE(first, std::string::npos) << key;
    EXPECT_EQ(csv.find(key, first + 1), std::string::npos) << key;
  }
}

}  // namespace
}  // namespace camplace::testing
