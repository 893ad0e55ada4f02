// `camplace compare` on a tiny scene: rows checked against direct `camplace evaluate` calls;
// a rerun gives identical files apart from timing.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "camplace/compare/optimizer_validation.hpp"
#include "command.hpp"
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

TEST(CompareReport, RowsMatchDirectEvaluationsAndRerunIsIdentical) {
  const std::string dir = temp_dir("compare");
  const std::string scene = write_file(dir + "/scene.json", kTinyScene);
  const std::string cams = write_file(dir + "/cams.json", kTinyCameras);
  const std::string args = scene + " --cameras " + cams + " --resolutions 4x4x4,8x8x8 --out " + dir + "/a";
  const CommandResult first = run_camplace(CAMPLACE_BINARY, "compare " + args);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const auto rows = read_csv(dir + "/a/compare.csv");
  ASSERT_EQ(rows.size(), 2u * 2u * 2u);  // states × modes × resolutions
  const auto exact = evaluate(scene + " --cameras " + cams + " --pipeline exact");
  for (const auto& row : rows) {
    const auto voxel = evaluate(scene + " --cameras " + cams + " --mode " + row.at("mode") + " --resolution " + row.at("resolution"));
    const int l = std::stoi(row.at("event"));
    EXPECT_NEAR(std::stod(row.at("d_voxel_m")), voxel["states"][l]["d_model"].get<double>(), 1e-9);
    EXPECT_NEAR(std::stod(row.at("volume_voxel_m3")), voxel["states"][l]["model_volume"].get<double>(), 1e-9);
    EXPECT_NEAR(std::stod(row.at("d_exact_m")), exact["states"][l]["d_model"].get<double>(), 1e-9);
    EXPECT_NEAR(std::stod(row.at("d_true_m")), exact["states"][l]["d_true"].get<double>(), 1e-9);
    EXPECT_NEAR(std::stod(row.at("volume_exact_m3")), exact["states"][l]["model_volume"].get<double>(), 1e-9);
    if (row.at("mode") == "conservative") {
      EXPECT_EQ(row.at("exact_voxels_outside_voxel_model"), "0");
      EXPECT_EQ(row.at("d_voxel_over_estimates"), "no");
    }
  }
}

TEST(CompareReport, RerunIsByteIdenticalApartFromTiming) {
  const std::string dir = temp_dir("compare-rerun");
  const std::string scene = write_file(dir + "/scene.json", kTinyScene);
  const std::string cams = write_file(dir + "/cams.json", kTinyCameras);
  const std::string args = "compare " + scene + " --cameras " + cams + " --out " + dir + "/out";
  ASSERT_EQ(run_camplace(CAMPLACE_BINARY, args).exit_code, 0);
  const std::string csv = read(dir + "/out/compare.csv");
  const std::string png = read(dir + "/out/d_voxel_vs_d_exact.png");
  std::string md = read(dir + "/out/report.md");
  ASSERT_EQ(run_camplace(CAMPLACE_BINARY, args).exit_code, 0);
  EXPECT_EQ(read(dir + "/out/compare.csv"), csv);
  EXPECT_EQ(read(dir + "/out/d_voxel_vs_d_exact.png"), png);
  const std::string md2 = read(dir + "/out/report.md");
  EXPECT_EQ(md2.substr(0, md2.find("## Timing")), md.substr(0, md.find("## Timing")));
  EXPECT_FALSE(png.empty());
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
