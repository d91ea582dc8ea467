#include "app/interrupt.h"

#include <signal.h>

#include <atomic>

#include <fmt/format.h>

#include "common/errors.h"

namespace ecpsim::app {
namespace {

// written by the handler, read by the run loop: a lock-free atomic is async-signal-safe
std::atomic<int> received_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);
CancelFlag interrupt_flag;  // (lock-free too)

bool guard_alive = false;
struct sigaction previous_int, previous_term;

void RecordSignal(int signal) {
  int none = 0;
  received_signal.compare_exchange_strong(none, signal);  // the first signal is the one kept
  interrupt_flag.Raise();
}

// installs RecordSignal for `signal` unless it is ignored; keeps the old action in `previous`
void Install(int signal, struct sigaction& previous) {
  sigaction(signal, nullptr, &previous);
  if (previous.sa_handler == SIG_IGN) return;
  struct sigaction action = {};
  action.sa_handler = RecordSignal;
  sigemptyset(&action.sa_mask);
  // interrupted system calls (a write to ffmpeg, a frame's fwrite) resume instead of failing
  action.sa_flags = SA_RESTART;
  sigaction(signal, &action, nullptr);
}

}  // namespace

InterruptGuard::InterruptGuard() {
  ECPSIM_DEMAND(!guard_alive);
  guard_alive = true;
  received_signal = 0;
  interrupt_flag.Clear();
  Install(SIGINT, previous_int);
  Install(SIGTERM, previous_term);
}

InterruptGuard::~InterruptGuard() {
  sigaction(SIGINT, &previous_int, nullptr);
  sigaction(SIGTERM, &previous_term, nullptr);
  guard_alive = false;
}

int InterruptSignal() { return received_signal.load(); }

const CancelFlag& InterruptFlag() { return interrupt_flag; }

std::string SignalName(int signal) {
  if (signal == SIGINT) return "SIGINT";
  if (signal == SIGTERM) return "SIGTERM";
  return fmt::format("signal {}", signal);
}

}  // namespace ecpsim::app
