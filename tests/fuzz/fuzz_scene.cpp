// libFuzzer target: the scene loader (core::load_scene) on arbitrary bytes as a scene file.
#include <cstdint>

#include "camplace/core/scene.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = camplace::fuzz::write_input("scene.json", data, size);
  camplace::fuzz::expect_success_or_input_error([&] { (void)camplace::core::load_scene(path); });
  return 0;
}
