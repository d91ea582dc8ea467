#include "evaluation/scaling.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <new>
#include <stdexcept>

#include <fmt/format.h>

#include "common/child_process_call.h"
#include "common/cpu_clock.h"
#include "common/errors.h"
#include "common/memory_usage.h"
#include "common/reservoir_median.h"
#include "engine/state.h"
#include "evaluation/cpu_budget.h"
#include "evaluation/csv_file.h"

namespace ecpsim::evaluation {
namespace {

constexpr double kMebibyte = 1024.0 * 1024.0;  // bytes
constexpr double kGibibyte = 1024.0 * kMebibyte;

// scaling.csv's columns, in order
using Row = ScalingRow;
constexpr int kDigits = 9;  // significant digits: times and sizes, not a state
const std::vector<CsvColumn<Row>> kColumns = {
    TextColumn<Row>("method", &Row::method),
    WholeColumn<Row>("bodies", &Row::bodies),
    WholeColumn<Row>("steps", &Row::steps),
    WholeColumn<Row>("repeats", &Row::repeats),
    WholeColumn<Row>("timed_steps", &Row::timed_steps),
    WholeColumn<Row>("rounds", &Row::rounds),
    FlagColumn<Row>("failed", &Row::failed),
    NumberColumn<Row>("cpu_per_step", kDigits, &Row::cpu_per_step),
    NumberColumn<Row>("wall_per_step", kDigits, &Row::wall_per_step),
    NumberColumn<Row>("rss_start_mib", kDigits, &Row::rss_start_mib),
    NumberColumn<Row>("rss_k_mib", kDigits, &Row::rss_k_mib),
    NumberColumn<Row>("rss_2k_mib", kDigits, &Row::rss_2k_mib),
    NumberColumn<Row>("rss_peak_mib", kDigits, &Row::rss_peak_mib),
    TextColumn<Row>("failure", &Row::failure),
};

// what the measuring child hands back: plain numbers in shared memory, −1 until measured
struct Measured {
  long steps = 0;
  double cpu_per_step = -1, wall_per_step = -1;
  double rss_start = -1, rss_k = -1, rss_2k = -1, rss_peak = -1;  // bytes
};

double WallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// steps one grid with `method` as ScalingOptions says, filling `out` as it goes (in the child)
void Measure(const Method& method, int bodies, const ScalingOptions& options, Measured& out) {
  LimitAddressSpace(options.memory_limit_bytes);
  out.rss_start = ReadMemoryUsage().resident_bytes;
  const std::unique_ptr<Stepper> stepper = MakeStepper(method, MakeStackGrid(bodies));
  // the limit stops a step of minutes within a solver iteration of it
  CpuBudget budget(options.cpu_limit_s);
  stepper->StopOn(budget.flag());
  const auto charge = [&](const auto& steps) {
    if (budget.Charge(steps) != CpuBudget::Outcome::kWithin) {
      throw std::runtime_error(
          fmt::format("CPU limit of {} s reached after {} steps", options.cpu_limit_s, out.steps));
    }
  };
  const auto step = [&] {
    charge([&] {
      stepper->Step();
      ++out.steps;
    });
  };
  const auto check_finite = [&] {
    for (const engine::BodyState& b : stepper->state().bodies) {
      if (!engine::IsFinite(b)) {
        throw std::runtime_error(fmt::format("non-finite state after {} steps", out.steps));
      }
    }
  };
  for (int k = 0; k < options.warmup_steps; ++k) step();
  // the blocks' per-step times; the clocks read once per block, outside the step
  ReservoirMedian cpu, wall;
  for (int r = 0; r < options.repeats; ++r) {
    charge([&] {
      const double cpu_start = ThreadCpuSeconds(), wall_start = WallSeconds();
      for (int k = 0; k < options.steps_per_repeat; ++k) stepper->Step(), ++out.steps;
      cpu.Add((ThreadCpuSeconds() - cpu_start) / options.steps_per_repeat);
      wall.Add((WallSeconds() - wall_start) / options.steps_per_repeat);
    });
  }
  check_finite();
  out.cpu_per_step = cpu.Median();
  out.wall_per_step = wall.Median();
  // bounded memory: as many steps again must not hold more
  const long k_steps = out.steps;
  out.rss_k = ReadMemoryUsage().resident_bytes;
  for (long k = 0; k < k_steps; ++k) step();
  check_finite();
  const MemoryUsage end = ReadMemoryUsage();
  out.rss_2k = end.resident_bytes;
  out.rss_peak = end.peak_resident_bytes;
}

double Mebibytes(double bytes) { return bytes < 0 ? -1 : bytes / kMebibyte; }

ScalingRow MeasureInChild(const Method& method, int bodies, const ScalingOptions& options) {
  Measured measured;
  const std::string failure = CallInChildProcess<Measured>(measured, [&](Measured& out) {
    try {
      Measure(method, bodies, options, out);
    } catch (const std::bad_alloc&) {
      out.rss_peak = ReadMemoryUsage().peak_resident_bytes;
      throw std::runtime_error(fmt::format(
          "out of memory: an allocation past the limit of {:g} GiB of address space after {} "
          "steps",
          options.memory_limit_bytes / kGibibyte, out.steps));
    } catch (...) {
      // how far the memory got before the failure
      out.rss_peak = ReadMemoryUsage().peak_resident_bytes;
      throw;
    }
  });
  ScalingRow row;
  row.method = method.name;
  row.bodies = bodies;
  row.steps = measured.steps;
  row.repeats = options.repeats;
  row.timed_steps = static_cast<long>(options.repeats) * options.steps_per_repeat;
  row.failed = !failure.empty();
  row.failure = CsvField(failure);
  // a failed run's time is that of another computation (its retries, the step that threw)
  if (!row.failed) {
    row.cpu_per_step = measured.cpu_per_step;
    row.wall_per_step = measured.wall_per_step;
  }
  row.rss_start_mib = Mebibytes(measured.rss_start);
  row.rss_k_mib = Mebibytes(measured.rss_k);
  row.rss_2k_mib = Mebibytes(measured.rss_2k);
  row.rss_peak_mib = Mebibytes(measured.rss_peak);
  return row;
}

// one row of a group's rounds: the median of their times, the most memory any of them took and
// the largest growth; failed when any round failed (its message and steps)
ScalingRow CombineRounds(const std::vector<ScalingRow>& rounds) {
  ScalingRow row = rounds.front();
  row.rounds = static_cast<int>(rounds.size());
  ReservoirMedian cpu, wall;
  for (const ScalingRow& r : rounds) {
    if (r.failed && !row.failed) {
      row.failed = true;
      row.failure = r.failure;
      row.steps = r.steps;
    }
    cpu.Add(r.cpu_per_step);
    wall.Add(r.wall_per_step);
    row.rss_start_mib = std::max(row.rss_start_mib, r.rss_start_mib);
    row.rss_peak_mib = std::max(row.rss_peak_mib, r.rss_peak_mib);
    if (r.rss_2k_mib - r.rss_k_mib > row.rss_2k_mib - row.rss_k_mib) {
      row.rss_k_mib = r.rss_k_mib;
      row.rss_2k_mib = r.rss_2k_mib;
    }
  }
  row.cpu_per_step = row.failed ? -1 : cpu.Median();
  row.wall_per_step = row.failed ? -1 : wall.Median();
  return row;
}

}  // namespace

const std::vector<int>& DefaultScalingSizes() {
  static const std::vector<int> sizes = {1, 4, 16, 64, 250, 1000};
  return sizes;
}

bool AppliesToStackGrid(const Method& method) {
  return method.external || (method.model != engine::ContactModel::kPlanar &&
                             method.model != engine::ContactModel::kMultiPatch &&
                             method.selection != engine::Selection::kLeastEnergy);
}

std::vector<ScalingRow> RunScaling(const std::vector<Method>& methods,
                                   const ScalingOptions& options) {
  ECPSIM_DEMAND(options.shard_count >= 1 && options.shard_index >= 1 &&
                options.shard_index <= options.shard_count);
  ECPSIM_DEMAND(options.warmup_steps >= 0 && options.repeats >= 1 &&
                options.steps_per_repeat >= 1 && options.rounds >= 1);
  for (int bodies : options.sizes) ECPSIM_DEMAND(bodies >= 1 && bodies <= kMaxGridBodies);
  // this shard's groups
  std::vector<std::pair<const Method*, int>> groups;
  int group = -1;
  for (const Method& method : methods) {
    if (!AppliesToStackGrid(method)) continue;
    for (int bodies : options.sizes) {
      if (++group % options.shard_count == options.shard_index - 1) {
        groups.emplace_back(&method, bodies);
      }
    }
  }
  // every group once per round, so that a group's rounds lie minutes apart
  std::vector<std::vector<ScalingRow>> measured(groups.size());
  for (int round = 1; round <= options.rounds; ++round) {
    for (size_t g = 0; g < groups.size(); ++g) {
      const auto [method, bodies] = groups[g];
      measured[g].push_back(MeasureInChild(*method, bodies, options));
      if (!options.progress) continue;
      const ScalingRow& r = measured[g].back();
      const std::string what = fmt::format("scaling {} / {} bodies (round {} of {})", method->name,
                                           bodies, round, options.rounds);
      options.progress(
          r.failed ? fmt::format("{}: failed after {} steps: {}", what, r.steps, r.failure)
                   : fmt::format("{}: {:.3g} ms CPU per step, peak RSS {:.1f} MiB, {:+.1f} MiB "
                                 "from K to 2K steps",
                                 what, 1e3 * r.cpu_per_step, r.rss_peak_mib,
                                 r.rss_2k_mib - r.rss_k_mib));
    }
  }
  std::vector<ScalingRow> rows;
  for (const std::vector<ScalingRow>& rounds : measured) rows.push_back(CombineRounds(rounds));
  return rows;
}

std::optional<PowerLaw> FitScaling(const std::vector<ScalingRow>& rows, const std::string& method,
                                   bool wall) {
  std::vector<double> bodies, cost;
  for (const ScalingRow& r : rows) {
    if (r.method != method || r.failed || r.bodies < kSlopeFitMinBodies) continue;
    bodies.push_back(static_cast<double>(r.bodies));
    cost.push_back(wall ? r.wall_per_step : r.cpu_per_step);
  }
  return FitPowerLaw(bodies, cost);
}

std::string ScalingCsv(const std::vector<ScalingRow>& rows) { return WriteCsv(kColumns, rows); }

std::vector<ScalingRow> ReadScalingCsv(const std::string& path) { return ReadCsv(path, kColumns); }

}  // namespace ecpsim::evaluation
