#pragma once
// Private to serve/: the long work of the page on worker threads (optimise from here, check
// exactly), each with a list of events the page reads as server-sent events, and a cancel flag.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "camplace/serve/planner.hpp"

namespace camplace::serve::detail {

/// One long piece of work: its events so far (the last has "type": "done" when it ended) and
/// its cancel flag.
class Job {
 public:
  Job(int id, std::string kind) : id_(id), kind_(std::move(kind)) {}
  int id() const { return id_; }
  const std::string& kind() const { return kind_; }
  /// Raised by cancel(): the work stops at its next check.
  std::atomic<bool>& cancel_flag() { return cancel_; }
  void cancel() { cancel_ = true; }
  /// Appends an event (its "job" and "seq" members are filled in); "type": "done" ends the job.
  void emit(nlohmann::json event);
  /// The events from index `from` on, waiting up to `timeout` for one when there is none yet;
  /// `finished` says whether the job has ended.
  std::vector<nlohmann::json> events_from(std::size_t from, std::chrono::milliseconds timeout,
                                          bool& finished);
  bool finished() const;

 private:
  int id_;
  std::string kind_;
  std::atomic<bool> cancel_{false};
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<nlohmann::json> events_;
  bool finished_ = false;
};

/// The jobs of one server: at most one of each kind runs at a time.
class Jobs {
 public:
  explicit Jobs(Planner& planner) : planner_(planner) {}
  ~Jobs();
  /// Starts "optimise from here" with the request's settings ({"algorithm", "time_limit",
  /// "max_evaluations", "seed", "threads"}, all optional). Returns the job. Throws
  /// core::InputError for a bad setting or while an optimisation runs.
  std::shared_ptr<Job> start_optimise(const nlohmann::json& request);
  /// Starts "check exactly" of the current configuration. Throws core::InputError while one
  /// runs, or when this build has no exact pipeline.
  std::shared_ptr<Job> start_exact();
  /// The job `id`; throws core::InputError("request", "/job", ...) when there is none.
  std::shared_ptr<Job> get(int id) const;
  /// Cancels every job and waits for their threads.
  void stop_all();

 private:
  std::shared_ptr<Job> start(const std::string& kind, std::function<void(Job&)> work);

  Planner& planner_;
  mutable std::mutex mutex_;
  std::map<int, std::shared_ptr<Job>> jobs_;
  std::vector<std::thread> threads_;
  int next_id_ = 1;
};

}  // namespace camplace::serve::detail
