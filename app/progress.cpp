#include "progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace camplace::app {

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
}

ProgressLine::~ProgressLine() { finish(); }

void ProgressLine::update(const std::string& what, long done, long total) {
  if (!enabled_) return;
  const Clock::time_point now = Clock::now();
  const bool changed = what != what_;
  if (changed) {
    what_ = what;
    what_start_ = now;
    what_done_ = done;
  }
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double spent = std::chrono::duration<double>(now - what_start_).count();
  const long counted = done - what_done_;  // steps done since this stage's first update
  std::string text = what + " " + std::to_string(done) + "/" + std::to_string(total) + ", " +
                     duration_text(elapsed) + " elapsed";
  if (counted > 0 && done < total) {
    text += ", ETA " + duration_text(spent / counted * static_cast<double>(total - done));
  }
  print(text, changed || done >= total);
}

void ProgressLine::stage(const std::string& what) {
  if (!enabled_) return;
  what_ = what;
  what_start_ = Clock::now();
  what_done_ = 0;
  const double elapsed = std::chrono::duration<double>(what_start_ - start_).count();
  print(what + ", " + duration_text(elapsed) + " elapsed", true);
}

void ProgressLine::print(const std::string& text, bool force) {
  const Clock::time_point now = Clock::now();
  if (!force && open_ && now - last_ < std::chrono::milliseconds(250)) return;
  last_ = now;
  open_ = true;
  std::fprintf(stderr, "%s%s: %s%s", tty_ ? "\r\033[K" : "", name_.c_str(), text.c_str(),
               tty_ ? "" : "\n");
  std::fflush(stderr);
}

void ProgressLine::finish() {
  if (enabled_ && tty_ && open_) std::fputs("\n", stderr);
  open_ = false;
}

}  // namespace camplace::app
