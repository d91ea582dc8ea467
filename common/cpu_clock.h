#pragma once
// The calling thread's CPU time, for the benchmarks' and reports' timings.

namespace ecpsim {

/// Seconds of CPU time the calling thread has used (CLOCK_THREAD_CPUTIME_ID): unlike wall time,
/// not counting what other processes on a shared machine take.
double ThreadCpuSeconds();

}  // namespace ecpsim
