#pragma once
// Independent jobs spread over the machine's cores, each index once, on whichever thread is free.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace ecpsim {

/// Calls `job(i)` for each i in [0, count) on up to the hardware's thread count (the caller's
/// thread among them) and returns when all have ended. The jobs must be independent, each
/// writing only its own results, so that those do not depend on the thread count. If jobs
/// throw, the exception of the lowest such index is rethrown.
template <class Job>
void ParallelFor(std::size_t count, const Job& job) {
  std::vector<std::exception_ptr> errors(count);
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t i = next++; i < count; i = next++) {
      try {
        job(i);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  const std::size_t threads =
      std::min<std::size_t>(count, std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::thread> helpers;
  for (std::size_t t = 1; t < threads; ++t) helpers.emplace_back(work);
  work();
  for (std::thread& helper : helpers) helper.join();
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);
}

}  // namespace ecpsim
