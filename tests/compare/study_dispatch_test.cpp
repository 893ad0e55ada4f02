// compare::run_study with a RunDispatcher (the MPI path) standing in for the ranks:
// the dispatcher gets exactly the launches the serial study makes, longest expected first, and
// its outcomes are judged as the serial study judges a launch.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "camplace/compare/study.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

std::string read_all(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Writes the run file a launch would write: the bundled study's cameras-3 run with the
/// launch's settings (as study_test.cpp's FakeOptimize does).
void write_run_file(const compare::OptimizeLaunch& launch) {
  std::map<std::string, std::string> value;
  std::string out;
  for (std::size_t i = 0; i < launch.args.size(); ++i) {
    if (launch.args[i].rfind("--out=", 0) == 0) out = launch.args[i].substr(6);
    if (i + 1 < launch.args.size()) value[launch.args[i]] = launch.args[i + 1];
  }
  nlohmann::ordered_json run = nlohmann::ordered_json::parse(read_all(
      std::string(CAMPLACE_SOURCE_DIR) + "/docs/reports/study_cameras/runs/cameras-3/run-1.json"));
  run["algorithm"] = value.at("--algorithm");
  run["seed"] = std::stoi(value.at("--seed"));
  run["threads"] = std::stoi(value.at("--threads"));
  run["context"]["mode"] = value.at("--mode");
  run["context"]["time_limit_s"] = std::stod(value.at("--time-limit"));
  run["context"]["max_evaluations"] = std::stoll(value.at("--max-evals"));
  // As a run file of format 1 or 2 (no provenance): made on the folder's scene copy.
  run.erase("format_version");
  run.erase("provenance");
  write_file(out + "/run-" + value.at("--seed") + ".json", run.dump(2) + "\n");
}

/// Two groups (3 and 5 cameras), two runs each.
std::string study_json() {
  return R"({"description": "dispatch", "algorithm": "gaco", "mode": "conservative",
    "runs_per_group": 2, "threads": 1, "time_limit_s": 120, "max_evaluations": 50,
    "examinations": [{"name": "cameras", "family": "cameras", "params": [3, 5]}]})";
}

compare::StudyOptions options_for(const std::string& dir) {
  compare::StudyOptions options;
  options.study_file = write_file(dir + "/study.json", study_json());
  options.out_dir = dir + "/out";
  options.command = "test";
  return options;
}

TEST(StudyDispatch, TheDispatcherGetsTheSerialLaunchesLongestFirst) {
  const std::string dir = temp_dir("study-dispatch");
  // The serial study's launches, in its order.
  compare::StudyOptions serial = options_for(dir + "/serial");
  std::vector<compare::OptimizeLaunch> serial_launches;
  serial.launch = [&](const compare::OptimizeLaunch& launch) {
    serial_launches.push_back(launch);
    write_run_file(launch);
    return compare::LaunchOutcome{};
  };
  ASSERT_EQ(compare::run_study(serial).runs_done_now, 4);
  ASSERT_EQ(serial_launches.size(), 4u);

  compare::StudyOptions spread = options_for(dir + "/serial");  // the same folder: same paths
  spread.restart = true;
  std::vector<compare::PendingRun> given;
  spread.dispatch = [&](const std::vector<compare::PendingRun>& runs) {
    given = runs;
    std::vector<compare::LaunchOutcome> ended(runs.size());
    for (const compare::PendingRun& run : runs) write_run_file(run.launch);
    return ended;
  };
  const compare::StudyOutcome outcome = compare::run_study(spread);
  EXPECT_EQ(outcome.runs_done_now, 4);
  EXPECT_FALSE(outcome.interrupted);
  ASSERT_EQ(given.size(), 4u);
  // cameras-5 (5 cameras: each evaluation costs 5/3 of cameras-3's) first, then cameras-3; each
  // launch exactly the serial one of that run.
  const std::vector<int> serial_index = {2, 3, 0, 1};
  for (std::size_t i = 0; i < given.size(); ++i) {
    EXPECT_EQ(given[i].launch.args, serial_launches[serial_index[i]].args) << i;
    EXPECT_EQ(given[i].launch.output_file, serial_launches[serial_index[i]].output_file) << i;
  }
  EXPECT_EQ(given[0].label, "cameras-5 seed 1");
  EXPECT_EQ(given[3].label, "cameras-3 seed 2");
  EXPECT_EQ(given[0].run_file, dir + "/serial/out/runs/cameras-5/run-1.json");
  EXPECT_DOUBLE_EQ(given[0].cost / given[2].cost, 5.0 / 3.0);
}

TEST(StudyDispatch, RunsNotStartedMakeTheStudyInterruptedAndAFailedRunIsAnError) {
  const std::string dir = temp_dir("study-dispatch-outcomes");
  compare::StudyOptions options = options_for(dir);
  // Two runs finish, two are never started (an interrupt): the report covers the two.
  options.dispatch = [](const std::vector<compare::PendingRun>& runs) {
    std::vector<compare::LaunchOutcome> ended(runs.size());
    for (std::size_t i = 0; i < runs.size(); ++i) {
      if (i < 2) {
        write_run_file(runs[i].launch);
      } else {
        ended[i].interrupted = true;
      }
    }
    return ended;
  };
  compare::StudyOutcome outcome = compare::run_study(options);
  EXPECT_TRUE(outcome.interrupted);
  EXPECT_EQ(outcome.runs_done_now, 2);
  EXPECT_NE(read_all(options.out_dir + "/report.md").find("nterrupted"), std::string::npos);

  // The two left: one wrote no run file and failed.
  options.dispatch = [](const std::vector<compare::PendingRun>& runs) {
    std::vector<compare::LaunchOutcome> ended(runs.size());
    write_run_file(runs[0].launch);
    ended[1].failure = "exit status 1";
    return ended;
  };
  try {
    compare::run_study(options);
    FAIL() << "a failed run is an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("seed 2 wrote no run file (exit status 1; its standard "
                                         "output is in "),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace camplace::testing
