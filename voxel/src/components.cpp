// 6-connected components of a voxel model and the plausibility filter (SPEC §4–5), on runs:
// maximal segments of model voxels along x. Two runs connect when they lie in face-adjacent
// rows (j ± 1 or k ± 1) and share an x index; union–find over runs gives the components.
#include "camplace/voxel/components.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <numeric>

#include "union_find.hpp"

namespace camplace::voxel {

namespace {

struct Run {
  int row;     ///< j + ny·k
  int i0, i1;  ///< x range, inclusive
};

/// Eight model bytes as one word with 1 in each byte that is not 0, 0 elsewhere (byte k holds
/// p[k]: little-endian order).
inline std::uint64_t nonzero_bytes(const std::uint8_t* p) {
  std::uint64_t w;
  std::memcpy(&w, p, sizeof w);
  constexpr std::uint64_t low7 = 0x7f7f7f7f7f7f7f7fULL;
  return (((w & low7) + low7) | w) >> 7 & 0x0101010101010101ULL;
}

using detail::find;
using detail::unite;

/// The model's runs and their union–find forest (parent[n]: run n's component is find(n)).
struct RunForest {
  std::vector<Run> runs;
  std::vector<int> parent;
};

RunForest run_forest(const std::uint8_t* m, const Grid& grid) {
  const int nx = grid.n[0], ny = grid.n[1], nz = grid.n[2];
  const int rows = ny * nz;
  RunForest forest;
  std::vector<Run>& runs = forest.runs;
  std::vector<int> row_start(rows + 1, 0);
  for (int r = 0; r < rows; ++r) {
    row_start[r] = static_cast<int>(runs.size());
    const std::uint8_t* row = m + static_cast<std::size_t>(r) * nx;
    // A run starts or ends where a byte differs from the one before (0 before the row). Eight
    // bytes at a time: byte k of w ^ (w << 8 | previous) is 1 where byte k differs from byte
    // k − 1; then byte by byte for the rest of the row.
    bool inside = false;
    int i0 = 0;
    auto toggle = [&](int i) {
      if (inside) runs.push_back({r, i0, i - 1});
      i0 = i;
      inside = !inside;
    };
    int i = 0;
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    std::uint64_t previous = 0;
    for (; i + 8 <= nx; i += 8) {
      const std::uint64_t w = nonzero_bytes(row + i);
      for (std::uint64_t edges = w ^ (w << 8 | previous); edges; edges &= edges - 1) {
        toggle(i + __builtin_ctzll(edges) / 8);
      }
      previous = w >> 56;
    }
#endif
    for (; i < nx; ++i) {
      if ((row[i] != 0) != inside) toggle(i);
    }
    if (inside) runs.push_back({r, i0, nx - 1});
  }
  row_start[rows] = static_cast<int>(runs.size());
  std::vector<int>& parent = forest.parent;
  parent.resize(runs.size());
  std::iota(parent.begin(), parent.end(), 0);
  // Face neighbours only: voxels meeting at an edge or a corner do not connect (SPEC §4); so
  // runs connect only through a shared x index in the row before (j − 1) or below (k − 1).
  auto connect = [&](int r, int other) {
    int a = row_start[r], b = row_start[other];
    const int a_end = row_start[r + 1], b_end = row_start[other + 1];
    while (a < a_end && b < b_end) {
      if (runs[a].i1 >= runs[b].i0 && runs[b].i1 >= runs[a].i0) unite(parent, a, b);
      if (runs[a].i1 < runs[b].i1) {
        ++a;
      } else {
        ++b;
      }
    }
  };
  for (int r = 0; r < rows; ++r) {
    const int j = r % ny;
    if (j > 0) connect(r, r - 1);
    if (r >= ny) connect(r, r - ny);
  }
  return forest;
}

}  // namespace

std::vector<int> component_labels(const std::vector<std::uint8_t>& model, const Grid& grid) {
  RunForest forest = run_forest(model.data(), grid);
  std::vector<int> id(forest.runs.size(), -1);
  std::vector<int> labels(model.size(), -1);
  int next = 0;
  for (std::size_t n = 0; n < forest.runs.size(); ++n) {
    const int root = find(forest.parent, static_cast<int>(n));
    if (id[root] < 0) id[root] = next++;
    const Run& run = forest.runs[n];
    std::fill_n(labels.begin() + static_cast<std::ptrdiff_t>(run.row) * grid.n[0] + run.i0,
                run.i1 - run.i0 + 1, id[root]);
  }
  return labels;
}

ComponentCount filter_components(std::vector<std::uint8_t>& model, const Grid& grid,
                                 const core::Plausibility& plausibility) {
  const int nx = grid.n[0], ny = grid.n[1];
  std::uint8_t* m = model.data();
  RunForest forest = run_forest(m, grid);
  const std::vector<Run>& runs = forest.runs;
  std::vector<int>& parent = forest.parent;
  // Volume (voxel count) and z-extent per component.
  struct Extent {
    long voxels = 0;
    int kmin = 0, kmax = -1;
  };
  std::vector<Extent> extent(runs.size());
  for (std::size_t n = 0; n < runs.size(); ++n) {
    Extent& e = extent[find(parent, static_cast<int>(n))];
    const int k = runs[n].row / ny;
    if (e.kmax < 0) {
      e.kmin = e.kmax = k;
    } else {
      e.kmin = std::min(e.kmin, k);
      e.kmax = std::max(e.kmax, k);
    }
    e.voxels += runs[n].i1 - runs[n].i0 + 1;
  }
  ComponentCount result;
  std::vector<std::uint8_t> keep(runs.size(), 0);
  for (std::size_t n = 0; n < runs.size(); ++n) {
    if (find(parent, static_cast<int>(n)) != static_cast<int>(n)) continue;
    const double volume = static_cast<double>(extent[n].voxels) * grid.voxel_volume();
    const double height = (extent[n].kmax - extent[n].kmin + 1) * grid.step.z();
    keep[n] = plausibility.keeps(volume, height);
    ++(keep[n] ? result.kept : result.removed);
  }
  for (std::size_t n = 0; n < runs.size(); ++n) {
    const Run& run = runs[n];
    std::memset(m + static_cast<std::size_t>(run.row) * nx + run.i0,
                keep[find(parent, static_cast<int>(n))], run.i1 - run.i0 + 1);
  }
  return result;
}

}  // namespace camplace::voxel
