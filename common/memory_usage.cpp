#include "common/memory_usage.h"

#include <sys/resource.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace ecpsim {
namespace {

constexpr double kKibibyte = 1024;  // bytes: /proc/self/status counts in "kB", i.e. KiB

// the value of a "Name:   1234 kB" line of /proc/self/status, in bytes; −1 when it is not one
double KibibyteField(const std::string& line, const std::string& name) {
  if (line.rfind(name + ":", 0) != 0) return -1;
  std::istringstream fields(line.substr(name.size() + 1));
  long long kib = -1;
  std::string unit;
  if (!(fields >> kib >> unit) || unit != "kB" || kib < 0) return -1;
  return static_cast<double>(kib) * kKibibyte;
}

}  // namespace

MemoryUsage ReadMemoryUsage() {
  const char* const path = "/proc/self/status";
  std::ifstream status(path);
  MemoryUsage usage;
  usage.resident_bytes = usage.peak_resident_bytes = -1;
  for (std::string line; std::getline(status, line);) {
    if (const double rss = KibibyteField(line, "VmRSS"); rss >= 0) usage.resident_bytes = rss;
    if (const double hwm = KibibyteField(line, "VmHWM"); hwm >= 0) usage.peak_resident_bytes = hwm;
  }
  if (usage.resident_bytes < 0 || usage.peak_resident_bytes < 0) {
    throw std::runtime_error(std::string(path) +
                             ": no VmRSS and VmHWM lines in kB (Linux procfs expected)");
  }
  return usage;
}

void LimitAddressSpace(double bytes) {
  rlimit limit;
  limit.rlim_cur = limit.rlim_max = static_cast<rlim_t>(bytes);
  if (setrlimit(RLIMIT_AS, &limit) != 0) {
    throw std::runtime_error(std::string("cannot limit the address space to ") +
                             std::to_string(bytes) + " bytes: " + std::strerror(errno));
  }
}

}  // namespace ecpsim
