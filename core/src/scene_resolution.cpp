// Voxel resolutions: parsing NXxNYxNZ and the limits a resolution must respect.
#include <array>
#include <sstream>
#include <string>

#include "camplace/core/error.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::core {

std::array<int, 3> parse_resolution(const std::string& text, const std::string& what) {
  std::array<int, 3> n{};
  std::istringstream in(text);
  char x1 = 0, x2 = 0;
  std::string rest;
  if (!(in >> n[0] >> x1 >> n[1] >> x2 >> n[2]) || (x1 != 'x' && x1 != 'X') ||
      (x2 != 'x' && x2 != 'X') || (in >> rest)) {
    throw InputError("command line", what,
                     "expected NXxNYxNZ (e.g. 16x12x12), got \"" + text + "\"");
  }
  const std::string problem = resolution_problem(n);
  if (!problem.empty()) throw InputError("command line", what, problem + " in \"" + text + "\"");
  return n;
}

std::string resolution_problem(const std::array<int, 3>& n) {
  for (int v : n) {
    if (v < 1 || v > kMaxVoxelsPerAxis) {
      return "every voxel count must lie in [1, " + std::to_string(kMaxVoxelsPerAxis) + "]";
    }
  }
  const long long total = static_cast<long long>(n[0]) * n[1] * n[2];
  if (total > kMaxVoxels) {
    return "too many voxels (" + std::to_string(total) + "; at most " + std::to_string(kMaxVoxels) +
           ")";
  }
  return "";
}

}  // namespace camplace::core
