// `camplace robustness` and `camplace plan` as a user runs them: bad input refused before any
// work, zero tolerance, the perturbation bound, the worst case reproduced by `evaluate`, and a
// plan's recommendation checked against separately run `optimize` and `evaluate`.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "camplace/compare/plan.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/core/scene_writer.hpp"
#include "command.hpp"

namespace camplace::testing {
namespace {

namespace fs = std::filesystem;

CommandResult run(const std::string& args) { return run_camplace(CAMPLACE_BINARY, args); }

const std::string kSource = std::string(CAMPLACE_SOURCE_DIR) + "/";
const std::string kCell = kSource + "examples/first_cell/first_cell.json";
const std::string kCellCameras = kSource + "examples/first_cell/cameras.json";

/// A fresh, empty folder for one test.
fs::path fresh_dir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("camplace-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

nlohmann::json read_json(const fs::path& path) { return nlohmann::json::parse(read_text(path)); }

/// The rows of a CSV file with a header, as maps from column to text.
std::vector<std::map<std::string, std::string>> read_csv(const fs::path& path) {
  std::istringstream in(read_text(path));
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) cells.push_back(cell);
    if (line.back() == ',') cells.emplace_back();
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

/// Exit status 1, exactly one line, starting "error: ", and no output folder made.
void expect_refused(const std::string& args, const fs::path& out, const std::string& says) {
  const CommandResult r = run(args);
  EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.output;
  EXPECT_EQ(r.output.rfind("error: ", 0), 0u) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_NE(r.output.find(says), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out)) << args;
}

TEST(PlanCommand, BadCountsAreRefusedBeforeAnythingStarts) {
  const fs::path out = fresh_dir("plan-bad");
  const std::string plan = "plan " + kCell + " --out " + out.string() + " --counts ";
  expect_refused(plan + "''", out, "--counts");
  expect_refused(plan + "5..2", out, "reversed");
  expect_refused(plan + "2..257", out, "exceed");
  expect_refused(plan + "0..3", out, "at least 1");
  expect_refused(plan + "2..x", out, "--counts");
}

TEST(RobustnessCommand, BadTolerancesAndCameraFilesAreRefusedBeforeAnythingStarts) {
  const fs::path out = fresh_dir("robustness-bad");
  const std::string base =
      "robustness " + kCell + " --cameras " + kCellCameras + " --out " + out.string() + " ";
  expect_refused(base + "--position-tol -0.01 --angle-tol 1", out, "--position-tol");
  expect_refused(base + "--position-tol nan --angle-tol 1", out, "--position-tol");
  expect_refused(base + "--position-tol inf --angle-tol 1", out, "--position-tol");
  expect_refused(base + "--position-tol 0.01 --angle-tol -1", out, "--angle-tol");
  expect_refused(base + "--position-tol 0.01 --angle-tol inf", out, "--angle-tol");
  expect_refused(base + "--position-tol 0.01 --angle-tol nan", out, "--angle-tol");
  // Six cameras for a scene of two.
  expect_refused("robustness " + kCell + " --cameras " + kSource +
                     "data/paper_basic_corners.json --position-tol 0.01 --angle-tol 1 --out " +
                     out.string(),
                 out, "holds 6 cameras");
  // A camera below the scene's domain (the upper fourth of the height: z ≥ 1.875 m).
  const fs::path low = fs::temp_directory_path() / ("camplace-low-" + std::to_string(::getpid()));
  std::ofstream(low)
      << R"({"cameras": [{"position": [0, 0, 1.0], "yaw_deg": 36.87, "pitch_deg": -35},
    {"position": [4, 3, 2.5], "yaw_deg": -143.13, "pitch_deg": -35}]})";
  expect_refused("robustness " + kCell + " --cameras " + low.string() +
                     " --position-tol 0.01 --angle-tol 1 --out " + out.string(),
                 out, "outside the placement domain");
  fs::remove(low);
  // A run file made for another scene (paper_basic's), its cameras those of the tutorial cell.
  const fs::path other = fresh_dir("robustness-other");
  const CommandResult o = run("optimize " + kSource + "data/paper_basic.json --max-evals 50 " +
                              "--quiet --threads 1 --out " + other.string());
  ASSERT_EQ(o.exit_code, 0) << o.output;
  nlohmann::json runfile = read_json(other / "run-1.json");
  runfile["cameras"] = read_json(kCellCameras)["cameras"];
  std::ofstream(other / "run-x.json") << runfile.dump(1);
  expect_refused("robustness " + kCell + " --cameras " + (other / "run-x.json").string() +
                     " --position-tol 0.01 --angle-tol 1 --out " + out.string(),
                 out, "changed");
}

// Zero tolerance: every perturbed configuration is the planned one, so every sample, the search
// and every camera alone give the planned Err.
TEST(RobustnessCommand, ZeroToleranceGivesThePlannedErrEverywhere) {
  const fs::path out = fresh_dir("robustness-zero");
  const CommandResult r = run("robustness " + kCell + " --cameras " + kCellCameras +
                              " --position-tol 0 --angle-tol 0 --samples 25 --search-evals 50 "
                              "--exact-checks 0 --out " +
                              out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = read_json(out / "robustness.json");
  const double planned = j["planned"]["voxel_err"].get<double>();
  // The planned configuration's Err as `evaluate` gives it.
  const CommandResult e = run("evaluate " + kCell + " --cameras " + kCellCameras + " --json");
  ASSERT_EQ(e.exit_code, 0) << e.output;
  EXPECT_EQ(nlohmann::json::parse(e.output)["err"].get<double>(), planned);
  const auto rows = read_csv(out / "samples.csv");
  ASSERT_EQ(rows.size(), 25u);
  for (const auto& row : rows) {
    EXPECT_EQ(std::stod(row.at("err")), planned);
    EXPECT_EQ(std::stod(row.at("max_moved_m")), 0.0);
  }
  EXPECT_EQ(j["worst"]["err"].get<double>(), planned);
  EXPECT_EQ(j["p95_err"].get<double>(), planned);
  for (const auto& c : j["per_camera"]) EXPECT_EQ(c["worst_voxel_err"].get<double>(), planned);
}

/// Unit viewing direction of a camera file entry (SPEC §1).
std::array<double, 3> direction(const nlohmann::json& camera) {
  const double yaw = camera["yaw_deg"].get<double>() * M_PI / 180.0;
  const double pitch = camera["pitch_deg"].get<double>() * M_PI / 180.0;
  return {std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch)};
}

// The bound: every camera of the written worst configuration lies within the tolerances of the
// planned one (measured here from the two camera files), and inside its domain (optimize refuses
// a start file outside it); every sample's recorded deviation is within the bound too.
TEST(RobustnessCommand, PerturbedCamerasStayWithinTheTolerancesAndTheirDomains) {
  const fs::path out = fresh_dir("robustness-bound");
  const double position_tol = 0.2, angle_tol_deg = 10.0;
  const CommandResult r = run("robustness " + kCell + " --cameras " + kCellCameras +
                              " --position-tol 0.2 --angle-tol 10 --samples 60 --search-evals 300 "
                              "--exact-checks 0 --out " +
                              out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json planned = read_json(kCellCameras)["cameras"];
  const nlohmann::json worst = read_json(out / "worst-cameras.json")["cameras"];
  ASSERT_EQ(worst.size(), planned.size());
  bool moved = false;
  for (std::size_t i = 0; i < planned.size(); ++i) {
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double d =
          worst[i]["position"][k].get<double>() - planned[i]["position"][k].get<double>();
      d2 += d * d;
    }
    EXPECT_LE(std::sqrt(d2), position_tol * (1 + 1e-9)) << i;
    const auto a = direction(planned[i]), b = direction(worst[i]);
    const double dot = std::clamp(a[0] * b[0] + a[1] * b[1] + a[2] * b[2], -1.0, 1.0);
    EXPECT_LE(std::acos(dot) * 180.0 / M_PI, angle_tol_deg + 1e-6) << i;
    // The domain: z in the upper fourth, looking level or down.
    EXPECT_GE(worst[i]["position"][2].get<double>(), 1.875 - 1e-9);
    EXPECT_LE(worst[i]["position"][2].get<double>(), 2.5 + 1e-9);
    EXPECT_LE(worst[i]["pitch_deg"].get<double>(), 1e-9);
    moved = moved || d2 > 0.0;
  }
  EXPECT_TRUE(moved);
  const CommandResult start =
      run("optimize " + kCell + " --start " + (out / "worst-cameras.json").string() +
          " --max-evals 1 --quiet --out " + (out / "start").string());
  EXPECT_EQ(start.exit_code, 0) << start.output;
  for (const auto& row : read_csv(out / "samples.csv")) {
    EXPECT_LE(std::stod(row.at("max_moved_m")), position_tol * (1 + 1e-9));
    EXPECT_LE(std::stod(row.at("max_turned_deg")), angle_tol_deg + 1e-6);
  }
  // The worst is at least every sample's Err, and the 95th percentile lies between.
  const nlohmann::json j = read_json(out / "robustness.json");
  for (const auto& row : read_csv(out / "samples.csv")) {
    EXPECT_LE(std::stod(row.at("err")), j["worst"]["err"].get<double>() * (1 + 1e-6));
  }
  EXPECT_LE(j["p95_err"].get<double>(), j["worst"]["err"].get<double>());
}

// Mounts and keep-out boxes: the perturbed cameras of the catalogue cell stay on their mounts and
// out of the keep-out box (optimize accepts the worst file as a start).
TEST(RobustnessCommand, PerturbedCamerasStayOnTheirMounts) {
  const fs::path out = fresh_dir("robustness-mounts");
  const std::string scene = kSource + "data/cell_catalogue.json";
  const CommandResult o = run("optimize " + scene + " --max-evals 200 --quiet --threads 1 --out " +
                              (out / "run").string());
  ASSERT_EQ(o.exit_code, 0) << o.output;
  const CommandResult r =
      run("robustness " + scene + " --cameras " + (out / "run/run-1.json").string() +
          " --position-tol 0.3 --angle-tol 15 --samples 30 --search-evals 100 "
          "--exact-checks 0 --out " +
          (out / "rob").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const CommandResult start =
      run("optimize " + scene + " --start " + (out / "rob/worst-cameras.json").string() +
          " --max-evals 1 --quiet --out " + (out / "start").string());
  EXPECT_EQ(start.exit_code, 0) << start.output;
}

// The worst case written is the one reported: `evaluate` of the file gives its voxel Err and,
// with the exact pipeline, its exact Err, to the last bit.
TEST(RobustnessCommand, EvaluateReproducesTheWorstCase) {
  const fs::path out = fresh_dir("robustness-worst");
  const CommandResult r = run("robustness " + kCell + " --cameras " + kCellCameras +
                              " --position-tol 0.1 --angle-tol 5 --samples 40 --search-evals 200 "
                              "--exact-checks 1 --out " +
                              out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = read_json(out / "robustness.json");
  const std::string worst = (out / "worst-cameras.json").string();
  const CommandResult v = run("evaluate " + kCell + " --cameras " + worst + " --json");
  ASSERT_EQ(v.exit_code, 0) << v.output;
  EXPECT_EQ(nlohmann::json::parse(v.output)["err"].get<double>(),
            j["worst"]["voxel_err"].get<double>());
  EXPECT_EQ(j["worst"]["err"].get<double>(), j["worst"]["voxel_err"].get<double>());
  ASSERT_FALSE(j["worst"]["exact_err"].is_null()) << j["worst"].dump();
  const CommandResult x =
      run("evaluate " + kCell + " --cameras " + worst + " --pipeline exact --json");
  ASSERT_EQ(x.exit_code, 0) << x.output;
  EXPECT_EQ(nlohmann::json::parse(x.output)["err"].get<double>(),
            j["worst"]["exact_err"].get<double>());
  // The report names what made it.
  EXPECT_FALSE(j["provenance"]["commit"].get<std::string>().empty());
  EXPECT_FALSE(j["provenance"]["scene_sha256"].get<std::string>().empty());
}

// --pipeline exact: every sample's Err is the exact one, and the worst is reproduced by
// `evaluate --pipeline exact`.
TEST(RobustnessCommand, ExactPipelineSamplesAreExactAndTheWorstIsReproduced) {
  const fs::path out = fresh_dir("robustness-exact");
  const CommandResult r = run("robustness " + kCell + " --cameras " + kCellCameras +
                              " --position-tol 0.05 --angle-tol 3 --samples 4 --search-evals 20 "
                              "--pipeline exact --out " +
                              out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = read_json(out / "robustness.json");
  for (const auto& row : read_csv(out / "samples.csv")) {
    ASSERT_FALSE(row.at("exact_err").empty());
    EXPECT_EQ(row.at("err"), row.at("exact_err"));
  }
  const CommandResult x = run("evaluate " + kCell + " --cameras " +
                              (out / "worst-cameras.json").string() + " --pipeline exact --json");
  ASSERT_EQ(x.exit_code, 0) << x.output;
  EXPECT_EQ(nlohmann::json::parse(x.output)["err"].get<double>(), j["worst"]["err"].get<double>());
  EXPECT_EQ(j["worst"]["err"].get<double>(), j["worst"]["exact_err"].get<double>());
}

// The cycled scenes: camera i of the catalogue cell with n cameras has the model and domain of
// the cell's camera i mod 4.
TEST(PlanScenes, CamerasAreCycled) {
  const core::Scene scene = core::load_scene(kSource + "data/cell_catalogue.json");
  ASSERT_EQ(scene.cameras.count, 4);
  for (const int n : {1, 3, 9}) {
    const core::Scene s = compare::scene_with_cameras(scene, n);
    ASSERT_EQ(s.cameras.count, n);
    ASSERT_EQ(s.cameras.models.size(), static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      EXPECT_EQ(s.cameras.models[i].name, scene.cameras.models[i % 4].name);
      ASSERT_EQ(s.cameras.domains[i].mount.has_value(),
                scene.cameras.domains[i % 4].mount.has_value());
      if (s.cameras.domains[i].mount) {
        EXPECT_EQ(s.cameras.domains[i].mount->name, scene.cameras.domains[i % 4].mount->name);
      }
    }
  }
}

/// The tutorial cell with `cost` in its camera block (the single-model form), as a file.
fs::path cell_with_cost(const std::string& cost) {
  nlohmann::json scene = read_json(kCell);
  scene["cameras"]["cost"] = nlohmann::json::parse(cost);
  const fs::path file = fs::temp_directory_path() /
                        ("camplace-cost-" + std::to_string(std::hash<std::string>{}(cost)) + "-" +
                         std::to_string(::getpid()) + ".json");
  std::ofstream(file) << scene.dump(1);
  return file;
}

// A camera model's optional cost: read, written back by the scene writer, refused when negative,
// and summed per count by plan, which then plots Err against it.
TEST(PlanScenes, CostIsReadWrittenAndSummed) {
  const fs::path file = cell_with_cost("250.5");
  const core::Scene scene = core::load_scene(file.string());
  ASSERT_TRUE(scene.cameras.models.front().cost.has_value());
  EXPECT_EQ(*scene.cameras.models.front().cost, 250.5);
  EXPECT_EQ(*compare::cameras_cost(compare::scene_with_cameras(scene, 3)), 3 * 250.5);
  EXPECT_EQ(nlohmann::json::parse(core::scene_text(scene))["cameras"]["cost"].get<double>(), 250.5);
  const core::Scene without = core::load_scene(kCell);
  EXPECT_FALSE(compare::cameras_cost(without).has_value());
  for (const char* bad : {"-1", "\"cheap\""}) {
    const fs::path b = cell_with_cost(bad);
    EXPECT_THROW(core::load_scene(b.string()), core::InputError) << bad;
    fs::remove(b);
  }
  const fs::path out = fresh_dir("plan-cost");
  const CommandResult r = run("plan " + file.string() + " --counts 1..2 --runs 1 --max-evals 100 " +
                              "--threads 1 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto rows = read_csv(out / "plan.csv");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(std::stod(rows[0].at("cost")), 250.5);
  EXPECT_EQ(std::stod(rows[1].at("cost")), 501.0);
  EXPECT_TRUE(fs::exists(out / "plan_cost.png"));
  fs::remove(file);
}

// A tiny plan: 1..3 cameras of the tutorial cell, 2 runs of 1,500 evaluations each. Every
// count's best run is what `optimize` gives on the written scene alone, its exact Err what
// `evaluate --pipeline exact` gives, and the recommendation the smallest count whose exact Err
// reaches the tolerance (one camera cannot: it sees one side of the person only). A rerun resumes
// without running anything.
TEST(PlanCommand, RecommendsTheSmallestCountThatReachesTheToleranceByExactErr) {
  const fs::path out = fresh_dir("plan");
  const std::string command = "plan " + kCell +
                              " --counts 1..3 --runs 2 --max-evals 1500 --threads 1 --out " +
                              out.string();
  const CommandResult r = run(command);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json plan = read_json(out / "plan.json");
  ASSERT_EQ(plan["counts"].size(), 3u);
  std::optional<int> expected;
  for (const auto& c : plan["counts"]) {
    const int n = c["cameras"].get<int>();
    ASSERT_EQ(c["runs_done"].get<int>(), 2);
    // Each seed again, by optimize alone on the count's scene.
    const std::string scene =
        (out / "scenes" / ("cameras-" + std::to_string(n) + ".json")).string();
    double best = 1e300;
    std::string best_file;
    for (const int seed : {1, 2}) {
      const fs::path dir = out / ("again-" + std::to_string(n) + "-" + std::to_string(seed));
      const CommandResult o =
          run("optimize " + scene + " --seed " + std::to_string(seed) +
              " --max-evals 1500 --time-limit 120 --threads 1 --quiet --out " + dir.string());
      ASSERT_EQ(o.exit_code, 0) << o.output;
      const std::string file = (dir / ("run-" + std::to_string(seed) + ".json")).string();
      const double err = read_json(file)["err"].get<double>();
      if (err < best) {
        best = err;
        best_file = file;
      }
    }
    EXPECT_EQ(c["voxel_err"].get<double>(), best) << n;
    const CommandResult x =
        run("evaluate " + scene + " --cameras " + best_file + " --pipeline exact --json");
    ASSERT_EQ(x.exit_code, 0) << x.output;
    const double exact = nlohmann::json::parse(x.output)["err"].get<double>();
    EXPECT_EQ(c["exact_err"].get<double>(), exact) << n;
    if (!expected && exact <= c["tolerance"].get<double>()) expected = n;
    if (n == 1) {
      EXPECT_GT(exact, c["tolerance"].get<double>());
    }
  }
  ASSERT_TRUE(expected.has_value());
  EXPECT_EQ(plan["recommended_cameras"].get<int>(), *expected);
  EXPECT_TRUE(fs::exists(out / "plan.png"));
  EXPECT_TRUE(fs::exists(out / "plan.md"));
  EXPECT_EQ(read_csv(out / "plan.csv").size(), 3u);
  // Resumed: nothing runs again, the same table.
  const std::string csv = read_text(out / "plan.csv");
  const CommandResult again = run(command);
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(again.output.find("plan: 1 cameras seed"), std::string::npos) << again.output;
  EXPECT_EQ(read_text(out / "plan.csv"), csv);
}

// Ctrl-C (SIGINT to the process group, as a terminal sends it) keeps the finished runs and ends
// with exit status 130; the same command then runs only the missing ones.
TEST(PlanCommand, InterruptedPlanResumesWithoutRepeatingRuns) {
  const fs::path out = fresh_dir("plan-int");
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    setpgid(0, 0);
    const int devnull = ::open("/dev/null", O_WRONLY);
    ::dup2(devnull, STDOUT_FILENO);
    ::dup2(devnull, STDERR_FILENO);
    execl(CAMPLACE_BINARY, CAMPLACE_BINARY, "plan", kCell.c_str(), "--counts", "1..3", "--runs",
          "2", "--max-evals", "4000", "--threads", "1", "--out", out.c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  setpgid(pid, pid);
  const auto start = std::chrono::steady_clock::now();
  while (!fs::exists(out / "runs/1/run-1.json") &&
         std::chrono::steady_clock::now() - start < std::chrono::seconds(60)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  kill(-pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  int finished = 0;
  for (const auto& e : fs::recursive_directory_iterator(out / "runs")) {
    const std::string name = e.path().filename().string();
    if (name.rfind("run-", 0) == 0 &&
        read_json(e.path())["stop_reason"].get<std::string>() != "interrupted") {
      ++finished;
    }
  }
  ASSERT_GE(finished, 1);
  ASSERT_LT(finished, 6) << "the plan finished before the interrupt; the test proves nothing";
  const CommandResult resumed =
      run("plan " + kCell + " --counts 1..3 --runs 2 --max-evals 4000 --threads 1 --out " +
          out.string());
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("(1 of " + std::to_string(6 - finished) + ")"), std::string::npos)
      << resumed.output;
  for (const auto& c : read_json(out / "plan.json")["counts"]) {
    EXPECT_EQ(c["runs_done"].get<int>(), 2);
    EXPECT_FALSE(c["exact_err"].is_null());
  }
  EXPECT_TRUE(read_json(out / "plan.json")["recommendation_final"].get<bool>());
}

}  // namespace
}  // namespace camplace::testing
