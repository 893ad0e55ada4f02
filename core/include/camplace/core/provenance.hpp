#pragma once
/// What made a result: the camplace build, content hashes of the scene and its mesh files, the
/// host and the time. Every output file records these (README: provenance).
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "camplace/core/json_reader.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::core {

/// The camplace version, the git commit it was built from ("<sha>-dirty" when the work tree
/// had uncommitted changes, "unknown" outside a git checkout) and the build type.
struct BuildInfo {
  std::string version;
  std::string commit;
  std::string build_type;  ///< CMAKE_BUILD_TYPE: Release, Debug, ...
};
BuildInfo build_info();

/// Lower-case hex SHA-256 of the bytes.
std::string sha256_hex(const std::string& bytes);
/// SHA-256 of a file's content; throws InputError naming the file when it cannot be read.
std::string sha256_file(const std::string& path);

/// Content hashes of a scene: its file and every mesh file it references, and one hash over
/// all of them (what identifies the scene's content; the same scene at another path has the
/// same hashes).
struct SceneHashes {
  std::string scene;                                        ///< SHA-256 of the scene file
  std::vector<std::pair<std::string, std::string>> meshes;  ///< (path, SHA-256) per mesh file
  std::string combined;  ///< SHA-256 over the scene hash and the mesh hashes, in order
};
/// Hashes the files the scene was loaded from (scene.file and scene.mesh_files) as they are
/// now; throws InputError when one cannot be read.
SceneHashes hash_scene(const Scene& scene);
/// The SceneHashes of a scene file with SHA-256 `scene_file_sha256` using the mesh files
/// `meshes` ((path, SHA-256) in order): fills in `combined` as hash_scene does (for a scene that
/// is not on disk yet, e.g. a generated one about to be written).
SceneHashes combine_scene_hashes(std::string scene_file_sha256,
                                 std::vector<std::pair<std::string, std::string>> meshes);

/// How the scene content `now` differs from `recorded` (the hashes a result file recorded),
/// one line per difference, empty when the combined hashes agree: "scene F changed (sha256
/// 1d6fa5ee238a… → 9d6df9c590de…)" for the scene file, "mesh file M changed (…)" per mesh file
/// (M: its path now), "scene F uses 2 mesh files, 1 before" when the lists differ. F is
/// `scene_file`, the scene's path as the caller names it. The one rule by which `optimize` and
/// `study` refuse to resume and `validate` and `compare-optimizer` refuse a run of another
/// scene.
std::vector<std::string> scene_changes(const SceneHashes& recorded, const SceneHashes& now,
                                       const std::string& scene_file);

/// Refuses a result made for another scene: throws InputError naming `file` (the result file),
/// the entry "/provenance/scene_sha256" and the lines of scene_changes when `recorded` (the
/// hashes the file recorded) differ from `now` (those of the scene at `scene_file`).
void check_same_scene(const SceneHashes& recorded, const SceneHashes& now,
                      const std::string& scene_file, const std::string& file);

/// The machine's host name and the current local time as ISO 8601 ("2026-11-29T08:26:25+0000").
std::string host_name();
std::string now_iso8601();

/// Everything a result file records about what made it.
struct Provenance {
  BuildInfo build;
  std::string scene_file;  ///< the scene's path as given
  SceneHashes scene;
  std::string host;
  std::string started;  ///< ISO 8601 local time
};
/// The provenance of work on `scene` starting now.
Provenance make_provenance(const Scene& scene);
/// {"camplace_version", "commit", "scene", "scene_sha256", "scene_file_sha256", "mesh_files":
/// [{"path", "sha256"}], "host", "started"}.
nlohmann::ordered_json provenance_json(const Provenance& provenance);
/// The inverse of provenance_json; InputError naming the entry on a malformed object.
Provenance provenance_from_json(const JsonNode& node);

}  // namespace camplace::core
