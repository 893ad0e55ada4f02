#pragma once
// A base voxel model as bit rows (components.cpp): the form in which the labeller hands each
// state's model to the filter and the distance, 1 bit per voxel instead of 1 byte.
#include <cstdint>
#include <vector>

#include "camplace/core/scene.hpp"
#include "camplace/voxel/components.hpp"
#include "camplace/voxel/grid.hpp"

namespace camplace::voxel::detail {

/// A model of a grid (1 = in M) as bits: per row j + ny·k, words_per_row(nx) words, voxel
/// (i, j, k) at bit i % 64 of the row's word i / 64; the bits at i ≥ nx are 0.
using Rows = std::vector<std::uint64_t>;

inline int words_per_row(int nx) { return (nx + 63) / 64; }

/// The number of set bits of x. Inline bit arithmetic: without a popcnt target (the default
/// x86-64 build) __builtin_popcountll is a call into libgcc, 1–2 % of a many-state evaluation.
inline int bit_count(std::uint64_t x) {
  x = x - ((x >> 1) & 0x5555555555555555ULL);
  x = (x & 0x3333333333333333ULL) + ((x >> 2) & 0x3333333333333333ULL);
  x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0FULL;
  return static_cast<int>((x * 0x0101010101010101ULL) >> 56);
}

/// Whether voxel v (index i + nx·(j + ny·k)) is in `rows`.
inline bool row_bit(const std::uint64_t* rows, int nx, int words, int v) {
  const int r = v / nx, i = v - r * nx;
  return (rows[static_cast<std::size_t>(r) * words + (i >> 6)] >> (i & 63)) & 1;
}

/// The rows of each state of a chunk of `count` ≤ 64 states from the chunk's per-voxel masks
/// (`masks[v]` bit s: voxel v is in M in state s, no bit at s ≥ count; grid.count() of them):
/// into `out[s]`, resized.
void rows_from_masks(const std::uint64_t* masks, int count, const Grid& grid, Rows* const* out);

/// A model of one byte per voxel (not 0 = in M) as rows, and back (1 = in M), resized.
void rows_from_bytes(const std::vector<std::uint8_t>& model, const Grid& grid, Rows& rows);
void bytes_from_rows(const Rows& rows, const Grid& grid, std::vector<std::uint8_t>& model);

/// A maximal segment of model voxels along x: row j + ny·k, voxels i0..i1 (inclusive).
struct RowRun {
  int row;
  int i0, i1;
};

/// A component's cell count and z-extent (layer indices kmin..kmax; kmax < 0: no cells yet).
struct ComponentExtent {
  long cells = 0;
  long kmin = 0, kmax = -1;
};

/// The voxels that every model of a set holds (a chunk's states: they share most voxels), with
/// their components, found once (core_of_rows) so that filtering each model joins only the
/// model's own voxels to them (filter_rows with a core).
struct RowCore {
  Rows bits;                             ///< the voxels every model holds
  std::vector<RowRun> runs;              ///< bits' runs, row by row, ascending
  std::vector<int> row_start;            ///< per row: its first run (rows + 1 offsets)
  std::vector<int> component;            ///< per run: its component among bits' components
  std::vector<ComponentExtent> extents;  ///< per component
  /// Per component c: its runs component_runs[component_start[c] ..].
  std::vector<int> component_start, component_runs;
  /// The filter on bits alone (a model that holds no other voxel): per component whether it
  /// keeps it, what it keeps, and its count.
  std::vector<std::uint8_t> keep;
  Rows kept;
  ComponentCount count;
};

/// The core of models[0 .. count − 1] (each of `grid`), into `core` (its memory reused).
void core_of_rows(const Rows* const* models, int count, const Grid& grid,
                  const core::Plausibility& plausibility, RowCore& core);

/// filter_components on rows: clears the bits of every component the filter removes.
ComponentCount filter_rows(Rows& rows, const Grid& grid, const core::Plausibility& plausibility);

/// The same on rows that hold every voxel of `core`: the same components (each of the core's
/// components lies in one of the model's; docs/design/distance.md C1), found from the core's
/// and the model's other voxels.
ComponentCount filter_rows(Rows& rows, const RowCore& core, const Grid& grid,
                           const core::Plausibility& plausibility);

}  // namespace camplace::voxel::detail
