// `ecpsim bench`: the work–precision sweep and the stability maps of every method (issue 6),
// as CSV, PNG charts and results.md; shards of it for job schedulers, and their merge.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "common/atomic_file.h"
#include "app/bench_report.h"
#include "app/commands.h"
#include "app/option_checks.h"
#include "evaluation/method.h"
#include "evaluation/scenario.h"
#include "evaluation/stability_map.h"
#include "evaluation/work_precision.h"
#include "common/errors.h"

namespace ecpsim::app {
namespace {

namespace fs = std::filesystem;

struct BenchOptions {
  std::string out_dir = "out/bench";
  bool quick = false;
  std::vector<std::string> scenarios;
  std::vector<std::string> methods;
  std::vector<std::string> maps;
  std::vector<double> steps;
  std::string shard = "1/1";
  bool skip_work_precision = false;
  bool skip_stability = false;
  bool charts = true;
  std::vector<std::string> merge;
  std::string scenes_dir = ECPSIM_SCENES_DIR;
  double cpu_limit_s = 300;
};

// steps of the full sweep and of --quick (each divides the 0.02 s sample interval)
const std::vector<double> kFullSteps = {0.02, 0.01, 0.005, 0.002, 0.001, 0.0005, 0.0002};
const std::vector<double> kQuickSteps = {0.01, 0.002};
constexpr double kQuickConvergedDuration = 0.5;  // s of the desk, T-bar and dumbbell in --quick
constexpr double kFullConvergedDuration = 1.0;   // s

void ParseShard(const std::string& text, int& index, int& count) {
  int used = 0;
  if (std::sscanf(text.c_str(), "%d/%d%n", &index, &count, &used) != 2 ||
      used != static_cast<int>(text.size()) || count < 1 || index < 1 || index > count) {
    throw InputError(fmt::format("--shard '{}': expected i/N with 1 ≤ i ≤ N, e.g. 3/16", text));
  }
}

template <typename T, typename Name>
std::vector<T> Select(const std::vector<T>& all, const std::vector<std::string>& names,
                      const char* option, Name name) {
  if (names.empty()) return all;
  std::vector<T> chosen;
  for (const std::string& wanted : names) {
    std::string choices;
    bool found = false;
    for (const T& item : all) {
      if (name(item) == wanted) chosen.push_back(item), found = true;
      choices += (choices.empty() ? "" : ", ") + name(item);
    }
    if (!found) {
      throw InputError(fmt::format("{} '{}': expected one of {}", option, wanted, choices));
    }
  }
  return chosen;
}

void Progress(const std::string& line) { std::fprintf(stderr, "bench: %s\n", line.c_str()); }

void Merge(const BenchOptions& o) {
  std::vector<evaluation::WorkPrecisionRow> wp;
  std::vector<evaluation::StabilityRow> st;
  for (const std::string& dir : o.merge) {
    const fs::path wp_csv = fs::path(dir) / "work_precision.csv";
    const fs::path st_csv = fs::path(dir) / "stability.csv";
    if (!fs::exists(wp_csv) && !fs::exists(st_csv)) {
      throw InputError(fmt::format("--merge {}: neither work_precision.csv nor stability.csv "
                                   "there (expected the output folder of an `ecpsim bench "
                                   "--shard` run)",
                                   dir));
    }
    if (fs::exists(wp_csv)) {
      for (auto& row : evaluation::ReadWorkPrecisionCsv(wp_csv.string())) wp.push_back(row);
    }
    if (fs::exists(st_csv)) {
      for (auto& row : evaluation::ReadStabilityCsv(st_csv.string())) st.push_back(row);
    }
  }
  fs::create_directories(o.out_dir);
  if (!wp.empty()) {
    WriteFileAtomically((fs::path(o.out_dir) / "work_precision.csv").string(),
                        evaluation::WorkPrecisionCsv(wp));
  }
  if (!st.empty()) {
    WriteFileAtomically((fs::path(o.out_dir) / "stability.csv").string(),
                        evaluation::StabilityCsv(st));
  }
  for (const std::string& path : WriteBenchReport(o.out_dir, wp, st, o.charts)) {
    std::printf("wrote %s\n", path.c_str());
  }
  std::printf("merged %zu work-precision rows and %zu stability rows from %zu folders\n",
              wp.size(), st.size(), o.merge.size());
}

void Run(const BenchOptions& o) {
  if (!o.merge.empty()) return Merge(o);
  int shard_index = 1, shard_count = 1;
  ParseShard(o.shard, shard_index, shard_count);
  const std::vector<evaluation::Method> methods =
      Select(evaluation::AllMethods(), o.methods, "--methods",
             [](const evaluation::Method& m) { return m.name; });
  const std::vector<double> steps =
      o.steps.empty() ? (o.quick ? kQuickSteps : kFullSteps) : o.steps;
  fs::create_directories(o.out_dir);
  std::vector<evaluation::WorkPrecisionRow> wp;
  std::vector<evaluation::StabilityRow> st;
  if (!o.skip_work_precision) {
    const std::vector<evaluation::Scenario> scenarios = Select(
        evaluation::WorkPrecisionScenarios(
            o.scenes_dir, o.quick ? kQuickConvergedDuration : kFullConvergedDuration),
        o.scenarios, "--scenarios", [](const evaluation::Scenario& s) { return s.name; });
    evaluation::SweepOptions sweep;
    sweep.steps = steps;
    sweep.cpu_limit_s = o.cpu_limit_s;
    sweep.shard_index = shard_index;
    sweep.shard_count = shard_count;
    sweep.progress = Progress;
    wp = evaluation::RunWorkPrecision(scenarios, methods, sweep);
    WriteFileAtomically((fs::path(o.out_dir) / "work_precision.csv").string(),
                        evaluation::WorkPrecisionCsv(wp));
  }
  if (!o.skip_stability) {
    const std::vector<evaluation::StabilityMapSpec> maps =
        Select(evaluation::StabilityMaps(), o.maps, "--maps",
               [](const evaluation::StabilityMapSpec& m) { return m.name; });
    st = evaluation::RunStabilityMaps(maps, methods, steps, shard_index, shard_count,
                                      o.cpu_limit_s, Progress);
    WriteFileAtomically((fs::path(o.out_dir) / "stability.csv").string(),
                        evaluation::StabilityCsv(st));
  }
  // a shard's charts would show a part of the sweep: they are drawn by the merge
  for (const std::string& path : WriteBenchReport(o.out_dir, wp, st, o.charts && shard_count == 1)) {
    std::printf("wrote %s\n", path.c_str());
  }
}

}  // namespace

void AddBenchCommand(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* bench = app.add_subcommand(
      "bench", "Speed against accuracy: work-precision charts of every contact model and of "
               "MuJoCo, Bullet and ODE (where built), and stability maps (docs/benchmarks.md)");
  bench->add_option("-o,--output", o->out_dir, "output folder")->capture_default_str();
  bench->add_flag("--quick", o->quick,
                  "steps 0.01 and 0.002 s only, converged scenes cut to 0.5 s (for CI)");
  bench->add_option("--scenarios", o->scenarios,
                    "work-precision scenarios (default all): slide, spin, push_slide, rest, "
                    "desk, tbar, dumbbell")
      ->delimiter(',');
  bench->add_option("--methods", o->methods,
                    "methods (default all available): hull, hull-tol1e-08, hull-tol1e-05, "
                    "planar, multipatch, point, mujoco-default, mujoco-coulomb, bullet-default, "
                    "bullet-coulomb, ode-default, ode-coulomb")
      ->delimiter(',');
  bench->add_option("--maps", o->maps,
                    "stability maps (default all): impact, thin_plate, tbar_mass_ratio")
      ->delimiter(',');
  bench->add_option("--steps", o->steps,
                    "step sizes in s, each dividing 0.02 (default 0.02,0.01,0.005,0.002,0.001,"
                    "0.0005,0.0002)")
      ->delimiter(',')
      ->check(FinitePositive("--steps", engine::kTimeRange));
  bench->add_option("--shard", o->shard,
                    "run part i of N of the sweep (i/N); join the parts with --merge")
      ->capture_default_str();
  bench->add_flag("--no-work-precision", o->skip_work_precision, "skip the work-precision sweep");
  bench->add_flag("--no-stability", o->skip_stability, "skip the stability maps");
  bench->add_flag("!--no-charts", o->charts, "write CSV and results.md only");
  bench->add_option("--merge", o->merge,
                    "join the CSVs of these shard output folders into -o and draw the charts")
      ->expected(1, -1);
  bench->add_option("--scenes", o->scenes_dir, "folder of desk.yaml, tbar.yaml, dumbbell.yaml")
      ->capture_default_str();
  bench->add_option("--cpu-limit", o->cpu_limit_s, "CPU seconds allowed per run")
      ->capture_default_str()
      ->check(FinitePositive("--cpu-limit", engine::kTimeRange));
  bench->callback([o] { Run(*o); });
}

}  // namespace ecpsim::app
