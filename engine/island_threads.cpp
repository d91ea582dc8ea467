#include "engine/island_threads.h"

#include <chrono>
#include <utility>

#include <fmt/format.h>

#include "common/errors.h"

namespace ecpsim::engine {
namespace {

// how long a thread watches for what it waits on before it sleeps, whose wake-up costs more: a
// worker for the next job (a step's serial part between two jobs, the broad phase, the islands,
// the commit, takes tens of microseconds on scenes of many islands), the caller for the workers'
// last islands
constexpr std::chrono::microseconds kWatchAfterJob(200);
constexpr int kPausesBetweenLooks = 16;

// a spin-wait hint to the processor (a no-op where it has none)
inline void Pause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

// spins while `waiting()` holds, for at most kWatchAfterJob
template <typename Condition>
void WatchWhile(const Condition& waiting) {
  const auto until = std::chrono::steady_clock::now() + kWatchAfterJob;
  while (waiting() && std::chrono::steady_clock::now() < until) {
    for (int i = 0; i < kPausesBetweenLooks; ++i) Pause();
  }
}

}  // namespace

IslandThreads::~IslandThreads() { StopWorkers(); }

void IslandThreads::SetThreads(int threads) {
  if (threads < 1)
    throw InputError(fmt::format("threads = {}: expected a number of threads ≥ 1", threads));
  if (threads == this->threads()) return;
  StopWorkers();
  stopping_ = false;
  for (int i = 1; i < threads; ++i) {
    workers_.push_back(std::make_unique<Worker>());
    Worker& worker = *workers_.back();
    worker.thread = std::thread([this, &worker] { Work(worker); });
  }
}

void IslandThreads::StopWorkers() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  job_posted_.notify_all();
  for (auto& worker : workers_) worker->thread.join();
  workers_.clear();
}

void IslandThreads::ForEach(const std::vector<int>& order, StepWorkspace& caller,
                            const std::function<void(StepWorkspace&, const TakeItem&)>& work) {
  if (workers_.empty() || order.size() < 2) {
    size_t next = 0;
    work(caller, [&](int& item) {
      if (next == order.size()) return false;
      item = order[next++];
      return true;
    });
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    order_ = &order;
    work_ = &work;
    next_.store(0, std::memory_order_relaxed);
    thrown_ = nullptr;
    open_ = true;
    ++generation_;
    posted_.store(generation_, std::memory_order_release);
  }
  job_posted_.notify_all();
  RunWork(caller);
  // the items are all taken: a worker not yet in stays out, and those in finish theirs
  std::unique_lock<std::mutex> lock(mutex_);
  open_ = false;
  // (the last island of a worker ends within microseconds: watched, not slept on)
  lock.unlock();
  WatchWhile([this] { return busy_.load(std::memory_order_acquire) > 0; });
  lock.lock();
  worker_left_.wait(lock, [this] { return busy_.load(std::memory_order_relaxed) == 0; });
  order_ = nullptr;
  work_ = nullptr;
  if (thrown_) std::rethrow_exception(std::exchange(thrown_, nullptr));
}

void IslandThreads::RunWork(StepWorkspace& workspace) {
  const std::vector<int>& order = *order_;
  try {
    (*work_)(workspace, [&](int& item) {
      const size_t k = next_.fetch_add(1, std::memory_order_relaxed);
      if (k >= order.size()) return false;
      item = order[k];
      return true;
    });
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!thrown_) thrown_ = std::current_exception();
  }
}

void IslandThreads::Work(Worker& worker) {
  std::uint64_t seen = 0;
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    job_posted_.wait(lock, [&] { return stopping_ || generation_ != seen; });
    if (stopping_) return;
    seen = generation_;
    if (!open_) continue;
    ++busy_;
    lock.unlock();
    RunWork(worker.workspace);
    lock.lock();
    if (--busy_ == 0) worker_left_.notify_all();
    // the next step's islands come within microseconds: watch for them a while before sleeping,
    // whose wake-up would cost the step more than the watch
    lock.unlock();
    WatchWhile([&] { return posted_.load(std::memory_order_acquire) == seen; });
    lock.lock();
  }
}

IslandThreads& IslandThreadsOf(StepWorkspace& workspace) { return workspace.Part<IslandThreads>(); }

}  // namespace ecpsim::engine
