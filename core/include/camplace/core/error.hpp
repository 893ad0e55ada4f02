#pragma once
/// Errors and internal checks shared by every camplace module.
#include <stdexcept>
#include <string>

namespace camplace::core {

/// Bad user input (scene file, mesh, camera file, command-line value). The message names the
/// file, the entry (a JSON pointer where there is one) and the reason.
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, const std::string& entry, const std::string& reason);
  const std::string& file() const { return file_; }
  const std::string& entry() const { return entry_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string file_, entry_, reason_;
};

/// Reports a failed internal invariant with file and line, then aborts.
[[noreturn]] void assertion_failed(const char* expr, const char* file, int line);

}  // namespace camplace::core

#if defined(CAMPLACE_ENABLE_ASSERTS) || !defined(NDEBUG)
#define CAMPLACE_ASSERT(expr) \
  ((expr) ? void(0) : ::camplace::core::assertion_failed(#expr, __FILE__, __LINE__))
#else
#define CAMPLACE_ASSERT(expr) void(0)
#endif
