#pragma once
// The threads a step solves its islands on: the caller's own and workers kept from step to step
// (as Box2D v3's and Jolt's job systems), each worker with a StepWorkspace of its own. Islands are
// independent within a step and a solve does not depend on what a workspace holds, so a step's
// result is the same whatever the number of threads and whichever thread solves which island.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "engine/step_workspace.h"

namespace ecpsim::engine {

class IslandThreads {
 public:
  /// The caller's thread alone.
  IslandThreads() = default;
  ~IslandThreads();
  IslandThreads(const IslandThreads&) = delete;
  IslandThreads& operator=(const IslandThreads&) = delete;

  /// Solve on `threads` threads: the caller's and threads − 1 workers (started or stopped here).
  /// @throws InputError for threads < 1.
  void SetThreads(int threads);
  int threads() const { return static_cast<int>(workers_.size()) + 1; }

  /// Takes the next item of the current job into `item`; false when none is left.
  using TakeItem = std::function<bool(int& item)>;
  /// Work on the items [0, count) listed in `order` (a permutation: the dearest first, so that
  /// the last item left is a cheap one): each thread calls `work(workspace, take)` with its own
  /// workspace (`caller` on the caller's thread) and handles each item `take` gives it, so that
  /// every item is handled once. Workers that wake after the items are all taken stay out.
  /// Returns once every thread is done; rethrows what a `work` threw (one of them).
  void ForEach(const std::vector<int>& order, StepWorkspace& caller,
               const std::function<void(StepWorkspace&, const TakeItem&)>& work);

 private:
  struct Worker {
    std::thread thread;
    StepWorkspace workspace;
  };
  void Work(Worker& worker);
  // runs the current job's work on `workspace`, keeping the first exception
  void RunWork(StepWorkspace& workspace);
  void StopWorkers();

  std::vector<std::unique_ptr<Worker>> workers_;
  std::mutex mutex_;
  std::condition_variable job_posted_, worker_left_;
  // the job, valid while `open_` (guarded by mutex_ but for `next_`, which threads take items by)
  const std::vector<int>* order_ = nullptr;
  const std::function<void(StepWorkspace&, const TakeItem&)>* work_ = nullptr;
  std::atomic<size_t> next_{0};
  std::exception_ptr thrown_;
  bool open_ = false;
  std::uint64_t generation_ = 0;          // jobs posted so far: a worker joins each at most once
  std::atomic<std::uint64_t> posted_{0};  // generation_, for workers watching without the lock
  std::atomic<int> busy_{0};              // workers inside the current job (changed under the lock)
  bool stopping_ = false;
};

/// The IslandThreads of `workspace` (one thread until SetThreads): a copy of a workspace starts
/// with one.
IslandThreads& IslandThreadsOf(StepWorkspace& workspace);

}  // namespace ecpsim::engine
