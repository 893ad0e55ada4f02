// Studies and generated scenes on any base scene, and the provenance header of
// the reports: each family applied to a small base that is not the paper's
// gives the scene computed here by hand; a family that cannot apply is an error naming the
// family, the base and the reason (in a study file: the file and the examination, before any
// run); a study runs on the base, its report names the base with the SHA-256 `sha256sum`
// computes, and a changed base stops a resume.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "camplace/core/error.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/core/provenance.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/scenes/generator.hpp"
#include "command.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

namespace fs = std::filesystem;
using core::Vec3;
using scenes::BaseScene;
using scenes::generate_scene_json;

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A 3 x 2 x 2.5 m cell, 8x6x6 voxels, 2 cameras anywhere: a table (tetrahedron), a robot link
// (tetrahedron, top 0.9 m) in one time step, two events with one tall target each (weights 0.6
// and 0.4). Volumes by hand: table base triangle ½·0.8·0.6 = 0.24 m², height 0.8 m → 0.064 m³;
// target base ½·0.4·0.3 = 0.06 m², height 1.6 m → 0.032 m³.
const char* kBase = R"({
 "area": {"min": [0, 0, 0], "max": [3, 2, 2.5]},
 "voxels": [8, 6, 6],
 "cameras": {"count": 2, "half_angle_deg": 30, "fov": "cone", "domain": "room"},
 "static_obstacles": [
  {"name": "table", "tetrahedron": [[2.1, 1.3, 0], [2.9, 1.3, 0], [2.1, 1.9, 0], [2.3, 1.5, 0.8]]}],
 "time_steps": [
  {"dynamic_obstacles": [
    {"name": "link", "tetrahedron": [[0.2, 0.2, 0], [0.6, 0.2, 0], [0.2, 0.6, 0], [0.3, 0.3, 0.9]]}],
   "events": [
    {"weight": 0.6, "targets": [
      {"name": "t1", "tetrahedron": [[1.2, 0.9, 0], [1.6, 0.9, 0], [1.4, 1.2, 0], [1.4, 1.0, 1.6]]}]},
    {"weight": 0.4, "targets": [
      {"name": "t2", "tetrahedron": [[1.8, 0.4, 0], [2.2, 0.4, 0], [2.0, 0.7, 0], [2.0, 0.5, 1.6]]}]}]}],
 "plausibility": {"min_volume": 0.03, "min_height": 1.5}
})";

struct Fixture {
  std::string dir, base_path;
  BaseScene base;
};

const Fixture& fixture() {
  static const Fixture f = [] {
    Fixture x;
    x.dir = temp_dir("base-scene");
    x.base_path = write_file(x.dir + "/cell.json", kBase);
    x.base = scenes::load_base_scene(x.base_path, "cell.json");
    return x;
  }();
  return f;
}

core::Scene on_base(const std::string& family, std::optional<int> param, unsigned seed = 1) {
  const std::string text = generate_scene_json(family, param, seed, &fixture().base);
  static int n = 0;
  return core::load_scene(write_file(fixture().dir + "/g" + std::to_string(n++) + ".json", text));
}

int facets(const std::vector<core::SceneObject>& objects) {
  int n = 0;
  for (const auto& o : objects) n += static_cast<int>(o.mesh.triangles.size());
  return n;
}

/// The reason of the error generate_scene_json throws, or "" when it does not throw.
std::string error_of(const std::string& family, std::optional<int> param,
                     const BaseScene& base = fixture().base) {
  try {
    (void)generate_scene_json(family, param, 1, &base);
  } catch (const core::OptionError& e) {
    EXPECT_EQ(e.option(), "base");
    return e.reason();
  }
  return "";
}

TEST(BaseScene, ResolutionScalesTheBasesVoxelsByAQuarterPerStepRounded) {
  // 8·5/4 = 10, 6·5/4 = 7.5 → 8 (rounded half away from zero); 8·6/4 = 12, 6·6/4 = 9.
  EXPECT_EQ(on_base("resolution", 1).voxels, (std::array<int, 3>{10, 8, 8}));
  EXPECT_EQ(on_base("resolution", 2).voxels, (std::array<int, 3>{12, 9, 9}));
  // Nothing else changes: the base's objects, cameras and thresholds.
  const core::Scene s = on_base("resolution", 0);
  EXPECT_EQ(s.voxels, (std::array<int, 3>{8, 6, 6}));
  EXPECT_EQ(s.cameras.count, 2);
  EXPECT_EQ(s.plausibility.min_volume, 0.03);
  EXPECT_EQ(s.plausibility.min_height, 1.5);
}

// The finer objects' vertices are rounded to micrometres: volumes agree to about 1e-7 m³.
constexpr double kVolumeSlack = 1e-6;

TEST(BaseScene, FacetFamiliesMakeTheBasesTetrahedraFinerWithTheSameVolume) {
  const core::Scene s = on_base("static_facets", 1);
  ASSERT_EQ(s.static_obstacles.size(), 1u);
  EXPECT_EQ(facets(s.static_obstacles), 34);  // 4 + 30·1
  EXPECT_NEAR(std::abs(core::signed_volume(s.static_obstacles[0].mesh)), 0.064, kVolumeSlack);
  EXPECT_NEAR(s.static_obstacles[0].bounds.max.z(), 0.8, 1e-12);  // same apex

  const core::Scene d = on_base("dynamic_facets", 2);
  EXPECT_EQ(facets(d.time_steps[0].dynamic_obstacles), 24);  // 4 + 10·2
  EXPECT_NEAR(std::abs(core::signed_volume(d.time_steps[0].dynamic_obstacles[0].mesh)),
              0.5 * 0.4 * 0.4 * 0.9 / 3.0, kVolumeSlack);
  EXPECT_EQ(facets(d.time_steps[0].critical), 24);  // the default critical objects follow

  const core::Scene u = on_base("unmodelled_facets", 1);
  ASSERT_EQ(u.time_steps[0].events.size(), 2u);
  for (const core::Event& e : u.time_steps[0].events) {
    EXPECT_EQ(facets(e.targets), 14);  // 4 + 10·1
    EXPECT_NEAR(std::abs(core::signed_volume(e.targets[0].mesh)), 0.032, kVolumeSlack);
  }
  EXPECT_EQ(u.plausibility.min_volume, 0.03);  // targets keep volume and height
}

TEST(BaseScene, StaticObjectsAddThePapersFurnitureStretchedToTheBasesFloor) {
  const core::Scene s = on_base("static_objects", 1);
  ASSERT_EQ(s.static_obstacles.size(), 2u);
  EXPECT_EQ(s.static_obstacles[1].name, "shelf");
  // The paper's shelf (0.1, 2.3, 0) (0.7, 2.9, 0) (0.1, 2.9, 0) (0.25, 2.75, 1.6) on its 4 × 3 m
  // floor, x·3/4 and y·2/3 on the base's 3 × 2 m floor: x 0.075–0.525, y 1.533333–1.933333.
  EXPECT_NEAR(s.static_obstacles[1].bounds.min.x(), 0.075, 1e-12);
  EXPECT_NEAR(s.static_obstacles[1].bounds.max.x(), 0.525, 1e-12);
  EXPECT_NEAR(s.static_obstacles[1].bounds.min.y(), 1.533333, 1e-12);
  EXPECT_NEAR(s.static_obstacles[1].bounds.max.y(), 1.933333, 1e-12);
  EXPECT_NEAR(s.static_obstacles[1].bounds.max.z(), 1.6, 1e-12);
}

TEST(BaseScene, RandomFamiliesPlaceTheirObjectsInTheBasesArea) {
  const core::Scene d = on_base("dynamic_objects", 1, 7);
  ASSERT_EQ(d.time_steps.size(), 1u);
  EXPECT_EQ(d.time_steps[0].dynamic_obstacles.size(), 3u);   // 2 + 1
  EXPECT_EQ(facets(d.time_steps[0].dynamic_obstacles), 28);  // 24 + 4
  for (const core::SceneObject& o : d.time_steps[0].dynamic_obstacles) {
    EXPECT_LE(o.bounds.max.z(), 0.95 + 1e-9);
    EXPECT_GE(o.bounds.min.x(), 0.05 - 1e-9);
    EXPECT_LE(o.bounds.max.x(), 2.95 + 1e-9);
    EXPECT_LE(o.bounds.max.y(), 1.95 + 1e-9);
  }
  const core::Scene u = on_base("unmodelled_objects", 0, 3);
  ASSERT_EQ(u.time_steps[0].events.size(), 1u);
  EXPECT_EQ(u.time_steps[0].events[0].weight, 1.0);
  EXPECT_EQ(u.time_steps[0].events[0].targets.size(), 2u);
  double lowest = 10.0;
  for (const auto& o : u.time_steps[0].events[0].targets) {
    lowest = std::min(lowest, o.bounds.size().z());
    EXPECT_GE(o.bounds.size().z(), 1.5 - 1e-9);
  }
  // New targets: the height threshold is the smallest target's height, rounded down.
  EXPECT_LE(u.plausibility.min_height, lowest);
  EXPECT_GT(u.plausibility.min_height, lowest - 1e-6);
}

TEST(BaseScene, EventsCamerasAndDomainsFollowTheBase) {
  // The first event alone carries the step's whole weight: 0.6 · (1.0 / 0.6) = 1.
  const core::Scene one = on_base("unmodelled_events", 1);
  ASSERT_EQ(one.time_steps[0].events.size(), 1u);
  EXPECT_NEAR(one.time_steps[0].events[0].weight, 1.0, 1e-15);
  EXPECT_EQ(one.time_steps[0].events[0].targets[0].name, "t1");
  const core::Scene two = on_base("unmodelled_events", 2);
  EXPECT_NEAR(two.time_steps[0].events[1].weight, 0.4, 1e-15);

  const core::Scene cams = on_base("cameras", 5);
  EXPECT_EQ(cams.cameras.count, 5);
  ASSERT_EQ(cams.cameras.domains.size(), 5u);
  EXPECT_EQ(cams.cameras.domains[4].x.hi, 3.0);
  EXPECT_EQ(cams.cameras.domains[4].z.hi, 2.5);

  const core::Scene ceiling = on_base("domain_ceiling", std::nullopt);
  EXPECT_EQ(ceiling.cameras.domains[0].z.lo, 2.5);  // the base's ceiling, not the paper's 3 m
  EXPECT_EQ(ceiling.cameras.domains[0].z.hi, 2.5);
  const core::Scene upper = on_base("domain_upper_fourth", std::nullopt);
  EXPECT_EQ(upper.cameras.domains[0].z.lo, 2.5 * 0.75);
}

TEST(BaseScene, FamiliesThatCannotApplyNameTheFamilyTheBaseAndTheReason) {
  std::string e = error_of("dynamic_steps", 2);
  EXPECT_NE(e.find("family dynamic_steps cannot be applied to the base scene cell.json"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("robot arm"), std::string::npos) << e;
  e = error_of("unmodelled_events", 3);
  EXPECT_NE(e.find("i = 3 needs 3 events in every time step, and its time step 0 has 2"),
            std::string::npos)
      << e;
  // A base whose static obstacle is a box (12 facets): only tetrahedra are made finer.
  std::string boxed = kBase;
  const std::string table =
      R"("tetrahedron": [[2.1, 1.3, 0], [2.9, 1.3, 0], [2.1, 1.9, 0], [2.3, 1.5, 0.8]])";
  boxed.replace(boxed.find(table), table.size(),
                R"("box": {"min": [2.1, 1.3, 0], "max": [2.9, 1.9, 0.8]})");
  const BaseScene box_base =
      scenes::load_base_scene(write_file(fixture().dir + "/boxed.json", boxed), "boxed.json");
  e = error_of("static_facets", 1, box_base);
  EXPECT_NE(e.find("static obstacle \"table\" has 12 facets; only tetrahedra are made finer"),
            std::string::npos)
      << e;
  EXPECT_EQ(error_of("static_facets", 1), "");
  // The paper's parameter ranges still hold.
  EXPECT_THROW(generate_scene_json("cameras", 10, 1, &fixture().base), core::OptionError);
}

TEST(BaseScene, TheDescriptionRecordsTheBasesHashSoAChangedBaseChangesTheScene) {
  const std::string text = generate_scene_json("cameras", 3, 1, &fixture().base);
  const std::string description = nlohmann::json::parse(text).at("description");
  EXPECT_NE(description.find("--base cell.json"), std::string::npos) << description;
  EXPECT_NE(description.find(fixture().base.hashes.combined), std::string::npos) << description;
  // One byte more in the base (a space): another hash, another scene text.
  const std::string changed = write_file(fixture().dir + "/cell2.json", std::string(kBase) + " ");
  const BaseScene other = scenes::load_base_scene(changed, "cell.json");
  EXPECT_NE(generate_scene_json("cameras", 3, 1, &other), text);
  // Without a base: the paper's basic setup as before (the base text is not mentioned).
  EXPECT_EQ(generate_scene_json("cameras", 3, 1).find("--base"), std::string::npos);
}

TEST(BaseScene, AMeshFileOfTheBaseThatChangesOnlyInBytesStillChangesTheScene) {
  // The table read from an OFF file; the second copy differs by a trailing blank line only, so
  // the meshes are the same and only the SHA-256 in the description tells them apart.
  const std::string dir = temp_dir("base-mesh");
  const std::string off =
      "OFF\n4 4 0\n2.1 1.3 0\n2.9 1.3 0\n2.1 1.9 0\n2.3 1.5 0.8\n"
      "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  std::string with_file = kBase;
  const std::string table =
      R"("tetrahedron": [[2.1, 1.3, 0], [2.9, 1.3, 0], [2.1, 1.9, 0], [2.3, 1.5, 0.8]])";
  with_file.replace(with_file.find(table), table.size(), R"("file": "table.off")");
  const std::string scene = write_file(dir + "/cell.json", with_file);
  write_file(dir + "/table.off", off);
  const BaseScene before = scenes::load_base_scene(scene, "cell.json");
  ASSERT_EQ(before.hashes.meshes.size(), 1u);
  const std::string text = generate_scene_json("resolution", 1, 1, &before);
  write_file(dir + "/table.off", off + "\n");
  const BaseScene after = scenes::load_base_scene(scene, "cell.json");
  EXPECT_EQ(after.scene.static_obstacles[0].mesh.vertices,
            before.scene.static_obstacles[0].mesh.vertices);
  EXPECT_NE(after.hashes.meshes[0].second, before.hashes.meshes[0].second);
  const std::string changed = generate_scene_json("resolution", 1, 1, &after);
  EXPECT_NE(changed, text);
  EXPECT_NE(changed.find(after.hashes.combined), std::string::npos);
}

/// `sha256sum FILE`'s digest: an implementation independent of camplace's.
std::string sha256sum(const std::string& path) {
  FILE* pipe = popen(("sha256sum '" + path + "'").c_str(), "r");
  EXPECT_NE(pipe, nullptr);
  char buffer[65] = {0};
  const std::size_t n = pipe ? std::fread(buffer, 1, 64, pipe) : 0;
  if (pipe) pclose(pipe);
  return std::string(buffer, n);
}

TEST(BaseScene, Sha256OfAKnownStringAndOfAFileAgreeWithSha256sum) {
  // FIPS 180-2's example: SHA-256("abc").
  EXPECT_EQ(core::sha256_hex("abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(core::sha256_file(fixture().base_path), sha256sum(fixture().base_path));
}

TEST(GenerateCommand, BaseOptionWritesTheFamilyOnTheBaseAndRejectsAnInapplicableFamily) {
  const std::string dir = temp_dir("generate-base");
  const std::string base = write_file(dir + "/cell.json", kBase);
  const CommandResult ok = run_camplace(
      CAMPLACE_BINARY, "generate cameras --param 4 --base " + base + " --out " + dir + "/c.json");
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  const core::Scene s = core::load_scene(dir + "/c.json");
  EXPECT_EQ(s.cameras.count, 4);
  EXPECT_EQ(s.area.max, Vec3(3, 2, 2.5));
  const CommandResult bad =
      run_camplace(CAMPLACE_BINARY,
                   "generate dynamic_steps --param 1 --base " + base + " --out " + dir + "/d.json");
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_EQ(bad.output.rfind("error:", 0), 0u) << bad.output;
  EXPECT_NE(bad.output.find("--base"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("dynamic_steps"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(dir + "/d.json"));
}

std::string study_json(const std::string& base, const std::string& examinations) {
  return R"({"description": "on a base", "base": ")" + base +
         R"(", "algorithm": "gaco", "mode": "center", "runs_per_group": 1, "threads": 1,
    "time_limit_s": 120, "max_evaluations": 40, "examinations": )" +
         examinations + "}";
}

TEST(BaseScene, AStudyWithAnInapplicableFamilyFailsBeforeAnyRunNamingFileAndExamination) {
  const std::string dir = temp_dir("study-base-bad");
  write_file(dir + "/scenes/cell.json", kBase);
  const std::string study = write_file(
      dir + "/study.json", study_json("scenes/cell.json", R"([{"family": "cameras", "params": [3]},
                                         {"family": "dynamic_steps", "params": [1]}])"));
  const CommandResult r =
      run_camplace(CAMPLACE_BINARY, "study " + study + " --out " + dir + "/out");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("error: " + study), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("/examinations/1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("family dynamic_steps cannot be applied to the base scene "
                          "scenes/cell.json"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir + "/out/runs"));
  // A base that does not exist names the study file's "base".
  const std::string missing =
      write_file(dir + "/missing.json", study_json("nowhere.json", R"([{"family": "cameras",
                                                                        "params": [3]}])"));
  const CommandResult m =
      run_camplace(CAMPLACE_BINARY, "study " + missing + " --out " + dir + "/o2");
  EXPECT_EQ(m.exit_code, 1) << m.output;
  EXPECT_NE(m.output.find("/base"), std::string::npos) << m.output;
}

TEST(BaseScene, AStudyRunsOnTheBaseRecordsItsHashAndRefusesToResumeOnAChangedBase) {
  const std::string dir = temp_dir("study-base");
  const std::string base = write_file(dir + "/in/cell.json", kBase);
  const std::string study = write_file(
      dir + "/in/study.json", study_json("cell.json", R"([{"family": "cameras", "params": [3]}])"));
  const std::string args = "study " + study + " --out " + dir + "/out";
  const CommandResult first = run_camplace(CAMPLACE_BINARY, args);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const core::Scene group = core::load_scene(dir + "/out/scenes/cameras-3.json");
  EXPECT_EQ(group.cameras.count, 3);
  EXPECT_EQ(group.area.max, Vec3(3, 2, 2.5));  // the base's area, not the paper's
  // The report's provenance header: version, base with its SHA-256 (short and full), host,
  // start time, the resolved options.
  const std::string report = read(dir + "/out/report.md");
  const std::string digest = sha256sum(base);
  ASSERT_EQ(digest.size(), 64u);
  EXPECT_NE(report.find("| base scene | `" + dir + "/in/cell.json`, SHA-256 `" +
                        digest.substr(0, 12) + "…`"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("| `" + dir + "/in/cell.json` | " + digest + " |"), std::string::npos)
      << report;
  EXPECT_NE(report.find("| scene of cameras-3 | `scenes/cameras-3.json`, SHA-256 `" +
                        sha256sum(dir + "/out/scenes/cameras-3.json").substr(0, 12)),
            std::string::npos)
      << report;
  char host[256] = {0};
  gethostname(host, sizeof host - 1);
  EXPECT_NE(report.find("| host | " + std::string(host) + " |"), std::string::npos) << report;
  EXPECT_NE(report.find("| started | 20"), std::string::npos) << report;
  EXPECT_NE(report.find("| camplace | " + core::build_info().version + ", commit `"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("mode center, refine 0, algorithm gaco, objective err, runs per group 1"),
            std::string::npos)
      << report;

  // The base changes (one space more): the group's scene changes with it, the resume stops.
  write_file(base, std::string(kBase) + " ");
  const CommandResult resumed = run_camplace(CAMPLACE_BINARY, args);
  EXPECT_EQ(resumed.exit_code, 1) << resumed.output;
  EXPECT_NE(resumed.output.find("cameras-3.json changed"), std::string::npos) << resumed.output;
}

}  // namespace
}  // namespace camplace::testing
