#pragma once
// A function run in a forked child process, its result returned through memory shared with the
// parent: a measurement whose peak memory is its own (not the process's history), and whose crash
// (an engine's abort, a segmentation fault) ends the child, not the caller.

#include <cstddef>
#include <functional>
#include <string>
#include <type_traits>

namespace ecpsim {

namespace detail {
std::string CallInChildProcess(void* result, std::size_t bytes,
                               const std::function<void(void* shared)>& work);
}  // namespace detail

/// Runs `work(result)` in a child process forked from this one (no exec: the child has this
/// process's memory at the call), with `result` in memory shared with it, and copies the result
/// back when the child has ended, whatever ended it: what the child wrote before a failure stays.
/// The child leaves with _exit (no atexit handlers, no flush of stdio buffers it inherited).
/// @return "" when `work` returned; else what ended the child: the message of the exception it
///         threw, "killed by signal N (NAME)", or "exit status N" if something in it called exit.
/// @throws std::runtime_error if the shared memory or the child cannot be made.
template <typename Result>
std::string CallInChildProcess(Result& result, const std::function<void(Result&)>& work) {
  // bytes copied across processes: no pointers, no owned memory
  static_assert(std::is_trivially_copyable_v<Result>);
  return detail::CallInChildProcess(&result, sizeof(Result),
                                    [&work](void* shared) { work(*static_cast<Result*>(shared)); });
}

}  // namespace ecpsim
