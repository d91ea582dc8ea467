#pragma once
// A CPU-time limit that reaches inside a step: a thread that raises a CancelFlag once the thread
// that made the watchdog has used a given CPU time, so that a step of minutes stops within a
// solver iteration of the limit instead of after it.

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>

#include <pthread.h>

#include "common/cancel_flag.h"

namespace ecpsim {

class CpuWatchdog {
 public:
  /// Watches the calling thread: raises `flag` once that thread's CPU time (ThreadCpuSeconds,
  /// read every `period_s` of wall time) exceeds the deadline, which is none until SetDeadline.
  explicit CpuWatchdog(CancelFlag& flag, double period_s = kDefaultPeriod);
  /// Stops watching (the flag stays as it is); before the watched thread ends.
  ~CpuWatchdog();
  CpuWatchdog(const CpuWatchdog&) = delete;
  CpuWatchdog& operator=(const CpuWatchdog&) = delete;

  // s: a limit is met within this much CPU, one clock read per period costing nothing measurable
  static constexpr double kDefaultPeriod = 0.01;

  /// The watched thread's ThreadCpuSeconds() beyond which the flag is raised (from any thread).
  void SetDeadline(double thread_cpu_s) { deadline_.store(thread_cpu_s); }

 private:
  void Watch(double period_s);

  CancelFlag& flag_;
  clockid_t clock_;
  std::atomic<double> deadline_;
  std::mutex mutex_;
  std::condition_variable stop_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace ecpsim
