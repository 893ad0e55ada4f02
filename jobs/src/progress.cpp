#include "camplace/jobs/progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace camplace::jobs {

std::string duration_text(double seconds) {
  char text[32];
  if (seconds < 60) {
    std::snprintf(text, sizeof text, "%.0fs", seconds);
  } else if (seconds < 3600) {
    std::snprintf(text, sizeof text, "%dm%02ds", int(seconds) / 60, int(seconds) % 60);
  } else {
    std::snprintf(text, sizeof text, "%dh%02dm", int(seconds) / 3600, int(seconds) / 60 % 60);
  }
  return text;
}

ProgressLine::ProgressLine(std::string name, bool wanted)
    : name_(std::move(name)), start_(Clock::now()), last_(start_), what_start_(start_) {
  tty_ = ::isatty(STDERR_FILENO) == 1;
  enabled_ = tty_ || wanted;
  if (enabled_) ticker_ = std::thread([this] { repeat(); });
}

ProgressLine::~ProgressLine() { finish(); }

std::string ProgressLine::text(Clock::time_point now) const {
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (total_ < 0) return what_ + ", " + duration_text(elapsed) + " elapsed";
  std::string line = what_ + " " + std::to_string(done_) + "/" + std::to_string(total_) + ", " +
                     duration_text(elapsed) + " elapsed";
  const long counted = done_ - what_done_;  // steps done since this stage's first update
  if (counted > 0 && done_ < total_) {
    const double spent = std::chrono::duration<double>(now - what_start_).count();
    line += ", ETA " + duration_text(spent / counted * static_cast<double>(total_ - done_));
  }
  return line;
}

void ProgressLine::update(const std::string& what, long done, long total) {
  if (!enabled_) return;
  const std::lock_guard<std::mutex> lock(mutex_);
  const Clock::time_point now = Clock::now();
  const bool changed = what != what_ || total_ < 0;
  if (changed) {
    what_ = what;
    what_start_ = now;
    what_done_ = done;
  }
  done_ = done;
  total_ = total;
  print(text(now), changed || done >= total);
}

void ProgressLine::stage(const std::string& what) {
  if (!enabled_) return;
  const std::lock_guard<std::mutex> lock(mutex_);
  what_ = what;
  what_start_ = Clock::now();
  what_done_ = done_ = 0;
  total_ = -1;
  print(text(what_start_), true);
}

void ProgressLine::print(const std::string& line, bool force) {
  const Clock::time_point now = Clock::now();
  if (!force && open_ && now - last_ < std::chrono::milliseconds(250)) return;
  last_ = now;
  open_ = true;
  std::fprintf(stderr, "%s%s: %s%s", tty_ ? "\r\033[K" : "", name_.c_str(), line.c_str(),
               tty_ ? "" : "\n");
  std::fflush(stderr);
}

void ProgressLine::repeat() {
  const auto every = tty_ ? std::chrono::seconds(1) : std::chrono::seconds(30);
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    wake_.wait_for(lock, std::chrono::milliseconds(200));
    if (stop_) break;
    const Clock::time_point now = Clock::now();
    if (open_ && now - last_ >= every) print(text(now), true);
  }
}

void ProgressLine::finish() {
  if (!enabled_) return;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (stop_) return;
    stop_ = true;
    if (tty_ && open_) std::fputs("\n", stderr);
    open_ = false;
  }
  wake_.notify_all();
  if (ticker_.joinable()) ticker_.join();
}

}  // namespace camplace::jobs
