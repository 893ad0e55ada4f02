// 6-connected components and the plausibility filter (SPEC §4–5), one rule (ComponentTally) on
// the base model as bit rows (detail::filter_rows; filter_components on bytes goes through it) and
// on refined cells (detail::filter_cells). Voxels on runs: maximal segments of model voxels along
// x. Two runs connect when they lie in face-adjacent rows (j ± 1 or k ± 1) and share an x index;
// union–find over runs gives the components. A chunk of states' models share most voxels: the
// components of the voxels all of them hold (detail::RowCore) are found once, and each model's
// other runs are joined to them (docs/design/distance.md C1).
#include "camplace/voxel/components.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

#include "camplace/core/error.hpp"
#include "cells.hpp"
#include "rows.hpp"
#include "union_find.hpp"

namespace camplace::voxel {

namespace {

using Run = detail::RowRun;
using detail::ComponentExtent;
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
    ComponentExtent& e = extent_[c];
    if (e.kmax < 0) {
      e.kmin = k0;
      e.kmax = k1;
    } else {
      e.kmin = std::min(e.kmin, k0);
      e.kmax = std::max(e.kmax, k1);
    }
    e.cells += count;
  }
  int size() const { return static_cast<int>(extent_.size()); }
  const ComponentExtent& extent(int c) const { return extent_[c]; }
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
  std::vector<ComponentExtent> extent_;
};

/// The model's runs and their union–find forest (parent[n]: run n's component is find(n)), with
/// run_forest's working memory (reused when the forest is).
struct RunForest {
  std::vector<Run> runs;
  std::vector<int> parent;
  std::vector<int> row_start;
};

/// Into `forest` (its memory reused), from the model's rows (detail::Rows). `occupied`: rows
/// (ascending) among which are all that hold voxels, or null for all rows; only they are read
/// (a model's voxels beyond its chunk's core lie in few rows).
void run_forest(const std::uint64_t* bits, const Grid& grid, const std::vector<int>* occupied,
                RunForest& forest) {
  const int ny = grid.n[1], nz = grid.n[2];
  const int words = detail::words_per_row(grid.n[0]);
  const int rows = ny * nz;
  const int listed = occupied ? static_cast<int>(occupied->size()) : rows;
  auto row_at = [&](int n) { return occupied ? (*occupied)[n] : n; };
  std::vector<Run>& runs = forest.runs;
  runs.clear();
  std::vector<int>& row_start = forest.row_start;
  row_start.resize(rows + 1);
  // A run starts at a 1 bit with a 0 (or the row's start) before it and ends at a 1 bit with a
  // 0 (or the row's end) after it, across words; starts and ends alternate along the row. Rows
  // not listed hold no runs: they start where the next listed row does.
  int filled = 0;  // row_start is written for rows before this one
  for (int n = 0; n < listed; ++n) {
    const int r = row_at(n);
    std::fill(row_start.begin() + filled, row_start.begin() + r + 1, static_cast<int>(runs.size()));
    filled = r + 1;
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
  std::fill(row_start.begin() + filled, row_start.end(), static_cast<int>(runs.size()));
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
  // (A row without runs has nothing to connect.)
  for (int n = 0; n < listed; ++n) {
    const int r = row_at(n);
    if (row_start[r] == row_start[r + 1]) continue;
    const int j = r % ny;
    if (j > 0 && row_start[r - 1] < row_start[r]) connect(r, r - 1);
    if (r >= ny && row_start[r - ny] < row_start[r - ny + 1]) connect(r, r - ny);
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

/// Bits lo .. hi (0 ≤ lo ≤ hi ≤ 63) of a word.
std::uint64_t span(int lo, int hi) {
  return (hi == 63 ? ~std::uint64_t{0} : (std::uint64_t{1} << (hi + 1)) - 1) &
         ~((std::uint64_t{1} << lo) - 1);
}

/// Sets voxels run.i0 .. run.i1 of the run's row in `rows` (words per row) to `value`.
void set_run(std::uint64_t* rows, int words, const Run& run, bool value) {
  std::uint64_t* row = rows + static_cast<std::size_t>(run.row) * words;
  for (int i = run.i0; i <= run.i1;) {
    // Bits i .. min(i1, end of its word) at once.
    const int w = i >> 6, lo = i & 63, hi = std::min(run.i1 - 64 * w, 63);
    row[w] = value ? row[w] | span(lo, hi) : row[w] & ~span(lo, hi);
    i = 64 * w + hi + 1;
  }
}

/// Whether voxel i of row r is in `rows` (words per row).
bool has_bit(const std::uint64_t* rows, int words, int r, int i) {
  return (rows[static_cast<std::size_t>(r) * words + (i >> 6)] >> (i & 63)) & 1;
}

}  // namespace

std::vector<int> component_labels(const std::vector<std::uint8_t>& model, const Grid& grid) {
  Rows rows;
  detail::rows_from_bytes(model, grid, rows);
  RunForest forest;
  run_forest(rows.data(), grid, nullptr, forest);
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

std::vector<ComponentCount> filter_components_together(
    std::vector<std::vector<std::uint8_t>>& models, const Grid& grid,
    const core::Plausibility& plausibility) {
  std::vector<Rows> rows(models.size());
  std::vector<const Rows*> all;
  for (std::size_t m = 0; m < models.size(); ++m) {
    detail::rows_from_bytes(models[m], grid, rows[m]);
    all.push_back(&rows[m]);
  }
  std::vector<ComponentCount> counts(models.size());
  if (models.empty()) return counts;
  detail::RowCore core;
  detail::core_of_rows(all.data(), static_cast<int>(all.size()), grid, plausibility, core);
  for (std::size_t m = 0; m < models.size(); ++m) {
    counts[m] = detail::filter_rows(rows[m], core, grid, plausibility);
    detail::bytes_from_rows(rows[m], grid, models[m]);
  }
  return counts;
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
  const std::uint64_t all = count == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << count) - 1;
  std::uint64_t a[64];
  for (int r = 0; r < rows; ++r) {
    for (int w = 0; w < words; ++w) {
      const int i0 = 64 * w, n = std::min(64, nx - i0);
      const std::uint64_t* m = masks + static_cast<std::size_t>(r) * nx + i0;
      // `same`: voxel by voxel, in M in every state or in none (most words: the states share
      // most of their models), then each state's word is `held`, without a transpose.
      std::uint64_t held = 0;
      bool same = true;
      for (int i = 0; i < n; ++i) {
        a[i] = m[i];
        held |= static_cast<std::uint64_t>(m[i] != 0) << i;
        same &= (m[i] == 0) | (m[i] == all);
      }
      const std::size_t at = static_cast<std::size_t>(r) * words + w;
      if (same) {
        for (int s = 0; s < count; ++s) (*out[s])[at] = held;
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

void core_of_rows(const Rows* const* models, int count, const Grid& grid,
                  const core::Plausibility& plausibility, RowCore& core) {
  const int ny = grid.n[1];
  const int words = words_per_row(grid.n[0]);
  core.bits = *models[0];
  for (int m = 1; m < count; ++m) {
    for (std::size_t w = 0; w < core.bits.size(); ++w) core.bits[w] &= (*models[m])[w];
  }
  // The core's components (numbered in order of their first run), their extents and runs.
  thread_local RunForest forest;
  run_forest(core.bits.data(), grid, nullptr, forest);
  core.runs = forest.runs;
  core.row_start = forest.row_start;
  const std::size_t runs = core.runs.size();
  core.component.assign(runs, -1);
  ComponentTally tally;
  for (std::size_t n = 0; n < runs; ++n) {
    const int root = find(forest.parent, static_cast<int>(n));
    if (core.component[root] < 0) core.component[root] = tally.add_component();
    const int c = core.component[root];
    core.component[n] = c;
    const long k = core.runs[n].row / ny;
    tally.add_cells(c, core.runs[n].i1 - core.runs[n].i0 + 1, k, k);
  }
  // Each component's runs, by counting sort.
  const int components = tally.size();
  core.extents.resize(components);
  core.component_start.assign(components + 1, 0);
  for (int c = 0; c < components; ++c) core.extents[c] = tally.extent(c);
  for (std::size_t n = 0; n < runs; ++n) ++core.component_start[core.component[n] + 1];
  std::partial_sum(core.component_start.begin(), core.component_start.end(),
                   core.component_start.begin());
  core.component_runs.resize(runs);
  thread_local std::vector<int> next;
  next.assign(core.component_start.begin(), core.component_start.end() - 1);
  for (std::size_t n = 0; n < runs; ++n) {
    core.component_runs[next[core.component[n]]++] = static_cast<int>(n);
  }
  // The filter on the core alone.
  core.count = tally.decide(plausibility, grid.voxel_volume(), grid.step.z(), core.keep);
  core.kept = core.bits;
  for (std::size_t n = 0; n < runs; ++n) {
    if (!core.keep[core.component[n]]) set_run(core.kept.data(), words, core.runs[n], false);
  }
}

ComponentCount filter_rows(Rows& rows, const Grid& grid, const core::Plausibility& plausibility) {
  // The core of this model alone (C1: every voxel is the core's).
  thread_local RowCore core;
  const Rows* models[1] = {&rows};
  core_of_rows(models, 1, grid, plausibility, core);
  rows = core.kept;
  return core.count;
}

ComponentCount filter_rows(Rows& rows, const RowCore& core, const Grid& grid,
                           const core::Plausibility& plausibility) {
  const int nx = grid.n[0], ny = grid.n[1], nz = grid.n[2];
  const int words = words_per_row(nx);
  // The model's voxels beyond the core (E of C1); the rows start as what the core's filter
  // keeps and all of E, and only components that hold voxels of E change that.
  thread_local Rows own;
  own.resize(rows.size());
  thread_local std::vector<int> occupied;  // the rows that hold voxels of E
  occupied.clear();
  std::uint64_t any = 0;
  for (std::size_t w = 0; w < rows.size(); ++w) {
    CAMPLACE_ASSERT((core.bits[w] & ~rows[w]) == 0);  // the model holds the core
    own[w] = rows[w] & ~core.bits[w];
    rows[w] = core.kept[w] | own[w];
    any |= own[w];
  }
  if (!any) return core.count;
  for (int r = 0; r < ny * nz; ++r) {
    std::uint64_t held = 0;
    for (int w = 0; w < words; ++w) held |= own[static_cast<std::size_t>(r) * words + w];
    if (held) occupied.push_back(r);
  }
  // E's runs joined among themselves (nodes 0 .. runs − 1), then the core's components they
  // touch (C1, 2): at either end in the run's row, overlapping it in the four rows beside it.
  // A core component no run of E touches is a component of the model too, and the core's
  // filter decided it already.
  thread_local RunForest forest;
  run_forest(own.data(), grid, &occupied, forest);
  const std::vector<Run>& runs = forest.runs;
  std::vector<int>& parent = forest.parent;
  const int own_runs = static_cast<int>(runs.size());
  thread_local std::vector<int> node_of;  // per core component: its node, or −1
  node_of.resize(core.extents.size(), -1);
  thread_local std::vector<int> touched;  // the core components touched, in order of nodes
  touched.clear();
  auto join_row = [&](int n, int r, int i0, int i1) {
    for (int c = core.row_start[r]; c < core.row_start[r + 1]; ++c) {
      const Run& run = core.runs[c];
      if (run.i0 > i1) break;
      if (run.i1 < i0) continue;
      int& node = node_of[core.component[c]];
      if (node < 0) {
        node = own_runs + static_cast<int>(touched.size());
        touched.push_back(core.component[c]);
        parent.push_back(node);
      }
      unite(parent, n, node);
    }
  };
  const std::uint64_t* core_bits = core.bits.data();
  for (int n = 0; n < own_runs; ++n) {
    const Run& run = runs[n];
    const int r = run.row, j = r % ny, k = r / ny;
    if (run.i0 > 0 && has_bit(core_bits, words, r, run.i0 - 1)) {
      join_row(n, r, run.i0 - 1, run.i0 - 1);
    }
    if (run.i1 + 1 < nx && has_bit(core_bits, words, r, run.i1 + 1)) {
      join_row(n, r, run.i1 + 1, run.i1 + 1);
    }
    if (j > 0) join_row(n, r - 1, run.i0, run.i1);
    if (j + 1 < ny) join_row(n, r + 1, run.i0, run.i1);
    if (k > 0) join_row(n, r - ny, run.i0, run.i1);
    if (k + 1 < nz) join_row(n, r + ny, run.i0, run.i1);
  }
  // Volume and z-extent of each component that holds voxels of E: its runs' and its core
  // components'.
  const int nodes = static_cast<int>(parent.size());
  ComponentTally tally;
  thread_local std::vector<int> id;
  id.assign(nodes, -1);
  for (int x = 0; x < nodes; ++x) {
    const int root = find(parent, x);
    if (id[root] < 0) id[root] = tally.add_component();
    id[x] = id[root];
    if (x < own_runs) {
      const long k = runs[x].row / ny;
      tally.add_cells(id[x], runs[x].i1 - runs[x].i0 + 1, k, k);
    } else {
      const ComponentExtent& e = core.extents[touched[x - own_runs]];
      tally.add_cells(id[x], e.cells, e.kmin, e.kmax);
    }
  }
  thread_local std::vector<std::uint8_t> keep;
  const ComponentCount changed =
      tally.decide(plausibility, grid.voxel_volume(), grid.step.z(), keep);
  // The core's count with its touched components' decisions replaced by the components that
  // hold them; their runs and E's runs as those components are decided.
  ComponentCount result = core.count;
  result.kept += changed.kept;
  result.removed += changed.removed;
  for (int n = 0; n < own_runs; ++n) {
    if (!keep[id[n]]) set_run(rows.data(), words, runs[n], false);
  }
  for (std::size_t t = 0; t < touched.size(); ++t) {
    const int c = touched[t];
    node_of[c] = -1;
    const bool kept = keep[id[own_runs + t]];
    --(core.keep[c] ? result.kept : result.removed);
    if (kept == static_cast<bool>(core.keep[c])) continue;
    for (int at = core.component_start[c]; at < core.component_start[c + 1]; ++at) {
      set_run(rows.data(), words, core.runs[core.component_runs[at]], kept);
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
