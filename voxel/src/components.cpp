// 6-connected components of a voxel model and the plausibility filter (SPEC §4–5).
#include "camplace/voxel/components.hpp"

#include <algorithm>
#include <cstring>

namespace camplace::voxel {

namespace {

/// Index of the first nonzero byte of data[from, n), or n; eight bytes at a time.
int next_nonzero(const std::uint8_t* data, int from, int n) {
  while (from < n && (from & 7)) {
    if (data[from]) return from;
    ++from;
  }
  while (from + 8 <= n) {
    std::uint64_t word;
    std::memcpy(&word, data + from, 8);
    if (word) break;
    from += 8;
  }
  while (from < n && !data[from]) ++from;
  return from;
}

}  // namespace

ComponentCount filter_components(std::vector<std::uint8_t>& model, const Grid& grid,
                                 const core::Plausibility& plausibility) {
  const int nx = grid.n[0], ny = grid.n[1], nz = grid.n[2];
  const int nxy = nx * ny, count = grid.count();
  const double voxel_volume = grid.voxel_volume();
  // Model bytes: 1 = in M and not yet reached, 2 = reached (a component found so far).
  std::uint8_t* m = model.data();
  for (int v = 0; v < count; ++v) m[v] = m[v] != 0;
  std::vector<int> stack, members;
  ComponentCount result;
  for (int start = next_nonzero(m, 0, count); start < count;
       start = next_nonzero(m, start + 1, count)) {
    if (m[start] != 1) continue;
    members.clear();
    stack.assign(1, start);
    m[start] = 2;
    int kmin = nz, kmax = -1;
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      members.push_back(v);
      const int k = v / nxy, rest = v - k * nxy, j = rest / nx, i = rest - j * nx;
      kmin = std::min(kmin, k);
      kmax = std::max(kmax, k);
      auto visit = [&](int w) {
        if (m[w] == 1) {
          m[w] = 2;
          stack.push_back(w);
        }
      };
      // Face neighbours only: voxels meeting at an edge or a corner do not connect (SPEC §4).
      if (i > 0) visit(v - 1);
      if (i + 1 < nx) visit(v + 1);
      if (j > 0) visit(v - nx);
      if (j + 1 < ny) visit(v + nx);
      if (k > 0) visit(v - nxy);
      if (k + 1 < nz) visit(v + nxy);
    }
    const double volume = static_cast<double>(members.size()) * voxel_volume;
    const double height = (kmax - kmin + 1) * grid.step.z();
    if (plausibility.keeps(volume, height)) {
      ++result.kept;
    } else {
      for (int v : members) m[v] = 0;
      ++result.removed;
    }
  }
  for (int v = 0; v < count; ++v) m[v] = m[v] != 0;
  return result;
}

}  // namespace camplace::voxel
