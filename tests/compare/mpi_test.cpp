// `mpirun -n N camplace study|validate`: the runs spread over the ranks give the same
// results as a serial study; a run killed on a worker is redone elsewhere, a job killed as a
// whole resumes, each run made exactly once; validate under mpirun writes the same checks as a
// serial validate. Registered only when camplace is built with MPI. Tiny runs: seconds each.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <iterator>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cluster_support.hpp"
#include "command.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

namespace fs = std::filesystem;

CommandResult camplace(const std::string& args) { return run_camplace(CAMPLACE_BINARY, args); }

/// `mpirun -n ranks camplace args`. Open MPI refuses to run as root (CI containers) unless told
/// to, and warns about fork() on some networks: both only for this command. --bind-to none:
/// the ranks' runs may use any core.
CommandResult mpirun(int ranks, const std::string& args) {
  return run_camplace(
      "env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_mpi_warn_on_fork=0 "
      "mpirun --oversubscribe --bind-to none -n " +
          std::to_string(ranks) + " " + CAMPLACE_BINARY,
      args);
}

std::string study_file(int max_evaluations) {
  return write_file(temp_dir("mpi-study-" + std::to_string(max_evaluations)) + "/small.json",
                    small_study_json(max_evaluations));
}

/// How many times the output says a run was handed to a rank ("study: cameras-3 seed 1 on rank 2
/// (3 of 4 to run)", "... on rank 0 (again)").
int handed_out(const std::string& output) {
  const std::regex line(R"(study: \S+ seed \d+ on rank \d+ \()");
  return static_cast<int>(std::distance(std::sregex_iterator(output.begin(), output.end(), line),
                                        std::sregex_iterator()));
}

/// The named columns of a CSV file (no quoted fields), row by row: "a,b\n...".
std::string csv_columns(const std::string& path, const std::vector<std::string>& names) {
  std::istringstream in(read_text(path));
  auto split = [](const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) cells.push_back(cell);
    return cells;
  };
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split(line);
  std::vector<std::size_t> at;
  for (const std::string& name : names) {
    const auto found = std::find(header.begin(), header.end(), name);
    if (found == header.end()) return "no column " + name + " in " + path;
    at.push_back(static_cast<std::size_t>(found - header.begin()));
  }
  std::string out;
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = split(line);
    for (std::size_t i : at) out += (i < cells.size() ? cells[i] : "?") + ",";
    out += "\n";
  }
  return out;
}

TEST(MpiStudy, ThreeRanksGiveTheSerialStudysRunResults) {
  const std::string study = study_file(200);
  const std::string serial = temp_dir("mpi-serial"), spread = temp_dir("mpi-spread");
  const CommandResult s = camplace("study " + study + " --out " + serial);
  ASSERT_EQ(s.exit_code, 0) << s.output;
  const CommandResult m = mpirun(3, "study " + study + " --out " + spread);
  ASSERT_EQ(m.exit_code, 0) << m.output;
  EXPECT_NE(m.output.find("runs: 4 (0 found, 4 run now)\nreport: " + spread + "/report.md"),
            std::string::npos)
      << m.output;
  EXPECT_EQ(handed_out(m.output), 4) << m.output;
  // Longest first: the 4-camera group's runs are handed out before the 3-camera group's.
  EXPECT_LT(m.output.find("cameras-4 seed 2 on rank"), m.output.find("cameras-3 seed 1 on rank"))
      << m.output;
  const auto expected = run_results(serial);
  ASSERT_EQ(expected.size(), 4u);
  EXPECT_EQ(run_results(spread), expected);
  // The report's rows in the same (the study's) order with the same results.
  EXPECT_TRUE(fs::exists(spread + "/report.md"));
  EXPECT_EQ(csv_columns(spread + "/runs.csv", {"param", "seed", "err_m2", "evaluations"}),
            csv_columns(serial + "/runs.csv", {"param", "seed", "err_m2", "evaluations"}));
  const CommandResult again = mpirun(2, "study " + study + " --out " + spread);
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("runs: 4 (4 found, 0 run now)"), std::string::npos) << again.output;
}

/// The pid of a `camplace optimize` of the study into `out` whose parent is an MPI rank other
/// than 0, or 0. (Other tests may run studies at the same time.)
pid_t worker_run(const std::string& out) {
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string pid = e.path().filename().string();
    if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
    std::string cmdline = read_text("/proc/" + pid + "/cmdline");
    if (cmdline.find(std::string(CAMPLACE_BINARY) + '\0' + "optimize") != 0 ||
        cmdline.find("--out=" + out + "/runs/") == std::string::npos) {
      continue;
    }
    std::istringstream stat(read_text("/proc/" + pid + "/stat"));
    std::string field;
    for (int i = 0; i < 4; ++i) stat >> field;  // pid (comm) state ppid
    const std::string environ = read_text("/proc/" + field + "/environ");
    const std::string rank = std::string("OMPI_COMM_WORLD_RANK=");
    const std::size_t at = environ.find(rank);
    if (at != std::string::npos && environ.compare(at + rank.size(), 2, std::string("0\0", 2)) != 0)
      return static_cast<pid_t>(std::stol(pid));
  }
  return 0;
}

TEST(MpiStudy, ARunKilledOnAWorkerIsRedoneElsewhereAndEachRunIsMadeOnce) {
  const std::string study = study_file(3000);
  const std::string serial = temp_dir("mpi-kill-serial"), spread = temp_dir("mpi-kill");
  auto job = std::async(std::launch::async,
                        [&] { return mpirun(3, "study " + study + " --out " + spread); });
  pid_t victim = 0;
  for (int i = 0; i < 3000 && victim == 0; ++i) {
    victim = worker_run(spread);
    if (victim == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_NE(victim, 0) << "no run on a worker seen";
  ::kill(victim, SIGKILL);
  const CommandResult m = job.get();
  ASSERT_EQ(m.exit_code, 0) << m.output;
  EXPECT_NE(m.output.find("killed by signal 9 (Killed); handing it out again"), std::string::npos)
      << m.output;
  EXPECT_EQ(handed_out(m.output), 5) << m.output;  // 4 runs, one of them twice
  EXPECT_NE(m.output.find("runs: 4 (0 found, 4 run now)"), std::string::npos) << m.output;
  // The rerun finds every run; each was made once, as the serial study makes it.
  const CommandResult again = mpirun(3, "study " + study + " --out " + spread);
  EXPECT_NE(again.output.find("runs: 4 (4 found, 0 run now)"), std::string::npos) << again.output;
  const CommandResult s = camplace("study " + study + " --out " + serial);
  ASSERT_EQ(s.exit_code, 0) << s.output;
  EXPECT_EQ(run_results(spread), run_results(serial));
}

TEST(MpiStudy, AJobWhoseWorkerDiesResumesWithTheSameCommand) {
  const std::string study = study_file(3000);
  const std::string spread = temp_dir("mpi-worker-dies");
  auto job = std::async(std::launch::async,
                        [&] { return mpirun(3, "study " + study + " --out " + spread); });
  pid_t run = 0;
  for (int i = 0; i < 3000 && run == 0; ++i) {
    run = worker_run(spread);
    if (run == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_NE(run, 0) << "no run on a worker seen";
  // The worker rank itself (the run's parent): Open MPI ends the whole job.
  std::istringstream stat(read_text("/proc/" + std::to_string(run) + "/stat"));
  std::string field;
  for (int i = 0; i < 4; ++i) stat >> field;
  ::kill(static_cast<pid_t>(std::stol(field)), SIGKILL);
  const CommandResult killed = job.get();
  EXPECT_NE(killed.exit_code, 0) << killed.output;
  std::size_t kept = 0;  // finished runs (a run the signal stopped wrote an interrupted one)
  for (const auto& [file, result] : run_results(spread))
    kept += result.stop_reason != "interrupted";
  EXPECT_LT(kept, 4u) << killed.output;
  const CommandResult again = mpirun(2, "study " + study + " --out " + spread);
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("runs: 4 (" + std::to_string(kept) + " found, " +
                              std::to_string(4 - kept) + " run now)"),
            std::string::npos)
      << killed.output << again.output;
  EXPECT_EQ(handed_out(again.output), static_cast<int>(4 - kept)) << again.output;
  EXPECT_EQ(run_results(spread).size(), 4u);
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

/// validation.csv without the `seconds` column (the time each check took).
std::string without_seconds(const std::string& csv) {
  std::istringstream in(csv);
  std::string line, out;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) cells.push_back(cell);
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (i != 11) out += cells[i] + ",";  // 11: seconds
    }
    out += "\n";
  }
  return out;
}

TEST(MpiValidate, ChecksOnTwoRanksEqualTheSerialChecks) {
  const std::string dir = temp_dir("mpi-validate");
  const std::string scene = write_file(dir + "/cell.json", kCell);
  const CommandResult made = camplace("optimize " + scene +
                                      " --mode center --max-evals 20 --runs 5 --threads 1 "
                                      "--quiet --out " +
                                      dir + "/serial");
  ASSERT_EQ(made.exit_code, 0) << made.output;
  fs::copy(dir + "/serial", dir + "/spread", fs::copy_options::recursive);
  const CommandResult s = camplace("validate " + dir + "/serial --threads 1");
  ASSERT_EQ(s.exit_code, 0) << s.output;
  const CommandResult m = mpirun(2, "validate " + dir + "/spread --threads 1");
  ASSERT_EQ(m.exit_code, 0) << m.output;
  EXPECT_NE(m.output.find("checked 5 runs"), std::string::npos) << m.output;
  const std::string expected = read_text(dir + "/serial/validation.csv");
  ASSERT_NE(expected.find("run-5.json"), std::string::npos) << expected;
  EXPECT_EQ(without_seconds(read_text(dir + "/spread/validation.csv")), without_seconds(expected));
  // Every check is in the folder's cache, as after a serial validate.
  int entries = 0;
  for (const auto& e : fs::directory_iterator(dir + "/spread/validation-cache")) {
    entries += e.path().extension() == ".json";
  }
  EXPECT_EQ(entries, 5);
}

}  // namespace
}  // namespace camplace::testing
