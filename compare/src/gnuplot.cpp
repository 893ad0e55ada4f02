#include "gnuplot.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "camplace/core/files.hpp"

extern char** environ;

namespace camplace::compare::detail {

namespace {

/// Runs `gnuplot script` (found on PATH, no shell) with its stderr in `log`; true when it
/// exited with status 0.
bool run_gnuplot(const std::string& script, const std::string& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::string program = "gnuplot";
  // A relative name starting with '-' would be read as an option.
  std::string file = script.rfind('-', 0) == 0 ? "./" + script : script;
  std::vector<char*> argv = {program.data(), file.data(), nullptr};
  pid_t pid = 0;
  const int spawn_error =
      posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawn_error != 0) {
    throw std::runtime_error("cannot run gnuplot: " + std::string(std::strerror(spawn_error)) +
                             " (install the Debian package gnuplot-nox)");
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return false;
  }
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

}  // namespace

void gnuplot_png(const std::string& png, const std::string& script, int width, int height) {
  namespace fs = std::filesystem;
  fs::path gp = png;
  gp.replace_extension(".gp");
  const fs::path tmp_png = png + ".part";
  const std::string full = "set terminal pngcairo size " + std::to_string(width) + "," +
                           std::to_string(height) + " font 'DejaVu Sans,10'\n" + "set output " +
                           gnuplot_string(tmp_png.string()) + "\n" + script + "\nunset output\n";
  core::write_file_atomically(gp.string(), full);
  if (!run_gnuplot(gp.string(), png + ".log")) {
    throw std::runtime_error("gnuplot failed on " + gp.string() + " (see " + png + ".log)");
  }
  std::error_code ec;
  fs::remove(png + ".log", ec);
  fs::rename(tmp_png, png);
}

std::string gnuplot_string(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace camplace::compare::detail
