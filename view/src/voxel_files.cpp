// NPY + JSON + legacy VTK voxel files (docs/files.md). NPY format 1.0:
// https://numpy.org/doc/stable/reference/generated/numpy.lib.format.html
#include "camplace/view/voxel_files.hpp"

#include <sstream>

#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"

namespace camplace::view {

std::string npy_bytes(const std::array<int, 3>& n, const std::vector<VoxelLayer>& layers) {
  std::string header = "{'descr': '|u1', 'fortran_order': False, 'shape': (" +
                       std::to_string(layers.size()) + ", " + std::to_string(n[2]) + ", " +
                       std::to_string(n[1]) + ", " + std::to_string(n[0]) + "), }";
  // Magic (6) + version (2) + header length (2) + header, padded with spaces and ended by a
  // newline to a multiple of 64 bytes (what numpy itself writes).
  const std::size_t unpadded = 10 + header.size() + 1;
  header.append((64 - unpadded % 64) % 64, ' ');
  header += '\n';
  std::string out("\x93NUMPY\x01\x00", 8);
  out += static_cast<char>(header.size() & 0xff);
  out += static_cast<char>(header.size() >> 8);
  out += header;
  const std::size_t count = static_cast<std::size_t>(n[0]) * n[1] * n[2];
  for (const VoxelLayer& layer : layers) {
    CAMPLACE_ASSERT(layer.model.size() == count);
    for (std::uint8_t b : layer.model) out += static_cast<char>(b ? 1 : 0);
  }
  return out;
}

std::vector<FileContent> voxel_files(const voxel::Grid& grid, const std::vector<VoxelLayer>& layers,
                                     const std::string& npy_path,
                                     const nlohmann::ordered_json& extra) {
  const std::string suffix = ".npy";
  CAMPLACE_ASSERT(npy_path.size() > suffix.size() &&
                  npy_path.compare(npy_path.size() - suffix.size(), suffix.size(), suffix) == 0);
  const std::string stem = npy_path.substr(0, npy_path.size() - suffix.size());
  const std::string file_name = npy_path.substr(npy_path.find_last_of('/') + 1);
  const auto& n = grid.n;

  nlohmann::ordered_json sidecar;
  sidecar["data"] = file_name;
  sidecar["dtype"] = "uint8";
  sidecar["shape"] = {layers.size(), n[2], n[1], n[0]};
  sidecar["axes"] = {"state", "z", "y", "x"};
  sidecar["index_order"] =
      "array[s, k, j, i] = voxel (i, j, k) of state s = flat index i + nx*(j + ny*k)";
  sidecar["values"] = "1 = voxel in the model M after the plausibility filter, 0 = not";
  sidecar["dimensions"] = {n[0], n[1], n[2]};
  sidecar["origin"] = {grid.area.min.x(), grid.area.min.y(), grid.area.min.z()};
  sidecar["spacing"] = {grid.step.x(), grid.step.y(), grid.step.z()};
  sidecar["voxel_box"] = "[origin + (i, j, k) * spacing, origin + (i+1, j+1, k+1) * spacing], m";
  sidecar["frame"] = "camplace world frame: right-handed, z up, metres";
  nlohmann::ordered_json states = nlohmann::ordered_json::array();
  for (const VoxelLayer& layer : layers) {
    states.push_back({{"time_step", layer.time_step}, {"event", layer.event}});
  }
  sidecar["states"] = states;
  for (const auto& [key, value] : extra.items()) sidecar[key] = value;

  // Legacy VTK structured points: the grid's points are the voxel corners, the states cell
  // arrays; cells run x fastest, then y, then z, as the voxel index. unsigned_char data needs
  // no byte order.
  std::ostringstream vtk;
  vtk.precision(17);
  vtk << "# vtk DataFile Version 3.0\n"
      << "camplace voxel model (1 = in M), one cell array per state, metres, z up\n"
      << "BINARY\nDATASET STRUCTURED_POINTS\n"
      << "DIMENSIONS " << n[0] + 1 << " " << n[1] + 1 << " " << n[2] + 1 << "\n"
      << "ORIGIN " << grid.area.min.x() << " " << grid.area.min.y() << " " << grid.area.min.z()
      << "\nSPACING " << grid.step.x() << " " << grid.step.y() << " " << grid.step.z() << "\n"
      << "CELL_DATA " << grid.count() << "\n";
  for (const VoxelLayer& layer : layers) {
    vtk << "SCALARS state_h" << layer.time_step << "_e" << layer.event
        << " unsigned_char 1\nLOOKUP_TABLE default\n";
    for (std::uint8_t b : layer.model) vtk.put(static_cast<char>(b ? 1 : 0));
    vtk << "\n";
  }
  return {{npy_path, npy_bytes(n, layers)},
          {stem + ".json", sidecar.dump(2) + "\n"},
          {stem + ".vtk", vtk.str()}};
}

void write_voxel_files(const voxel::Grid& grid, const std::vector<VoxelLayer>& layers,
                       const std::string& npy_path, const nlohmann::ordered_json& extra) {
  for (const auto& [path, content] : voxel_files(grid, layers, npy_path, extra)) {
    core::write_file_atomically(path, content);
  }
}

}  // namespace camplace::view
