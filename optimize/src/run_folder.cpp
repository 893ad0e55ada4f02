// The run files of an output folder: discarding them (a fresh start) and gathering the runs it
// holds for the summary.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "camplace/core/camera.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/statistics.hpp"
#include "camplace/optimize/report.hpp"

namespace camplace::optimize {

int discard_runs(const std::string& dir) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  std::error_code ec;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (it->is_regular_file() &&
        (run_file_seed(name) || name == "summary.json" || name == "summary.csv")) {
      files.push_back(it->path());
    }
  }
  int runs = 0;
  for (const fs::path& file : files) {
    std::error_code removed;
    fs::remove(file, removed);
    if (removed) {
      throw std::runtime_error("cannot remove " + file.string() + ": " + removed.message());
    }
    runs += run_file_seed(file.filename().string()).has_value();
  }
  return runs;
}

std::vector<RunResult> runs_in_folder(const std::string& dir, const std::vector<RunResult>& mine) {
  namespace fs = std::filesystem;
  std::map<unsigned, RunResult> by_seed;
  std::error_code ec;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    const std::optional<unsigned> seed = run_file_seed(it->path().filename().string());
    if (!seed || !it->is_regular_file()) continue;
    try {
      by_seed[*seed] = read_run_file(it->path().string()).run;
    } catch (const std::exception&) {
      // Not a run file this version reads (check_resume reported it when the job started).
    }
  }
  for (const RunResult& run : mine) by_seed[run.seed] = run;
  std::vector<RunResult> out;
  for (auto& [seed, run] : by_seed) out.push_back(std::move(run));
  return out;
}

}  // namespace camplace::optimize
