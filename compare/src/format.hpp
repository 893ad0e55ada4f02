#pragma once
// Number and resolution formatting shared by the reports (fixed digits, so reruns are
// byte-identical). Private to compare.
#include <array>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "camplace/core/provenance.hpp"
#include "camplace/core/table_text.hpp"

namespace camplace::compare::detail {

/// v with a fixed number of decimals ("%.*f").
inline std::string num(double v, int digits = 6) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

/// Every bit of v ("%.17g"), for data files: reads back as the same double.
inline std::string full_number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

/// v to 6 significant digits ("%.6g"), for texts ("0.03 m").
inline std::string short_number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

/// "NXxNYxNZ".
inline std::string resolution_text(const std::array<int, 3>& n) {
  return std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" + std::to_string(n[2]);
}

/// One scene file of a report's provenance header: its path as the report names it, and the
/// hashes of it and of the mesh files it references.
struct HeaderScene {
  std::string role;  ///< what the scene is to the report ("scene", "base scene", a group's name)
  std::string path;
  core::SceneHashes hashes;
};

/// What every report starts with: a table of the camplace version and commit,
/// the scene files with the first 12 hex digits of their SHA-256 (mesh files too), the resolved
/// options (name, value), the command, the host and the start time (ISO 8601), then a details
/// block with every full SHA-256 (beyond the first 3 scenes one row counts the others, their
/// hashes only in the details). `scene_note`, when not empty, is a row of its own before the
/// scenes (e.g. a scene that has no file). `builds`, when not empty, follows the camplace row:
/// what made the work the report reads when that is not only this build (a resumed study).
/// Lines: "| camplace | VERSION, commit COMMIT |", "| started | TIME |", "| host | NAME |" ...
inline std::string provenance_header(
    const std::vector<HeaderScene>& scenes,
    const std::vector<std::pair<std::string, std::string>>& options, const std::string& command,
    const std::string& started, const std::string& scene_note = "",
    const std::string& builds = "") {
  const core::BuildInfo build = core::build_info();
  auto short_hash = [](const std::string& hex) { return "`" + hex.substr(0, 12) + "…`"; };
  std::string md = "| provenance | |\n|---|---|\n| camplace | " + build.version + ", commit `" +
                   build.commit + "` |\n";
  if (!builds.empty()) md += "| runs made by | " + core::md_cell(builds) + " |\n";
  if (!scene_note.empty()) md += "| scene | " + scene_note + " |\n";
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    const HeaderScene& s = scenes[i];
    if (i == 3) {
      md += "| | and " + std::to_string(scenes.size() - 3) +
            " more scene files (their SHA-256 in the details below) |\n";
      break;
    }
    md += "| " + core::md_cell(s.role) + " | " + core::md_cell("`" + s.path + "`") + ", SHA-256 " +
          short_hash(s.hashes.scene);
    for (const auto& [mesh, hash] : s.hashes.meshes) {
      md += "; mesh file " + core::md_cell("`" + mesh + "`") + ", SHA-256 " + short_hash(hash);
    }
    md += " |\n";
  }
  std::string resolved;
  for (const auto& [name, value] : options) {
    resolved += (resolved.empty() ? "" : ", ") + name + " " + value;
  }
  md += "| options | " + core::md_cell(resolved) + " |\n| command | " +
        core::md_cell("`" + command + "`") + " |\n| host | " + core::md_cell(core::host_name()) +
        " |\n| started | " + started + " |\n";
  if (!scenes.empty()) {
    md +=
        "\n<details><summary>Full SHA-256 of the scene and mesh files</summary>\n\n"
        "| file | SHA-256 |\n|---|---|\n";
    for (const HeaderScene& s : scenes) {
      md += "| " + core::md_cell("`" + s.path + "`") + " | " + s.hashes.scene + " |\n";
      for (const auto& [mesh, hash] : s.hashes.meshes) {
        md += "| " + core::md_cell("`" + mesh + "`") + " | " + hash + " |\n";
      }
      if (!s.hashes.meshes.empty()) {
        md += "| " + core::md_cell("`" + s.path + "`") + " with its mesh files (combined) | " +
              s.hashes.combined + " |\n";
      }
    }
    md += "\n</details>\n";
  }
  return md + "\n";
}

}  // namespace camplace::compare::detail
