#pragma once
// A contact's warm start for the next step: the unknowns of the model that solved the contact
// last, of a type that model defines (models/hull_warm_start.h, models/multipatch_warm_start.h).
// The state carries it without knowing what it holds.

#include <cstddef>
#include <new>
#include <typeinfo>
#include <utility>

namespace ecpsim::engine {

/// Empty (no warm start: a model switch, a contact apart, the planar and point models, which
/// start from the contact's own fields) or one model's value. The value lives inside the warm
/// start, not on the heap: contacts come and go every step in a scattered scene, and a heap box
/// per arrival costs more than the solve of a resting contact. Copying a warm start over one of
/// the same type copies into its storage (a contact copied over the last step's copy reuses its
/// buffers).
class WarmStart {
 public:
  /// Bytes a model's warm-start type may take (the hull model's is the largest, ~390).
  static constexpr std::size_t kCapacity = 448;

  WarmStart() = default;
  WarmStart(const WarmStart& other) : ops_(other.ops_) {
    if (ops_ != nullptr) ops_->copy_construct(other.storage_, storage_);
  }
  WarmStart(WarmStart&& other) noexcept : ops_(other.ops_) {
    if (ops_ != nullptr) ops_->move_construct(other.storage_, storage_);
  }
  WarmStart& operator=(const WarmStart& other) {
    if (this == &other) return *this;
    if (ops_ != nullptr && ops_ == other.ops_) {
      ops_->copy_assign(other.storage_, storage_);
    } else {
      Reset();
      if (other.ops_ != nullptr) other.ops_->copy_construct(other.storage_, storage_);
      ops_ = other.ops_;
    }
    return *this;
  }
  WarmStart& operator=(WarmStart&& other) noexcept {
    if (this == &other) return *this;
    if (ops_ != nullptr && ops_ == other.ops_) {
      ops_->move_assign(other.storage_, storage_);
    } else {
      Reset();
      if (other.ops_ != nullptr) other.ops_->move_construct(other.storage_, storage_);
      ops_ = other.ops_;
    }
    return *this;
  }
  ~WarmStart() { Reset(); }

  bool empty() const { return ops_ == nullptr; }
  void Reset() {
    if (ops_ != nullptr) ops_->destroy(storage_);
    ops_ = nullptr;
  }

  /// The value if it is a T, else null.
  template <typename T>
  const T* Get() const {
    return Holds<T>() ? std::launder(reinterpret_cast<const T*>(storage_)) : nullptr;
  }
  template <typename T>
  T* Get() {
    return Holds<T>() ? std::launder(reinterpret_cast<T*>(storage_)) : nullptr;
  }
  /// The value as a T: the one held if it is a T (its storage kept), else a new T.
  template <typename T>
  T& Emplace() {
    static_assert(sizeof(T) <= kCapacity && alignof(T) <= alignof(std::max_align_t),
                  "a warm-start type must fit WarmStart::kCapacity");
    if (T* value = Get<T>()) return *value;
    Reset();
    T* value = ::new (static_cast<void*>(storage_)) T();
    ops_ = &kOps<T>;
    return *value;
  }
  /// Holds `value` (moved in).
  template <typename T>
  void Set(T value) {
    Emplace<T>() = std::move(value);
  }

 private:
  // what the held type's special members are, without knowing the type here
  struct Ops {
    const std::type_info& type;
    void (*destroy)(void* value);
    void (*copy_construct)(const void* from, void* to);
    void (*move_construct)(void* from, void* to);
    void (*copy_assign)(const void* from, void* to);
    void (*move_assign)(void* from, void* to);
  };
  template <typename T>
  static constexpr Ops kOps = {
      typeid(T),
      [](void* value) { static_cast<T*>(value)->~T(); },
      [](const void* from, void* to) { ::new (to) T(*static_cast<const T*>(from)); },
      [](void* from, void* to) { ::new (to) T(std::move(*static_cast<T*>(from))); },
      [](const void* from, void* to) { *static_cast<T*>(to) = *static_cast<const T*>(from); },
      [](void* from, void* to) { *static_cast<T*>(to) = std::move(*static_cast<T*>(from)); },
  };

  // the same Ops object, or (across shared libraries) the same type
  template <typename T>
  bool Holds() const {
    return ops_ != nullptr && (ops_ == &kOps<T> || ops_->type == typeid(T));
  }

  alignas(std::max_align_t) unsigned char storage_[kCapacity];
  const Ops* ops_ = nullptr;
};

}  // namespace ecpsim::engine
