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

/// filter_components on rows: clears the bits of every component the filter removes.
ComponentCount filter_rows(Rows& rows, const Grid& grid, const core::Plausibility& plausibility);

}  // namespace camplace::voxel::detail
