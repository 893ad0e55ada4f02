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
  struct Cell {
    int v, i, j, k;
  };
  std::vector<Cell> stack;
  std::vector<int> members;
  ComponentCount result;
  for (int start = next_nonzero(m, 0, count); start < count;
       start = next_nonzero(m, start + 1, count)) {
    if (m[start] != 1) continue;
    members.clear();
    const int k0 = start / nxy, j0 = (start - k0 * nxy) / nx;
    stack.assign(1, {start, start - k0 * nxy - j0 * nx, j0, k0});
    m[start] = 2;
    int kmin = nz, kmax = -1;
    while (!stack.empty()) {
      const Cell c = stack.back();
      stack.pop_back();
      members.push_back(c.v);
      kmin = std::min(kmin, c.k);
      kmax = std::max(kmax, c.k);
      auto visit = [&](int w, int i, int j, int k) {
        if (m[w] == 1) {
          m[w] = 2;
          stack.push_back({w, i, j, k});
        }
      };
      // Face neighbours only: voxels meeting at an edge or a corner do not connect (SPEC §4).
      if (c.i > 0) visit(c.v - 1, c.i - 1, c.j, c.k);
      if (c.i + 1 < nx) visit(c.v + 1, c.i + 1, c.j, c.k);
      if (c.j > 0) visit(c.v - nx, c.i, c.j - 1, c.k);
      if (c.j + 1 < ny) visit(c.v + nx, c.i, c.j + 1, c.k);
      if (c.k > 0) visit(c.v - nxy, c.i, c.j, c.k - 1);
      if (c.k + 1 < nz) visit(c.v + nxy, c.i, c.j, c.k + 1);
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
