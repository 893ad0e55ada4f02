#include "camplace/core/error.hpp"

#include <cstdio>
#include <cstdlib>

namespace camplace::core {

namespace {
std::string compose(const std::string& file, const std::string& entry, const std::string& reason) {
  std::string message = file;
  if (!entry.empty()) message += ": " + entry;
  return message + ": " + reason;
}
}  // namespace

InputError::InputError(const std::string& file, const std::string& entry, const std::string& reason)
    : std::runtime_error(compose(file, entry, reason)),
      file_(file),
      entry_(entry),
      reason_(reason) {}

void assertion_failed(const char* expr, const char* file, int line) {
  std::fprintf(stderr, "camplace: internal check failed: %s (%s:%d)\n", expr, file, line);
  std::abort();
}

}  // namespace camplace::core
