// The report of every mesh repaired while loading a scene (docs/scene-format.md#repair).
#include <string>
#include <vector>

#include "camplace/core/json_reader.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/core/table_text.hpp"

namespace camplace::core {

std::vector<std::string> repair_warnings(const Scene& scene) {
  std::vector<std::string> lines;
  for (const MeshRepair& r : scene.repairs) {
    const std::string shape = r.method == "hull" ? "hull" : "wrap";
    std::string line =
        scene.file + ": " + r.entry + ": mesh \"" + r.object + "\" repaired by " + r.method + " (";
    if (r.method == "wrap") line += "offset " + format_number(r.offset) + " m, ";
    line += thousands(r.triangles_before) + " → " + thousands(r.triangles_after) + " triangles): ";
    line += r.defect.empty() ? "it passed the checks, repaired because \"always\" is true"
                             : "it failed the checks (" + r.defect + ")";
    const std::string role = r.role.empty() ? "object" : r.role;
    if (r.role == "target" || r.role == "critical object") {
      line += "; as a " + role + " the " + shape +
              " is conservative: it contains the mesh it replaces, so distances can only shrink";
    } else {
      line += "; as " + std::string(role == "object" ? "an " : "a ") + role + " the " + shape +
              " occludes more and leaves less room for a person than the mesh it replaces";
    }
    lines.push_back(std::move(line));
  }
  return lines;
}

}  // namespace camplace::core
