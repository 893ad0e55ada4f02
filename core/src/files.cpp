#include "camplace/core/files.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "camplace/core/error.hpp"

namespace camplace::core {

void write_file_atomically(const std::string& path, const std::string& text) {
  namespace fs = std::filesystem;
  if (path.empty()) throw std::runtime_error("cannot write a file with an empty name");
  const fs::path target(path);
  std::error_code ec;
  if (fs::is_directory(target, ec)) throw std::runtime_error(path + ": is a directory, not a file");
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  // Unique per process, so concurrent writers of different results never share a temp file.
  fs::path tmp = target;
  tmp += ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path + ": cannot open for writing");
    out << text;
    out.flush();
    if (!out) throw std::runtime_error(path + ": write failed");
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    const std::string reason = ec.message();
    fs::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot write: " + reason);
  }
}

void create_output_directory(const std::string& dir, const std::string& option) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!dir.empty()) fs::create_directories(dir, ec);
  if (dir.empty() || ec || !fs::is_directory(dir)) {
    throw InputError(
        "command line", option,
        "cannot create directory \"" + dir + "\"" + (ec ? ": " + ec.message() : std::string()));
  }
}

}  // namespace camplace::core
