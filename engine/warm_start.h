#pragma once
// A contact's warm start for the next step: the unknowns of the model that solved the contact
// last, of a type that model defines (models/hull_warm_start.h, models/multipatch_warm_start.h).
// The state carries it without knowing what it holds.

#include <memory>
#include <typeinfo>
#include <utility>

namespace ecpsim::engine {

/// Empty (no warm start: a model switch, a contact apart, the planar and point models, which
/// start from the contact's own fields) or one model's value. Copying a warm start over one of
/// the same type copies into its storage (a contact copied over the last step's copy reuses its
/// buffers).
class WarmStart {
 public:
  WarmStart() = default;
  WarmStart(const WarmStart& other) : held_(other.held_ ? other.held_->Clone() : nullptr) {}
  WarmStart(WarmStart&&) noexcept = default;
  WarmStart& operator=(const WarmStart& other) {
    if (!other.held_) {
      held_.reset();
    } else if (held_ && held_->Type() == other.held_->Type()) {
      held_->AssignFrom(*other.held_);
    } else {
      held_ = other.held_->Clone();
    }
    return *this;
  }
  WarmStart& operator=(WarmStart&&) noexcept = default;

  bool empty() const { return !held_; }
  void Reset() { held_.reset(); }

  /// The value if it is a T, else null.
  template <typename T>
  const T* Get() const {
    return held_ && held_->Type() == typeid(T) ? &static_cast<const Held<T>&>(*held_).value
                                               : nullptr;
  }
  template <typename T>
  T* Get() {
    return held_ && held_->Type() == typeid(T) ? &static_cast<Held<T>&>(*held_).value : nullptr;
  }
  /// The value as a T: the one held if it is a T (its storage kept), else a new T.
  template <typename T>
  T& Emplace() {
    if (T* value = Get<T>()) return *value;
    held_ = std::make_unique<Held<T>>();
    return static_cast<Held<T>&>(*held_).value;
  }
  /// Holds `value` (moved in).
  template <typename T>
  void Set(T value) {
    Emplace<T>() = std::move(value);
  }

 private:
  struct Holder {
    virtual ~Holder() = default;
    virtual const std::type_info& Type() const = 0;
    virtual std::unique_ptr<Holder> Clone() const = 0;
    virtual void AssignFrom(const Holder& other) = 0;  // other of the same Type()
  };
  template <typename T>
  struct Held final : Holder {
    T value;
    const std::type_info& Type() const override { return typeid(T); }
    std::unique_ptr<Holder> Clone() const override { return std::make_unique<Held>(*this); }
    void AssignFrom(const Holder& other) override { value = static_cast<const Held&>(other).value; }
  };
  std::unique_ptr<Holder> held_;
};

}  // namespace ecpsim::engine
