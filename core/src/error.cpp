#include "camplace/core/error.hpp"

#include <cstdio>
#include <cstdlib>
#include <string>

namespace camplace::core {

namespace {
/// `text` with its control characters escaped as in JSON (\n, \t, \u0000), so that a message
/// stays one whole line whatever the keys, names and paths in it hold: a NUL would end it early,
/// a line break would start a line that looks like another error. With `indented_lines`, a line
/// break followed by a space stays: the indented continuation lines of a reason that lists
/// several items (they cannot pass for an `error:` line).
std::string escape_controls(const std::string& text, bool indented_lines = false) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    const auto byte = static_cast<unsigned char>(c);
    const bool indented_break =
        indented_lines && c == '\n' && i + 1 < text.size() && text[i + 1] == ' ';
    if ((byte >= 0x20 && byte != 0x7f) || indented_break) {
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
          compose(escape_controls(file), escape_controls(entry), escape_controls(reason, true))),
      file_(escape_controls(file)),
      entry_(escape_controls(entry)),
      reason_(escape_controls(reason, true)) {}

void assertion_failed(const char* expr, const char* file, int line) {
  std::fprintf(stderr, "camplace: internal check failed: %s (%s:%d)\n", expr, file, line);
  std::abort();
}

}  // namespace camplace::core
