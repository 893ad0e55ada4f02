#include "camplace/core/files.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "camplace/core/error.hpp"

namespace camplace::core {
namespace {

/// Writes all of `text` to `fd`; false with errno set when a write fails.
bool write_all(int fd, const std::string& text) {
  const char* data = text.data();
  std::size_t left = text.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  return true;
}

}  // namespace

void write_file_atomically(const std::string& path, const std::string& text) {
  namespace fs = std::filesystem;
  if (path.empty()) throw WriteError("cannot write a file with an empty name");
  const fs::path target(path);
  std::error_code ec;
  if (fs::is_directory(target, ec)) throw WriteError(path + ": is a directory, not a file");
  if (target.has_parent_path()) {
    fs::create_directories(target.parent_path(), ec);
    if (ec) {
      throw WriteError(path + ": cannot create its folder " + target.parent_path().string() + ": " +
                       ec.message());
    }
  }
  // Unique per process, so concurrent writers of different results never share a temp file.
  // On every failure it is removed again: no half-written file is left behind.
  const std::string tmp = path + kTempSuffix + std::to_string(::getpid());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) throw WriteError(path + ": cannot write: " + std::strerror(errno));
  const auto fail = [&](int error, const char* what) {
    ::unlink(tmp.c_str());
    throw WriteError(path + ": " + what + ": " + std::strerror(error));
  };
  if (!write_all(fd, text)) {
    const int error = errno;
    ::close(fd);
    fail(error, "cannot write");
  }
  if (::close(fd) != 0) fail(errno, "cannot write");
  if (::rename(tmp.c_str(), path.c_str()) != 0) fail(errno, "cannot write");
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
  probe_writable(dir, option);
  remove_stale_temp_files(dir);
}

int remove_stale_temp_files(const std::string& dir) {
  namespace fs = std::filesystem;
  const std::string suffix = kTempSuffix;
  const auto now = fs::file_time_type::clock::now();
  int removed = 0;
  std::error_code ec;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const std::size_t at = name.rfind(suffix);
    if (at == std::string::npos || at == 0) continue;
    const std::string digits = name.substr(at + suffix.size());
    if (digits.empty() || digits.size() > 9 ||
        digits.find_first_not_of("0123456789") != std::string::npos) {
      continue;
    }
    const long pid = std::stol(digits);
    // Its writer still runs here (or the pid is of a process we may not signal): kept.
    if (pid <= 0 || pid == ::getpid() || ::kill(static_cast<pid_t>(pid), 0) == 0 ||
        errno != ESRCH) {
      continue;
    }
    std::error_code time_error;
    const auto changed = fs::last_write_time(it->path(), time_error);
    if (time_error || now - changed < std::chrono::minutes(1)) continue;
    std::error_code remove_error;
    if (fs::remove(it->path(), remove_error)) ++removed;
  }
  return removed;
}

void probe_output_directory(const std::string& dir, const std::string& option) {
  namespace fs = std::filesystem;
  // The folder, or the nearest folder above it that exists (where it would be made).
  fs::path existing = fs::absolute(dir.empty() ? fs::path(".") : fs::path(dir));
  std::error_code ec;
  while (!fs::exists(existing, ec) && existing.has_parent_path() &&
         existing.parent_path() != existing) {
    existing = existing.parent_path();
  }
  if (fs::exists(existing, ec) && !fs::is_directory(existing, ec)) {
    throw InputError(
        "command line", option,
        "cannot create directory \"" + dir + "\": " + existing.string() + " is not a directory");
  }
  probe_writable(existing.string(), option);
}

void probe_writable(const std::string& dir, const std::string& option) {
  // A file created and removed again: a read-only or full folder is found before the work.
  const std::string probe =
      (std::filesystem::path(dir) /
       (".camplace-probe" + std::string(kTempSuffix) + std::to_string(::getpid())))
          .string();
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  int error = fd < 0 ? errno : 0;
  if (fd >= 0) {
    if (!write_all(fd, "camplace\n")) error = errno;
    if (::close(fd) != 0 && error == 0) error = errno;
    ::unlink(probe.c_str());
  }
  if (error != 0) {
    throw InputError("command line", option,
                     "cannot write into \"" + dir + "\": " + std::strerror(error));
  }
}

}  // namespace camplace::core
