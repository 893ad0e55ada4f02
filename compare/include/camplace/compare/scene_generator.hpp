#pragma once
/// Scenes of the paper's examinations (SPEC §9 table), all derived from the basic setup of
/// data/paper_basic.json: one parameter changed per family.
#include <optional>
#include <string>
#include <vector>

namespace camplace::compare {

/// One scene family of SPEC §9 and the range of its parameter i.
struct SceneFamily {
  std::string name;       ///< e.g. "resolution", "dynamic_objects", "domain_ceiling"
  bool has_param = true;  ///< false for the domain presets (no --param)
  int min_param = 0;      ///< smallest i (inclusive)
  int max_param = 0;      ///< largest i (inclusive)
  bool random = false;    ///< placement depends on the seed
  std::string what;       ///< one line: what i changes (the SPEC §9 formula)
};

/// All families, in the order of the SPEC §9 table.
const std::vector<SceneFamily>& scene_families();

/// The scene JSON (SPEC §2 format as core::scene_text writes it, with a "description"
/// naming family, param, seed and the facet and object counts) of `family` with parameter
/// `param` (must be empty exactly for the families without one); random placements are drawn
/// from std::mt19937(seed). Same arguments ⇒ identical text. Throws
/// core::InputError("command line", "FAMILY" or "--param", reason) on bad input.
std::string generate_scene_json(const std::string& family, std::optional<int> param, unsigned seed);

/// Generates the scene, checks that it loads (core::load_scene) and writes it to `path`
/// atomically (temporary file, then rename). Returns the scene's description. Throws
/// core::InputError on bad arguments or an unwritable path.
std::string write_generated_scene(const std::string& family, std::optional<int> param,
                                  unsigned seed, const std::string& path);

}  // namespace camplace::compare
