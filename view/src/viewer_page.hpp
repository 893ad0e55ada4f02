#pragma once
// Private to view/: the viewer page (view/assets/index.html, compiled in by CMake).
#include <string>

namespace camplace::view::detail {

/// The text of index.html.
std::string viewer_page();

}  // namespace camplace::view::detail
