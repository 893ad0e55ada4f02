// libFuzzer target: the study-file reader (compare's parse_study: examinations, groups, the
// base scene and every group's generated scene), without the exact pipeline the rest of
// camplace::compare needs.
#include <cstdint>

#include "fuzz_common.hpp"
#include "study_definition.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = camplace::fuzz::write_input("study.json", data, size);
  camplace::fuzz::expect_success_or_input_error(
      [&] { (void)camplace::compare::detail::parse_study(path); });
  return 0;
}
