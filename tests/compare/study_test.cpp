// `camplace study`: a study finishes, reruns identically, and an interrupted or damaged study
// resumes without repeating or losing runs; paths are names, never shell text; a run file the
// study cannot read is an error naming it. Also compare::run_study with launchers standing in
// for `camplace optimize`.
#include "camplace/compare/study.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

#include "camplace/core/error.hpp"
#include "camplace/optimize/report.hpp"
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

int count_lines(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

std::string study_json(int max_evaluations) {
  return R"({"description": "test study", "algorithm": "gaco", "mode": "conservative",
    "runs_per_group": 2, "threads": 1, "first_seed": 1, "scene_seed": 1,
    "time_limit_s": 120, "max_evaluations": )" +
         std::to_string(max_evaluations) + R"(,
    "examinations": [{"name": "cameras", "family": "cameras", "params": [3, 4]},
                     {"name": "ceiling", "family": "domain_ceiling"}]})";
}

/// A study of one group (3 cameras), `runs` runs of at most `max_evaluations` evaluations.
std::string tiny_study_json(int runs, int max_evaluations) {
  return R"({"description": "tiny", "algorithm": "gaco", "mode": "conservative",
    "runs_per_group": )" +
         std::to_string(runs) + R"(, "threads": 1, "time_limit_s": 120,
    "max_evaluations": )" +
         std::to_string(max_evaluations) + R"(,
    "examinations": [{"name": "cameras", "family": "cameras", "params": [3]}]})";
}

using CsvRow = std::map<std::string, std::string>;

/// A CSV file (no quoted fields) as rows of column name → value.
std::vector<CsvRow> read_csv(const std::string& path) {
  std::stringstream in(read(path));
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
  std::vector<CsvRow> rows;
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = split(line);
    EXPECT_EQ(cells.size(), header.size()) << line;
    CsvRow row;
    for (std::size_t i = 0; i < header.size() && i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

/// The rows without the timing columns of runs.csv (they vary between runs).
std::vector<CsvRow> without_timing(std::vector<CsvRow> rows) {
  for (CsvRow& row : rows) {
    for (const char* column :
         {"vm_peak_kb", "seconds", "labelling_ms", "clustering_ms", "distance_ms", "total_ms"}) {
      EXPECT_EQ(row.erase(column), 1u) << column;
    }
  }
  return rows;
}

/// Runs the camplace binary with `args`, one argument each, in the directory `cwd` (no shell),
/// capturing stdout and stderr.
CommandResult run_in(const std::string& cwd, const std::vector<std::string>& args) {
  std::vector<std::string> words = {CAMPLACE_BINARY};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  int out[2];
  EXPECT_EQ(pipe(out), 0);
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(out[1], STDOUT_FILENO);
    dup2(out[1], STDERR_FILENO);
    close(out[0]);
    close(out[1]);
    if (chdir(cwd.c_str()) == 0) execv(CAMPLACE_BINARY, argv.data());
    _exit(127);
  }
  close(out[1]);
  CommandResult result;
  char buffer[4096];
  ssize_t n = 0;
  while ((n = ::read(out[0], buffer, sizeof buffer)) > 0) result.output.append(buffer, n);
  close(out[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
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
  const std::vector<CsvRow> rows = read_csv(dir + "/out/runs.csv");
  const std::string report = read(dir + "/out/report.md");
  EXPECT_NE(report.find("## Budget"), std::string::npos);
  EXPECT_TRUE(fs::exists(dir + "/out/err_vs_cameras.png"));
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
  EXPECT_EQ(without_timing(read_csv(dir + "/out/runs.csv")), without_timing(rows));
  // Apart from the header's start time (when the study was run).
  auto without_start = [](std::string md) {
    const std::size_t started = md.find("\n| started | ");
    EXPECT_NE(started, std::string::npos);
    if (started != std::string::npos) md.erase(started, md.find('\n', started + 1) - started);
    return md.substr(0, md.find("## Time and memory"));
  };
  const std::string report2 = read(dir + "/out/report.md");
  EXPECT_EQ(without_start(report2), without_start(report));

  // The header names the build of every run, not only the one writing the report: a run made
  // by another build (a study resumed after an update) is counted apart.
  const std::string build =
      "0.1.0, commit " +
      nlohmann::json::parse(read(kept))["provenance"]["commit"].get<std::string>();
  EXPECT_NE(report2.find("| runs made by | " + build + " (6 runs) |"), std::string::npos)
      << report2;
  nlohmann::ordered_json other = nlohmann::ordered_json::parse(read(gone));
  other["provenance"]["commit"] = "0123456789abcdef0123456789abcdef01234567";
  write_file(gone, other.dump(2) + "\n");
  const CommandResult third = run_camplace(CAMPLACE_BINARY, args + " --report-only");
  ASSERT_EQ(third.exit_code, 0) << third.output;
  EXPECT_NE(read(dir + "/out/report.md")
                .find("| runs made by | 0.1.0, commit 0123456789abcdef0123456789abcdef01234567 "
                      "(1 runs); " +
                      build + " (5 runs) |"),
            std::string::npos)
      << read(dir + "/out/report.md");
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
    execl(CAMPLACE_BINARY, CAMPLACE_BINARY, "study", study.c_str(), "--out", out.c_str(),
          static_cast<char*>(nullptr));
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
    if (e.path().filename().string().rfind("run-", 0) == 0 &&
        read(e.path().string()).find("\"interrupted\"") == std::string::npos) {
      ++finished_before;
    }
  }
  ASSERT_GE(finished_before, 1);
  ASSERT_LT(finished_before, 6)
      << "the study finished before the interrupt; the test proves nothing";
  const CommandResult resumed =
      run_camplace(CAMPLACE_BINARY, "study " + study + " --out " + dir + "/out");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("runs: 6 (" + std::to_string(finished_before) + " found, " +
                                std::to_string(6 - finished_before) + " run now)"),
            std::string::npos)
      << resumed.output;
  const std::vector<CsvRow> rows = read_csv(dir + "/out/runs.csv");
  EXPECT_EQ(rows.size(), 6u);
  // Every (group, seed) exactly once.
  std::multiset<std::string> runs;
  for (const CsvRow& row : rows) {
    runs.insert(row.at("family") + "," + row.at("param") + "," + row.at("seed"));
  }
  for (const char* key : {"cameras,3,1", "cameras,3,2", "cameras,4,1", "cameras,4,2",
                          "domain_ceiling,0,1", "domain_ceiling,0,2"}) {
    EXPECT_EQ(runs.count(key), 1u) << key;
  }
}

TEST(Study, PathsWithQuotesAndSpacesAreNamesNotShellText) {
  // The study file and the output directory (so the generated scene, the run directory and the
  // plots' files) carry a quote and a space; the output directory is a shell injection
  // attempt, which must create a directory of that name and run nothing.
  const std::string dir = temp_dir("study-quote") + "/it's a dir";
  const std::string study = write_file(dir + "/it's study.json", tiny_study_json(2, 60));
  const std::string out = "x';touch injected;'";
  const CommandResult r = run_in(dir, {"study", study, "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("runs: 2 (0 found, 2 run now)"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir + "/injected"));
  EXPECT_FALSE(fs::exists(dir + "/x"));
  const std::string run_file = dir + "/" + out + "/runs/cameras-3/run-2.json";
  ASSERT_TRUE(fs::exists(run_file));
  const nlohmann::json run = nlohmann::json::parse(read(run_file));
  EXPECT_EQ(run.at("context").at("scene"), out + "/scenes/cameras-3.json");
  EXPECT_EQ(run.at("evaluations"), 60);
  EXPECT_EQ(read_csv(dir + "/" + out + "/runs.csv").size(), 2u);
  EXPECT_TRUE(fs::exists(dir + "/" + out + "/err_vs_cameras.png"));
  EXPECT_TRUE(fs::exists(dir + "/" + out + "/time_vs_cameras.png"));
  // The kept script names its files relative to its folder (rerunnable there), so the folder's
  // quote never reaches gnuplot's text.
  const std::string gp = read(dir + "/" + out + "/err_vs_cameras.gp");
  EXPECT_EQ(gp.find("touch injected"), std::string::npos) << gp;
  EXPECT_NE(gp.find("set output 'err_vs_cameras.png'"), std::string::npos) << gp;
  EXPECT_NE(gp.find("'err_vs_cameras.dat'"), std::string::npos) << gp;
}

TEST(Study, DamagedRunFilesAndUnknownFormatsAreErrorsNamingTheFileAndInterruptedRunsRunAgain) {
  const std::string dir = temp_dir("study-damaged");
  const std::string study = write_file(dir + "/study.json", tiny_study_json(2, 80));
  const std::vector<std::string> args = {"study", study, "--out", dir + "/out"};
  const CommandResult first = run_in(dir, args);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const std::string run1 = dir + "/out/runs/cameras-3/run-1.json";
  const std::string run2 = dir + "/out/runs/cameras-3/run-2.json";
  const std::string good1 = read(run1), good2 = read(run2);

  // Not JSON: an error naming the file; the file is kept as it is, not run again.
  write_file(run1, "{\"cameras\": [");
  const CommandResult damaged = run_in(dir, args);
  EXPECT_EQ(damaged.exit_code, 1) << damaged.output;
  EXPECT_NE(damaged.output.find("error: " + run1 + ": not valid JSON"), std::string::npos)
      << damaged.output;
  EXPECT_EQ(read(run1), "{\"cameras\": [");
  write_file(run1, good1);

  // A format this version does not know (written by a newer camplace, say).
  nlohmann::ordered_json newer = nlohmann::ordered_json::parse(good2);
  EXPECT_EQ(newer.at("format_version"), optimize::kRunFileFormat);
  newer["format_version"] = 99;
  write_file(run2, newer.dump(2));
  const CommandResult unknown = run_in(dir, args);
  EXPECT_EQ(unknown.exit_code, 1) << unknown.output;
  EXPECT_NE(unknown.output.find("error: " + run2 + ": /format_version: unknown run file format 99"),
            std::string::npos)
      << unknown.output;
  // A run file without the version is format 1 (the files under docs/reports).
  newer.erase("format_version");
  newer.erase("provenance");
  write_file(run2, newer.dump(2));

  // An interrupted run is run again, with the same result (evaluation budget, same seed).
  nlohmann::ordered_json interrupted = nlohmann::ordered_json::parse(good1);
  interrupted["stop_reason"] = "interrupted";
  write_file(run1, interrupted.dump(2));
  const CommandResult resumed = run_in(dir, args);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("runs: 2 (1 found, 1 run now)"), std::string::npos)
      << resumed.output;
  const nlohmann::json again = nlohmann::json::parse(read(run1));
  const nlohmann::json before = nlohmann::json::parse(good1);
  EXPECT_EQ(again.at("stop_reason"), before.at("stop_reason"));
  EXPECT_EQ(again.at("err"), before.at("err"));
  EXPECT_EQ(again.at("cameras"), before.at("cameras"));
}

/// A stand-in for `camplace optimize`: records the launch and copies a real run file (from
/// docs/reports, 3 cameras, format 1) to where the run's `--out=` directory puts it, with the
/// launch's settings (so that a rerun of the study finds it one of its runs).
struct FakeOptimize {
  std::vector<compare::OptimizeLaunch> launches;
  bool write_run_file = true;
  compare::LaunchOutcome outcome;

  compare::LaunchOutcome operator()(const compare::OptimizeLaunch& launch) {
    launches.push_back(launch);
    std::map<std::string, std::string> value;
    std::string out;
    for (std::size_t i = 0; i < launch.args.size(); ++i) {
      if (launch.args[i].rfind("--out=", 0) == 0) out = launch.args[i].substr(6);
      if (i + 1 < launch.args.size()) value[launch.args[i]] = launch.args[i + 1];
    }
    if (write_run_file) {
      nlohmann::ordered_json run = nlohmann::ordered_json::parse(
          read(std::string(CAMPLACE_SOURCE_DIR) +
               "/docs/reports/study_cameras/runs/cameras-3/run-1.json"));
      run["algorithm"] = value.at("--algorithm");
      run["seed"] = std::stoi(value.at("--seed"));
      run["threads"] = std::stoi(value.at("--threads"));
      run["context"]["mode"] = value.at("--mode");
      run["context"]["time_limit_s"] = std::stod(value.at("--time-limit"));
      run["context"]["max_evaluations"] = std::stoll(value.at("--max-evals"));
      if (value.count("--refine")) run["context"]["refine"] = std::stoi(value.at("--refine"));
      if (value.count("--objective")) run["objective"] = value.at("--objective");
      write_file(out + "/run-" + value.at("--seed") + ".json", run.dump(2) + "\n");
    }
    return outcome;
  }
};

TEST(Study, RunStudyLaunchesEachMissingRunWithOneArgumentPerValue) {
  const std::string dir = temp_dir("study-launcher") + "/it's out";
  const std::string study = write_file(dir + "/study.json", tiny_study_json(2, 50));
  compare::StudyOptions options;
  options.study_file = study;
  options.out_dir = dir;
  options.command = "test";
  auto fake = std::make_shared<FakeOptimize>();
  options.launch = [fake](const compare::OptimizeLaunch& l) { return (*fake)(l); };
  const compare::StudyOutcome outcome = compare::run_study(options);
  EXPECT_EQ(outcome.runs_total, 2);
  EXPECT_EQ(outcome.runs_done_now, 2);
  EXPECT_FALSE(outcome.interrupted);
  ASSERT_EQ(fake->launches.size(), 2u);
  const std::string run_dir = dir + "/runs/cameras-3";
  const std::vector<std::string> expected = {"--algorithm",  "gaco",
                                             "--seed",       "2",
                                             "--runs",       "1",
                                             "--threads",    "1",
                                             "--time-limit", "120.000",
                                             "--max-evals",  "50",
                                             "--mode",       "conservative",
                                             "--quiet",      "--out=" + run_dir,
                                             "--",           dir + "/scenes/cameras-3.json"};
  EXPECT_EQ(fake->launches[1].args, expected);
  EXPECT_EQ(fake->launches[1].output_file, run_dir + "/output-2.txt");
  // The rows are the copied run file's.
  const std::vector<CsvRow> rows = read_csv(dir + "/runs.csv");
  ASSERT_EQ(rows.size(), 2u);
  const nlohmann::json run = nlohmann::json::parse(read(
      std::string(CAMPLACE_SOURCE_DIR) + "/docs/reports/study_cameras/runs/cameras-3/run-1.json"));
  EXPECT_EQ(rows[1].at("seed"), "2");
  EXPECT_EQ(rows[1].at("evaluations"), std::to_string(run.at("evaluations").get<long long>()));
  EXPECT_EQ(rows[1].at("stop_reason"), run.at("stop_reason").get<std::string>());

  // Everything found: nothing is launched.
  fake->launches.clear();
  EXPECT_EQ(compare::run_study(options).runs_done_before, 2);
  EXPECT_TRUE(fake->launches.empty());
}

TEST(Study, AnExaminationsOwnRefineAndObjectiveReachItsRunsAndTheirResume) {
  const std::string dir = temp_dir("study-overrides");
  auto study_text = [](const std::string& own) {
    return R"({"algorithm": "gaco", "mode": "conservative", "refine": 1, "runs_per_group": 1,
      "threads": 1, "time_limit_s": 120, "max_evaluations": 50,
      "examinations": [{"name": "cameras", "family": "cameras", "params": [3])" +
           own + R"(}, {"name": "ceiling", "family": "domain_ceiling"}]})";
  };
  const std::string study = write_file(
      dir + "/study.json", study_text(R"(, "refine": 2, "objective": "err+touching-volume")"));
  compare::StudyOptions options;
  options.study_file = study;
  options.out_dir = dir + "/out";
  options.command = "test";
  auto fake = std::make_shared<FakeOptimize>();
  options.launch = [fake](const compare::OptimizeLaunch& l) { return (*fake)(l); };
  compare::run_study(options);
  ASSERT_EQ(fake->launches.size(), 2u);
  auto value_of = [](const std::vector<std::string>& args, const std::string& option) {
    const auto it = std::find(args.begin(), args.end(), option);
    return it == args.end() || it + 1 == args.end() ? std::string("absent") : *(it + 1);
  };
  // The examination's own values, and the study's (objective err: no option) for the other.
  EXPECT_EQ(value_of(fake->launches[0].args, "--refine"), "2");
  EXPECT_EQ(value_of(fake->launches[0].args, "--objective"), "err+touching-volume");
  EXPECT_EQ(value_of(fake->launches[1].args, "--refine"), "1");
  EXPECT_EQ(value_of(fake->launches[1].args, "--objective"), "absent");
  const std::string report = read(dir + "/out/report.md");
  EXPECT_NE(report.find("1; 2 for \"cameras\""), std::string::npos) << report;
  EXPECT_NE(report.find("err; err+touching-volume for \"cameras\""), std::string::npos) << report;

  // Resuming checks each group against its own values: the same study launches nothing, another
  // level for the examination is a changed setting of its runs.
  fake->launches.clear();
  std::filesystem::remove_all(dir + "/out/runs/domain_ceiling");  // another scene: copied file
  compare::run_study(options);
  ASSERT_EQ(fake->launches.size(), 1u);
  EXPECT_EQ(value_of(fake->launches[0].args, "--seed"), "1");
  EXPECT_NE(fake->launches[0].output_file.find("domain_ceiling"), std::string::npos);
  std::filesystem::remove_all(dir + "/out/runs/domain_ceiling");
  write_file(study, study_text(R"(, "refine": 3, "objective": "err+touching-volume")"));
  try {
    compare::run_study(options);
    ADD_FAILURE() << "a changed examination refine was resumed";
  } catch (const optimize::SettingsChanged& e) {
    EXPECT_NE(std::string(e.what()).find("refine: 2 → 3"), std::string::npos) << e.what();
  }
}

TEST(Study, AnExaminationsOwnRefineAndObjectiveAreCheckedLikeTheStudys) {
  const std::string dir = temp_dir("study-overrides-bad");
  auto attempt = [&dir](const std::string& mode, const std::string& own) {
    const std::string study = write_file(dir + "/study.json", R"({"mode": ")" + mode +
                                                                  R"(", "runs_per_group": 1,
          "time_limit_s": 120, "max_evaluations": 50,
          "examinations": [{"family": "cameras", "params": [3]}, {"family": "cameras",
          "name": "more", "params": [4], )" + own + "}]}");
    compare::StudyOptions options;
    options.study_file = study;
    options.out_dir = dir + "/out";
    options.launch = [](const compare::OptimizeLaunch&) { return compare::LaunchOutcome{}; };
    try {
      compare::run_study(options);
    } catch (const core::InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(attempt("center", R"("refine": 1)")
                .find("/examinations/1/refine: refinement needs \"mode\": \"conservative\""),
            std::string::npos);
  EXPECT_NE(attempt("conservative", R"("refine": 11)").find("/examinations/1/refine"),
            std::string::npos);
  EXPECT_NE(
      attempt("conservative", R"("refine": 5)").find("/examinations/1/refine: cameras-4: 5 levels"),
      std::string::npos);
  EXPECT_NE(attempt("conservative", R"("objective": "volume")")
                .find("/examinations/1/objective: unknown objective \"volume\""),
            std::string::npos);
  EXPECT_NE(attempt("conservative", R"("seeds": 3)").find("/examinations/1"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir + "/out/runs"));
}

TEST(Study, RunStudyStopsAtAnInterruptAndReportsAFailedRun) {
  const std::string dir = temp_dir("study-launch-fail");
  const std::string study = write_file(dir + "/study.json", tiny_study_json(3, 50));
  compare::StudyOptions options;
  options.study_file = study;
  options.out_dir = dir + "/out";
  auto fake = std::make_shared<FakeOptimize>();
  options.launch = [fake](const compare::OptimizeLaunch& l) { return (*fake)(l); };

  // Ctrl-C during the first run, which still finishes: the study stops after it.
  fake->outcome.interrupted = true;
  compare::StudyOutcome outcome = compare::run_study(options);
  EXPECT_TRUE(outcome.interrupted);
  EXPECT_EQ(outcome.runs_done_now, 1);
  EXPECT_EQ(fake->launches.size(), 1u);
  EXPECT_NE(read(dir + "/out/report.md").find("**Interrupted**"), std::string::npos);

  // A run that ends without a run file and without Ctrl-C is an error naming the run.
  fake->outcome = {false, "exit status 1"};
  fake->write_run_file = false;
  try {
    compare::run_study(options);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("cameras-3 seed 2"), std::string::npos) << what;
    EXPECT_NE(what.find("exit status 1"), std::string::npos) << what;
  }
  // Killed by Ctrl-C before writing anything: interrupted, no error.
  fake->outcome = {true, "killed by signal 2 (Interrupt)"};
  outcome = compare::run_study(options);
  EXPECT_TRUE(outcome.interrupted);
  EXPECT_EQ(outcome.runs_done_before, 1);
  EXPECT_EQ(outcome.runs_done_now, 0);
}

}  // namespace
}  // namespace camplace::testing
