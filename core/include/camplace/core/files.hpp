#pragma once
/// Result files: written to a temporary file beside the target, then renamed, so a crash or
/// Ctrl-C never leaves half a file.
#include <string>

namespace camplace::core {

/// Writes `text` to `path` atomically (creating missing parent directories). Throws
/// std::runtime_error naming the path when it cannot be written.
void write_file_atomically(const std::string& path, const std::string& text);

}  // namespace camplace::core
