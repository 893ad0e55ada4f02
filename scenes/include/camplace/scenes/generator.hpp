#pragma once
/// Scenes of the paper's examinations (SPEC §9 table): a family applied to a base scene, one
/// parameter changed per family. The default base is the paper's basic setup,
/// data/paper_basic.json (built in: the file's text is embedded at build time).
#include <optional>
#include <string>
#include <vector>

#include "camplace/core/provenance.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::scenes {

/// One scene family of SPEC §9 and the range of its parameter i.
struct SceneFamily {
  std::string name;       ///< e.g. "resolution", "dynamic_objects", "domain_ceiling"
  bool has_param = true;  ///< false for the domain presets (no --param)
  int min_param = 0;      ///< smallest i (inclusive)
  int max_param = 0;      ///< largest i (inclusive)
  bool random = false;    ///< placement depends on the seed
  std::string what;       ///< one line: what i changes (the SPEC §9 formula)
  /// One line: what i changes when the family is applied to another base scene, or why it
  /// cannot be ("" = as `what`).
  std::string on_base;
};

/// All families, in the order of the SPEC §9 table.
const std::vector<SceneFamily>& scene_families();

/// A scene the families are applied to instead of the paper's basic setup.
struct BaseScene {
  core::Scene scene;         ///< as core::load_scene read it
  std::string label;         ///< the path as the user gave it (study file, --base), for texts
  core::SceneHashes hashes;  ///< SHA-256 of its file and of each mesh file it references
};

/// Loads the scene file `path` as a base; `label` is how the user named it (written into the
/// generated scenes' descriptions, so it should not depend on the working directory). Throws
/// core::InputError naming the file when it does not load.
BaseScene load_base_scene(const std::string& path, const std::string& label);

/// The scene JSON (SPEC §2 format as core::scene_text writes it, with a "description"
/// naming family, param, seed, the base and the facet and object counts) of `family` with
/// parameter `param` (must be empty exactly for the families without one); random placements
/// are drawn from std::mt19937(seed). Same arguments ⇒ identical text.
///
/// Without `base` the family is applied to the paper's basic setup (data/paper_basic.json, as
/// embedded at build time), with the SPEC §9 formulas. With one, to that scene (see
/// SceneFamily::on_base); the result is checked by core::load_scene, and its description records
/// the base's label and combined SHA-256, so a changed base (or mesh file) changes every scene
/// generated from it.
///
/// Throws core::OptionError("family" or "param", reason) on a bad family or param, and
/// core::OptionError("base", reason) when the family cannot be applied to the base (the reason
/// names the family, the base's label and why).
std::string generate_scene_json(const std::string& family, std::optional<int> param, unsigned seed,
                                const BaseScene* base = nullptr);

/// Generates the scene, checks that it loads (core::load_scene) and writes it to `path`
/// atomically (temporary file, then rename). Returns the scene's description. Throws
/// core::InputError on bad arguments or an unwritable path.
std::string write_generated_scene(const std::string& family, std::optional<int> param,
                                  unsigned seed, const std::string& path,
                                  const BaseScene* base = nullptr);

}  // namespace camplace::scenes
