// `camplace compare` on a tiny scene: rows checked against direct `camplace evaluate` calls;
// a rerun gives identical files apart from timing.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "camplace/compare/optimizer_validation.hpp"
#include "command.hpp"
#include "report_header.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

const char* kTinyScene = R"({
  "area": {"min": [0, 0, 0], "max": [2, 2, 2]},
  "voxels": [4, 4, 4],
  "cameras": {"count": 2, "half_angle_deg": 35, "fov": "pyramid", "sides": 4},
  "time_steps": [{
    "dynamic_obstacles": [{"name": "robot", "box": {"min": [1.5, 1.5, 0], "max": [1.9, 1.9, 0.6]}}],
    "events": [
      {"weight": 0.7, "targets": [{"name": "person", "box": {"min": [0.3, 0.3, 0], "max": [0.7, 0.6, 1.6]}}]},
      {"weight": 0.3, "targets": [{"name": "person", "box": {"min": [0.2, 1.2, 0], "max": [0.5, 1.5, 1.6]}}]}]
  }],
  "dynamic_mode": "modelled"
})";
const char* kTinyCameras = R"({"cameras": [
  {"position": [0.0, 0.0, 2.0], "yaw_deg": 45, "pitch_deg": -40},
  {"position": [2.0, 0.1, 1.8], "yaw_deg": 135, "pitch_deg": -30}]})";

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::map<std::string, std::string>> read_csv(const std::string& path) {
  std::vector<std::map<std::string, std::string>> rows;
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> header;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) cells.push_back(cell);
    if (header.empty()) {
      header = cells;
      continue;
    }
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size() && i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

nlohmann::json evaluate(const std::string& args) {
  const CommandResult r = run_camplace(CAMPLACE_BINARY, "evaluate " + args + " --json");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return nlohmann::json::parse(r.output);
}

/// Every file of dir by name, with its contents.
std::map<std::string, std::string> read_dir(const std::string& dir) {
  std::map<std::string, std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    files[entry.path().filename().string()] = read(entry.path().string());
  }
  return files;
}

/// text with the last cell of every line removed, from the first line that starts with `from`
/// on (from "" = every line); cells end at `separator`, a line's trailing separator is ignored.
/// Drops the timing columns of err.csv and of report.md's timing table.
std::string without_last_cells(const std::string& text, char separator, const std::string& from) {
  std::istringstream in(text);
  std::string out;
  std::string line;
  bool dropping = from.empty();
  while (std::getline(in, line)) {
    dropping = dropping || line.rfind(from, 0) == 0;
    if (dropping) {
      std::string cells = line;
      if (!cells.empty() && cells.back() == separator) cells.pop_back();
      const std::size_t last = cells.rfind(separator);
      if (last != std::string::npos) line = cells.substr(0, last);
    }
    out += line + "\n";
  }
  return out;
}

/// The files of a compare run with the timing removed: err.csv's `ms` column and the last column
/// of report.md's "## Timing" table. Everything else must rerun byte for byte.
std::map<std::string, std::string> without_timing(std::map<std::string, std::string> files) {
  if (files.count("err.csv")) files["err.csv"] = without_last_cells(files["err.csv"], ',', "");
  if (files.count("report.md")) {
    // The provenance header's start time differs between runs by design.
    std::string& md = files["report.md"];
    const std::size_t started = md.find("\n| started | ");
    if (started != std::string::npos) md.erase(started, md.find('\n', started + 1) - started);
    md = without_last_cells(md, '|', "## Timing");
  }
  return files;
}

// `camplace compare` at two resolutions: every row equals what `camplace evaluate` prints for
// that state, mode and resolution (voxel) or for the exact pipeline; then the same command again
// (same output directory) must rewrite every file byte for byte, apart from the timing columns.
TEST(CompareReport, RowsMatchDirectEvaluationsAndRerunIsIdentical) {
  const std::string dir = temp_dir("compare");
  const std::string scene = write_file(dir + "/scene.json", kTinyScene);
  const std::string cams = write_file(dir + "/cams.json", kTinyCameras);
  const std::string args =
      scene + " --cameras " + cams + " --resolutions 4x4x4,8x8x8 --out " + dir + "/a";
  const CommandResult first = run_camplace(CAMPLACE_BINARY, "compare " + args);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const auto rows = read_csv(dir + "/a/compare.csv");
  ASSERT_EQ(rows.size(), 2u * 2u * 2u);  // states × modes × resolutions
  const auto exact = evaluate(scene + " --cameras " + cams + " --pipeline exact");
  for (const auto& row : rows) {
    const auto voxel = evaluate(scene + " --cameras " + cams + " --mode " + row.at("mode") +
                                " --resolution " + row.at("resolution"));
    const int l = std::stoi(row.at("event"));
    EXPECT_NEAR(std::stod(row.at("d_voxel_m")), voxel["states"][l]["d_model"].get<double>(), 1e-9);
    EXPECT_NEAR(std::stod(row.at("volume_voxel_m3")),
                voxel["states"][l]["model_volume"].get<double>(), 1e-9);
    EXPECT_NEAR(std::stod(row.at("d_exact_m")), exact["states"][l]["d_model"].get<double>(), 1e-9);
    EXPECT_NEAR(std::stod(row.at("d_true_m")), exact["states"][l]["d_true"].get<double>(), 1e-9);
    EXPECT_NEAR(std::stod(row.at("volume_exact_m3")),
                exact["states"][l]["model_volume"].get<double>(), 1e-9);
    if (row.at("mode") == "conservative") {
      EXPECT_EQ(row.at("exact_voxels_outside_voxel_model"), "0");
      EXPECT_EQ(row.at("d_voxel_over_estimates"), "no");
    }
  }

  const std::map<std::string, std::string> before = read_dir(dir + "/a");
  expect_provenance_header(before.at("report.md"), "# Voxel pipeline against the exact pipeline",
                           scene, scene, "resolutions 4x4x4, 8x8x8, refine 0");
  // The files the report promises, each non-empty, and the timing really is where it is dropped.
  for (const char* name : {"compare.csv", "err.csv", "report.md", "error_vs_resolution.png",
                           "d_voxel_vs_d_exact.png"}) {
    ASSERT_TRUE(before.count(name)) << name;
    EXPECT_FALSE(before.at(name).empty()) << name;
  }
  EXPECT_EQ(before.at("err.csv").substr(0, before.at("err.csv").find('\n')),
            "pipeline,resolution,err_m2,ms");
  EXPECT_NE(before.at("report.md").find("## Timing"), std::string::npos);
  const CommandResult second = run_camplace(CAMPLACE_BINARY, "compare " + args);
  ASSERT_EQ(second.exit_code, 0) << second.output;
  const std::map<std::string, std::string> after = read_dir(dir + "/a");
  std::vector<std::string> names_before, names_after;
  for (const auto& [name, text] : before) names_before.push_back(name);
  for (const auto& [name, text] : after) names_after.push_back(name);
  ASSERT_EQ(names_after, names_before);  // no file added (say, a temporary) or lost
  const auto stable_before = without_timing(before);
  const auto stable_after = without_timing(after);
  for (const auto& [name, text] : stable_before) {
    EXPECT_TRUE(stable_after.at(name) == text) << name << " differs between the two runs";
  }
}

TEST(CompareReport, KendallTauByHand) {
  EXPECT_DOUBLE_EQ(compare::kendall_tau_b({1, 2, 3, 4}, {10, 20, 30, 40}), 1.0);
  EXPECT_DOUBLE_EQ(compare::kendall_tau_b({1, 2, 3, 4}, {4, 3, 2, 1}), -1.0);
  // Pairs: (1,2) C, (1,3) C, (2,3) D → (2 − 1)/3.
  EXPECT_NEAR(compare::kendall_tau_b({1, 2, 3}, {1, 3, 2}), 1.0 / 3.0, 1e-15);
  // With a tie in b: pairs (1,2) tie_b, (1,3) C, (2,3) C → 2 / sqrt(3·2).
  EXPECT_NEAR(compare::kendall_tau_b({1, 2, 3}, {1, 1, 2}), 2.0 / std::sqrt(6.0), 1e-15);
  EXPECT_TRUE(std::isnan(compare::kendall_tau_b({1, 2, 3}, {5, 5, 5})));
}

}  // namespace
}  // namespace camplace::testing
