#pragma once
// Ctrl-C during Simulation.step and record: Python runs its SIGINT handler only on the main thread,
// and only once that thread holds the GIL again, which a step gives up for its whole length. So
// while the main thread steps, SIGINT goes to a handler of the module's own, which raises the
// step's stop flag (the step then ends within a solver iteration, undone: engine::StopStepsOn), and
// the signal is handed back to Python's handler once the GIL is held again.

#include <cstdint>
#include <functional>

#include "common/cancel_flag.h"
#include "python/py_simulation.h"

namespace ecpsim::python {

/// While it lives on Python's main thread, SIGINT raises `flag` and is recorded instead of
/// reaching Python's handler. Elsewhere (another thread, or where SIGINT is ignored or has the
/// system's default action, as Python's signal.SIG_IGN and SIG_DFL set them) it does nothing.
/// The destructor puts Python's handler back. Made and destroyed without the GIL; one at a time.
class StepInterrupt {
 public:
  explicit StepInterrupt(CancelFlag& flag);
  ~StepInterrupt();
  StepInterrupt(const StepInterrupt&) = delete;
  StepInterrupt& operator=(const StepInterrupt&) = delete;

  /// Whether SIGINT arrived while this lived.
  bool interrupted() const;

 private:
  bool installed_ = false;
};

/// Records which thread is Python's main thread (`threading.main_thread()`); with the GIL, once,
/// at the module's import.
void RecordMainThread();

/// `n` steps of `self` with the GIL held, `after_step` after each (without the GIL, with the
/// simulation's lock), Ctrl-C stopping the step in progress: it is left undone and Python's SIGINT
/// handler runs, its exception (KeyboardInterrupt by default) thrown from here; where the program's
/// handler raises nothing, that step is taken again and the rest after it.
void StepInterruptibly(
    PySimulation& self, std::int64_t n, const std::function<void()>& after_step = [] {});

/// Hands a SIGINT that a StepInterrupt caught to Python's handler (with the GIL): throws
/// pybind11::error_already_set with what it raises (KeyboardInterrupt by default); returns where
/// the handler the program set raises nothing.
void HandOverInterrupt();

}  // namespace ecpsim::python
