#pragma once
/// Progress of long commands on stderr (issue 16): "NAME: WHAT done/total UNIT, 12s elapsed,
/// ETA 40s". On a terminal one line updated in place, otherwise (with --progress) one line per
/// update; at most four updates a second, plus every stage change and the last step.
#include <chrono>
#include <string>

namespace camplace::app {

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
  /// A stage without a count ("setting up the voxel pipeline at 256x256x64").
  void stage(const std::string& what);
  /// Ends the line on a terminal (the next output starts on its own line).
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  void print(const std::string& text, bool force);

  std::string name_;
  bool enabled_ = false, tty_ = false, open_ = false;
  Clock::time_point start_, last_, what_start_;
  std::string what_;
  long what_done_ = 0;
};

}  // namespace camplace::app
