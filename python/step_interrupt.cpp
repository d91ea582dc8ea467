#include "python/step_interrupt.h"

#include <atomic>
#include <csignal>
#include <memory>
#include <mutex>

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

void StepInterruptibly(PySimulation& self, std::int64_t n,
                       const std::function<void()>& after_step) {
  while (n > 0) {
    bool interrupted = false;
    {
      pybind11::gil_scoped_release release;
      const std::lock_guard<std::mutex> lock(self.mutex);
      CancelFlag flag;
      self.sim.StopOn(&flag);
      // (the flag dies with this scope, whatever leaves it)
      const std::unique_ptr<Simulation, void (*)(Simulation*)> unhook(
          &self.sim, [](Simulation* sim) { sim->StopOn(nullptr); });
      const StepInterrupt guard(flag);
      try {
        for (; n > 0; --n) {
          self.sim.Step(1);
          after_step();
        }
      } catch (const Cancelled&) {
        // only the guard raises the flag
      }
      interrupted = guard.interrupted();
    }
    // the lock is let go first: the bindings' getters take it while holding the GIL
    if (!interrupted) return;
    HandOverInterrupt();
  }
}

}  // namespace ecpsim::python
