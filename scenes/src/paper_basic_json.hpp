#pragma once
// The text of data/paper_basic.json, embedded at build time (scenes/CMakeLists.txt generates
// paper_basic_json.cpp from scenes/src/paper_basic_json.cpp.in). Private to scenes.
#include <string_view>

namespace camplace::scenes::detail {

/// data/paper_basic.json as it was when camplace was configured, byte for byte.
std::string_view paper_basic_json();

}  // namespace camplace::scenes::detail
