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

/// A bad value of a named option of a library call (a solver name, a population, a folder of
/// runs). Libraries name the option as their options struct does ("algorithm", "runs"); the
/// command-line tool maps it to its flag ("--algorithm"), so no library names a flag.
class OptionError : public InputError {
 public:
  OptionError(const std::string& option, const std::string& reason)
      : InputError("option", option, reason) {}
  const std::string& option() const { return entry(); }
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
