// The scene generator of the paper's examinations (SPEC §9): every scene loads
// and validates, has the facet and object counts of the SPEC table (expected numbers from the
// table's formulas, counted on the loaded scene), keeps the plausibility rule valid, and is
// reproducible from its seed.
#include "camplace/scenes/generator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "camplace/core/error.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/core/scene.hpp"
#include "command.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using scenes::generate_scene_json;
using scenes::scene_families;
using scenes::SceneFamily;

const std::string kBasicScene = std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_basic.json";

core::Scene load_text(const std::string& text, const std::string& name) {
  static const std::string dir = temp_dir("scene-generator");
  return core::load_scene(write_file(dir + "/" + name + ".json", text));
}

std::optional<int> param_of(const SceneFamily& f, int i) {
  return f.has_param ? std::optional<int>(i) : std::nullopt;
}

std::vector<int> params_of(const SceneFamily& f) {
  std::vector<int> out;
  if (!f.has_param) return {0};
  for (int i = f.min_param; i <= f.max_param; ++i) out.push_back(i);
  return out;
}

core::Scene generate(const std::string& family, std::optional<int> param, unsigned seed = 1) {
  return load_text(generate_scene_json(family, param, seed),
                   family + "-" + std::to_string(param.value_or(-1)) + "-" + std::to_string(seed));
}

struct Counts {
  int static_facets = 8, static_objects = 2;
  int dynamic_facets = 24, dynamic_objects = 6, time_steps = 2;  // over all time steps
  int target_facets = 24, target_objects = 6, events = 3;        // over the events of one step
  int cameras = 6;
  std::array<int, 3> voxels{16, 12, 12};
  bool operator==(const Counts& o) const {
    return static_facets == o.static_facets && static_objects == o.static_objects &&
           dynamic_facets == o.dynamic_facets && dynamic_objects == o.dynamic_objects &&
           time_steps == o.time_steps && target_facets == o.target_facets &&
           target_objects == o.target_objects && events == o.events && cameras == o.cameras &&
           voxels == o.voxels;
  }
};

std::ostream& operator<<(std::ostream& out, const Counts& c) {
  return out << "static " << c.static_facets << "/" << c.static_objects << ", dynamic "
             << c.dynamic_facets << "/" << c.dynamic_objects << " in " << c.time_steps
             << " steps, targets " << c.target_facets << "/" << c.target_objects << " in "
             << c.events << " events, " << c.cameras << " cameras, voxels " << c.voxels[0] << "x"
             << c.voxels[1] << "x" << c.voxels[2];
}

// The SPEC §9 table's formulas; the basic setup (8 static facets at 2 objects, 24 dynamic
// facets at 6 objects in 2 steps, 24 target facets at 6 objects in 3 events) elsewhere.
Counts expected(const std::string& family, int i) {
  Counts c;
  if (family == "resolution") {
    c.voxels = {16 + 4 * i, 12 + 3 * i, 12 + 3 * i};
  } else if (family == "static_facets") {
    c.static_facets = 8 + 60 * i;
  } else if (family == "static_objects") {
    // The table's "6+4i facets at 2+i objects" cannot be closed polyhedra (≥ 4 facets each):
    // 2+i tetrahedra instead.
    c.static_objects = 2 + i;
    c.static_facets = 4 * (2 + i);
  } else if (family == "dynamic_facets") {
    c.dynamic_facets = 24 + 60 * i;
  } else if (family == "dynamic_objects") {
    c.dynamic_objects = 2 + i;
    c.dynamic_facets = 24 + 4 * i;
    c.time_steps = 1;
  } else if (family == "dynamic_steps") {
    c.time_steps = i;
    c.dynamic_objects = 2 * i;
    c.dynamic_facets = 8 * i;
  } else if (family == "unmodelled_facets") {
    c.target_facets = 24 + 60 * i;
  } else if (family == "unmodelled_objects") {
    c.target_objects = 2 + i;
    c.target_facets = 24 + 4 * i;
    c.events = 1;
  } else if (family == "unmodelled_events") {
    c.events = i;
    c.target_objects = 2 * i;
    c.target_facets = 8 * i;
    c.time_steps = 3;  // the basic robot of 3 tetrahedra per step
    c.dynamic_objects = 9;
    c.dynamic_facets = 36;
  } else if (family == "cameras") {
    c.cameras = i;
  }
  return c;
}

int facets(const std::vector<core::SceneObject>& objects) {
  int n = 0;
  for (const auto& o : objects) n += static_cast<int>(o.mesh.triangles.size());
  return n;
}

Counts counted(const core::Scene& s) {
  Counts c;
  c.static_facets = facets(s.static_obstacles);
  c.static_objects = static_cast<int>(s.static_obstacles.size());
  c.dynamic_facets = c.dynamic_objects = 0;
  for (const auto& step : s.time_steps) {
    c.dynamic_facets += facets(step.dynamic_obstacles);
    c.dynamic_objects += static_cast<int>(step.dynamic_obstacles.size());
  }
  c.time_steps = static_cast<int>(s.time_steps.size());
  c.target_facets = c.target_objects = 0;
  for (const auto& e : s.time_steps[0].events) {
    c.target_facets += facets(e.targets);
    c.target_objects += static_cast<int>(e.targets.size());
  }
  c.events = static_cast<int>(s.time_steps[0].events.size());
  c.cameras = s.cameras.count;
  c.voxels = s.voxels;
  return c;
}

void expect_same_objects(const std::vector<core::SceneObject>& a,
                         const std::vector<core::SceneObject>& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].mesh.vertices, b[k].mesh.vertices) << what << " object " << k;
    EXPECT_EQ(a[k].mesh.triangles.size(), b[k].mesh.triangles.size()) << what << " object " << k;
  }
}

std::vector<core::Vec3> all_vertices(const core::Scene& s) {
  std::vector<core::Vec3> out;
  auto add = [&](const std::vector<core::SceneObject>& objects) {
    for (const auto& o : objects)
      out.insert(out.end(), o.mesh.vertices.begin(), o.mesh.vertices.end());
  };
  add(s.static_obstacles);
  for (const auto& step : s.time_steps) {
    add(step.dynamic_obstacles);
    for (const auto& e : step.events) add(e.targets);
  }
  return out;
}

// Properties of the basic setup every generated scene keeps (data/README.md): the robot stays
// below 1 m and every target part is ≥ 1.45 m tall, the plausibility thresholds are the
// smallest target part's volume and height rounded down to 6 decimals, the targets are the same
// in every time step, the weights of each step sum to 1, every step has critical objects.
void expect_basic_properties(const core::Scene& s, const std::string& what) {
  double min_volume = 1e9, min_height = 1e9;
  for (const auto& step : s.time_steps) {
    EXPECT_FALSE(step.critical.empty()) << what;
    for (const auto& o : step.dynamic_obstacles)
      EXPECT_LT(o.bounds.max.z(), 1.0) << what << " " << o.name;
    double weights = 0;
    ASSERT_EQ(step.events.size(), s.time_steps[0].events.size()) << what;
    for (std::size_t l = 0; l < step.events.size(); ++l) {
      const auto& e = step.events[l];
      weights += e.weight;
      expect_same_objects(e.targets, s.time_steps[0].events[l].targets, what + " targets");
      EXPECT_EQ(e.weight, s.time_steps[0].events[l].weight) << what;
      for (const auto& o : e.targets) {
        EXPECT_GE(o.bounds.size().z(), 1.45) << what << " " << o.name;
        min_volume = std::min(min_volume, core::signed_volume(o.mesh));
        min_height = std::min(min_height, o.bounds.size().z());
      }
    }
    EXPECT_NEAR(weights, 1.0, 1e-12) << what;
  }
  EXPECT_LE(s.plausibility.min_volume, min_volume) << what;
  EXPECT_GT(s.plausibility.min_volume, min_volume - 1e-6) << what;
  EXPECT_LE(s.plausibility.min_height, min_height) << what;
  EXPECT_GT(s.plausibility.min_height, min_height - 1e-6) << what;
  EXPECT_EQ(s.dynamic_mode, core::DynamicMode::masked) << what;
  EXPECT_EQ(s.area.min, core::Vec3(0, 0, 0)) << what;
  EXPECT_EQ(s.area.max, core::Vec3(4, 3, 3)) << what;
}

TEST(SceneGenerator, EveryFamilyAndParamLoadsWithTheCountsOfTheSpecTable) {
  int scenes = 0;
  for (const SceneFamily& f : scene_families()) {
    for (int i : params_of(f)) {
      const std::string what = f.name + " i=" + std::to_string(i);
      const std::string text = generate_scene_json(f.name, param_of(f, i), 1);
      core::Scene s;
      ASSERT_NO_THROW(s = load_text(text, f.name + std::to_string(i))) << what;
      EXPECT_EQ(counted(s), expected(f.name, i)) << what;
      expect_basic_properties(s, what);
      // The description names family, param, seed and the counts.
      const std::string description = nlohmann::json::parse(text)["description"];
      EXPECT_NE(description.find("family " + f.name), std::string::npos) << description;
      if (f.has_param) {
        EXPECT_NE(description.find("param i = " + std::to_string(i)), std::string::npos)
            << description;
      }
      EXPECT_NE(description.find("seed 1"), std::string::npos) << description;
      const Counts c = expected(f.name, i);
      EXPECT_NE(description.find("Static " + std::to_string(c.static_facets) + " facets at " +
                                 std::to_string(c.static_objects) + " objects"),
                std::string::npos)
          << description;
      ++scenes;
    }
  }
  EXPECT_EQ(scenes, 6 + 6 + 4 + 6 + 4 + 5 + 6 + 4 + 5 + 7 + 2);
}

TEST(SceneGenerator, DomainFamiliesSetTheCameraDomainPreset) {
  const core::Scene ceiling = generate("domain_ceiling", std::nullopt);
  ASSERT_EQ(ceiling.cameras.domains.size(), 6u);
  for (const auto& d : ceiling.cameras.domains) {
    EXPECT_EQ(d.z.lo, 3.0);
    EXPECT_EQ(d.z.hi, 3.0);
    EXPECT_EQ(d.x.lo, 0.0);
    EXPECT_EQ(d.x.hi, 4.0);
  }
  const core::Scene upper = generate("domain_upper_fourth", std::nullopt);
  for (const auto& d : upper.cameras.domains) {
    EXPECT_EQ(d.z.lo, 2.25);
    EXPECT_EQ(d.z.hi, 3.0);
  }
  for (const auto& d : generate("cameras", 3).cameras.domains) {
    EXPECT_EQ(d.z.lo, 0.0);
    EXPECT_EQ(d.z.hi, 3.0);
  }
}

// The first scene of each facet/count sweep that starts at the basic setup is the basic setup
// itself, object for object, as data/paper_basic.json holds it.
TEST(SceneGenerator, FirstScenesOfTheSweepsAreThePapersBasicSetup) {
  const core::Scene basic = core::load_scene(kBasicScene);
  const std::vector<std::pair<std::string, int>> firsts = {
      {"resolution", 0},     {"static_facets", 0},     {"static_objects", 0},
      {"dynamic_facets", 0}, {"unmodelled_facets", 0}, {"unmodelled_events", 3},
      {"cameras", 6}};
  for (const auto& [family, i] : firsts) {
    const std::string what = family + " i=" + std::to_string(i);
    const core::Scene s = generate(family, i);
    EXPECT_EQ(s.voxels, basic.voxels) << what;
    EXPECT_EQ(s.cameras.count, basic.cameras.count) << what;
    EXPECT_EQ(s.cameras.models[0].half_angle, basic.cameras.models[0].half_angle) << what;
    EXPECT_EQ(s.plausibility.min_volume, basic.plausibility.min_volume) << what;
    EXPECT_EQ(s.plausibility.min_height, basic.plausibility.min_height) << what;
    expect_same_objects(s.static_obstacles, basic.static_obstacles, what + " static");
    // unmodelled_events has a third robot pose; its first two steps are the basic ones.
    ASSERT_GE(s.time_steps.size(), basic.time_steps.size()) << what;
    for (std::size_t h = 0; h < basic.time_steps.size(); ++h) {
      expect_same_objects(s.time_steps[h].dynamic_obstacles, basic.time_steps[h].dynamic_obstacles,
                          what + " dynamic");
      ASSERT_EQ(s.time_steps[h].events.size(), basic.time_steps[h].events.size()) << what;
      for (std::size_t l = 0; l < basic.time_steps[h].events.size(); ++l) {
        EXPECT_EQ(s.time_steps[h].events[l].weight, basic.time_steps[h].events[l].weight) << what;
        expect_same_objects(s.time_steps[h].events[l].targets,
                            basic.time_steps[h].events[l].targets, what + " targets");
      }
    }
  }
}

// Finer objects replace each basic tetrahedron by a pyramid with the same apex and a base of the
// same area in the same plane: the volume (|base|·height/3) is the basic tetrahedron's, computed
// here from data/paper_basic.json, and so is the z-range when the base is horizontal.
TEST(SceneGenerator, FinerObjectsKeepTheVolumeAndHeightOfTheBasicTetrahedra) {
  const core::Scene basic = core::load_scene(kBasicScene);
  auto expect_like = [](const std::vector<core::SceneObject>& fine,
                        const std::vector<core::SceneObject>& coarse, int facets_each,
                        const std::string& what) {
    ASSERT_EQ(fine.size(), coarse.size()) << what;
    for (std::size_t k = 0; k < fine.size(); ++k) {
      EXPECT_EQ(static_cast<int>(fine[k].mesh.triangles.size()), facets_each) << what;
      const double v = core::signed_volume(coarse[k].mesh);
      // Generated vertices are rounded to micrometres.
      EXPECT_NEAR(core::signed_volume(fine[k].mesh), v, 1e-4 * v + 1e-8)
          << what << " " << fine[k].name;
      // With a horizontal base (points 0-2 of the tetrahedron; all but the robot's forearm) the
      // z-range is the tetrahedron's too.
      const auto& p = coarse[k].mesh.vertices;
      if (p[0].z() == p[1].z() && p[1].z() == p[2].z()) {
        EXPECT_NEAR(fine[k].bounds.min.z(), coarse[k].bounds.min.z(), 1e-9) << what;
        EXPECT_NEAR(fine[k].bounds.max.z(), coarse[k].bounds.max.z(), 1e-9) << what;
      }
    }
  };
  for (int i = 1; i <= 5; ++i) {
    const std::string n = " i=" + std::to_string(i);
    expect_like(generate("static_facets", i).static_obstacles, basic.static_obstacles, 4 + 30 * i,
                "static_facets" + n);
    const core::Scene dyn = generate("dynamic_facets", i);
    for (int h = 0; h < 2; ++h) {
      expect_like(dyn.time_steps[h].dynamic_obstacles, basic.time_steps[h].dynamic_obstacles,
                  4 + 10 * i, "dynamic_facets" + n);
    }
    const core::Scene tgt = generate("unmodelled_facets", i);
    for (int l = 0; l < 3; ++l) {
      expect_like(tgt.time_steps[0].events[l].targets, basic.time_steps[0].events[l].targets,
                  4 + 10 * i, "unmodelled_facets" + n);
    }
  }
}

TEST(SceneGenerator, SameSeedGivesIdenticalText) {
  for (const SceneFamily& f : scene_families()) {
    for (int i : params_of(f)) {
      for (unsigned seed : {1u, 12345u}) {
        EXPECT_EQ(generate_scene_json(f.name, param_of(f, i), seed),
                  generate_scene_json(f.name, param_of(f, i), seed))
            << f.name << " i=" << i << " seed " << seed;
      }
    }
  }
}

TEST(SceneGenerator, DifferentSeedsPlaceOnlyTheRandomFamiliesDifferently) {
  int random_families = 0;
  for (const SceneFamily& f : scene_families()) {
    random_families += f.random;
    for (int i : params_of(f)) {
      const auto a = all_vertices(generate(f.name, param_of(f, i), 1));
      const auto b = all_vertices(generate(f.name, param_of(f, i), 2));
      if (f.random) {
        EXPECT_NE(a, b) << f.name << " i=" << i;
      } else {
        EXPECT_EQ(a, b) << f.name << " i=" << i;
      }
    }
  }
  EXPECT_EQ(random_families, 2);  // dynamic_objects, unmodelled_objects
}

// Random placements never make a target meet an obstacle of its state nor leave S, which the
// loader checks (exactly, with CGAL) for every seed tried here.
TEST(SceneGenerator, RandomPlacementsLoadForManySeeds) {
  for (const char* family : {"dynamic_objects", "unmodelled_objects"}) {
    for (int i = 0; i <= 3; ++i) {
      for (unsigned seed = 1; seed <= 12; ++seed) {
        const std::string what =
            std::string(family) + " i=" + std::to_string(i) + " seed " + std::to_string(seed);
        core::Scene s;
        ASSERT_NO_THROW(s = generate(family, i, seed)) << what;
        EXPECT_EQ(counted(s), expected(family, i)) << what;
        expect_basic_properties(s, what);
      }
    }
  }
}

void expect_rejected(const std::string& family, std::optional<int> param, const std::string& entry,
                     const std::string& words) {
  try {
    generate_scene_json(family, param, 1);
    ADD_FAILURE() << family << " " << param.value_or(-1) << " was accepted";
  } catch (const core::OptionError& e) {
    EXPECT_EQ(e.option(), entry) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(SceneGenerator, BadFamilyOrParamIsRejected) {
  expect_rejected("resolutions", 1, "family", "unknown scene family \"resolutions\"");
  expect_rejected("", 1, "family", "expected one of: resolution, static_facets");
  expect_rejected("resolution", 6, "param", "[0, 5]");
  expect_rejected("resolution", -1, "param", "got -1");
  expect_rejected("static_objects", 4, "param", "[0, 3]");
  expect_rejected("dynamic_steps", 0, "param", "[1, 5]");
  expect_rejected("unmodelled_events", 6, "param", "[1, 5]");
  expect_rejected("cameras", 2, "param", "[3, 9]");
  expect_rejected("cameras", 10, "param", "[3, 9]");
  expect_rejected("cameras", std::nullopt, "param", "needs a parameter i in [3, 9]");
  expect_rejected("domain_ceiling", 0, "param", "takes no parameter");
}

TEST(SceneGenerator, WriteGeneratedSceneWritesTheTextAtomically) {
  const std::string dir = temp_dir("scene-generator-write");
  const std::string path = dir + "/sub/scene.json";
  scenes::write_generated_scene("dynamic_objects", 2, 5, path);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), generate_scene_json("dynamic_objects", 2, 5));
  int files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir + "/sub"))
    ++files;
  EXPECT_EQ(files, 1);  // no temporary file left behind
  write_file(dir + "/plain", "x");
  EXPECT_THROW(scenes::write_generated_scene("cameras", 3, 1, dir + "/plain/scene.json"),
               core::InputError);
}

// `camplace generate` as a user runs it.
TEST(GenerateCommand, WritesALoadableSceneAndRejectsABadParam) {
  const std::string dir = temp_dir("generate-command");
  const std::string path = dir + "/scene.json";
  CommandResult r =
      run_camplace(CAMPLACE_BINARY, "generate unmodelled_objects --param 1 --seed 3 --out " + path);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("family unmodelled_objects"), std::string::npos) << r.output;
  const core::Scene s = core::load_scene(path);
  EXPECT_EQ(counted(s), expected("unmodelled_objects", 1));
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), generate_scene_json("unmodelled_objects", 1, 3));

  r = run_camplace(CAMPLACE_BINARY, "generate resolution --param 9 --out " + dir + "/bad.json");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--param"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/bad.json"));
  r = run_camplace(CAMPLACE_BINARY, "generate nosuchfamily --out " + dir + "/bad.json");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("unknown scene family"), std::string::npos) << r.output;

  // The default seed is 1.
  r = run_camplace(CAMPLACE_BINARY, "generate dynamic_objects --param 0 --out " + dir + "/d.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream d(dir + "/d.json");
  std::stringstream dt;
  dt << d.rdbuf();
  EXPECT_EQ(dt.str(), generate_scene_json("dynamic_objects", 0, 1));
}

}  // namespace
}  // namespace camplace::testing
