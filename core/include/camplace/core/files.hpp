#pragma once
/// Result files: written to a temporary file beside the target, then renamed, so a crash or
/// Ctrl-C never leaves half a file.
#include <string>

namespace camplace::core {

/// Writes `text` to `path` atomically (creating missing parent directories). Throws
/// std::runtime_error naming the path when it cannot be written.
void write_file_atomically(const std::string& path, const std::string& text);

/// Creates the output directory `dir` (and its parents) before any work is done; throws
/// InputError naming the command-line `option` when it cannot.
void create_output_directory(const std::string& dir, const std::string& option);

}  // namespace camplace::core
