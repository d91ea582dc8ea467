#include "python/step_interrupt.h"

#include <atomic>
#include <csignal>

#include <pybind11/pybind11.h>

namespace ecpsim::python {
namespace {

unsigned long main_thread = 0;  // Python's main thread's ident (PyThread_get_thread_ident)
// the flag of the living StepInterrupt, and whether SIGINT arrived (both read by the handler)
std::atomic<CancelFlag*> current_flag{nullptr};
std::atomic<bool> arrived{false};
static_assert(std::atomic<CancelFlag*>::is_always_lock_free &&
              std::atomic<bool>::is_always_lock_free);
struct sigaction python_action;  // the handler put back by ~StepInterrupt

extern "C" void OnSigint(int) {
  arrived.store(true, std::memory_order_relaxed);
  if (CancelFlag* flag = current_flag.load(std::memory_order_relaxed)) flag->Raise();
}

}  // namespace

void RecordMainThread() {
  main_thread = pybind11::module_::import("threading")
                    .attr("main_thread")()
                    .attr("ident")
                    .cast<unsigned long>();
}

StepInterrupt::StepInterrupt(CancelFlag& flag) {
  if (PyThread_get_thread_ident() != main_thread) return;
  struct sigaction now {};
  if (sigaction(SIGINT, nullptr, &now) != 0) return;
  if (!(now.sa_flags & SA_SIGINFO) && (now.sa_handler == SIG_IGN || now.sa_handler == SIG_DFL))
    return;
  python_action = now;
  arrived.store(false, std::memory_order_relaxed);
  current_flag.store(&flag, std::memory_order_relaxed);
  struct sigaction ours {};
  ours.sa_handler = OnSigint;
  sigemptyset(&ours.sa_mask);
  installed_ = sigaction(SIGINT, &ours, nullptr) == 0;
}

StepInterrupt::~StepInterrupt() {
  if (!installed_) return;
  sigaction(SIGINT, &python_action, nullptr);
  current_flag.store(nullptr, std::memory_order_relaxed);
}

bool StepInterrupt::interrupted() const {
  return installed_ && arrived.load(std::memory_order_relaxed);
}

void HandOverInterrupt() {
  PyErr_SetInterrupt();
  if (PyErr_CheckSignals() != 0) throw pybind11::error_already_set();
}

}  // namespace ecpsim::python
