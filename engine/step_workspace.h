#pragma once
// The memory a time step works in, owned by the caller (as Box2D's, MuJoCo's and Jolt's steps
// leave it to theirs): kept from step to step, so that a step of sizes seen before allocates
// nothing of its own, and with no state hidden on the thread.

#include <memory>
#include <utility>
#include <vector>

namespace ecpsim::engine {

/// Each stage of the step (the driver's island lists, a model's scales, the solver's matrices)
/// keeps its storage here as a part of its own type, made on first use. Working memory only,
/// never state: a step's result does not depend on what earlier steps left here, so a copy starts
/// empty. One step at a time uses a workspace; threads stepping at once need one each.
class StepWorkspace {
 public:
  StepWorkspace() = default;
  StepWorkspace(const StepWorkspace&) {}
  StepWorkspace& operator=(const StepWorkspace&) {
    parts_.clear();
    return *this;
  }
  StepWorkspace(StepWorkspace&&) noexcept = default;
  StepWorkspace& operator=(StepWorkspace&&) noexcept = default;

  /// The part of type T, default-constructed on first use.
  template <typename T>
  T& Part() {
    // (a type's key is the address of its own variable: comparing type_infos compares their
    // names with strcmp, a step's largest cost of looking its parts up)
    const void* const key = &kKey<T>;
    for (Slot& slot : parts_) {
      if (slot.key == key) return *static_cast<T*>(slot.part.get());
    }
    parts_.push_back({key, Owned(new T(), [](void* part) { delete static_cast<T*>(part); })});
    return *static_cast<T*>(parts_.back().part.get());
  }

 private:
  template <typename T>
  static inline const char kKey = 0;
  using Owned = std::unique_ptr<void, void (*)(void*)>;
  struct Slot {
    const void* key;
    Owned part;
  };
  std::vector<Slot> parts_;
};

}  // namespace ecpsim::engine
