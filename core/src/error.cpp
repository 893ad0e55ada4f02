#include "camplace/core/error.hpp"

#include <cstdio>
#include <cstdlib>
#include <string>

namespace camplace::core {

namespace {
/// `text` with its control characters escaped as in JSON (\n, \t, \u0000), so that a message
/// stays one whole line whatever the keys, names and paths in it hold: a NUL would end it early,
/// a line break would start a line that looks like another error.
std::string escape_controls(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte != 0x7f) {
      out += c;
      continue;
    }
    switch (c) {
      case '\b':
        out += "\\b";
        break;
      case '\f':
        out += "\\f";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default: {
        char code[8];
        std::snprintf(code, sizeof code, "\\u%04x", byte);
        out += code;
      }
    }
  }
  return out;
}

std::string compose(const std::string& file, const std::string& entry, const std::string& reason) {
  std::string message = file;
  if (!entry.empty()) message += ": " + entry;
  return message + ": " + reason;
}
}  // namespace

InputError::InputError(const std::string& file, const std::string& entry, const std::string& reason)
    : std::runtime_error(
          compose(escape_controls(file), escape_controls(entry), escape_controls(reason))),
      file_(escape_controls(file)),
      entry_(escape_controls(entry)),
      reason_(escape_controls(reason)) {}

void assertion_failed(const char* expr, const char* file, int line) {
  std::fprintf(stderr, "camplace: internal check failed: %s (%s:%d)\n", expr, file, line);
  std::abort();
}

}  // namespace camplace::core
