#pragma once
// The scene families of SPEC §9 and the one way to apply one to a base scene. Private to scenes.
#include <string>
#include <vector>

#include "camplace/core/scene.hpp"
#include "camplace/scenes/generator.hpp"

namespace camplace::scenes::detail {

/// All families, in the order of the SPEC §9 table.
const std::vector<SceneFamily>& families();

/// A generated scene and what its description says beyond the scene itself.
struct GeneratedScene {
  core::Scene scene;
  std::string domain;  ///< the cameras' domain preset ("" = the base's domains)
  std::string note;    ///< appended to the description
};

/// `family` with parameter i (in its range) applied to `base`. `paper` says the base is the
/// paper's basic setup (data/paper_basic.json): then the families follow the SPEC §9 table
/// (dynamic_steps moves its robot arm, unmodelled_events adds its persons and a third robot
/// pose, the cameras' domain is the "room" preset, times are 0, 1, ..., every step's critical
/// objects are its dynamic obstacles and the plausibility thresholds are recomputed). Throws
/// core::OptionError("base", reason) when the family cannot be applied to the base.
GeneratedScene apply_family(const SceneFamily& family, int i, unsigned seed, const BaseScene& base,
                            bool paper);

/// Thrown when `family` cannot be applied to the base: names the family, the base and why.
[[noreturn]] void not_applicable(const SceneFamily& family, const BaseScene& base,
                                 const std::string& reason);

}  // namespace camplace::scenes::detail
