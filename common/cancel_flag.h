#pragma once
// A request to stop work in progress, raised from another thread or from a signal handler: a
// step that sees it stops within one solver iteration and leaves its state as it was.

#include <atomic>
#include <stdexcept>
#include <string>

namespace ecpsim {

/// Lock-free, so that a signal handler may raise it.
class CancelFlag {
 public:
  void Raise() { raised_.store(true, std::memory_order_relaxed); }
  void Clear() { raised_.store(false, std::memory_order_relaxed); }
  bool raised() const { return raised_.load(std::memory_order_relaxed); }

 private:
  static_assert(std::atomic<bool>::is_always_lock_free);
  std::atomic<bool> raised_{false};
};

/// Thrown by work that saw its CancelFlag raised; what it was doing is left undone.
class Cancelled : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Throws Cancelled("`what` stopped: cancelled") if `flag` is given and raised.
inline void ThrowIfCancelled(const CancelFlag* flag, const char* what) {
  if (flag != nullptr && flag->raised()) throw Cancelled(std::string(what) + " stopped: cancelled");
}

}  // namespace ecpsim
