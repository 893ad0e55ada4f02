#pragma once
// Private: the pagmo user-defined problem and the shared state of one run (counters, best,
// history, stop criteria). Not part of the public interface.
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <pagmo/problem.hpp>
#include <pagmo/types.hpp>
#include <string>
#include <utility>
#include <vector>

#include "camplace/optimize/encoding.hpp"
#include "camplace/optimize/objective.hpp"
#include "camplace/optimize/optimizer.hpp"

namespace camplace::optimize::detail {

/// Thrown through pagmo's evolve() to end a run at once; the run's state keeps the best.
struct StopRequested {};

/// `err` when it is finite; otherwise throws std::runtime_error. A NaN or infinite Err would
/// never become the run's best (nor reach a stop criterion), leaving the run without a result;
/// core::load_scene bounds the weights so that the voxel Err stays finite (core::kMaxErr), so
/// this is an internal error, or a bug in an objective of one's own.
double checked_err(double err);

/// State of one run shared by every copy of the problem pagmo makes.
class RunState {
 public:
  using Clock = std::chrono::steady_clock;

  RunState(const Objective& objective, const Encoding& encoding, const OptimizeOptions& options,
           double tolerance, double lower_bound);
  ~RunState();

  const Encoding& encoding() const { return encoding_; }
  const Objective& objective() const { return objective_; }
  tbb::task_arena& arena() const { return *arena_; }
  int threads() const { return threads_; }
  /// The value the solvers minimise for a score (OptimizeOptions::objective): tie_break_fitness()
  /// for "err+volume", Err + Score::touching_excess for "err+touching-volume", else Err itself.
  double fitness(const Score& score) const;

  /// Interrupt or time limit, checked without the lock (cheap; called per evaluation).
  std::optional<StopReason> external_stop() const;
  /// Evaluations still allowed by the budget (max of uint64 when there is none).
  std::uint64_t remaining_budget() const;
  /// Records one finished evaluation (in a deterministic order); returns true when the run
  /// must stop (tolerance or lower bound reached, or budget used up). The best is the least
  /// (Err, tie-breaker) in lexicographic order with ties broken, the least Err otherwise; on
  /// full ties the earlier evaluation stays. Stop criteria and history use the true Err.
  bool record(const pagmo::vector_double& x, const Score& score, const core::Timing& timing);
  /// Marks the run as stopped for `reason` unless a reason is already set.
  void stop(StopReason reason);

  double seconds() const;

  // Read after the run (no concurrent access then).
  std::optional<StopReason> stop_reason() const { return stop_reason_; }
  std::uint64_t evaluations() const { return evaluations_; }
  double best_err() const { return best_err_; }
  double best_tie_breaker() const { return best_tie_breaker_; }
  const pagmo::vector_double& best_x() const { return best_x_; }
  std::uint64_t best_index() const { return best_index_; }
  const std::vector<HistoryPoint>& history() const { return history_; }
  const core::Timing& timing_sum() const { return timing_sum_; }

 private:
  const Objective& objective_;
  const Encoding& encoding_;
  double tolerance_;
  double lower_bound_;  ///< stop when the best Err reaches it; 0 = never
  bool tie_break_;      ///< objective "err+volume"
  bool touching_;       ///< objective "err+touching-volume"
  std::uint64_t max_evaluations_;
  const std::atomic<bool>* interrupt_;
  std::function<void(const Progress&)> on_progress_;
  Clock::time_point start_;
  std::optional<Clock::time_point> deadline_;
  int threads_;
  std::unique_ptr<tbb::task_arena> arena_;

  mutable std::mutex mutex_;
  std::atomic<std::uint64_t> evaluations_{0};
  double best_err_ = std::numeric_limits<double>::infinity();
  double best_tie_breaker_ = 0.0;
  pagmo::vector_double best_x_;
  std::uint64_t best_index_ = 0;
  std::vector<HistoryPoint> history_;
  core::Timing timing_sum_;
  std::optional<StopReason> stop_reason_;
};

/// The pagmo UDP: minimise Err (with its tie-breaker, RunState::fitness) over the encoding's free
/// variables. fitness() serves the
/// sequential solvers; batch_fitness() (used through pagmo::member_bfe) evaluates a generation
/// on the run's threads and records the results in batch order, so that counts, best and
/// history do not depend on thread timing.
class CameraProblem {
 public:
  CameraProblem() = default;
  explicit CameraProblem(std::shared_ptr<RunState> state) : state_(std::move(state)) {}

  pagmo::vector_double fitness(const pagmo::vector_double& x) const;
  pagmo::vector_double batch_fitness(const pagmo::vector_double& dvs) const;
  std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const;
  std::string get_name() const { return "camplace camera placement (Err, SPEC §4)"; }
  pagmo::thread_safety get_thread_safety() const { return pagmo::thread_safety::basic; }

 private:
  std::shared_ptr<RunState> state_;
};

}  // namespace camplace::optimize::detail
