// Resuming into a folder: the settings a run file records, how they differ from this job's, and
// the check that refuses a folder whose runs were made with other settings.
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
namespace {

std::string conflicts_text(const std::vector<SettingsConflict>& conflicts) {
  // Each distinct change once (a study of 1,100 runs with another budget is one line), with the
  // first run file showing it and how many more do; changes shared by the same runs together.
  struct Change {
    std::string text, first_run;
    int runs = 0;
  };
  std::vector<Change> changes;
  for (const SettingsConflict& c : conflicts) {
    for (const std::string& text : c.changes) {
      auto found = std::find_if(changes.begin(), changes.end(),
                                [&](const Change& seen) { return seen.text == text; });
      if (found == changes.end()) {
        changes.push_back({text, c.run_file, 1});
      } else {
        ++found->runs;
      }
    }
  }
  struct Runs {
    std::string first_run;
    int runs = 0;
    std::vector<std::string> changes;
  };
  std::vector<Runs> by_runs;
  for (const Change& change : changes) {
    auto found = std::find_if(by_runs.begin(), by_runs.end(), [&](const Runs& r) {
      return r.first_run == change.first_run && r.runs == change.runs;
    });
    if (found == by_runs.end()) {
      by_runs.push_back({change.first_run, change.runs, {change.text}});
    } else {
      found->changes.push_back(change.text);
    }
  }
  constexpr std::size_t kShown = 20;
  std::string text = "holds runs made with other settings than this command:";
  std::size_t shown = 0;
  for (const Runs& r : by_runs) {
    if (shown >= kShown) break;
    text += "\n  " + r.first_run;
    const int more = r.runs - 1;
    if (more > 0)
      text += " (and " + std::to_string(more) + (more == 1 ? " more run)" : " more runs)");
    text += ":";
    if (r.changes.size() == 1) {
      text += " " + r.changes.front();
      ++shown;
      continue;
    }
    for (const std::string& change : r.changes) {
      if (shown == kShown) break;
      text += "\n    " + change;
      ++shown;
    }
  }
  if (changes.size() > shown) {
    text += "\n  ... and " + std::to_string(changes.size() - shown) + " more differences";
  }
  return text;
}

}  // namespace

RunSettings recorded_settings(const RunFile& file) {
  RunSettings s;
  s.scene_file = file.context.scene_file;
  if (file.context.provenance) s.scene = file.context.provenance->scene;
  s.mode = file.context.mode;
  s.resolution = file.context.resolution;
  s.refine = file.context.refine;
  s.algorithm = file.run.algorithm;
  s.objective = file.run.objective;
  s.start = file.context.start;
  s.time_limit = file.context.time_limit;
  s.max_evaluations = file.context.max_evaluations;
  s.tolerance = file.run.tolerance;
  s.population = file.run.population;
  s.seed = file.run.seed;
  s.threads = file.run.threads;
  s.format = file.format_version;
  return s;
}

std::vector<std::string> settings_changes(const RunSettings& recorded, const RunSettings& now) {
  std::vector<std::string> out;
  auto compare = [&out](const char* name, const std::string& before, const std::string& after) {
    if (before != after) out.push_back(std::string(name) + ": " + before + " → " + after);
  };
  auto resolution = [](const std::array<int, 3>& n) {
    return std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" + std::to_string(n[2]);
  };
  if (recorded.scene && now.scene) {
    for (std::string& line : core::scene_changes(*recorded.scene, *now.scene, now.scene_file)) {
      out.push_back(std::move(line));
    }
  }
  if (now.ceiling_pitch && recorded.format < 4) {
    out.push_back(
        "cameras.domain \"ceiling\": now pitch −90°…0° (looking down or level); this run "
        "file (format " +
        std::to_string(recorded.format) +
        ", a camplace from before the ceiling preset looked only down) was made when ceiling "
        "cameras could look up");
  }
  compare("mode", recorded.mode, now.mode);
  if (recorded.resolution && now.resolution) {
    compare("resolution", resolution(*recorded.resolution), resolution(*now.resolution));
  }
  compare("refine", std::to_string(recorded.refine), std::to_string(now.refine));
  compare("algorithm", recorded.algorithm, now.algorithm);
  compare("objective", recorded.objective, now.objective);
  compare("start", recorded.start, now.start);
  // Exact comparisons: both sides hold what the run file's JSON round trip keeps exactly.
  if (recorded.time_limit != now.time_limit) {
    out.push_back("time_limit_s: " + core::format_number(recorded.time_limit) + " → " +
                  core::format_number(now.time_limit));
  }
  compare("max_evaluations", std::to_string(recorded.max_evaluations),
          std::to_string(now.max_evaluations));
  if (recorded.tolerance && now.tolerance && *recorded.tolerance != *now.tolerance) {
    out.push_back("tolerance: " + core::format_number(*recorded.tolerance) + " → " +
                  core::format_number(*now.tolerance));
  }
  if (recorded.population && now.population) {
    compare("population", std::to_string(*recorded.population), std::to_string(*now.population));
  }
  if (recorded.seed && now.seed) {
    compare("seed", std::to_string(*recorded.seed), std::to_string(*now.seed));
  }
  if (recorded.threads && now.threads) {
    compare("threads", std::to_string(*recorded.threads), std::to_string(*now.threads));
  }
  return out;
}

SettingsChanged::SettingsChanged(const std::string& dir,
                                 const std::vector<SettingsConflict>& conflicts)
    : core::InputError(dir, "", conflicts_text(conflicts)) {}

void check_resume(const std::string& dir, const RunSettings& now) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  std::error_code ec;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    if (it->is_regular_file() && run_file_seed(it->path().filename().string())) {
      files.push_back(it->path());
    }
  }
  std::sort(files.begin(), files.end());
  std::vector<SettingsConflict> conflicts;
  for (const fs::path& file : files) {
    RunSettings recorded = recorded_settings(read_run_file(file.string()));
    recorded.seed.reset();  // a run of any seed may join the folder
    std::vector<std::string> changes = settings_changes(recorded, now);
    if (!changes.empty()) conflicts.push_back({file.filename().string(), std::move(changes)});
  }
  if (!conflicts.empty()) throw SettingsChanged(dir, conflicts);
}

}  // namespace camplace::optimize
