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

/// Runs `gnuplot script` (found on PATH, no shell) in the folder `dir` (script: a name in it)
/// with its stderr in `log`; true when it exited with status 0.
bool run_gnuplot(const std::string& dir, const std::string& script, const std::string& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (!dir.empty()) posix_spawn_file_actions_addchdir_np(&actions, dir.c_str());
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
  // The script is kept beside the plot with every path relative to that folder, so that
  // `gnuplot NAME.gp` in the report's folder draws NAME.png again.
  const fs::path dir = fs::path(png).parent_path();
  const std::string name = fs::path(png).filename().string();
  std::string local = script;
  if (!dir.empty()) {
    std::string prefix = gnuplot_string(dir.string() + "/");
    prefix.pop_back();  // "'DIR/" → file names quoted relative to DIR
    for (std::size_t at = local.find(prefix); at != std::string::npos;
         at = local.find(prefix, at + 1)) {
      local.replace(at, prefix.size(), "'");
    }
  }
  const std::string terminal = "set terminal pngcairo size " + std::to_string(width) + "," +
                               std::to_string(height) + " font 'DejaVu Sans,10'\n";
  fs::path gp = png;
  gp.replace_extension(".gp");
  core::write_file_atomically(gp.string(), terminal + "set output " + gnuplot_string(name) + "\n" +
                                               local + "\nunset output\n");
  // Drawn through a temporary script into NAME.png.part, renamed when gnuplot succeeded.
  const std::string run_script = gp.filename().string() + ".run";
  const fs::path run_path = dir / run_script;
  core::write_file_atomically(run_path.string(), terminal + "set output " +
                                                     gnuplot_string(name + ".part") + "\n" + local +
                                                     "\nunset output\n");
  const bool ok = run_gnuplot(dir.string(), run_script, png + ".log");
  std::error_code ec;
  fs::remove(run_path, ec);
  if (!ok) {
    throw std::runtime_error("gnuplot failed on " + gp.string() + " (see " + png + ".log)");
  }
  fs::remove(png + ".log", ec);
  fs::rename(png + ".part", png);
}

std::string gnuplot_string(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace camplace::compare::detail
