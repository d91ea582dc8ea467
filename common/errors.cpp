#include "common/errors.h"

#include <cstdio>
#include <cstdlib>

namespace ecpsim {

void DemandFailed(const char* condition, const char* file, int line) {
  std::fprintf(stderr, "ecpsim: internal error: %s failed at %s:%d\n", condition, file, line);
  std::abort();
}

}  // namespace ecpsim
