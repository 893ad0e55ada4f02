// Study files and folders that used to give wrong results silently: a group named twice, names
// that break CSV and Markdown tables, and run files edited after their run.
#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "camplace/compare/run_validation.hpp"
#include "camplace/core/error.hpp"
#include "command.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

CommandResult camplace(const std::string& args) { return run_camplace(CAMPLACE_BINARY, args); }

/// A study of the given examinations, one run of 20 evaluations per group.
std::string study_json(const json& examinations) {
  json study = {{"algorithm", "gaco"}, {"mode", "center"},      {"runs_per_group", 1},
                {"threads", 1},        {"first_seed", 1},       {"scene_seed", 1},
                {"time_limit_s", 600}, {"max_evaluations", 20}, {"examinations", examinations}};
  return study.dump(1);
}

/// The records of a CSV text as RFC 4180 reads them (quoted fields may hold commas, doubled
/// quotes and line breaks).
std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows(1);
  std::string field;
  bool quoted = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      rows.back().push_back(field);
      field.clear();
    } else if (c == '\n') {
      rows.back().push_back(field);
      field.clear();
      rows.emplace_back();
    } else {
      field += c;
    }
  }
  if (rows.back().empty() && field.empty()) rows.pop_back();
  return rows;
}

TEST(StudyHardening, AGroupGivenTwiceIsRefusedWhenTheStudyFileIsRead) {
  const std::string dir = temp_dir("study-twice");
  const std::vector<std::pair<json, std::string>> cases = {
      {json::parse(R"([{"family": "cameras", "params": [3, 3]}])"),
       "/examinations/0/params/1: group \"cameras-3\" is given twice (also "
       "/examinations/0/params/0)"},
      {json::parse(R"([{"name": "a", "family": "cameras", "params": [4]},
                       {"name": "b", "family": "cameras", "params": [5, 4]}])"),
       "/examinations/1/params/1: group \"cameras-4\" is given twice (also "
       "/examinations/0/params/0)"},
      {json::parse(R"([{"name": "same", "family": "cameras", "params": [3]},
                       {"name": "same", "family": "resolution", "params": [1]}])"),
       "/examinations/1/name: examination \"same\" is named twice (also /examinations/0)"}};
  int k = 0;
  for (const auto& [examinations, message] : cases) {
    const std::string file =
        write_file(dir + "/s" + std::to_string(k) + ".json", study_json(examinations));
    const std::string out = dir + "/out" + std::to_string(k++);
    const CommandResult r = camplace("study " + file + " --out " + out);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("error: " + file + ": " + message), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out + "/runs")) << r.output;
  }
}

TEST(StudyHardening, NamesWithCommasQuotesBarsAndLineBreaksKeepTheTablesParseable) {
  const std::string dir = temp_dir("study-names");
  const std::string name = "a,\"b\"|c\nd";
  const std::string file = write_file(
      dir + "/names.json",
      study_json(json::array({{{"name", name}, {"family", "cameras"}, {"params", {3}}}})));
  const CommandResult r = camplace("study " + file + " --out " + dir + "/out");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<std::vector<std::string>> rows = parse_csv(read_text(dir + "/out/runs.csv"));
  ASSERT_EQ(rows.size(), 2u);
  ASSERT_EQ(rows[1].size(), rows[0].size());
  EXPECT_EQ(rows[1][0], name);
  EXPECT_EQ(rows[1][1], "cameras");
  const std::string report = read_text(dir + "/out/report.md");
  EXPECT_NE(report.find("| a,\"b\"\\|c<br>d | 3 |"), std::string::npos) << report;
}

TEST(StudyHardening, ARunFileEditedAfterItsRunIsFlaggedByValidateAndByTheReport) {
  const std::string dir = temp_dir("study-edited");
  const std::string file = write_file(
      dir + "/edited.json",
      study_json(json::array({{{"name", "cameras"}, {"family", "cameras"}, {"params", {3}}}})));
  const std::string out = dir + "/out";
  ASSERT_EQ(camplace("study " + file + " --out " + out).exit_code, 0);
  const std::string run_file = out + "/runs/cameras-3/run-1.json";
  json run = json::parse(read_text(run_file));
  const double err = run.at("err").get<double>();
  run["err"] = err / 2;  // a better Err than the cameras give
  write_file(run_file, run.dump(1));
  const CommandResult report = camplace("study " + file + " --out " + out + " --report-only");
  EXPECT_EQ(report.exit_code, 1) << report.output;
  EXPECT_NE(report.output.find("error: " + run_file + ": /err: the recorded Err "),
            std::string::npos)
      << report.output;
  EXPECT_NE(report.output.find("is not the Err of the recorded cameras"), std::string::npos)
      << report.output;
  const CommandResult validate = camplace("validate " + out);
  EXPECT_EQ(validate.exit_code, 1) << validate.output;
  const std::string csv = read_text(out + "/validation.csv");
  EXPECT_NE(csv.find("/err: the recorded Err "), std::string::npos) << csv;
  // The cameras moved instead (all into one corner, looking along the floor): the same.
  run["err"] = err;
  for (json& camera : run["cameras"]) {
    camera["position"] = {0.05, 0.05, 0.05};
    camera["pitch_deg"] = 0;
  }
  write_file(run_file, run.dump(1));
  const CommandResult moved = camplace("study " + file + " --out " + out + " --report-only");
  EXPECT_EQ(moved.exit_code, 1) << moved.output;
  EXPECT_NE(moved.output.find("is not the Err of the recorded cameras"), std::string::npos)
      << moved.output;
}

TEST(StudyHardening, ValidationCsvFieldsWithCommasQuotesAndLineBreaksReadBack) {
  // validation.csv as validate_runs writes it (RFC 4180): a failed check whose run path holds a
  // comma and whose error holds quotes and a line break, then a checked run. The reader used to
  // split records at every line break and dropped both.
  const std::string dir = temp_dir("validation-csv");
  const std::string header =
      "run,scene,mode,resolution,voxel_err,voxel_err_same_fov,exact_err,tolerance,reached_voxel,"
      "reached_exact,max_overestimate,seconds,err_lower_bound,target,error\n";
  const std::string failed =
      "\"runs/a,b/run-1.json\",s.json,,,,,,,,,,,,,\"first line\nsecond \"\"quoted\"\"\"\n";
  const std::string checked =
      "runs/c/run-2.json,s.json,conservative,16x12x12,0.25,0.25,0.125,0.046875,false,false,0,1.5,"
      "0.0625,0.046875,\n";
  write_file(dir + "/validation.csv", header + failed + checked);
  const std::vector<compare::RunValidation> rows = compare::read_validation_csv(dir);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].run, "runs/a,b/run-1.json");
  EXPECT_EQ(rows[0].error, "first line\nsecond \"quoted\"");
  EXPECT_EQ(rows[1].run, "runs/c/run-2.json");
  EXPECT_EQ(rows[1].resolution, (std::array<int, 3>{16, 12, 12}));
  EXPECT_EQ(rows[1].exact_err, 0.125);
  EXPECT_EQ(rows[1].err_lower_bound, 0.0625);
  EXPECT_TRUE(rows[1].error.empty());
  // A damaged field is refused by file, record and column, not read as 0 or skipped.
  std::string damaged = checked;
  damaged.replace(damaged.find("0.125"), 5, "0.1x5");
  write_file(dir + "/validation.csv", header + failed + damaged);
  try {
    compare::read_validation_csv(dir);
    ADD_FAILURE() << "a damaged validation.csv was read";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.file(), dir + "/validation.csv");
    EXPECT_EQ(e.entry(), "record 3, exact_err");
    EXPECT_NE(e.reason().find("not a number: \"0.1x5\""), std::string::npos) << e.reason();
  }
}

}  // namespace
}  // namespace camplace::testing
