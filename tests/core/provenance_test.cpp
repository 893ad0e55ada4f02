// Scene hashes and the one rule that compares them: the combined hash is the
// SHA-256 the run-file documentation gives (values computed independently with Python's
// hashlib), and scene_changes names exactly the files whose content differs.
#include "camplace/core/provenance.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "camplace/core/error.hpp"

namespace camplace::core {
namespace {

// hashlib.sha256(b"scene-a").hexdigest() and friends.
const std::string kSceneA = "e42dff4bb9ab53f4a000c88cdffca0339c5cf7e44686ee5d94f98025f8aee497";
const std::string kSceneB = core::sha256_hex("scene-b");  // f5f19f11942b…
const std::string kMesh1 = "eb50a17aee5a9da482ac566f7b55e7bc96a89dd8e19c75dc73886dbd490eb9d5";
const std::string kMesh2 = core::sha256_hex("mesh-2");  // 595dda1549a5…

TEST(Provenance, CombinedHashIsTheDocumentedSha256) {
  EXPECT_EQ(sha256_hex("scene-a"), kSceneA);
  EXPECT_EQ(sha256_hex("mesh-1"), kMesh1);
  // sha256(scene hash), and sha256(scene hash + "\n" + mesh hash).
  EXPECT_EQ(combine_scene_hashes(kSceneA, {}).combined,
            "106b123b429fd8266e514f406ac1df90bade883f758c536b1a40e3ae967212df");
  const SceneHashes with_mesh = combine_scene_hashes(kSceneA, {{"m.off", kMesh1}});
  EXPECT_EQ(with_mesh.combined, "61232ce8d173a429f1a52839cc801adac7be29e9d120cb0d7cd61c6599514950");
  EXPECT_EQ(with_mesh.scene, kSceneA);
  ASSERT_EQ(with_mesh.meshes.size(), 1u);
  EXPECT_EQ(with_mesh.meshes[0].second, kMesh1);
}

TEST(Provenance, SceneChangesNameEachFileWhoseContentDiffers) {
  const SceneHashes recorded = combine_scene_hashes(kSceneA, {{"old/m.off", kMesh1}});
  // The same content at other paths: no change.
  EXPECT_TRUE(
      scene_changes(recorded, combine_scene_hashes(kSceneA, {{"new/m.off", kMesh1}}), "new/x.json")
          .empty());
  // The scene file alone.
  EXPECT_EQ(
      scene_changes(recorded, combine_scene_hashes(kSceneB, {{"new/m.off", kMesh1}}), "x.json"),
      std::vector<std::string>{"scene x.json changed (sha256 e42dff4bb9ab… → f5f19f11942b…)"});
  // The mesh file alone, named by its path now.
  EXPECT_EQ(
      scene_changes(recorded, combine_scene_hashes(kSceneA, {{"new/m.off", kMesh2}}), "x.json"),
      std::vector<std::string>{
          "mesh file new/m.off changed (sha256 eb50a17aee5a… → 595dda1549a5…)"});
  // Another list of mesh files (the scene file lists them, so it changed too).
  EXPECT_EQ(
      scene_changes(recorded, combine_scene_hashes(kSceneB, {{"m.off", kMesh1}, {"n.off", kMesh2}}),
                    "x.json"),
      (std::vector<std::string>{"scene x.json changed (sha256 e42dff4bb9ab… → f5f19f11942b…)",
                                "scene x.json uses 2 mesh files, 1 before"}));
}

TEST(Provenance, CheckSameSceneRefusesAnotherSceneNamingTheFileAndEntry) {
  const SceneHashes a = combine_scene_hashes(kSceneA, {});
  EXPECT_NO_THROW(check_same_scene(a, a, "x.json", "run-1.json"));
  try {
    check_same_scene(a, combine_scene_hashes(kSceneB, {}), "y.json", "run-1.json");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "run-1.json");
    EXPECT_EQ(e.entry(), "/provenance/scene_sha256");
    EXPECT_EQ(e.reason(),
              "made for another scene (or the scene changed since): scene y.json changed (sha256 "
              "e42dff4bb9ab… → f5f19f11942b…)");
  }
}

}  // namespace
}  // namespace camplace::core
