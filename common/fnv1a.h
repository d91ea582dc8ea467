#pragma once
// FNV-1a, 64 bits (Fowler, Noll, Vo): a fast hash that any change of the bytes changes with
// overwhelming likelihood; the fingerprint of a run's inputs and of a cached mesh decomposition,
// the seed of a stream named by a file.

#include <cstddef>
#include <cstdint>
#include <string>

#include <fmt/format.h>

namespace ecpsim {

class Fnv1a {
 public:
  void Add(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) hash_ = (hash_ ^ bytes[i]) * kPrime;
  }
  std::uint64_t Value() const { return hash_; }
  std::string Hex() const { return fmt::format("{:016x}", hash_); }

 private:
  static constexpr std::uint64_t kOffsetBasis = 0xcbf29ce484222325ULL;
  static constexpr std::uint64_t kPrime = 0x100000001b3ULL;
  std::uint64_t hash_ = kOffsetBasis;
};

}  // namespace ecpsim
