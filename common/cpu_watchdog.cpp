#include "common/cpu_watchdog.h"

#include <chrono>
#include <ctime>
#include <limits>

#include "common/errors.h"

namespace ecpsim {

CpuWatchdog::CpuWatchdog(CancelFlag& flag, double period_s)
    : flag_(flag), deadline_(std::numeric_limits<double>::infinity()) {
  ECPSIM_DEMAND(pthread_getcpuclockid(pthread_self(), &clock_) == 0);
  thread_ = std::thread([this, period_s] { Watch(period_s); });
}

CpuWatchdog::~CpuWatchdog() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  stop_.notify_all();
  thread_.join();
}

void CpuWatchdog::Watch(double period_s) {
  const auto period = std::chrono::duration<double>(period_s);
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_.wait_for(lock, period, [this] { return stopping_; })) {
    timespec used{};
    ECPSIM_DEMAND(clock_gettime(clock_, &used) == 0);
    if (static_cast<double>(used.tv_sec) + 1e-9 * static_cast<double>(used.tv_nsec) >
        deadline_.load())
      flag_.Raise();
  }
}

}  // namespace ecpsim
