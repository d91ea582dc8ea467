// The resident-memory reader: positive numbers, a peak never below the present, and a block of
// memory touched shows in both.

#include "common/memory_usage.h"

#include <cstring>
#include <memory>

#include <gtest/gtest.h>

namespace ecpsim {
namespace {

TEST(MemoryUsage, ResidentAndPeakArePositiveAndOrdered) {
  const MemoryUsage usage = ReadMemoryUsage();
  EXPECT_GT(usage.resident_bytes, 0);
  EXPECT_GE(usage.peak_resident_bytes, usage.resident_bytes);
}

TEST(MemoryUsage, TouchedMemoryIsCounted) {
  constexpr std::size_t kBlock = 64u << 20;  // bytes: far above the kB granularity of the counts
  // the allocator's and the kernel's bookkeeping (page tables, a page the block shares with what
  // was resident before) may count up to this much less than the block itself
  constexpr double kBookkeeping = 1u << 20;  // bytes
  const MemoryUsage before = ReadMemoryUsage();
  const std::unique_ptr<char[]> block(new char[kBlock]);
  std::memset(block.get(), 1, kBlock);  // pages count once written
  const MemoryUsage after = ReadMemoryUsage();
  EXPECT_GE(after.resident_bytes - before.resident_bytes, kBlock - kBookkeeping);
  EXPECT_GE(after.peak_resident_bytes, before.resident_bytes + kBlock - kBookkeeping);
  EXPECT_EQ(block[kBlock - 1], 1);
}

}  // namespace
}  // namespace ecpsim
