// `compare`, `evaluate --pipeline exact|both` and `export --pipeline exact` as long work:
// progress, the memory check, the summary
// line naming each number's resolution, a signal ending compare within a second with the
// evaluations done kept in a report marked incomplete, and one shape of `evaluate --json`.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <thread>

#include "command.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

namespace fs = std::filesystem;

CommandResult run(const std::string& args) { return run_camplace(CAMPLACE_BINARY, args); }

const std::string kScene = std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic.json";
const std::string kCameras = std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic_corners.json";
const std::string kBasic = kScene + " --cameras " + kCameras;

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// Files in `dir` whose name holds ".tmp" (an unfinished atomic write).
int temporary_files(const std::string& dir) {
  int count = 0;
  std::error_code ec;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    count += has(it->path().filename().string(), ".tmp");
  }
  return count;
}

/// `camplace compare SCENE --cameras CAMERAS --resolutions R --out DIR` in the background.
pid_t start_compare(const std::string& resolutions, const std::string& dir,
                    const std::string& log) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::freopen(log.c_str(), "w", stdout);
    std::freopen(log.c_str(), "a", stderr);
    ::execl(CAMPLACE_BINARY, CAMPLACE_BINARY, "compare", kScene.c_str(), "--cameras",
            kCameras.c_str(), "--resolutions", resolutions.c_str(), "--out", dir.c_str(),
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

TEST(CompareLongWork, SummaryNamesEachResolutionAndProgressCountsStepsAndEvaluations) {
  const std::string dir = temp_dir("compare-summary") + "/out";
  const CommandResult r =
      run("compare " + kBasic + " --resolutions 8x6x6,16x12x12 --out " + dir + " --progress");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The exact pipeline in (state, camera) steps: paper_basic's 6 states × 6 cameras; then
  // 1 exact + 2 resolutions × (center, conservative) = 5 evaluations.
  EXPECT_TRUE(has(r.output, "compare: exact pipeline, (state, camera) steps 0/36")) << r.output;
  EXPECT_TRUE(has(r.output, "compare: exact pipeline, (state, camera) steps 36/36")) << r.output;
  EXPECT_TRUE(has(r.output, "compare: voxel pipelines, evaluations 5/5")) << r.output;
  for (const char* line :
       {"  voxel-center at 8x6x6: ", "  voxel-conservative at 8x6x6: ",
        "  voxel-center at 16x12x12: ", "  voxel-conservative at 16x12x12: ", "  exact: "}) {
    EXPECT_TRUE(has(r.output, line)) << line << "\n" << r.output;
  }
  // The printed numbers are err.csv's (9 decimals there, 6 significant digits here).
  const std::string err_csv = read_text(dir + "/err.csv");
  std::smatch m;
  ASSERT_TRUE(
      std::regex_search(r.output, m, std::regex("voxel-conservative at 16x12x12: ([0-9.e-]+)")));
  const double printed = std::stod(m[1]);
  ASSERT_TRUE(std::regex_search(err_csv, m, std::regex("voxel-conservative,16x12x12,([0-9.e-]+)")));
  EXPECT_NEAR(printed, std::stod(m[1]), 1e-5 * std::stod(m[1]));
  EXPECT_FALSE(has(read_text(dir + "/report.md"), "Incomplete"));
}

// A signal while the exact pipeline runs: nothing to keep yet, the process ends within a second.
TEST(CompareLongWork, SignalDuringTheExactPipelineEndsWithinASecondWritingNothing) {
  const std::string base = temp_dir("compare-signal-exact");
  const std::string dir = base + "/out", log = base + "/log";
  const pid_t pid = start_compare("16x12x12", dir, log);
  ASSERT_GT(pid, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  const auto sent = std::chrono::steady_clock::now();
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  const int status = wait_for(pid, 30.0);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  ASSERT_NE(status, -1);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
  EXPECT_LT(seconds, 1.0);
  EXPECT_TRUE(has(read_text(log), "interrupted: nothing was written")) << read_text(log);
  EXPECT_FALSE(fs::exists(dir + "/report.md"));
  EXPECT_EQ(temporary_files(dir), 0);
}

// A signal while a fine grid's voxel pipeline is set up, after the coarse grid's evaluations:
// within a second, the report of the evaluations done, marked incomplete.
TEST(CompareLongWork, SignalAfterSomeEvaluationsKeepsAnIncompleteReport) {
  const std::string base = temp_dir("compare-signal-voxel");
  const std::string dir = base + "/out", log = base + "/log";
  const pid_t pid = start_compare("8x6x6,256x256x64", dir, log);
  ASSERT_GT(pid, 0);
  // The first checkpoint: the exact pipeline and 8x6x6 center mode done.
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!fs::exists(dir + "/report.md") && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(fs::exists(dir + "/report.md")) << read_text(log);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const auto sent = std::chrono::steady_clock::now();
  ASSERT_EQ(::kill(pid, SIGINT), 0);
  const int status = wait_for(pid, 30.0);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  ASSERT_NE(status, -1);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGINT);
  EXPECT_LT(seconds, 1.0);
  // 1 exact + 2 × 8x6x6 done (the 256x256x64 set-up takes seconds), of 5.
  const std::string report = read_text(dir + "/report.md");
  EXPECT_TRUE(has(report, "**Incomplete**: interrupted after 3 of 5 evaluations")) << report;
  EXPECT_TRUE(has(read_text(log), "interrupted: " + dir +
                                      "/report.md and its files hold 3 of 5 evaluations "
                                      "(marked incomplete)"))
      << read_text(log);
  // compare.csv: a header and 6 states × 2 modes at 8x6x6.
  const std::string csv = read_text(dir + "/compare.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 13) << csv;
  EXPECT_FALSE(has(csv, "256x256x64"));
  EXPECT_EQ(temporary_files(dir), 0);
}

// compare-optimizer: progress over its exact evaluations (1 run + 2 samples) and voxel set-ups
// (1 resolution × 2 modes); a signal once runs.csv is written keeps it and says the rank
// agreement was not finished.
TEST(CompareLongWork, CompareOptimizerShowsProgressAndKeepsRunsCsvOnASignal) {
  const std::string base = temp_dir("compare-optimizer");
  const CommandResult optimize = run("optimize " + kScene + " --out " + base +
                                     "/runs --max-evals 50 --runs 1 --threads 1 --quiet");
  ASSERT_EQ(optimize.exit_code, 0) << optimize.output;
  const CommandResult r = run("compare-optimizer " + kScene + " --runs " + base +
                              "/runs --samples 2 --out " + base + "/full --progress");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "compare-optimizer: evaluations 0/5, ")) << r.output;
  EXPECT_TRUE(has(r.output, "compare-optimizer: evaluations 5/5, ")) << r.output;

  const std::string dir = base + "/cut", log = base + "/log";
  const std::string runs = base + "/runs";
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::freopen(log.c_str(), "w", stdout);
    std::freopen(log.c_str(), "a", stderr);
    ::execl(CAMPLACE_BINARY, CAMPLACE_BINARY, "compare-optimizer", kScene.c_str(), "--runs",
            runs.c_str(), "--samples", "6", "--out", dir.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ASSERT_GT(pid, 0);
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!fs::exists(dir + "/runs.csv") && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(fs::exists(dir + "/runs.csv")) << read_text(log);
  const auto sent = std::chrono::steady_clock::now();
  ASSERT_EQ(::kill(pid, SIGHUP), 0);
  const int status = wait_for(pid, 30.0);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  ASSERT_NE(status, -1);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGHUP);
  EXPECT_LT(seconds, 1.0);
  EXPECT_TRUE(has(read_text(log), "interrupted: " + dir +
                                      "/runs.csv (the exact Err of every run); the rank "
                                      "agreement was not finished"))
      << read_text(log);
  EXPECT_EQ(read_text(dir + "/runs.csv"), read_text(base + "/full/runs.csv"));
  EXPECT_FALSE(fs::exists(dir + "/report.md"));
  EXPECT_EQ(temporary_files(dir), 0);
}

// One shape for every pipeline; for exact and both the exact object and the
// differences are where a voxel run has null.
TEST(CompareLongWork, EvaluateJsonHasOneShapeForExactAndBoth) {
  const CommandResult exact = run("evaluate " + kBasic + " --pipeline exact --json");
  ASSERT_EQ(exact.exit_code, 0) << exact.output;
  const auto e = nlohmann::json::parse(exact.output);
  const CommandResult both = run("evaluate " + kBasic + " --pipeline both --json");
  ASSERT_EQ(both.exit_code, 0) << both.output;
  const auto b = nlohmann::json::parse(both.output);
  for (const auto* j : {&e, &b}) {
    for (const char* key : {"pipeline", "scene", "cameras_file", "voxel", "exact", "differences"})
      EXPECT_TRUE(j->contains(key)) << key;
    EXPECT_TRUE((*j)["exact"].is_object());
    EXPECT_EQ((*j)["exact"]["pipeline"], "exact");
  }
  EXPECT_TRUE(e["voxel"].is_null());
  EXPECT_TRUE(e["differences"].is_null());
  EXPECT_EQ(e["exact"]["err"], e["err"]);
  EXPECT_EQ(e["exact"]["states"], e["states"]);
  EXPECT_TRUE(b["voxel"].is_object());
  EXPECT_TRUE(b["differences"].is_object());
  EXPECT_FALSE(b.contains("err"));  // each pipeline has its own
  // The exact pipeline does not depend on whether the voxel one ran too.
  EXPECT_EQ(b["exact"]["err"], e["err"]);
}

// `export --pipeline exact` counts the exact pipeline's (state, camera) steps, as evaluate and
// compare do, and refuses up front what its memory estimate rules out, creating nothing.
TEST(ExportLongWork, ExactExportShowsProgressAndChecksMemoryFirst) {
  const std::string dir = temp_dir("export-exact");
  const CommandResult r =
      run("export " + kBasic + " --pipeline exact --progress --out " + dir + "/view");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "export: exact evaluation, (state, camera) steps 36/36")) << r.output;
  const CommandResult refused =
      run_camplace("CAMPLACE_MEM_AVAILABLE_KB=150000 " + std::string(CAMPLACE_BINARY),
                   "export " + kBasic + " --pipeline exact --threads 1 --out " + dir + "/refused");
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_TRUE(has(refused.output,
                  "error: the exact pipeline with 6 cameras, 1 thread and up to "
                  "28 triangles per state needs about 0.19 GiB, more than the "
                  "0.14 GiB available"))
      << refused.output;
  EXPECT_FALSE(fs::exists(dir + "/refused"));
}

}  // namespace
}  // namespace camplace::testing
