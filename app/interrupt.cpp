#include "interrupt.hpp"

#include <signal.h>

#include <csignal>

namespace camplace::app {
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

}  // namespace camplace::app
