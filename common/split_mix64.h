#pragma once
// SplitMix64's output function (Steele, Lea, Flood 2014): a bijective mix of a 64-bit value whose
// outputs pass BigCrush, for deterministic hashing and seeding.

#include <cstdint>

namespace ecpsim {

inline std::uint64_t SplitMix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

}  // namespace ecpsim
