#pragma once
/// Progress of long commands on stderr: "NAME: WHAT done/total, 12s elapsed, ETA
/// 40s". On a terminal one line updated in place, otherwise (with --progress) one line per
/// update; at most four updates a second, plus every stage change and the last step. While a
/// step takes long (an exact evaluation, an evaluator's set-up) the line is repeated with the
/// time elapsed: every second on a terminal, every 30 seconds otherwise.
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace camplace::jobs {

/// "42s", "3m05s", "2h10m".
std::string duration_text(double seconds);

class ProgressLine {
 public:
  /// `name`: the command ("evaluate"); `wanted`: --progress. Prints when stderr is a terminal
  /// or `wanted`.
  ProgressLine(std::string name, bool wanted);
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  bool enabled() const { return enabled_; }
  /// `done` of `total` steps of `what` ("exact evaluations"); the estimate assumes the
  /// remaining steps take as long as the done ones took on average, counted from the first
  /// update of this `what`.
  void update(const std::string& what, long done, long total);
  /// A stage without a count ("voxel set-up 256x256x64").
  void stage(const std::string& what);
  /// Ends the line on a terminal (the next output starts on its own line) and the repeats.
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  /// The line for the current state (mutex_ held).
  std::string text(Clock::time_point now) const;
  void print(const std::string& text, bool force);  // mutex_ held
  void repeat();                                    // the ticker thread

  std::string name_;
  bool enabled_ = false, tty_ = false, open_ = false;
  Clock::time_point start_, last_, what_start_;
  std::string what_;
  long done_ = 0, total_ = -1;  ///< total_ < 0: a stage without a count
  long what_done_ = 0;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread ticker_;
};

}  // namespace camplace::jobs
