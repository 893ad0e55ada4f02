// `--refine` on the command line: evaluate reports it and its refined model,
// and every command refuses a bad value before starting, naming the option, with exit code 1.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "command.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

CommandResult run(const std::string& args) { return run_camplace(CAMPLACE_BINARY, args); }

const std::string kData = std::string(CAMPLACE_SOURCE_DIR) + "/data/";
const std::string kEvaluate =
    "evaluate " + kData + "paper_basic.json --cameras " + kData + "paper_basic_corners.json";

TEST(RefineOption, EvaluateReportsTheLevelsAndARefinedModel) {
  const CommandResult plain = run(kEvaluate + " --json");
  const CommandResult fine = run(kEvaluate + " --refine 2 --json");
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  ASSERT_EQ(fine.exit_code, 0) << fine.output;
  const auto a = nlohmann::json::parse(plain.output), b = nlohmann::json::parse(fine.output);
  EXPECT_EQ(a["refine"], 0);
  EXPECT_EQ(b["refine"], 2);
  EXPECT_EQ(b["resolution"], a["resolution"]);
  EXPECT_EQ(b["tolerance"], a["tolerance"]);  // the voxels' tolerance, refined or not
  EXPECT_LT(b["err_lower_bound"].get<double>(), a["err_lower_bound"].get<double>());
  ASSERT_EQ(a["states"].size(), b["states"].size());
  for (std::size_t s = 0; s < a["states"].size(); ++s) {
    // The refined model lies in the unrefined one: farther from C, not larger.
    EXPECT_GE(b["states"][s]["d_model"].get<double>(), a["states"][s]["d_model"].get<double>());
    EXPECT_LE(b["states"][s]["model_volume"].get<double>(),
              a["states"][s]["model_volume"].get<double>());
  }
  const CommandResult table = run(kEvaluate + " --refine 2");
  ASSERT_EQ(table.exit_code, 0) << table.output;
  EXPECT_NE(table.output.find("resolution 16x12x12, refine 2"), std::string::npos) << table.output;
}

TEST(RefineOption, BadValuesExitOneNamingTheOption) {
  const std::string dir = temp_dir("refine_option");
  const std::string study =
      write_file(dir + "/study.json",
                 R"({"mode": "conservative", "refine": 5, "runs_per_group": 1, "time_limit_s": 1,
          "max_evaluations": 10, "examinations": [{"family": "cameras", "params": [6]}]})");
  const std::string center_study =
      write_file(dir + "/center.json",
                 R"({"mode": "center", "refine": 1, "runs_per_group": 1, "time_limit_s": 1,
          "max_evaluations": 10, "examinations": [{"family": "cameras", "params": [6]}]})");
  struct Case {
    std::string args, expect;
  };
  const std::string scene = kData + "paper_basic.json";
  const Case cases[] = {
      {kEvaluate + " --refine -1", "--refine"},
      {kEvaluate + " --refine 11", "--refine"},
      {kEvaluate + " --refine two", "--refine"},
      // Center labels take no refinement.
      {kEvaluate + " --mode center --refine 1", "--refine: refinement needs conservative"},
      // 5 levels at 16×12×12: about 3 GiB in the worst case, above the 2 GiB limit.
      {kEvaluate + " --refine 5", "--refine: 5 levels on the 16x12x12 grid may need up to"},
      {kEvaluate + " --resolution 64x48x48 --refine 3", "--refine: 3 levels on the 64x48x48"},
      {"optimize " + scene + " --refine 5 --out " + dir + "/never", "--refine: 5 levels"},
      {"optimize " + scene + " --refine -2 --out " + dir + "/never", "--refine"},
      {"optimize " + scene + " --mode center --refine 2 --out " + dir + "/never", "--refine"},
      {"compare " + scene + " --cameras " + kData + "paper_basic_corners.json --refine 0,x --out " +
           dir + "/never",
       "--refine"},
      {"compare " + scene + " --cameras " + kData + "paper_basic_corners.json --refine 0,5 --out " +
           dir + "/never_compare",
       "--refine: 5 levels"},
      {"study " + study + " --out " + dir + "/study", "/refine: cameras-6: 5 levels"},
      {"study " + center_study + " --out " + dir + "/study", "/refine: refinement needs"},
  };
  for (const Case& c : cases) {
    const CommandResult r = run(c.args);
    EXPECT_EQ(r.exit_code, 1) << c.args << "\n" << r.output;
    EXPECT_EQ(r.output.rfind("error: ", 0), 0u) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.args << "\n" << r.output;
  }
  // Refused before anything started: optimize made no output folder, study ran nothing.
  EXPECT_FALSE(std::filesystem::exists(dir + "/never"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/study/runs"));
}

// The run files record the levels ("context": {"refine": L}, omitted for 0), and resuming a
// folder with other levels is refused like any other changed setting.
TEST(RefineOption, OptimizeRecordsTheLevelsAndResumesOnlyWithTheSame) {
  const std::string dir = temp_dir("refine_resume");
  const std::string base = "optimize " + kData + "paper_basic.json --max-evals 3 --threads 1 " +
                           "--quiet --out " + dir + "/runs";
  const CommandResult first = run(base + " --refine 1");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  std::ifstream in(dir + "/runs/run-1.json");
  const auto file = nlohmann::json::parse(in);
  EXPECT_EQ(file["context"]["refine"], 1);
  EXPECT_EQ(file["context"]["mode"], "conservative");
  const CommandResult other = run(base + " --refine 2 --seed 2");
  EXPECT_EQ(other.exit_code, 1) << other.output;
  EXPECT_NE(other.output.find("refine: 1 → 2"), std::string::npos) << other.output;
  const CommandResult none = run(base + " --seed 2");
  EXPECT_EQ(none.exit_code, 1) << none.output;
  EXPECT_NE(none.output.find("refine: 1 → 0"), std::string::npos) << none.output;
  const CommandResult same = run(base + " --refine 1 --seed 2");
  EXPECT_EQ(same.exit_code, 0) << same.output;
}

}  // namespace
}  // namespace camplace::testing
