// `ecpsim bench`: the work–precision sweep and the stability maps of every method (issue 6), the
// drop sweep (issue 14) and the cost per step against the number of bodies (issue 30), as CSV,
// PNG charts and results.md; shards of it for job schedulers, and their merge.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/bench_report.h"
#include "app/commands.h"
#include "app/method_style.h"
#include "app/option_checks.h"
#include "common/atomic_file.h"
#include "common/errors.h"
#include "evaluation/auto_cost.h"
#include "evaluation/drop_sweep.h"
#include "evaluation/method.h"
#include "evaluation/scaling.h"
#include "evaluation/scenario.h"
#include "evaluation/stability_map.h"
#include "evaluation/work_precision.h"

namespace ecpsim::app {
namespace {

namespace fs = std::filesystem;

// the public mesh collection the drop sweep drops by default (Debian's assimp-testmodels)
constexpr const char* kDefaultMeshCollection = "/usr/share/assimp/models";

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
  bool skip_drops = false;
  bool skip_scaling = false;
  std::vector<int> scaling_sizes;  // empty: evaluation::DefaultScalingSizes() or kQuickScalingSizes
  int scaling_steps = evaluation::ScalingOptions{}.steps_per_repeat;
  int scaling_rounds = evaluation::ScalingOptions{}.rounds;
  int scaling_memory_gib = 8;  // evaluation::ScalingOptions::memory_limit_bytes
  std::vector<std::string> drop_kinds;
  std::vector<std::string> drop_steps;
  int drop_seeds = -1;  // per generated kind; −1: kFullDropSeeds or kQuickDropSeeds
  std::vector<std::string> drop_meshes = {kDefaultMeshCollection};
  int drop_poses = -1;  // per collection file; −1: kFullDropPoses or kQuickDropPoses
  std::vector<std::string> drop_cases;
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
// the drop sweep: generated cases per kind, poses per collection file, and in --quick also the
// first kQuickDropFiles files only
constexpr int kFullDropSeeds = 120;
constexpr int kFullDropPoses = 3;
constexpr int kQuickDropSeeds = 3;
constexpr int kQuickDropPoses = 1;
constexpr int kQuickDropFiles = 10;
// the most steps per timed block of the scaling benchmark: 100 s of one step of a millisecond
// per block, far past what a median needs
constexpr int kMaxScalingSteps = 100000;
// the most --scaling-rounds: a median of this many is far past any noise it could still remove
constexpr int kMaxScalingRounds = 100;
// GiB: the largest --scaling-memory-limit, a large server's memory
constexpr int kMaxScalingMemoryGib = 4096;
constexpr double kGibibyte = 1024.0 * 1024.0 * 1024.0;  // bytes
const char* const kDropCsv = "drop_sweep.csv";
// the scaling benchmark in --quick: up to a few stacks, seconds in all
const std::vector<int> kQuickScalingSizes = {1, 4, 16};
const char* const kScalingCsv = "scaling.csv";
const char* const kDropFailuresDir = "drop_failures";
const char* const kDropScratchDir = "drop_scratch";

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

// the fitted exponent of each method's cost against the number of bodies, a line per method
void PrintScalingSlopes(const std::vector<evaluation::ScalingRow>& rows) {
  for (const std::string& method : InOrder(rows, MethodOf<evaluation::ScalingRow>, MethodOrder())) {
    const auto cpu = evaluation::FitScaling(rows, method, false);
    const auto wall = evaluation::FitScaling(rows, method, true);
    if (!cpu || !wall) continue;
    std::printf(
        "scaling %s: slope %.2f (CPU), %.2f (wall) of log(time per step) against log N "
        "over %d sizes from N = %ld (1: linear)\n",
        method.c_str(), cpu->exponent, wall->exponent, cpu->points, evaluation::kSlopeFitMinBodies);
  }
}

// the auto-against-hull check (evaluation/auto_cost.h) in a line, with each scenario where auto
// is dearer
void PrintAutoCost(const std::vector<evaluation::WorkPrecisionRow>& rows) {
  const std::vector<evaluation::AutoCost> costs = evaluation::CompareAutoWithHull(rows);
  if (costs.empty()) return;
  std::string dearer;
  for (const evaluation::AutoCost& c : costs) {
    if (c.Dearer())
      dearer += fmt::format("{}{} ({:.2f})", dearer.empty() ? "" : ", ", c.scenario, c.median);
  }
  const std::string verdict = dearer.empty()
                                  ? fmt::format("not dearer on any of {} scenarios", costs.size())
                                  : "dearer on " + dearer;
  std::printf("auto against hull (median CPU ratio over the step sizes, dearer above %g): %s\n",
              evaluation::kMaxAutoOverHull, verdict.c_str());
}

void Merge(const BenchOptions& o) {
  std::vector<evaluation::WorkPrecisionRow> wp;
  std::vector<evaluation::StabilityRow> st;
  std::vector<evaluation::DropRow> drops;
  std::vector<evaluation::ScalingRow> scaling;
  fs::create_directories(o.out_dir);
  for (const std::string& dir : o.merge) {
    const fs::path wp_csv = fs::path(dir) / "work_precision.csv";
    const fs::path st_csv = fs::path(dir) / "stability.csv";
    const fs::path drop_csv = fs::path(dir) / kDropCsv;
    const fs::path scaling_csv = fs::path(dir) / kScalingCsv;
    if (!fs::exists(wp_csv) && !fs::exists(st_csv) && !fs::exists(drop_csv) &&
        !fs::exists(scaling_csv)) {
      throw InputError(
          fmt::format("--merge {}: neither work_precision.csv nor stability.csv "
                      "nor {} nor {} there (expected the output folder of an `ecpsim "
                      "bench --shard` run)",
                      dir, kDropCsv, kScalingCsv));
    }
    if (fs::exists(scaling_csv)) {
      for (auto& row : evaluation::ReadScalingCsv(scaling_csv.string())) scaling.push_back(row);
    }
    if (fs::exists(drop_csv)) {
      for (auto& row : evaluation::ReadDropSweepCsv(drop_csv.string())) drops.push_back(row);
      // the shard's reproductions of its failures
      const fs::path failures = fs::path(dir) / kDropFailuresDir;
      if (fs::is_directory(failures)) {
        fs::create_directories(fs::path(o.out_dir) / kDropFailuresDir);
        fs::copy(failures, fs::path(o.out_dir) / kDropFailuresDir,
                 fs::copy_options::overwrite_existing | fs::copy_options::recursive);
      }
    }
    if (fs::exists(wp_csv)) {
      for (auto& row : evaluation::ReadWorkPrecisionCsv(wp_csv.string())) wp.push_back(row);
    }
    if (fs::exists(st_csv)) {
      for (auto& row : evaluation::ReadStabilityCsv(st_csv.string())) st.push_back(row);
    }
  }
  if (!wp.empty()) {
    WriteFileAtomically((fs::path(o.out_dir) / "work_precision.csv").string(),
                        evaluation::WorkPrecisionCsv(wp));
  }
  if (!st.empty()) {
    WriteFileAtomically((fs::path(o.out_dir) / "stability.csv").string(),
                        evaluation::StabilityCsv(st));
  }
  if (!drops.empty()) {
    evaluation::SortDropRows(drops);
    WriteFileAtomically((fs::path(o.out_dir) / kDropCsv).string(), evaluation::DropSweepCsv(drops));
  }
  if (!scaling.empty()) {
    WriteFileAtomically((fs::path(o.out_dir) / kScalingCsv).string(),
                        evaluation::ScalingCsv(scaling));
  }
  for (const std::string& path : WriteBenchReport(o.out_dir, wp, st, drops, scaling, o.charts)) {
    std::printf("wrote %s\n", path.c_str());
  }
  std::printf(
      "merged %zu work-precision rows, %zu stability rows and %zu drop rows from %zu "
      "folders\n",
      wp.size(), st.size(), drops.size(), o.merge.size());
  if (!scaling.empty()) std::printf("merged %zu scaling rows\n", scaling.size());
  PrintScalingSlopes(scaling);
  PrintAutoCost(wp);
}

// the drop sweep of this shard, every option checked (PlanDropSweep)
evaluation::DropSweepOptions DropSweep(const BenchOptions& o, int shard_index, int shard_count) {
  evaluation::DropSweepOptions sweep;
  sweep.kinds = o.drop_kinds;
  sweep.seeds_per_kind = o.drop_seeds >= 0 ? o.drop_seeds
                         : o.quick         ? kQuickDropSeeds
                                           : kFullDropSeeds;
  sweep.poses_per_file = o.drop_poses >= 0 ? o.drop_poses
                         : o.quick         ? kQuickDropPoses
                                           : kFullDropPoses;
  sweep.max_files = o.quick ? kQuickDropFiles : -1;
  sweep.only = o.drop_cases;
  if (!o.drop_steps.empty()) {
    sweep.steps = Select(
        std::vector<evaluation::DropStep>{evaluation::DropStep::kFixed,
                                          evaluation::DropStep::kScaled},
        o.drop_steps, "--drop-steps",
        [](evaluation::DropStep step) -> std::string { return evaluation::DropStepName(step); });
  }
  sweep.cpu_limit_s = o.cpu_limit_s;
  sweep.shard_index = shard_index;
  sweep.shard_count = shard_count;
  sweep.progress = Progress;
  for (const std::string& dir : o.drop_meshes) {
    // the default collection is optional (Debian's assimp-testmodels); a folder asked for is not
    if (dir == kDefaultMeshCollection && !fs::is_directory(dir)) {
      Progress(fmt::format("no {} (package assimp-testmodels): its meshes are left out", dir));
      continue;
    }
    sweep.mesh_dirs.push_back(dir);
  }
  sweep.scratch_dir = (fs::path(o.out_dir) / kDropScratchDir).string();
  sweep.failures_dir = (fs::path(o.out_dir) / kDropFailuresDir).string();
  return sweep;
}

void Run(const BenchOptions& o) {
  if (!o.merge.empty()) return Merge(o);
  int shard_index = 1, shard_count = 1;
  ParseShard(o.shard, shard_index, shard_count);
  // every option is checked before any work: a typo in the last one must not cost the minutes
  // of the sweeps before it
  const std::vector<evaluation::Method> methods =
      o.methods.empty() ? evaluation::DefaultMethods()
                        : Select(evaluation::AllMethods(), o.methods, "--methods",
                                 [](const evaluation::Method& m) { return m.name; });
  const std::vector<double> steps =
      o.steps.empty() ? (o.quick ? kQuickSteps : kFullSteps) : o.steps;
  std::vector<evaluation::Scenario> scenarios;
  if (!o.skip_work_precision) {
    scenarios =
        Select(evaluation::WorkPrecisionScenarios(
                   o.scenes_dir, o.quick ? kQuickConvergedDuration : kFullConvergedDuration),
               o.scenarios, "--scenarios", [](const evaluation::Scenario& s) { return s.name; });
  }
  std::vector<evaluation::StabilityMapSpec> maps;
  if (!o.skip_stability) {
    maps = Select(evaluation::StabilityMaps(o.scenes_dir), o.maps, "--maps",
                  [](const evaluation::StabilityMapSpec& m) { return m.name; });
  }
  const evaluation::DropSweepOptions drop_sweep = DropSweep(o, shard_index, shard_count);
  const evaluation::DropPlan drop_plan =
      o.skip_drops ? evaluation::DropPlan{} : evaluation::PlanDropSweep(drop_sweep);
  evaluation::ScalingOptions scaling_options;
  if (!o.scaling_sizes.empty()) {
    scaling_options.sizes = o.scaling_sizes;
  } else if (o.quick) {
    scaling_options.sizes = kQuickScalingSizes;
  }
  scaling_options.steps_per_repeat = o.scaling_steps;
  scaling_options.rounds = o.scaling_rounds;
  scaling_options.cpu_limit_s = o.cpu_limit_s;
  scaling_options.memory_limit_bytes = o.scaling_memory_gib * kGibibyte;
  scaling_options.shard_index = shard_index;
  scaling_options.shard_count = shard_count;
  scaling_options.progress = Progress;

  fs::create_directories(o.out_dir);
  // first, while this process holds little: each measurement's process starts with its memory
  std::vector<evaluation::ScalingRow> scaling;
  if (!o.skip_scaling) {
    scaling = evaluation::RunScaling(methods, scaling_options);
    WriteFileAtomically((fs::path(o.out_dir) / kScalingCsv).string(),
                        evaluation::ScalingCsv(scaling));
    // a shard's slopes would fit a part of the sizes: the merge prints them
    if (shard_count == 1) PrintScalingSlopes(scaling);
  }
  std::vector<evaluation::WorkPrecisionRow> wp;
  std::vector<evaluation::StabilityRow> st;
  if (!o.skip_work_precision) {
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
    st = evaluation::RunStabilityMaps(maps, methods, steps, shard_index, shard_count, o.cpu_limit_s,
                                      Progress);
    WriteFileAtomically((fs::path(o.out_dir) / "stability.csv").string(),
                        evaluation::StabilityCsv(st));
  }
  // the drop sweep's part of this shard: drop_sweep.csv, and the mesh and the scene of every
  // failed case in drop_failures/
  std::vector<evaluation::DropRow> drops;
  if (!o.skip_drops) {
    drops = evaluation::RunDropSweep(drop_sweep, drop_plan);
    WriteFileAtomically((fs::path(o.out_dir) / kDropCsv).string(), evaluation::DropSweepCsv(drops));
  }
  // a shard's charts would show a part of the sweep: they are drawn by the merge
  for (const std::string& path :
       WriteBenchReport(o.out_dir, wp, st, drops, scaling, o.charts && shard_count == 1)) {
    std::printf("wrote %s\n", path.c_str());
  }
  // (a shard's ratios would cover a part of the sweep: the merge prints them)
  if (shard_count == 1) PrintAutoCost(wp);
}

}  // namespace

void AddBenchCommand(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* bench = app.add_subcommand(
      "bench",
      "Speed against accuracy: work-precision charts of every contact model and of "
      "MuJoCo, Bullet and ODE (where built), and stability maps (docs/benchmarks.md)");
  bench->add_option("-o,--output", o->out_dir, "output folder")->capture_default_str();
  bench->add_flag("--quick", o->quick,
                  "steps 0.01 and 0.002 s only, converged scenes cut to 0.5 s, 3 drops per "
                  "mesh kind and 10 collection files (for CI)");
  // listed from the scenarios themselves, so that the help names every one
  bench
      ->add_option("--scenarios", o->scenarios,
                   fmt::format("work-precision scenarios (default all): {}",
                               fmt::join(evaluation::WorkPrecisionScenarioNames(), ", ")))
      ->delimiter(',');
  bench
      ->add_option(
          "--methods", o->methods,
          "methods (default all available but auto-least-energy): hull, hull-tol1e-08, "
          "hull-tol1e-05, auto, auto-least-energy, planar, multipatch, point, mujoco-default, "
          "mujoco-coulomb, bullet-default, bullet-coulomb, ode-default, ode-coulomb")
      ->delimiter(',');
  bench
      ->add_option("--maps", o->maps,
                   "stability maps (default all): impact, thin_plate, tbar_mass_ratio, "
                   "push_speed")
      ->delimiter(',');
  bench
      ->add_option("--steps", o->steps,
                   "step sizes in s, each dividing 0.02 (default 0.02,0.01,0.005,0.002,0.001,"
                   "0.0005,0.0002)")
      ->delimiter(',')
      ->check(FinitePositive("--steps", engine::kTimeRange));
  bench
      ->add_option("--shard", o->shard,
                   "run part i of N of the sweep (i/N); join the parts with --merge")
      ->capture_default_str();
  bench->add_flag("--no-work-precision", o->skip_work_precision, "skip the work-precision sweep");
  bench->add_flag("--no-stability", o->skip_stability, "skip the stability maps");
  bench->add_flag("--no-drops", o->skip_drops, "skip the drop sweep");
  bench->add_flag("--no-scaling", o->skip_scaling,
                  "skip the scaling benchmark (cost per step against the number of bodies)");
  bench
      ->add_option(
          "--scaling-sizes", o->scaling_sizes,
          fmt::format("scaling: body counts, boxes in stacks of {} on a grid (default "
                      "{}; --quick {})",
                      evaluation::kStackHeight, fmt::join(evaluation::DefaultScalingSizes(), ","),
                      fmt::join(kQuickScalingSizes, ",")))
      ->delimiter(',')
      ->check(IntegerInRange("--scaling-sizes", 1, evaluation::kMaxGridBodies));
  bench
      ->add_option("--scaling-steps", o->scaling_steps,
                   fmt::format("scaling: steps per timed block ({} blocks after {} warm-up "
                               "steps, then as many steps again for the memory check)",
                               evaluation::ScalingOptions{}.repeats,
                               evaluation::ScalingOptions{}.warmup_steps))
      ->capture_default_str()
      ->check(IntegerInRange("--scaling-steps", 1, kMaxScalingSteps));
  bench
      ->add_option("--scaling-rounds", o->scaling_rounds,
                   "scaling: times each measurement is made, all once per round; the report "
                   "gives the median")
      ->capture_default_str()
      ->check(IntegerInRange("--scaling-rounds", 1, kMaxScalingRounds));
  bench
      ->add_option("--scaling-memory-limit", o->scaling_memory_gib,
                   "scaling: GiB of address space each measurement's process may take; a run "
                   "that needs more fails (it would page out the machine)")
      ->capture_default_str()
      ->check(IntegerInRange("--scaling-memory-limit", 1, kMaxScalingMemoryGib));
  bench
      ->add_option("--drop-kinds", o->drop_kinds,
                   "drop sweep: mesh kinds (default all): convex, l_shape, t_shape, u_shape, "
                   "torus, plate, needle, coplanar, terrain, disconnected, file (the collection)")
      ->delimiter(',');
  bench
      ->add_option("--drop-steps", o->drop_steps,
                   "drop sweep: step sizes (default both): fixed (h = 0.01 s), scaled (h = "
                   "0.01 s sqrt(size / 1 m))")
      ->delimiter(',');
  bench
      ->add_option("--drop-seeds", o->drop_seeds,
                   "drop sweep: cases per generated kind (default 120; --quick 3)")
      ->check(CLI::NonNegativeNumber);
  bench
      ->add_option("--drop-meshes", o->drop_meshes,
                   "drop sweep: folders of mesh files, searched recursively")
      ->capture_default_str()
      ->expected(1, -1);
  bench
      ->add_option("--drop-poses", o->drop_poses,
                   "drop sweep: poses per collection file (default 3; --quick 1, first 10 files)")
      ->check(CLI::NonNegativeNumber);
  bench
      ->add_option("--drop-case", o->drop_cases,
                   "drop sweep: run only these cases, KIND:SEED or MESH_FILE:SEED (as "
                   "results.md lists failures)")
      ->expected(1, -1);
  bench->add_flag("!--no-charts", o->charts, "write CSV and results.md only");
  bench
      ->add_option("--merge", o->merge,
                   "join the CSVs of these shard output folders into -o and draw the charts")
      ->expected(1, -1);
  bench
      ->add_option("--scenes", o->scenes_dir,
                   "folder of desk.yaml, tbar.yaml, dumbbell.yaml, stack.yaml, push_box.yaml, "
                   "tbar_push.yaml, pyramid.yaml, train.yaml, peg_in_hole.yaml, dominoes.yaml")
      ->capture_default_str();
  bench->add_option("--cpu-limit", o->cpu_limit_s, "CPU seconds allowed per run")
      ->capture_default_str()
      ->check(FinitePositive("--cpu-limit", engine::kTimeRange));
  bench->callback([o] { Run(*o); });
}

}  // namespace ecpsim::app
