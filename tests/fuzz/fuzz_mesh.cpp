// libFuzzer target: the mesh-file pre-scan and reader. The first byte picks the format (.off,
// .obj, .stl, .ply), the rest is the file, read as the target of a fixed valid scene.
#include <cstdint>
#include <fstream>
#include <string>

#include "camplace/core/scene.hpp"
#include "fuzz_common.hpp"

namespace {

const char* const kExtensions[] = {"off", "obj", "stl", "ply"};

std::string scene_for(const std::string& mesh_file) {
  return R"({"area": {"min": [0, 0, 0], "max": [4, 3, 3]}, "voxels": [8, 6, 6],
 "cameras": {"count": 1, "half_angle_deg": 30},
 "time_steps": [{"critical": [{"name": "robot", "box": [[3, 0, 0], [3.5, 0.5, 1]]}],
   "events": [{"weight": 1, "targets": [{"name": "person", "file": ")" +
         mesh_file + R"("}]}]}]})";
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string name = std::string("mesh.") + kExtensions[data[0] % 4];
  camplace::fuzz::write_input(name, data + 1, size - 1);
  const std::string scene = scene_for(name);
  const std::string path = camplace::fuzz::write_input(
      "mesh_scene.json", reinterpret_cast<const std::uint8_t*>(scene.data()), scene.size());
  camplace::fuzz::expect_success_or_input_error([&] { (void)camplace::core::load_scene(path); });
  return 0;
}
