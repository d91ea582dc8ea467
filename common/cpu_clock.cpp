#include "common/cpu_clock.h"

#include <ctime>

#include "common/errors.h"

namespace ecpsim {

double ThreadCpuSeconds() {
  timespec now{};
  ECPSIM_DEMAND(clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now) == 0);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

}  // namespace ecpsim
