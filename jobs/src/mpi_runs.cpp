// Child processes spread over MPI ranks (`mpirun camplace study`): the messages and the retries.
#include "camplace/jobs/mpi_runs.hpp"

#include <csignal>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <utility>

#include "camplace/jobs/interrupt.hpp"

namespace camplace::jobs::mpi {

namespace {

/// A run under way on this rank.
class RunTask : public Task {
 public:
  RunTask(const std::string& program, const std::string& payload) {
    try {
      process_ = std::make_unique<ChildProcess>(program, decode_launch(payload));
    } catch (const std::exception& e) {
      ProcessOutcome failed;
      failed.failure = std::string("could not be started: ") + e.what();
      result_ = encode_outcome(failed, InterruptSignals::flag().load());
    }
  }
  std::optional<std::string> poll() override {
    if (result_) return result_;
    const std::optional<ProcessOutcome> ended = process_->poll();
    if (!ended) return std::nullopt;
    return encode_outcome(*ended, InterruptSignals::flag().load());
  }

 private:
  std::unique_ptr<ChildProcess> process_;
  std::optional<std::string> result_;
};

/// A run whose process died of a signal its rank did not get (killed) is given to another rank
/// this often before it counts as failed.
constexpr int kAttempts = 3;

}  // namespace

std::string encode_launch(const ProcessLaunch& launch) {
  std::string text = launch.output_file;
  for (const std::string& arg : launch.args) text += '\0' + arg;
  return text;
}

ProcessLaunch decode_launch(const std::string& text) {
  ProcessLaunch launch;
  std::size_t start = 0;
  for (bool first = true;; first = false) {
    const std::size_t end = text.find('\0', start);
    std::string word = text.substr(start, end == std::string::npos ? end : end - start);
    if (first) {
      launch.output_file = std::move(word);
    } else {
      launch.args.push_back(std::move(word));
    }
    if (end == std::string::npos) return launch;
    start = end + 1;
  }
}

std::string encode_outcome(const ProcessOutcome& outcome, bool rank_signalled) {
  return std::string(rank_signalled ? "1" : "0") + (outcome.interrupted ? "1" : "0") +
         outcome.failure;
}

std::vector<ProcessOutcome> run_on_ranks(const Session& session, const std::string& program,
                                         const std::vector<RankRun>& runs,
                                         const std::string& name) {
  std::vector<std::string> payloads;
  for (const RankRun& run : runs) payloads.push_back(encode_launch(run.launch));
  std::vector<ProcessOutcome> outcomes(runs.size());
  std::vector<int> attempts(runs.size(), 0);
  int handed_out = 0;
  Handlers handlers;
  handlers.start = [program](const std::string& payload) {
    return std::make_unique<RunTask>(program, payload);
  };
  handlers.on_assign = [&](std::size_t item, int rank) {
    if (attempts[item] > 0) {
      std::fprintf(stderr, "%s: %s on rank %d (again)\n", name.c_str(), runs[item].label.c_str(),
                   rank);
      return;
    }
    std::fprintf(stderr, "%s: %s on rank %d (%d of %zu to run)\n", name.c_str(),
                 runs[item].label.c_str(), rank, ++handed_out, runs.size());
  };
  handlers.judge = [&](std::size_t item, int rank, const std::string& result) {
    ProcessOutcome& outcome = outcomes[item];
    const bool rank_signalled = result.size() >= 2 && result[0] == '1';
    outcome.interrupted = result.size() >= 2 && result[1] == '1';
    outcome.failure = result.size() >= 2 ? result.substr(2) : "a malformed MPI result";
    if (rank_signalled || InterruptSignals::flag().load()) {
      // The job is being stopped (mpirun signals its ranks one after another): rank 0 stops
      // its own run now too, as if the signal had reached it, and reports what is finished.
      if (!InterruptSignals::flag().load()) std::raise(SIGTERM);
      outcome.interrupted = true;
      return Verdict::stop;
    }
    const bool killed = outcome.interrupted || outcome.failure.rfind("killed by signal", 0) == 0;
    if (killed) {
      // The run's process died of a signal its rank did not get: redo it elsewhere, without
      // the interrupted result it may have written.
      std::error_code ec;
      std::filesystem::remove(runs[item].run_file, ec);
      const std::string how = outcome.failure.empty() ? "was stopped by a signal" : outcome.failure;
      if (++attempts[item] < kAttempts) {
        std::fprintf(stderr, "%s: %s on rank %d %s; handing it out again\n", name.c_str(),
                     runs[item].label.c_str(), rank, how.c_str());
        return Verdict::retry;
      }
      outcome.interrupted = false;
      outcome.failure = how + ", " + std::to_string(kAttempts) + " times";
      return Verdict::stop;
    }
    return outcome.failure.empty() ? Verdict::done : Verdict::stop;
  };
  handlers.interrupt = &InterruptSignals::flag();
  const std::vector<std::optional<std::string>> results = distribute(session, payloads, handlers);
  for (std::size_t i = 0; i < runs.size(); ++i) {
    // Not started (an interrupt, or an error elsewhere): as after Ctrl-C, run on resume.
    if (!results[i]) outcomes[i] = {true, ""};
  }
  return outcomes;
}

void serve_runs(const Session& session, const std::string& program) {
  Handlers handlers;
  handlers.start = [program](const std::string& payload) {
    return std::make_unique<RunTask>(program, payload);
  };
  serve(session, handlers);
}

}  // namespace camplace::jobs::mpi
