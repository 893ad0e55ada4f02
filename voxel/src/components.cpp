// 6-connected components and the plausibility filter (SPEC §4–5), one rule (ComponentTally) on
// the dense base model (filter_components) and on refined cells (detail::filter_cells). Voxels on
// runs: maximal segments of model voxels along x. Two runs connect when they lie in face-adjacent
// rows (j ± 1 or k ± 1) and share an x index; union–find over runs gives the components.
#include "camplace/voxel/components.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>

#include "cells.hpp"
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

/// Per component: its cell count and z-extent (layer indices), and the plausibility filter's
/// rule (SPEC §4–5), one for voxels and refined cells: volume = cell count × cell volume,
/// height = (layers spanned) × cell height.
class ComponentTally {
 public:
  int add_component() {
    extent_.push_back({});
    return static_cast<int>(extent_.size()) - 1;
  }
  /// Adds `count` cells in layers k0..k1 to component c.
  void add_cells(int c, long count, long k0, long k1) {
    Extent& e = extent_[c];
    if (e.kmax < 0) {
      e.kmin = k0;
      e.kmax = k1;
    } else {
      e.kmin = std::min(e.kmin, k0);
      e.kmax = std::max(e.kmax, k1);
    }
    e.cells += count;
  }
  /// keep[c] = 1 when `plausibility` keeps component c; how many it keeps and removes.
  ComponentCount decide(const core::Plausibility& plausibility, double cell_volume,
                        double cell_height, std::vector<std::uint8_t>& keep) const {
    ComponentCount result;
    keep.assign(extent_.size(), 0);
    for (std::size_t c = 0; c < extent_.size(); ++c) {
      const double volume = static_cast<double>(extent_[c].cells) * cell_volume;
      const double height =
          static_cast<double>(extent_[c].kmax - extent_[c].kmin + 1) * cell_height;
      keep[c] = plausibility.keeps(volume, height);
      ++(keep[c] ? result.kept : result.removed);
    }
    return result;
  }

 private:
  struct Extent {
    long cells = 0;
    long kmin = 0, kmax = -1;
  };
  std::vector<Extent> extent_;
};

/// The model's runs and their union–find forest (parent[n]: run n's component is find(n)), with
/// run_forest's working memory (reused when the forest is).
struct RunForest {
  std::vector<Run> runs;
  std::vector<int> parent;
  std::vector<int> row_start;
  std::vector<std::uint64_t> bits;
};

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
/// The row's nx ≤ 64 model bytes as bits (bit i: byte i is not 0), eight bytes at a time: the
/// product gathers the low bit of each byte of nonzero_bytes into the top byte, byte k's at bit
/// 56 + k (the partial products 8k + 7m, m = 1..8, are distinct bits: no carry). The last eight
/// bytes, when fewer remain, overlap the ones before (same bits).
inline std::uint64_t row_bits(const std::uint8_t* row, int nx) {
  constexpr std::uint64_t gather = 0x0102040810204080ULL;
  std::uint64_t bits = 0;
  int i = 0;
  for (; i + 8 <= nx; i += 8) bits |= (nonzero_bytes(row + i) * gather >> 56) << i;
  if (i < nx && nx >= 8) {
    bits |= (nonzero_bytes(row + nx - 8) * gather >> 56) << (nx - 8);
  } else {
    for (; i < nx; ++i) bits |= std::uint64_t{row[i] != 0} << i;
  }
  return bits;
}
constexpr bool kRowBits = true;
#else
inline std::uint64_t row_bits(const std::uint8_t*, int) { return 0; }
constexpr bool kRowBits = false;
#endif

/// Into `forest` (its memory reused).
void run_forest(const std::uint8_t* m, const Grid& grid, RunForest& forest) {
  const int nx = grid.n[0], ny = grid.n[1], nz = grid.n[2];
  const int rows = ny * nz;
  std::vector<Run>& runs = forest.runs;
  runs.clear();
  std::vector<int>& row_start = forest.row_start;
  row_start.assign(rows + 1, 0);
  // Rows of at most 64 voxels as bit masks: runs start at a 1 bit with a 0 (or the row's start)
  // before it and end at a 1 bit with a 0 after it; two rows share no x index when their masks
  // do not meet (then connect has nothing to unite).
  const bool masks = kRowBits && nx <= 64;
  std::vector<std::uint64_t>& bits = forest.bits;
  bits.resize(masks ? rows : 0);
  for (int r = 0; r < rows; ++r) {
    row_start[r] = static_cast<int>(runs.size());
    const std::uint8_t* row = m + static_cast<std::size_t>(r) * nx;
    if (masks) {
      const std::uint64_t b = bits[r] = row_bits(row, nx);
      std::uint64_t starts = b & ~(b << 1), ends = b & ~(b >> 1);
      for (; starts; starts &= starts - 1, ends &= ends - 1) {
        runs.push_back({r, __builtin_ctzll(starts), __builtin_ctzll(ends)});
      }
      continue;
    }
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
    if (masks && !(bits[r] & bits[other])) return;
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
}

}  // namespace

std::vector<int> component_labels(const std::vector<std::uint8_t>& model, const Grid& grid) {
  RunForest forest;
  run_forest(model.data(), grid, forest);
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
  // Per thread, reused: the evaluator filters every state's model per evaluation.
  thread_local RunForest forest;
  run_forest(m, grid, forest);
  const std::vector<Run>& runs = forest.runs;
  std::vector<int>& parent = forest.parent;
  // Volume (voxel count) and z-extent per component, in order of their first run.
  ComponentTally tally;
  std::vector<int> id(runs.size(), -1);
  for (std::size_t n = 0; n < runs.size(); ++n) {
    const int root = find(parent, static_cast<int>(n));
    if (id[root] < 0) id[root] = tally.add_component();
    const long k = runs[n].row / ny;
    id[n] = id[root];
    tally.add_cells(id[root], runs[n].i1 - runs[n].i0 + 1, k, k);
  }
  std::vector<std::uint8_t> keep;
  const ComponentCount result =
      tally.decide(plausibility, grid.voxel_volume(), grid.step.z(), keep);
  for (std::size_t n = 0; n < runs.size(); ++n) {
    const Run& run = runs[n];
    std::memset(m + static_cast<std::size_t>(run.row) * nx + run.i0, keep[id[n]],
                run.i1 - run.i0 + 1);
  }
  return result;
}

namespace detail {

ComponentCount filter_cells(CellSet& set, const Octree& octree, const Grid& grid,
                            const core::Plausibility& plausibility) {
  const int cells = octree.cells;
  const int slots = static_cast<int>(set.voxels.size());
  const int nx = grid.n[0], ny = grid.n[1], nz = grid.n[2];
  const int side = octree.side;
  const std::uint8_t* in = set.cells.data();
  // Union–find over the cells; a slot whose cells are all in the set ("full": a base voxel
  // refinement left whole) stands for all of them with its first cell.
  thread_local std::vector<int> parent;
  thread_local std::vector<std::uint8_t> full;
  const std::size_t total = static_cast<std::size_t>(slots) * cells;
  parent.resize(total);
  full.assign(slots, 0);
  for (int slot = 0; slot < slots; ++slot) {
    const std::uint8_t* c = in + static_cast<std::size_t>(slot) * cells;
    full[slot] = (slot < static_cast<int>(set.whole.size()) && set.whole[slot]) ||
                 std::find(c, c + cells, std::uint8_t(0)) == c + cells;
    const int base = slot * cells;
    if (full[slot]) {
      parent[base] = base;
    } else {
      for (int m = 0; m < cells; ++m) parent[base + m] = base + m;
    }
  }
  // Base voxel → slot (−1: none), reset to −1 before returning.
  thread_local std::vector<int> slot_map;
  if (slot_map.size() != static_cast<std::size_t>(grid.count())) slot_map.assign(grid.count(), -1);
  for (int slot = 0; slot < slots; ++slot) slot_map[set.voxels[slot]] = slot;
  auto slot_of = [&](int v) { return slot_map[v]; };
  auto rep = [&](int slot, int m) { return full[slot] ? slot * cells : slot * cells + m; };
  // Face neighbours at +x, +y, +z only (each pair once): 6-connectivity of the finest cells.
  for (int slot = 0; slot < slots; ++slot) {
    const int v = set.voxels[slot];
    const int i = v % nx, j = (v / nx) % ny, k = v / (nx * ny);
    const int neighbour[3] = {i + 1 < nx ? slot_of(v + 1) : -1, j + 1 < ny ? slot_of(v + nx) : -1,
                              k + 1 < nz ? slot_of(v + nx * ny) : -1};
    const int base = slot * cells;
    if (full[slot]) {
      for (int a = 0; a < 3; ++a) {
        const int nb = neighbour[a];
        if (nb < 0) continue;
        if (full[nb]) {
          unite(parent, base, nb * cells);
          continue;
        }
        for (int m : octree.low_face[a]) {
          if (in[nb * cells + m]) unite(parent, base, nb * cells + m);
        }
      }
      continue;
    }
    for (int m = 0; m < cells; ++m) {
      if (!in[base + m]) continue;
      for (int a = 0; a < 3; ++a) {
        const int n = octree.next[a][m];
        if (octree.crosses[a][m]) {
          const int nb = neighbour[a];
          if (nb >= 0 && in[nb * cells + n]) unite(parent, base + m, rep(nb, n));
        } else if (in[base + n]) {
          unite(parent, base + m, base + n);
        }
      }
    }
  }
  // Components in order of their first cell (roots are the smallest index of their component);
  // cell count and z-extent (finest layer indices) of each.
  ComponentTally tally;
  thread_local std::vector<int> label;
  label.resize(total);
  for (int slot = 0; slot < slots; ++slot) {
    const long k0 = static_cast<long>(set.voxels[slot] / (nx * ny)) * side;
    const int base = slot * cells;
    for (int m = 0; m < (full[slot] ? 1 : cells); ++m) {
      if (!in[base + m]) continue;
      const int root = find(parent, base + m);
      if (root == base + m) label[root] = tally.add_component();
      label[base + m] = label[root];
      if (full[slot]) {
        tally.add_cells(label[root], cells, k0, k0 + side - 1);
      } else {
        const long K = k0 + octree.coords[m][2];
        tally.add_cells(label[root], 1, K, K);
      }
    }
  }
  for (int slot = 0; slot < slots; ++slot) slot_map[set.voxels[slot]] = -1;
  const double cell_volume = grid.voxel_volume() * std::ldexp(1.0, -3 * octree.levels);
  const double cell_height = grid.step.z() * std::ldexp(1.0, -octree.levels);
  std::vector<std::uint8_t> keep;
  const ComponentCount result = tally.decide(plausibility, cell_volume, cell_height, keep);
  for (int slot = 0; slot < slots; ++slot) {
    const int base = slot * cells;
    if (full[slot]) {
      std::fill_n(set.cells.begin() + base, cells, keep[label[base]]);
      if (slot < static_cast<int>(set.whole.size())) set.whole[slot] &= keep[label[base]];
      continue;
    }
    for (int m = 0; m < cells; ++m) {
      if (in[base + m]) set.cells[base + m] = keep[label[base + m]];
    }
  }
  return result;
}

}  // namespace detail

}  // namespace camplace::voxel
