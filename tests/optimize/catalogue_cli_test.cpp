// Runs the real `camplace` binary on data/cell_catalogue.json: optimize with --snap
// writes a snapped result whose Err `camplace evaluate` reproduces, whose cameras lie on their
// mounts and out of the keep-out box; bad --snap values exit 1 naming the option.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "command.hpp"

namespace {

using camplace::testing::capture;

namespace fs = std::filesystem;
using nlohmann::json;

const std::string kBinary = CAMPLACE_BINARY;
const std::string kScene = std::string(CAMPLACE_SOURCE_DIR) + "/data/cell_catalogue.json";

TEST(CatalogueCli, SnappedResultIsOnItsMountsAndEvaluateReproducesItsErr) {
  const fs::path out =
      fs::temp_directory_path() / ("camplace-catalogue-" + std::to_string(::getpid()));
  const std::string text = capture(kBinary + " optimize " + kScene + " --quiet --out " +
                                   out.string() + " --max-evals 300 --snap 0.1,5 2>&1; echo rc=$?");
  ASSERT_NE(text.find("rc=0\n"), std::string::npos) << text;
  EXPECT_NE(text.find("snapped to 0.1 m, 5° (seed 1): Err "), std::string::npos) << text;
  json run;
  std::ifstream(out / "run-1.json") >> run;
  ASSERT_TRUE(run.contains("snapped")) << run.dump(1);
  const json& snapped = run["snapped"];
  ASSERT_EQ(snapped["cameras"].size(), 4u);
  // Cameras 0 and 1 on the ceiling (z = 3), 2 on the west wall (x = 0, z ≥ 1.8), 3 on the north
  // wall (y = 3, z ≥ 1.8); none strictly inside the keep-out box [1.7,−0.1,−0.1]–[4.1,1.9,3.1].
  const auto position = [&](int i) { return snapped["cameras"][i]["position"]; };
  EXPECT_NEAR(position(0)[2].get<double>(), 3.0, 1e-9);
  EXPECT_NEAR(position(1)[2].get<double>(), 3.0, 1e-9);
  EXPECT_NEAR(position(2)[0].get<double>(), 0.0, 1e-9);
  EXPECT_GE(position(2)[2].get<double>(), 1.8 - 1e-9);
  EXPECT_NEAR(position(3)[1].get<double>(), 3.0, 1e-9);
  for (int i = 0; i < 4; ++i) {
    const double x = position(i)[0], y = position(i)[1], z = position(i)[2];
    EXPECT_FALSE(x > 1.7 + 1e-9 && x < 4.1 - 1e-9 && y > -0.1 + 1e-9 && y < 1.9 - 1e-9 &&
                 z > -0.1 + 1e-9 && z < 3.1 - 1e-9)
        << i;
    // On the 0.1 m grid along the mounts' edges (all edges here are axis-aligned from corners
    // on multiples of 0.1 m): every coordinate is a multiple of 0.1 m or a face of the box.
    for (double v : {x, y, z}) {
      const bool on_grid = std::abs(v * 10 - std::round(v * 10)) < 1e-6;
      EXPECT_TRUE(on_grid) << "camera " << i << " coordinate " << v;
    }
  }
  // evaluate on the snapped cameras gives the snapped Err.
  const fs::path cameras = out / "snapped.json";
  std::ofstream(cameras) << json{{"cameras", snapped["cameras"]}}.dump(1);
  const std::string evaluated =
      capture(kBinary + " evaluate " + kScene + " --cameras " + cameras.string() + " --json");
  const json e = json::parse(evaluated);
  EXPECT_EQ(e["err"].get<double>(), snapped["err"].get<double>());
  fs::remove_all(out);
}

TEST(CatalogueCli, EvaluateWarnsAboutACameraInAKeepOutBox) {
  const fs::path dir =
      fs::temp_directory_path() / ("camplace-catalogue-warn-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path cameras = dir / "cameras.json";
  // Camera 1 at (3, 1, 2): inside "robot reach" [1.7,−0.1,−0.1]–[4.1,1.9,3.1].
  std::ofstream(cameras) << R"({"cameras": [
    {"position": [1, 1, 3], "yaw_deg": 0, "pitch_deg": -90},
    {"position": [3, 1, 2], "yaw_deg": 0, "pitch_deg": -90},
    {"position": [0, 1.5, 2.5], "yaw_deg": 0, "pitch_deg": -30},
    {"position": [1, 3, 2.5], "yaw_deg": -90, "pitch_deg": -30}]})";
  const std::string text = capture(kBinary + " evaluate " + kScene + " --cameras " +
                                   cameras.string() + " 2>&1 >/dev/null; echo rc=$?");
  EXPECT_NE(text.find("warning: " + cameras.string() +
                      ": /cameras/1/position: camera 1 lies in keep-out box \"robot reach\""),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("/cameras/0/position"), std::string::npos) << text;
  EXPECT_NE(text.find("rc=0\n"), std::string::npos) << text;
  fs::remove_all(dir);
}

TEST(CatalogueCli, BadSnapValuesExitOneNamingTheOption) {
  const std::string out =
      (fs::temp_directory_path() / ("camplace-catalogue-bad-" + std::to_string(::getpid())))
          .string();
  for (const std::string value : {"0,5", "0.1,-1", "0.1", "x,5", "0.1,nan", "inf,5", "0.1,5,3"}) {
    const std::string text = capture(kBinary + " optimize " + kScene + " --quiet --out " + out +
                                     " --max-evals 10 --snap " + value + " 2>&1; echo rc=$?");
    EXPECT_EQ(text.rfind("error: command line: --snap: ", 0), 0u) << value << "\n" << text;
    EXPECT_NE(text.find("rc=1\n"), std::string::npos) << value << "\n" << text;
  }
  fs::remove_all(out);
}

}  // namespace
