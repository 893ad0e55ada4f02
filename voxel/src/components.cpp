// 6-connected components of a voxel model and the plausibility filter (SPEC §4–5).
#include "camplace/voxel/components.hpp"

#include <algorithm>

namespace camplace::voxel {

ComponentCount filter_components(std::vector<std::uint8_t>& model, const Grid& grid,
                                 const core::Plausibility& plausibility) {
  const int nx = grid.n[0], ny = grid.n[1], nz = grid.n[2];
  const double voxel_volume = grid.voxel_volume();
  std::vector<int> component(model.size(), -1);
  std::vector<int> stack, members;
  ComponentCount result;
  int next = 0;
  for (int start = 0; start < grid.count(); ++start) {
    if (!model[start] || component[start] >= 0) continue;
    members.clear();
    stack.assign(1, start);
    component[start] = next;
    int kmin = nz, kmax = -1;
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      members.push_back(v);
      const int i = v % nx, j = (v / nx) % ny, k = v / (nx * ny);
      kmin = std::min(kmin, k);
      kmax = std::max(kmax, k);
      auto visit = [&](int w) {
        if (model[w] && component[w] < 0) {
          component[w] = next;
          stack.push_back(w);
        }
      };
      // Face neighbours only: voxels meeting at an edge or a corner do not connect (SPEC §4).
      if (i > 0) visit(v - 1);
      if (i + 1 < nx) visit(v + 1);
      if (j > 0) visit(v - nx);
      if (j + 1 < ny) visit(v + nx);
      if (k > 0) visit(v - nx * ny);
      if (k + 1 < nz) visit(v + nx * ny);
    }
    ++next;
    const double volume = static_cast<double>(members.size()) * voxel_volume;
    const double height = (kmax - kmin + 1) * grid.step.z();
    if (plausibility.keeps(volume, height)) {
      ++result.kept;
    } else {
      for (int v : members) model[v] = 0;
      ++result.removed;
    }
  }
  return result;
}

}  // namespace camplace::voxel
