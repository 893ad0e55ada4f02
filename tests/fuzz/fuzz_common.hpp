#pragma once
// Shared by the libFuzzer targets: the loaders read files, so each input is written
// to a file in a per-process scratch folder; a loader may succeed or throw core::InputError,
// anything else (another exception, a crash, a sanitizer report, a hang) is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include "camplace/core/error.hpp"

namespace camplace::fuzz {

/// The scratch folder of this process (created on first use).
inline const std::filesystem::path& scratch() {
  static const std::filesystem::path dir = [] {
    const auto d = std::filesystem::temp_directory_path() /
                   ("camplace-fuzz-" + std::to_string(static_cast<long>(::getpid())));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

/// Writes `size` bytes to scratch()/name and returns the path.
inline std::string write_input(const std::string& name, const std::uint8_t* data,
                               std::size_t size) {
  const std::string path = (scratch() / name).string();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

/// Runs `load`; an InputError is the expected way to refuse an input, anything else aborts
/// (libFuzzer then keeps the input as a crash).
template <class F>
void expect_success_or_input_error(F&& load) {
  try {
    load();
  } catch (const core::InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz finding: unexpected exception: %s\n", e.what());
    std::abort();
  } catch (...) {
    std::fprintf(stderr, "fuzz finding: unexpected non-standard exception\n");
    std::abort();
  }
}

}  // namespace camplace::fuzz
