#pragma once
// How much memory this process holds: its resident set now and at its peak, as Linux reports them
// in /proc/self/status (the benchmarks' memory columns).

namespace ecpsim {

struct MemoryUsage {
  double resident_bytes = 0;       // VmRSS: resident now
  double peak_resident_bytes = 0;  // VmHWM: the most resident at any time so far
};

/// This process's resident set size now and its peak, in bytes.
/// @throws std::runtime_error if /proc/self/status cannot be read or lacks VmRSS or VmHWM (a
///         system without procfs).
MemoryUsage ReadMemoryUsage();

/// Caps this process's address space at `bytes` (RLIMIT_AS, soft and hard): an allocation past
/// it fails (std::bad_alloc, a null malloc) instead of paging out a shared machine; for a child
/// process that measures one run (common/child_process_call.h), never the main one.
/// @throws std::runtime_error if the system refuses the limit.
void LimitAddressSpace(double bytes);

}  // namespace ecpsim
