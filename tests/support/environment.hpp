#pragma once
// Test settings read from the environment: how many random cases a test checks and from which
// seed. The defaults keep the suite short; longer checks by hand set the variables.
#include <cerrno>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace camplace::testing {

/// The value of the environment variable `name`, a whole number ≥ 0, or `fallback` when it is
/// unset. Throws std::invalid_argument naming the variable when it holds anything else, so that a
/// mistyped value fails the test instead of quietly checking nothing.
inline unsigned long env_number(const char* name, unsigned long fallback) {
  const char* text = std::getenv(name);
  if (text == nullptr) return fallback;
  char* end = nullptr;
  errno = 0;
  const unsigned long value = std::strtoul(text, &end, 10);
  if (*text < '0' || *text > '9' || *end != '\0' || errno != 0)
    throw std::invalid_argument(std::string(name) + "=\"" + text +
                                "\": expected a whole number >= 0");
  return value;
}

}  // namespace camplace::testing
