// `camplace study --shard I/N` and `--report-only` (Slurm job arrays): the shards
// together make the same runs as the whole study, also when they run at the same time into one
// folder; a report of a partial study lists exactly the runs missing. Tiny runs: seconds.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cluster_support.hpp"
#include "command.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

namespace fs = std::filesystem;

CommandResult camplace(const std::string& args) { return run_camplace(CAMPLACE_BINARY, args); }

/// The serial study's results, made once for the whole program.
const std::map<std::string, RunResult>& serial_results(const std::string& study) {
  static const std::map<std::string, RunResult> results = [&] {
    const std::string out = temp_dir("shard-serial");
    const CommandResult r = camplace("study " + study + " --out " + out);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return run_results(out);
  }();
  return results;
}

std::string study_file() {
  static const std::string file =
      write_file(temp_dir("shard-study") + "/small.json", small_study_json(200));
  return file;
}

TEST(StudyShards, ThreeShardsInSequenceMakeTheWholeStudysRunsAndNoReport) {
  const std::string out = temp_dir("shards-sequence");
  int runs = 0;
  for (int i = 1; i <= 3; ++i) {
    const std::string shard = std::to_string(i) + "/3";
    const CommandResult r =
        camplace("study " + study_file() + " --out " + out + " --shard " + shard);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    // The 4 runs in the canonical order (cameras-3 seeds 1, 2, cameras-4 seeds 1, 2): run k goes
    // to shard k mod 3 + 1, so shard 1 has two, shards 2 and 3 one each.
    const int mine = i == 1 ? 2 : 1;
    runs += mine;
    EXPECT_NE(r.output.find("shard " + shard + ": runs: " + std::to_string(mine) +
                            " of the study's 4 (0 found, " + std::to_string(mine) + " run now)"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("no report"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out + "/report.md"));
    EXPECT_EQ(run_results(out).size(), static_cast<std::size_t>(runs));
  }
  EXPECT_EQ(run_results(out), serial_results(study_file()));
  // A shard run again finds its runs.
  const CommandResult again = camplace("study " + study_file() + " --out " + out + " --shard 2/3");
  EXPECT_NE(again.output.find("runs: 1 of the study's 4 (1 found, 0 run now)"), std::string::npos)
      << again.output;
  const CommandResult report =
      camplace("study " + study_file() + " --out " + out + " --report-only");
  ASSERT_EQ(report.exit_code, 0) << report.output;
  EXPECT_NE(report.output.find("runs: 4 (4 found, 0 missing)"), std::string::npos) << report.output;
  EXPECT_EQ(read_text(out + "/report.md").find("Missing runs"), std::string::npos);
}

TEST(StudyShards, ShardsAtTheSameTimeIntoOneFolderMakeTheWholeStudysRuns) {
  const std::string out = temp_dir("shards-parallel");
  std::string both;
  for (int i = 1; i <= 3; ++i) {
    both += std::string(CAMPLACE_BINARY) + " study " + study_file() + " --out " + out +
            " --shard " + std::to_string(i) + "/3 > " + out + "-" + std::to_string(i) +
            ".log 2>&1 & ";
  }
  const CommandResult r = run_camplace("", "sh -c '" + both + "wait'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (int i = 1; i <= 3; ++i) {
    const std::string log = read_text(out + "-" + std::to_string(i) + ".log");
    EXPECT_NE(log.find("run now)"), std::string::npos) << log;
  }
  EXPECT_EQ(run_results(out), serial_results(study_file()));
}

TEST(StudyShards, ReportOnlyListsExactlyTheMissingShardsRuns) {
  const std::string out = temp_dir("shards-missing");
  for (const char* shard : {"1/3", "3/3"}) {
    const CommandResult r =
        camplace("study " + study_file() + " --out " + out + " --shard " + shard);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  const CommandResult r = camplace("study " + study_file() + " --out " + out + " --report-only");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Shard 2/3 holds run k = 1 alone: cameras-3 seed 2.
  EXPECT_NE(r.output.find("runs: 4 (3 found, 1 missing)\nmissing: cameras-3 seed 2\nreport: "),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("study: "), std::string::npos) << "a run started\n" << r.output;
  const std::string report = read_text(out + "/report.md");
  const std::size_t missing = report.find("## Missing runs");
  ASSERT_NE(missing, std::string::npos) << report;
  EXPECT_NE(report.find("1 of the study's 4 runs", missing), std::string::npos) << report;
  EXPECT_NE(report.find("\n- cameras-3 seed 2\n", missing), std::string::npos) << report;
  EXPECT_EQ(report.find("\n- cameras-", report.find("\n- cameras-3 seed 2\n", missing) + 1),
            std::string::npos)
      << "more than one run listed\n"
      << report;
  EXPECT_FALSE(fs::exists(out + "/runs/cameras-3/run-2.json"));
  // The missing shard, then the report: complete.
  ASSERT_EQ(camplace("study " + study_file() + " --out " + out + " --shard 2/3").exit_code, 0);
  const CommandResult full = camplace("study " + study_file() + " --out " + out + " --report-only");
  EXPECT_NE(full.output.find("runs: 4 (4 found, 0 missing)"), std::string::npos) << full.output;
  EXPECT_EQ(read_text(out + "/report.md").find("Missing runs"), std::string::npos);
  EXPECT_EQ(run_results(out), serial_results(study_file()));
}

TEST(StudyShards, BadShardValuesAreRefusedNamingTheOption) {
  const std::string out = temp_dir("shards-bad");
  for (const char* bad : {"0/3", "4/3", "1/0", "3", "a/3", "1/-3", "-1/3", "1/3/2", "/3"}) {
    const CommandResult r = camplace("study " + study_file() + " --out " + out + " --shard=" + bad);
    EXPECT_EQ(r.exit_code, 1) << bad << "\n" << r.output;
    EXPECT_EQ(r.output.rfind("error: command line: --shard: must be I/N", 0), 0u) << bad << "\n"
                                                                                  << r.output;
  }
  for (const char* other : {"--restart", "--report-only", "--validate"}) {
    const CommandResult r =
        camplace("study " + study_file() + " --out " + out + " --shard 1/2 " + other);
    EXPECT_EQ(r.exit_code, 1) << other << "\n" << r.output;
    EXPECT_EQ(
        r.output.rfind(std::string("error: command line: --shard: cannot go with ") + other, 0), 0u)
        << r.output;
  }
  EXPECT_FALSE(fs::exists(out + "/runs"));
}

}  // namespace
}  // namespace camplace::testing
