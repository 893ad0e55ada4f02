#include "problem.hpp"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "camplace/core/err.hpp"
#include "camplace/core/error.hpp"

namespace camplace::optimize::detail {

RunState::RunState(const Objective& objective, const Encoding& encoding,
                   const OptimizeOptions& options, double tolerance, double lower_bound)
    : objective_(objective),
      encoding_(encoding),
      tolerance_(tolerance),
      lower_bound_(lower_bound),
      tie_break_(options.objective == "err+volume"),
      touching_(options.objective == "err+touching-volume"),
      max_evaluations_(options.max_evaluations),
      interrupt_(options.interrupt),
      on_progress_(options.on_progress),
      start_(Clock::now()) {
  if (options.time_limit > 0.0) {
    deadline_ = start_ + std::chrono::duration_cast<Clock::duration>(
                             std::chrono::duration<double>(options.time_limit));
  }
  threads_ = options.threads > 0
                 ? options.threads
                 : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  arena_ = std::make_unique<tbb::task_arena>(threads_);
}

RunState::~RunState() = default;

double RunState::seconds() const {
  return std::chrono::duration<double>(Clock::now() - start_).count();
}

std::optional<StopReason> RunState::external_stop() const {
  if (interrupt_ != nullptr && interrupt_->load(std::memory_order_relaxed)) {
    return StopReason::interrupted;
  }
  if (deadline_ && Clock::now() >= *deadline_) return StopReason::time_limit;
  return std::nullopt;
}

std::uint64_t RunState::remaining_budget() const {
  if (max_evaluations_ == 0) return std::numeric_limits<std::uint64_t>::max();
  const std::uint64_t done = evaluations_.load();
  return done >= max_evaluations_ ? 0 : max_evaluations_ - done;
}

void RunState::stop(StopReason reason) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!stop_reason_) stop_reason_ = reason;
}

double RunState::fitness(const Score& score) const {
  if (tie_break_) return tie_break_fitness(score.err, score.tie_breaker);
  if (touching_) return score.err + score.touching_excess;
  return score.err;
}

double checked_err(double err) {
  if (!std::isfinite(err)) {
    std::ostringstream value;
    value << err;
    throw std::runtime_error("internal error: the objective returned Err = " + value.str() +
                             ", not a finite number (Err must be finite to optimise)");
  }
  return err;
}

bool RunState::record(const pagmo::vector_double& x, const Score& score,
                      const core::Timing& timing) {
  const double err = checked_err(score.err);  // before anything is recorded: the caller's
                                              // exception ends the run
  Progress progress;
  bool must_stop = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::uint64_t index = ++evaluations_;
    timing_sum_.labelling_ms += timing.labelling_ms;
    timing_sum_.clustering_ms += timing.clustering_ms;
    timing_sum_.distance_ms += timing.distance_ms;
    timing_sum_.total_ms += timing.total_ms;
    const double now = seconds();
    // Strictly less: on ties the earlier evaluation stays the best (deterministic order).
    // With the tie-breaker the best is the least (Err, tie-breaker), compared exactly (not
    // through the fitness, which rounds Err), so the reported best Err never grows.
    const bool better_err = err < best_err_;
    if (better_err || (tie_break_ && err == best_err_ && score.tie_breaker < best_tie_breaker_)) {
      best_err_ = err;
      best_tie_breaker_ = score.tie_breaker;
      best_x_ = x;
      best_index_ = index;
      if (better_err) history_.push_back({index, now, err});
    }
    if (!stop_reason_) {
      if (best_err_ <= tolerance_) {
        stop_reason_ = StopReason::tolerance;
      } else if (lower_bound_ > 0.0 && best_err_ <= core::lower_bound_threshold(lower_bound_)) {
        // Err cannot fall below the bound (the relative slack absorbs summation rounding).
        stop_reason_ = StopReason::lower_bound;
      } else if (max_evaluations_ != 0 && index >= max_evaluations_) {
        stop_reason_ = StopReason::max_evaluations;
      }
    }
    must_stop = stop_reason_.has_value();
    progress = {index, best_err_, now};
    if (on_progress_) on_progress_(progress);
  }
  return must_stop;
}

pagmo::vector_double CameraProblem::fitness(const pagmo::vector_double& x) const {
  RunState& s = *state_;
  if (auto reason = s.external_stop()) {
    s.stop(*reason);
    throw StopRequested{};
  }
  core::Timing timing;
  const Score score = s.objective().score(s.encoding().decode(x), timing);
  if (s.record(x, score, timing)) throw StopRequested{};
  return {s.fitness(score)};
}

pagmo::vector_double CameraProblem::batch_fitness(const pagmo::vector_double& dvs) const {
  RunState& s = *state_;
  const std::size_t nx = s.encoding().dimension();
  CAMPLACE_ASSERT(nx > 0 && dvs.size() % nx == 0);
  const std::size_t n = dvs.size() / nx;
  if (auto reason = s.external_stop()) {
    s.stop(*reason);
    throw StopRequested{};
  }
  // The budget cuts the batch at a fixed index, so a budget-limited run is reproducible.
  const std::size_t count =
      static_cast<std::size_t>(std::min<std::uint64_t>(n, s.remaining_budget()));
  std::vector<Score> scores(count);
  std::vector<core::Timing> timings(count);
  std::vector<char> done(count, 0);
  s.arena().execute([&] {
    tbb::parallel_for(std::size_t{0}, count, [&](std::size_t i) {
      if (s.external_stop()) return;  // Ctrl-C or time limit: skip what has not started
      const pagmo::vector_double x(dvs.begin() + i * nx, dvs.begin() + (i + 1) * nx);
      scores[i] = s.objective().score(s.encoding().decode(x), timings[i]);
      done[i] = 1;
    });
  });
  bool must_stop = count < n;
  for (std::size_t i = 0; i < count; ++i) {
    if (!done[i]) continue;
    const pagmo::vector_double x(dvs.begin() + i * nx, dvs.begin() + (i + 1) * nx);
    must_stop = s.record(x, scores[i], timings[i]) || must_stop;
  }
  if (auto reason = s.external_stop()) s.stop(*reason);
  if (must_stop || s.stop_reason()) throw StopRequested{};
  pagmo::vector_double fitnesses(count);
  for (std::size_t i = 0; i < count; ++i) fitnesses[i] = s.fitness(scores[i]);
  return fitnesses;
}

std::pair<pagmo::vector_double, pagmo::vector_double> CameraProblem::get_bounds() const {
  if (!state_) return {{0.0}, {1.0}};
  return state_->encoding().bounds();
}

}  // namespace camplace::optimize::detail
