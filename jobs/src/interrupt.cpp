#include "camplace/jobs/interrupt.hpp"

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <thread>

namespace camplace::jobs {
namespace {

std::atomic<bool> g_flag{false};
std::atomic<int> g_signal{0};
std::atomic<int> g_forward{0};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free,
              "signal handlers may only touch lock-free atomics");

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};
struct sigaction g_previous[3];

extern "C" void on_interrupt(int sig) {
  int none = 0;
  g_signal.compare_exchange_strong(none, sig);
  g_flag.store(true);
  const int pid = g_forward.load();
  if (pid > 0 && sig != SIGINT) ::kill(pid, sig);  // Ctrl-C reaches the run by itself
}

std::string& description() {
  static std::string text;
  return text;
}

struct GlobalDeadline {
  bool set = false;
  std::chrono::steady_clock::time_point at;
  std::string message;
};
GlobalDeadline& global_deadline() {
  static GlobalDeadline deadline;
  return deadline;
}

}  // namespace

InterruptSignals::InterruptSignals() {
  for (int i = 0; i < 3; ++i) {
    struct sigaction action {};
    action.sa_handler = on_interrupt;
    sigemptyset(&action.sa_mask);
    // The first Ctrl-C stops cleanly, a second one kills (the handler is reset).
    action.sa_flags = kSignals[i] == SIGINT ? SA_RESETHAND : 0;
    sigaction(kSignals[i], &action, &g_previous[i]);
  }
}

InterruptSignals::~InterruptSignals() {
  for (int i = 0; i < 3; ++i) sigaction(kSignals[i], &g_previous[i], nullptr);
  g_forward.store(0);
}

std::atomic<bool>& InterruptSignals::flag() { return g_flag; }
int InterruptSignals::received() { return g_signal.load(); }
void InterruptSignals::forward_to(int pid) { g_forward.store(pid); }

int interrupted_exit_status() {
  const int sig = InterruptSignals::received();
  return 128 + (sig > 0 ? sig : SIGINT);
}

// The watcher polls the flag every 50 ms rather than being woken by the handler: a signal
// handler may touch only lock-free atomics (above), and 50 ms keeps "within a second" with room.
struct StopAtOnce::State {
  Options options;
  std::mutex mutex;  // guards stop and options.kept
  std::condition_variable wake;
  bool stop = false;
  std::thread watcher;

  static State*& current() {
    static State* state = nullptr;
    return state;
  }

  [[noreturn]] void end(bool deadline) {
    std::unique_lock<std::mutex> lock(writing());  // never in the middle of a write
    // core::write_file_atomically's temporary files (core::kTempSuffix, core/files.hpp).
    const std::string suffix = ".camplace-tmp" + std::to_string(::getpid());
    for (const std::string& dir : options.temp_dirs) {
      std::error_code ec;
      for (auto it = std::filesystem::directory_iterator(dir, ec);
           !ec && it != std::filesystem::directory_iterator(); it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.size() > suffix.size() &&
            name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
          std::error_code removed;
          std::filesystem::remove(it->path(), removed);
        }
      }
    }
    std::string kept;
    {
      const std::lock_guard<std::mutex> guard(mutex);
      kept = options.kept;
    }
    // A signal reached the forwarded process (a study's run) already; the deadline did not.
    const int child = g_forward.load();
    if (deadline && child > 0) ::kill(child, SIGTERM);
    if (::isatty(STDERR_FILENO) == 1) std::fputs("\n", stderr);
    if (deadline) {
      std::fprintf(stderr, "error: %s; %s\n", options.deadline_message.c_str(), kept.c_str());
    } else {
      std::fprintf(stderr, "interrupted: %s\n", kept.c_str());
    }
    std::fflush(stderr);
    std::fflush(stdout);
    ::_exit(deadline ? 1 : interrupted_exit_status());
  }

  void watch() {
    using Clock = std::chrono::steady_clock;
    const Clock::time_point start = Clock::now();
    bool has_deadline = options.deadline_seconds > 0.0;
    Clock::time_point deadline =
        start + std::chrono::duration_cast<Clock::duration>(
                    std::chrono::duration<double>(has_deadline ? options.deadline_seconds : 0.0));
    const GlobalDeadline& global = global_deadline();
    if (global.set && (!has_deadline || global.at < deadline)) {
      has_deadline = true;
      deadline = global.at;
      const std::lock_guard<std::mutex> guard(mutex);
      options.deadline_message = global.message;
    }
    std::unique_lock<std::mutex> lock(mutex);
    while (!stop) {
      if (options.end_on_signal && g_flag.load()) {
        lock.unlock();
        end(false);
      }
      if (has_deadline && Clock::now() >= deadline) {
        lock.unlock();
        end(true);
      }
      wake.wait_for(lock, std::chrono::milliseconds(50));
    }
  }
};

StopAtOnce::StopAtOnce(Options options) : state_(new State{}) {
  state_->options = std::move(options);
  State::current() = state_;
  state_->watcher = std::thread([this] { state_->watch(); });
}

StopAtOnce::~StopAtOnce() {
  {
    const std::lock_guard<std::mutex> guard(state_->mutex);
    state_->stop = true;
  }
  state_->wake.notify_all();
  state_->watcher.join();
  State::current() = nullptr;
  delete state_;
}

void StopAtOnce::set_kept(const std::string& kept) {
  State* state = State::current();
  if (state == nullptr) return;
  const std::lock_guard<std::mutex> guard(state->mutex);
  state->options.kept = kept;
}

std::mutex& StopAtOnce::writing() {
  static std::mutex mutex;
  return mutex;
}

bool StopAtOnce::active() { return State::current() != nullptr; }

void set_deadline(double seconds, const std::string& message) {
  GlobalDeadline& deadline = global_deadline();
  deadline.set = seconds > 0.0;
  deadline.message = message;
  deadline.at = std::chrono::steady_clock::now() +
                std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                    std::chrono::duration<double>(seconds > 0.0 ? seconds : 0.0));
}

double seconds_left() {
  const GlobalDeadline& deadline = global_deadline();
  if (!deadline.set) return std::numeric_limits<double>::infinity();
  return std::chrono::duration<double>(deadline.at - std::chrono::steady_clock::now()).count();
}

const std::string& deadline_message() { return global_deadline().message; }

void set_work_description(const std::string& text) { description() = text; }
const std::string& work_description() { return description(); }

}  // namespace camplace::jobs
