#pragma once
// The scaling benchmark: the cost of one step against the number of bodies, N boxes in a grid of
// stacks (stack_grid.h) from one to a thousand, for every method; each (method, N) measured in a
// process of its own, with its time per step, its peak memory and whether its memory grows with
// the run's length (issue 30, items 1 and 4).

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "evaluation/method.h"
#include "evaluation/power_law_fit.h"
#include "evaluation/stack_grid.h"

namespace ecpsim::evaluation {

/// One method at one N. Values not measured are −1 (never NaN).
struct ScalingRow {
  std::string method;
  long bodies = 0;
  long steps = 0;        // steps completed: warm-up, timed and the memory check's
  int repeats = 0;       // timed blocks (ScalingOptions::repeats)
  long timed_steps = 0;  // steps in the timed blocks, all of them
  int rounds = 0;        // measurements combined (ScalingOptions::rounds)
  bool failed = false;
  // s, the median over the rounds of the median over the repeats of a repeat's time divided by
  // its steps: the thread's CPU time and the wall-clock time; −1 where a round failed
  double cpu_per_step = -1;
  double wall_per_step = -1;
  // MiB resident: when the measurement's process began (the bench's own memory, before the
  // scene), after K steps and after 2K (K = warm-up and timed steps), and the process's peak;
  // over the rounds the most at the start and at the peak, K and 2K of the largest growth
  double rss_start_mib = -1;
  double rss_k_mib = -1;
  double rss_2k_mib = -1;
  double rss_peak_mib = -1;
  std::string failure;  // message of the failure (commas and newlines replaced)
};

/// The body counts of the full sweep: ×4 apart, evenly spaced in log N for the fit, each from 4
/// on a whole number of stacks (250 and 1,000 for the thousand).
const std::vector<int>& DefaultScalingSizes();

struct ScalingOptions {
  std::vector<int> sizes = DefaultScalingSizes();  // bodies, each in [1, kMaxGridBodies]
  int warmup_steps = 5;       // untimed: the stacks settle from their exact start, caches fill
  int repeats = 5;            // timed blocks; the median of their per-step times is reported
  int steps_per_repeat = 10;  // steps in a timed block (one clock read per block, not per step)
  // times every group is measured, each round over all groups before the next: a noisy minute
  // of a shared machine then spoils one round of a group, which the median of the rounds drops
  int rounds = 3;
  double cpu_limit_s = 300;  // CPU seconds per (method, N), every step counted
  // bytes of address space per (method, N) (its process's RLIMIT_AS): a run that needs more
  // fails instead of paging out the machine (MuJoCo 2.2's dense constraint buffers grow with the
  // square of the contacts)
  double memory_limit_bytes = 8.0 * (1 << 30);
  int shard_index = 1;  // this process runs shard shard_index of shard_count (1-based)
  int shard_count = 1;
  std::function<void(const std::string& message)> progress;  // one line per (method, N)
};

/// Whether `method` models the stack grid's contacts between bodies (the planar and the
/// multi-patch models do not: they stop with ModelInvalid on such a scene) at a cost the grid's
/// sizes allow (the least-energy selection's dense factorizations do not: engine/README.md).
bool AppliesToStackGrid(const Method& method);

/// Runs this shard's part of the measurement: (method, N) groups, methods outermost, N in the
/// given order; group g (0-based, counting the methods that apply) belongs to shard
/// (g mod shard_count) + 1. Every group is measured once per round, each time in a forked child
/// process (common/child_process_call.h): the grid is built, then warmup_steps, repeats ×
/// steps_per_repeat timed steps (K in all), the resident memory read, K more steps, the memory
/// read again. A group's row combines its rounds (ScalingRow says how). A solver
/// failure, an engine's InputError, a crash, the CPU limit or the memory limit make a failed row
/// with the message.
/// Precondition (ECPSIM_DEMAND): the options as documented, every size in [1, kMaxGridBodies].
std::vector<ScalingRow> RunScaling(const std::vector<Method>& methods,
                                   const ScalingOptions& options);

/// Bodies below which a size is left out of the fit: the first whole stack; a lone box has no
/// contact between bodies, a scene of another kind rather than a smaller one of the family.
constexpr long kSlopeFitMinBodies = kStackHeight;

/// The power law of `method`'s CPU (wall: `wall`) time per step against N over its rows that did
/// not fail, from kSlopeFitMinBodies bodies on; nullopt with fewer than two sizes.
std::optional<PowerLaw> FitScaling(const std::vector<ScalingRow>& rows, const std::string& method,
                                   bool wall);

/// The CSV text (header + one line per row).
std::string ScalingCsv(const std::vector<ScalingRow>& rows);

/// Parses a file written by ScalingCsv.
/// @throws InputError naming the file, line and column for anything else.
std::vector<ScalingRow> ReadScalingCsv(const std::string& path);

}  // namespace ecpsim::evaluation
