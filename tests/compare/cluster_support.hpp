#pragma once
// What the shard and MPI tests of `camplace study` share: a tiny study, and the
// results of every run file of a study folder.
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

namespace camplace::testing {

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A study of two groups (3 and 4 cameras), 2 runs each of at most `max_evaluations`
/// evaluations on one thread: deterministic (a budget of evaluations, not of time).
inline std::string small_study_json(int max_evaluations) {
  return R"({"description": "cluster test", "algorithm": "gaco", "mode": "center",
    "runs_per_group": 2, "threads": 1, "first_seed": 1, "scene_seed": 1,
    "time_limit_s": 600, "max_evaluations": )" +
         std::to_string(max_evaluations) + R"(,
    "examinations": [{"name": "cameras", "family": "cameras", "params": [3, 4]}]})";
}

/// A run's result as the study's report uses it: Err (exact text of the double), evaluations,
/// stop reason and the best cameras.
struct RunResult {
  std::string err, cameras, stop_reason;
  long long evaluations = 0;
  bool operator==(const RunResult& o) const {
    return err == o.err && cameras == o.cameras && stop_reason == o.stop_reason &&
           evaluations == o.evaluations;
  }
};

inline std::ostream& operator<<(std::ostream& out, const RunResult& r) {
  return out << "err " << r.err << ", " << r.evaluations << " evaluations, " << r.stop_reason
             << ", cameras " << r.cameras;
}

/// Every run file below DIR/runs, by its path relative to DIR.
inline std::map<std::string, RunResult> run_results(const std::string& dir) {
  namespace fs = std::filesystem;
  std::map<std::string, RunResult> out;
  if (!fs::is_directory(dir + "/runs")) return out;
  for (const auto& e : fs::recursive_directory_iterator(dir + "/runs")) {
    const std::string name = e.path().filename().string();
    if (!e.is_regular_file() || name.rfind("run-", 0) != 0) continue;
    const nlohmann::json run = nlohmann::json::parse(read_text(e.path().string()));
    RunResult r;
    r.err = run.at("err").dump();
    r.cameras = run.at("cameras").dump();
    r.stop_reason = run.at("stop_reason").get<std::string>();
    r.evaluations = run.at("evaluations").get<long long>();
    out[fs::relative(e.path(), dir).generic_string()] = r;
  }
  return out;
}

}  // namespace camplace::testing
