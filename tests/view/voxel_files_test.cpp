// The voxel files read back by the formats' own rules (NPY 1.0, legacy VTK), as numpy and
// ParaView read them.
#include "camplace/view/voxel_files.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using core::Vec3;

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(VoxelFiles, NpyJsonAndVtkDescribeTheSameVoxels) {
  const voxel::Grid grid = voxel::make_grid({Vec3(-1, 0, 0.5), Vec3(2, 2, 2.5)}, {3, 2, 4});
  std::vector<view::VoxelLayer> layers(2);
  for (int s = 0; s < 2; ++s) {
    layers[s].time_step = s;
    layers[s].event = 1 - s;
    layers[s].model.resize(grid.count());
    for (int v = 0; v < grid.count(); ++v) layers[s].model[v] = (v * 7 + s) % 3 == 0;
  }
  const std::string dir = temp_dir("voxelfiles");
  view::write_voxel_files(grid, layers, dir + "/m.npy", {{"mode", "conservative"}});

  // NPY 1.0: magic, version, little-endian header length, a Python dict, data in C order.
  const std::string npy = read_bytes(dir + "/m.npy");
  ASSERT_EQ(npy.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  const std::size_t header_length =
      static_cast<unsigned char>(npy[8]) | (static_cast<unsigned char>(npy[9]) << 8);
  EXPECT_EQ((10 + header_length) % 64, 0u);
  const std::string header = npy.substr(10, header_length);
  EXPECT_EQ(header.back(), '\n');
  EXPECT_NE(header.find("'descr': '|u1'"), std::string::npos);
  EXPECT_NE(header.find("'fortran_order': False"), std::string::npos);
  EXPECT_NE(header.find("'shape': (2, 4, 2, 3)"), std::string::npos);  // states, nz, ny, nx
  const std::string data = npy.substr(10 + header_length);
  ASSERT_EQ(data.size(), 2u * 24u);
  // array[s, k, j, i] at offset ((s·nz + k)·ny + j)·nx + i is voxel i + nx·(j + ny·k).
  for (int s = 0; s < 2; ++s) {
    for (int k = 0; k < 4; ++k) {
      for (int j = 0; j < 2; ++j) {
        for (int i = 0; i < 3; ++i) {
          EXPECT_EQ(data[((s * 4 + k) * 2 + j) * 3 + i], layers[s].model[i + 3 * (j + 2 * k)]);
        }
      }
    }
  }

  std::ifstream sidecar_in(dir + "/m.json");
  const auto sidecar = nlohmann::json::parse(sidecar_in);
  EXPECT_EQ(sidecar["data"], "m.npy");
  EXPECT_EQ(sidecar["shape"], nlohmann::json({2, 4, 2, 3}));
  EXPECT_EQ(sidecar["dimensions"], nlohmann::json({3, 2, 4}));
  EXPECT_EQ(sidecar["origin"], nlohmann::json({-1.0, 0.0, 0.5}));
  EXPECT_EQ(sidecar["spacing"], nlohmann::json({1.0, 1.0, 0.5}));
  EXPECT_EQ(sidecar["states"][1], nlohmann::json({{"time_step", 1}, {"event", 0}}));
  EXPECT_EQ(sidecar["mode"], "conservative");

  // Legacy VTK: structured points over the voxel corners, one unsigned_char cell array per
  // state, cells x fastest.
  const std::string vtk = read_bytes(dir + "/m.vtk");
  EXPECT_EQ(vtk.rfind("# vtk DataFile Version 3.0\n", 0), 0u);
  for (const char* line : {"\nBINARY\n", "\nDATASET STRUCTURED_POINTS\n", "\nDIMENSIONS 4 3 5\n",
                           "\nORIGIN -1 0 0.5\n", "\nSPACING 1 1 0.5\n", "\nCELL_DATA 24\n"}) {
    EXPECT_NE(vtk.find(line), std::string::npos) << line;
  }
  for (int s = 0; s < 2; ++s) {
    const std::string name = "SCALARS state_h" + std::to_string(s) + "_e" + std::to_string(1 - s) +
                             " unsigned_char 1\nLOOKUP_TABLE default\n";
    const std::size_t at = vtk.find(name);
    ASSERT_NE(at, std::string::npos);
    const std::string cells = vtk.substr(at + name.size(), 24);
    for (int v = 0; v < 24; ++v) EXPECT_EQ(cells[v], layers[s].model[v]) << v;
  }
}

}  // namespace
}  // namespace camplace::testing
