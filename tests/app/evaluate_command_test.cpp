// The `camplace evaluate` command as a user runs it: output schema, consistency, exit codes.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "command.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

CommandResult run(const std::string& args) { return run_camplace(CAMPLACE_BINARY, args); }

const std::string kData = std::string(CAMPLACE_SOURCE_DIR) + "/data/";

TEST(EvaluateCommand, JsonHasTheSchemaAndErrIsTheWeightedSum) {
  for (const char* mode : {"center", "conservative"}) {
    const CommandResult r = run("evaluate " + kData + "paper_basic.json --cameras " + kData +
                                "paper_basic_corners.json --mode " + mode + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto j = nlohmann::json::parse(r.output);
    EXPECT_EQ(j["pipeline"], "voxel");
    EXPECT_EQ(j["mode"], mode);
    EXPECT_EQ(j["resolution"], nlohmann::json({16, 12, 12}));
    ASSERT_EQ(j["states"].size(), 6u);
    double err = 0;
    for (const auto& s : j["states"]) {
      for (const char* key : {"time_step", "event", "weight", "d_true", "d_model", "model_volume",
                              "components", "components_removed"}) {
        EXPECT_TRUE(s.contains(key)) << key;
      }
      const double diff = s["d_true"].get<double>() - s["d_model"].get<double>();
      err += s["weight"].get<double>() * diff * diff;
    }
    EXPECT_NEAR(j["err"].get<double>(), err, 1e-12);
    for (const char* key : {"labelling", "clustering", "distance", "total"}) {
      EXPECT_GE(j["timing_ms"][key].get<double>(), 0.0) << key;
    }
  }
}

// The diagnostics. The nearest component's distance is d(C, M) measured again voxel by
// voxel; with every camera looking up at the ceiling nobody sees anything, the model is S minus
// the obstacles, touching the robot: d = 0 everywhere, no camera observes the nearest component,
// and evaluate warns.
TEST(EvaluateCommand, DiagnosticsNameTheNearestComponentAndWarnWhenNobodySeesIt) {
  for (const char* mode : {"center", "conservative"}) {
    const CommandResult r = run("evaluate " + kData + "paper_basic.json --cameras " + kData +
                                "paper_basic_corners.json --mode " + mode + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto j = nlohmann::json::parse(r.output);
    const auto& d = j.at("diagnostics");
    ASSERT_EQ(d["states"].size(), j["states"].size());
    int empty = 0;
    for (std::size_t s = 0; s < j["states"].size(); ++s) {
      const auto& c = d["states"][s]["nearest_component"];
      if (c.is_null()) {  // center mode loses the person in some states (README, Findings)
        EXPECT_EQ(j["states"][s]["components"], 0);
        ++empty;
        continue;
      }
      EXPECT_NEAR(c["distance"].get<double>(), j["states"][s]["d_model"].get<double>(), 1e-12);
      EXPECT_GE(c["cameras_observing"].get<int>(), 1);
      EXPECT_LE(c["cameras_observing"].get<int>(), 6);
    }
    ASSERT_EQ(d["cameras"].size(), 6u);
    for (const auto& c : d["cameras"]) {
      EXPECT_GT(c["fov_fraction"].get<double>(), 0.0);
      EXPECT_LE(c["fov_fraction"].get<double>(), 1.0);
    }
    if (empty == 0) {
      EXPECT_TRUE(d["warnings"].empty());
    } else {
      ASSERT_EQ(d["warnings"].size(), 1u);
      EXPECT_NE(d["warnings"][0].get<std::string>().find("the model is empty in " +
                                                         std::to_string(empty) + " of 6 states"),
                std::string::npos);
    }
  }
  const std::string dir = temp_dir("diagnostics");
  nlohmann::json cams = nlohmann::json::array();
  for (const auto& p :
       {std::array<double, 3>{0, 0, 3}, {4, 0, 3}, {4, 3, 3}, {0, 3, 3}, {2, 0, 3}, {2, 3, 3}}) {
    cams.push_back({{"position", p}, {"yaw_deg", 0.0}, {"pitch_deg", 89.0}});
  }
  std::ofstream(dir + "/up.json") << nlohmann::json{{"cameras", cams}}.dump();
  const CommandResult r =
      run("evaluate " + kData + "paper_basic.json --cameras " + dir + "/up.json --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  for (const auto& s : j["diagnostics"]["states"]) {
    EXPECT_EQ(s["nearest_component"]["distance"].get<double>(), 0.0);
    EXPECT_EQ(s["nearest_component"]["cameras_observing"].get<int>(), 0);
  }
  ASSERT_EQ(j["diagnostics"]["warnings"].size(), 1u);
  EXPECT_NE(j["diagnostics"]["warnings"][0].get<std::string>().find("d(C, M) = 0 in every state"),
            std::string::npos);
  const CommandResult table =
      run("evaluate " + kData + "paper_basic.json --cameras " + dir + "/up.json");
  EXPECT_NE(table.output.find("warning: d(C, M) = 0 in every state"), std::string::npos)
      << table.output;
}

TEST(EvaluateCommand, ResolutionOptionChangesTheGrid) {
  const CommandResult r = run("evaluate " + kData + "paper_basic.json --cameras " + kData +
                              "paper_basic_corners.json --resolution 20x15x15 --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(nlohmann::json::parse(r.output)["resolution"], nlohmann::json({20, 15, 15}));
}

TEST(EvaluateCommand, VoxelsOutHoldsTheModelWhoseVolumeIsReported) {
  const std::string dir = temp_dir("voxelsout");
  const CommandResult r = run("evaluate " + kData + "paper_basic.json --cameras " + kData +
                              "paper_basic_corners.json --json --voxels-out " + dir + "/model.npy");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto report = nlohmann::json::parse(r.output);
  std::ifstream sidecar_in(dir + "/model.json");
  const auto sidecar = nlohmann::json::parse(sidecar_in);
  EXPECT_EQ(sidecar["shape"], nlohmann::json({6, 12, 12, 16}));
  EXPECT_EQ(sidecar["spacing"], nlohmann::json({0.25, 0.25, 0.25}));
  EXPECT_EQ(sidecar["origin"], nlohmann::json({0.0, 0.0, 0.0}));
  EXPECT_EQ(sidecar["mode"], "conservative");
  // NPY 1.0: 10 bytes, the header (its length at bytes 8–9), then one byte per voxel.
  std::ifstream npy_in(dir + "/model.npy", std::ios::binary);
  std::stringstream npy_text;
  npy_text << npy_in.rdbuf();
  const std::string npy = npy_text.str();
  ASSERT_GT(npy.size(), 10u);
  const std::size_t header =
      static_cast<unsigned char>(npy[8]) | (static_cast<unsigned char>(npy[9]) << 8);
  const std::string data = npy.substr(10 + header);
  ASSERT_EQ(data.size(), 6u * 16u * 12u * 12u);
  for (std::size_t i = 0; i < 6; ++i) {
    const std::string model = data.substr(i * 2304, 2304);
    const double volume = std::count(model.begin(), model.end(), '\1') * 0.25 * 0.25 * 0.25;
    EXPECT_NEAR(volume, report["states"][i]["model_volume"].get<double>(), 1e-9) << i;
    EXPECT_EQ(sidecar["states"][i]["time_step"], report["states"][i]["time_step"]);
    EXPECT_EQ(sidecar["states"][i]["event"], report["states"][i]["event"]);
  }
}

TEST(EvaluateCommand, TableIsPrintedWithoutJson) {
  const CommandResult r =
      run("evaluate " + kData + "paper_basic.json --cameras " + kData + "paper_basic_corners.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("Err = "), std::string::npos);
  EXPECT_NE(r.output.find("d_model"), std::string::npos);
}

/// `text` with the first occurrence of `from` replaced (the test fails if there is none).
std::string replace_first(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

TEST(EvaluateCommand, BadInputsExitOneNamingFileEntryAndReason) {
  const std::string dir = temp_dir("evalcli");
  const std::string wrong_count = write_file(
      dir + "/two.json",
      R"({"cameras": [{"position": [1,1,1], "yaw_deg": 0, "pitch_deg": 0}, {"position": [1,1,1], "yaw_deg": 0, "pitch_deg": 0}]})");
  const std::string corners = read_text(kData + "paper_basic_corners.json");
  const std::string outside = write_file(
      dir + "/outside.json", replace_first(corners, "[4.0, 0.0, 3.0]", "[4.0e7, 0.0, 3.0]"));
  const std::string scene = read_text(kData + "paper_basic.json");
  const std::string huge_area = write_file(
      dir + "/huge.json", replace_first(scene, "\"min\": [\n   0,", "\"min\": [\n   -1e200,"));
  // Err overflowed (`"err": null` from evaluate, a failed internal check in optimize).
  const std::string huge_weight = write_file(
      dir + "/weight.json", replace_first(scene, "\"weight\": 0.3", "\"weight\": 1.7e308"));
  const std::string basic =
      "evaluate " + kData + "paper_basic.json --cameras " + kData + "paper_basic_corners.json";
  const std::string npy_dir = dir + "/d.npy";
  std::filesystem::create_directories(npy_dir);
  const std::string compare =
      "compare " + kData + "paper_basic.json --cameras " + kData + "paper_basic_corners.json";
  struct Case {
    std::string args, expect;
  } cases[] = {
      {"evaluate " + dir + "/none.json --cameras " + wrong_count, "none.json"},
      {"evaluate " + kData + "paper_basic.json --cameras " + wrong_count, "holds 2 cameras"},
      {basic + " --resolution 0x1x1", "--resolution"},
      {basic + " --mode fancy", "--mode"},
      {"evaluate " + kData + "paper_basic.json", "--cameras"},
      {"evaluate " + kData + "paper_basic.json --cameras " + outside,
       "/cameras/1/position: coordinates must lie within"},
      {"evaluate " + huge_area + " --cameras " + kData + "paper_basic_corners.json",
       "/area/min: coordinates must lie within"},
      {"evaluate " + kData + "paper_basic.json --cameras " + dir, "is a directory"},
      {"evaluate " + huge_weight + " --cameras " + kData + "paper_basic_corners.json --json",
       "weight.json: /time_steps/0/events/1/weight: weight 1.7e+308 is too large"},
      {"optimize " + huge_weight + " --max-evals 10 --out " + dir + "/o",
       "/time_steps/0/events/1/weight: weight 1.7e+308 is too large"},
      {basic + " --export-mesh " + dir, "--export-mesh: needs --pipeline exact"},
      {basic + " --exact-fractions", "--exact-fractions: needs --pipeline exact"},
      {basic + " --voxels-out " + dir, "--voxels-out: needs a file name ending in .npy"},
      {basic + " --voxels-out ''", "--voxels-out: needs a file name ending in .npy"},
      {basic + " --voxels-out " + npy_dir, "--voxels-out: " + npy_dir + ": is a directory"},
      {basic + " --bogus", "command line"},
      {"evaluat " + kData + "paper_basic.json", "unknown command \"evaluat\""},
      {compare + " --resolutions 16x12x12, --out " + dir + "/c", "--resolutions: empty entry"},
      {compare + " --out /proc/camplace-test", "--out: cannot create directory"},
      {"generate resolution --param 1 --out " + dir, "--out: \"" + dir + "\" is not a file name"},
  };
  for (const Case& c : cases) {
    const CommandResult r = run(c.args);
    EXPECT_EQ(r.exit_code, 1) << c.args;
    EXPECT_EQ(r.output.rfind("error: ", 0), 0u) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.args << "\n" << r.output;
  }
}

// A key holding a line break or a NUL: the message stays one `error:` line with the whole reason
// (the control characters escaped), neither split into a forged second line nor cut short.
TEST(EvaluateCommand, ControlCharactersInKeysStayEscapedOnTheOneErrorLine) {
  const std::string dir = temp_dir("evalctl");
  const std::string scene = read_text(kData + "paper_basic.json");
  const std::string cameras = " --cameras " + kData + "paper_basic_corners.json";
  const std::string line_break =
      write_file(dir + "/line.json", replace_first(scene, "{", R"({"x\nerror: forged": 1,)"));
  const std::string nul =
      write_file(dir + "/nul.json", replace_first(scene, "{", R"({"plaus\u0000ibility": {},)"));
  const std::string expected[] = {
      "error: " + line_break + ": /x\\nerror: forged: unknown field \"x\\nerror: forged\" ",
      "error: " + nul + ": /plaus\\u0000ibility: unknown field \"plaus\\u0000ibility\" ",
  };
  int i = 0;
  for (const std::string& file : {line_break, nul}) {
    const CommandResult r = run("evaluate " + file + cameras);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(r.output.rfind(expected[i++], 0), 0u) << r.output;
    EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << r.output;
    EXPECT_NE(r.output.find("(expected one of: area, "), std::string::npos) << r.output;
  }
}

}  // namespace
}  // namespace camplace::testing
