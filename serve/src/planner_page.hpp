#pragma once
// Private to serve/: the planner page (serve/assets/planner.html, compiled in by CMake).
#include <string>

namespace camplace::serve::detail {

/// The text of the planner page.
std::string planner_page();

}  // namespace camplace::serve::detail
