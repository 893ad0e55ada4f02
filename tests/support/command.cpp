#include "command.hpp"

#include <sys/wait.h>

#include <array>
#include <cstdio>

namespace camplace::testing {

CommandResult run_camplace(const std::string& binary, const std::string& args) {
  CommandResult r;
  const std::string cmd = binary + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  while (fgets(buf.data(), buf.size(), pipe)) r.output += buf.data();
  const int raw = pclose(pipe);
  r.exit_code = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return r;
}

}  // namespace camplace::testing
