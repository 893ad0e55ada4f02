// libFuzzer target: the camera-file loader (core::load_camera_config) for paper_basic.
#include <cstdint>
#include <optional>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const camplace::core::Scene scene =
      camplace::core::load_scene(CAMPLACE_SOURCE_DIR "/data/paper_basic.json");
  const std::string path = camplace::fuzz::write_input("cameras.json", data, size);
  camplace::fuzz::expect_success_or_input_error(
      [&] { (void)camplace::core::load_camera_config(path, scene); });
  return 0;
}
