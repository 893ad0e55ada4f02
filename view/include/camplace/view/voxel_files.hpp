#pragma once
/// Voxel models as files that numpy and ParaView read without custom code (docs/files.md,
/// `--voxels-out`): NAME.npy (uint8 array, shape (states, nz, ny, nx)), NAME.json (origin,
/// spacing, dimensions, index order, states) and NAME.vtk (legacy VTK structured points, one
/// cell array per state).
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "camplace/voxel/grid.hpp"

namespace camplace::view {

/// One state's voxel model: one byte per voxel in the grid's index order i + nx·(j + ny·k),
/// 1 = in M.
struct VoxelLayer {
  int time_step = 0;
  int event = 0;
  std::vector<std::uint8_t> model;
};

/// A file to write: path and content.
using FileContent = std::pair<std::string, std::string>;

/// The NPY (format 1.0) bytes of the layers as one C-order uint8 array of shape
/// (layers, nz, ny, nx): element [s, k, j, i] is voxel i + nx·(j + ny·k) of layer s.
std::string npy_bytes(const std::array<int, 3>& n, const std::vector<VoxelLayer>& layers);

/// The three files for `npy_path` (which ends in ".npy"; the others replace that suffix by
/// ".json" and ".vtk"). `extra`: members added to the JSON sidecar (pipeline, mode, ...).
std::vector<FileContent> voxel_files(const voxel::Grid& grid, const std::vector<VoxelLayer>& layers,
                                     const std::string& npy_path,
                                     const nlohmann::ordered_json& extra = {});

/// Writes voxel_files atomically (core::write_file_atomically), each file whole or not at all.
/// Throws std::runtime_error naming the path that cannot be written.
void write_voxel_files(const voxel::Grid& grid, const std::vector<VoxelLayer>& layers,
                       const std::string& npy_path, const nlohmann::ordered_json& extra = {});

}  // namespace camplace::view
