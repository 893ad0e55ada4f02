// 6-connected components and the plausibility filter (SPEC §4–5), one rule (ComponentTally) on
// the base model as bit rows (detail::filter_rows; filter_components on bytes goes through it) and
// on refined cells (detail::filter_cells). Voxels on runs: maximal segments of model voxels along
// x. Two runs connect when they lie in face-adjacent rows (j ± 1 or k ± 1) and share an x index;
// union–find over runs gives the components.
#include "camplace/voxel/components.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

#include "cells.hpp"
#include "rows.hpp"
#include "union_find.hpp"

namespace camplace::voxel {

namespace {

struct Run {
  int row;     ///< j + ny·k
  int i0, i1;  ///< x range, inclusive
};

using detail::find;
using detail::Rows;
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
};

/// Into `forest` (its memory reused), from the model's rows (detail::Rows).
void run_forest(const std::uint64_t* bits, const Grid& grid, RunForest& forest) {
  const int ny = grid.n[1], nz = grid.n[2];
  const int words = detail::words_per_row(grid.n[0]);
  const int rows = ny * nz;
  std::vector<Run>& runs = forest.runs;
  runs.clear();
  std::vector<int>& row_start = forest.row_start;
  row_start.assign(rows + 1, 0);
  // A run starts at a 1 bit with a 0 (or the row's start) before it and ends at a 1 bit with a
  // 0 (or the row's end) after it, across words; starts and ends alternate along the row.
  for (int r = 0; r < rows; ++r) {
    row_start[r] = static_cast<int>(runs.size());
    const std::uint64_t* row = bits + static_cast<std::size_t>(r) * words;
    int start = -1;  // the open run's first voxel
    for (int w = 0; w < words; ++w) {
      const std::uint64_t b = row[w];
      if (!b) continue;
      const std::uint64_t before = w > 0 ? row[w - 1] >> 63 : 0;
      const std::uint64_t after = w + 1 < words ? row[w + 1] << 63 : 0;
      std::uint64_t starts = b & ~(b << 1 | before), ends = b & ~(b >> 1 | after);
      while (starts | ends) {
        if (start < 0) {
          start = 64 * w + __builtin_ctzll(starts);
          starts &= starts - 1;
        } else {
          runs.push_back({r, start, 64 * w + __builtin_ctzll(ends)});
          ends &= ends - 1;
          start = -1;
        }
      }
    }
  }
  row_start[rows] = static_cast<int>(runs.size());
  std::vector<int>& parent = forest.parent;
  parent.resize(runs.size());
  std::iota(parent.begin(), parent.end(), 0);
  // Face neighbours only: voxels meeting at an edge or a corner do not connect (SPEC §4); so
  // runs connect only through a shared x index in the row before (j − 1) or below (k − 1). Rows
  // whose bits do not meet share no x index (then connect has nothing to unite).
  auto connect = [&](int r, int other) {
    const std::uint64_t* a_bits = bits + static_cast<std::size_t>(r) * words;
    const std::uint64_t* b_bits = bits + static_cast<std::size_t>(other) * words;
    std::uint64_t meet = 0;
    for (int w = 0; w < words; ++w) meet |= a_bits[w] & b_bits[w];
    if (!meet) return;
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

/// 64 × 64 bits: bit i of a[k] ↔ bit k of a[i] (blocks of 32, 16, ..., 1 swapped in place).
inline void transpose64(std::uint64_t a[64]) {
  std::uint64_t m = 0x00000000FFFFFFFFULL;
  for (int j = 32; j != 0; j >>= 1, m ^= m << j) {
    for (int k = 0; k < 64; k = ((k | j) + 1) & ~j) {
      const std::uint64_t t = ((a[k] >> j) ^ a[k | j]) & m;
      a[k] ^= t << j;
      a[k | j] ^= t;
    }
  }
}

}  // namespace

std::vector<int> component_labels(const std::vector<std::uint8_t>& model, const Grid& grid) {
  Rows rows;
  detail::rows_from_bytes(model, grid, rows);
  RunForest forest;
  run_forest(rows.data(), grid, forest);
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
  Rows rows;
  detail::rows_from_bytes(model, grid, rows);
  const ComponentCount result = detail::filter_rows(rows, grid, plausibility);
  detail::bytes_from_rows(rows, grid, model);
  return result;
}

namespace detail {

void rows_from_masks(const std::uint64_t* masks, int count, const Grid& grid, Rows* const* out) {
  const int nx = grid.n[0], rows = grid.n[1] * grid.n[2];
  const int words = words_per_row(nx);
  const std::size_t size = static_cast<std::size_t>(rows) * words;
  // Few states: each set bit of the masks into its state's row (a 64 × 64 transpose per word
  // would cost more than the bits); else the transpose.
  constexpr int kScatter = 8;
  if (count <= kScatter) {
    for (int s = 0; s < count; ++s) out[s]->assign(size, 0);
    for (int r = 0; r < rows; ++r) {
      const std::uint64_t* m = masks + static_cast<std::size_t>(r) * nx;
      for (int i = 0; i < nx; ++i) {
        const std::size_t at = static_cast<std::size_t>(r) * words + (i >> 6);
        for (std::uint64_t x = m[i]; x; x &= x - 1) {
          (*out[__builtin_ctzll(x)])[at] |= std::uint64_t{1} << (i & 63);
        }
      }
    }
    return;
  }
  for (int s = 0; s < count; ++s) out[s]->resize(size);
  std::uint64_t a[64];
  for (int r = 0; r < rows; ++r) {
    for (int w = 0; w < words; ++w) {
      const int i0 = 64 * w, n = std::min(64, nx - i0);
      const std::uint64_t* m = masks + static_cast<std::size_t>(r) * nx + i0;
      std::uint64_t any = 0;
      for (int i = 0; i < n; ++i) any |= a[i] = m[i];
      const std::size_t at = static_cast<std::size_t>(r) * words + w;
      if (!any) {
        for (int s = 0; s < count; ++s) (*out[s])[at] = 0;
        continue;
      }
      std::fill(a + n, a + 64, 0);
      transpose64(a);  // a[s] bit i: voxel i0 + i in state s
      for (int s = 0; s < count; ++s) (*out[s])[at] = a[s];
    }
  }
}

void rows_from_bytes(const std::vector<std::uint8_t>& model, const Grid& grid, Rows& rows) {
  const int nx = grid.n[0], count = grid.n[1] * grid.n[2];
  const int words = words_per_row(nx);
  rows.assign(static_cast<std::size_t>(count) * words, 0);
  for (int r = 0; r < count; ++r) {
    for (int i = 0; i < nx; ++i) {
      if (model[static_cast<std::size_t>(r) * nx + i]) {
        rows[static_cast<std::size_t>(r) * words + (i >> 6)] |= std::uint64_t{1} << (i & 63);
      }
    }
  }
}

void bytes_from_rows(const Rows& rows, const Grid& grid, std::vector<std::uint8_t>& model) {
  const int nx = grid.n[0], count = grid.n[1] * grid.n[2];
  const int words = words_per_row(nx);
  model.resize(static_cast<std::size_t>(count) * nx);
  for (int r = 0; r < count; ++r) {
    const std::uint64_t* row = rows.data() + static_cast<std::size_t>(r) * words;
    for (int i = 0; i < nx; ++i) {
      model[static_cast<std::size_t>(r) * nx + i] = (row[i >> 6] >> (i & 63)) & 1;
    }
  }
}

ComponentCount filter_rows(Rows& rows, const Grid& grid, const core::Plausibility& plausibility) {
  const int ny = grid.n[1];
  const int words = words_per_row(grid.n[0]);
  // Per thread, reused: the evaluator filters every state's model per evaluation.
  thread_local RunForest forest;
  run_forest(rows.data(), grid, forest);
  const std::vector<Run>& runs = forest.runs;
  std::vector<int>& parent = forest.parent;
  // Volume (voxel count) and z-extent per component, in order of their first run.
  ComponentTally tally;
  thread_local std::vector<int> id;
  id.assign(runs.size(), -1);
  for (std::size_t n = 0; n < runs.size(); ++n) {
    const int root = find(parent, static_cast<int>(n));
    if (id[root] < 0) id[root] = tally.add_component();
    const long k = runs[n].row / ny;
    id[n] = id[root];
    tally.add_cells(id[root], runs[n].i1 - runs[n].i0 + 1, k, k);
  }
  thread_local std::vector<std::uint8_t> keep;
  const ComponentCount result =
      tally.decide(plausibility, grid.voxel_volume(), grid.step.z(), keep);
  for (std::size_t n = 0; n < runs.size(); ++n) {
    if (keep[id[n]]) continue;
    const Run& run = runs[n];
    std::uint64_t* row = rows.data() + static_cast<std::size_t>(run.row) * words;
    for (int i = run.i0; i <= run.i1;) {
      // Bits i .. min(i1, end of its word) cleared at once.
      const int w = i >> 6, lo = i & 63, hi = std::min(run.i1 - 64 * w, 63);
      const std::uint64_t span =
          (hi == 63 ? ~std::uint64_t{0} : (std::uint64_t{1} << (hi + 1)) - 1) &
          ~((std::uint64_t{1} << lo) - 1);
      row[w] &= ~span;
      i = 64 * w + hi + 1;
    }
  }
  return result;
}

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
