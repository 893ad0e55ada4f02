// libFuzzer target: the run-file reader (optimize::read_run_file), which `optimize` (resuming a
// folder), `validate` and `study` use on files that may be damaged or edited.
#include <cstdint>

#include "camplace/optimize/report.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = camplace::fuzz::write_input("run-1.json", data, size);
  camplace::fuzz::expect_success_or_input_error(
      [&] { (void)camplace::optimize::read_run_file(path); });
  return 0;
}
