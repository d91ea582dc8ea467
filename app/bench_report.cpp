#include "app/bench_report.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <set>

#include <fmt/format.h>

#include "app/method_style.h"
#include "app/plot_writer.h"
#include "app/scaling_report.h"
#include "common/atomic_file.h"
#include "evaluation/auto_cost.h"
#include "evaluation/clutter_bin.h"
#include "evaluation/method.h"
#include "evaluation/scenario.h"

namespace ecpsim::app {
namespace {

namespace fs = std::filesystem;
using evaluation::Outcome;
using evaluation::StabilityRow;
using evaluation::WorkPrecisionRow;

// log axes cannot show 0: errors below this are drawn on it (and say so in the chart)
constexpr double kErrorFloor = 1e-16;  // m
// the drop sweep's tables: how many slowest cases, and how much of a failure's message
constexpr size_t kSlowestDrops = 10;
constexpr size_t kMessageLength = 300;  // characters

std::vector<std::string> MapOrder() {
  std::vector<std::string> names;
  // names only: a map reads its scene files when its scenarios are made, not here
  for (const evaluation::StabilityMapSpec& m : evaluation::StabilityMaps(""))
    names.push_back(m.name);
  return names;
}

std::string ScenarioOf(const WorkPrecisionRow& r) { return r.scenario; }
std::string MapOf(const StabilityRow& r) { return r.map; }

std::vector<double> SortedValues(const std::vector<StabilityRow>& rows, const std::string& map,
                                 bool steps) {
  std::set<double> values;
  for (const StabilityRow& r : rows) {
    if (r.map == map) values.insert(steps ? r.h : r.value);
  }
  return {values.begin(), values.end()};
}

std::string Sci(double value) { return value < 0 ? "–" : fmt::format("{:.2g}", value); }

void WorkPrecisionCharts(PlotWriter& writer, const std::vector<WorkPrecisionRow>& rows) {
  for (const std::string& scenario :
       InOrder(rows, ScenarioOf, evaluation::WorkPrecisionScenarioNames())) {
    // the state error where the scenario has a reference, else (a dropped pile) the drift at rest
    const bool referenced = std::any_of(rows.begin(), rows.end(), [&](const WorkPrecisionRow& r) {
      return r.scenario == scenario && r.error_state >= 0;
    });
    const auto precision = [&](const WorkPrecisionRow& r) {
      return referenced ? r.error_state : r.drift;
    };
    std::string plot;
    for (const std::string& method : InOrder(rows, MethodOf<WorkPrecisionRow>, MethodOrder())) {
      std::vector<const WorkPrecisionRow*> points;
      for (const WorkPrecisionRow& r : rows) {
        // a point needs both numbers: failed and zero-time runs have no cost (−1)
        if (r.scenario == scenario && r.method == method && !r.failed && precision(r) >= 0 &&
            r.cpu_per_sim_s >= 0) {
          points.push_back(&r);
        }
      }
      if (points.empty()) continue;
      std::sort(points.begin(), points.end(),
                [](const auto* a, const auto* b) { return a->h > b->h; });
      std::string data =
          fmt::format("# cpu_per_sim_s {} h\n", referenced ? "error_state" : "drift");
      for (const WorkPrecisionRow* r : points) {
        data += fmt::format("{:.9g} {:.9g} {:.9g}\n", r->cpu_per_sim_s,
                            std::max(kErrorFloor, precision(*r)), r->h);
      }
      const std::string file = writer.Data(fmt::format("wp_{}_{}", scenario, method), data);
      plot += fmt::format("{}{} using 1:2 with linespoints lw 2 {} title {}",
                          plot.empty() ? "plot " : ", \\\n  ", file, MethodLineStyle(method),
                          GnuplotQuote(method));
    }
    if (plot.empty()) continue;
    writer.BeginPng(fmt::format("work_precision_{}.png", scenario), 1100, 750);
    writer.Line("set logscale xy\nset format x '10^{%L}'\nset format y '10^{%L}'");
    writer.Line(fmt::format("set title {} noenhanced",
                            GnuplotQuote(fmt::format("work-precision: {} (each point one step "
                                                     "size; {} < {:g} m drawn at {:g})",
                                                     scenario, referenced ? "errors" : "drifts",
                                                     kErrorFloor, kErrorFloor))));
    writer.Line("set xlabel 'CPU seconds per simulated second'");
    writer.Line(referenced ? "set ylabel 'max state error |dp| + L |dtheta| (m)'"
                           : "set ylabel 'drift at rest: max CM displacement after settling (m)'");
    writer.Line("set key outside right noenhanced");
    writer.Line(plot);
    writer.EndPng();
  }
}

const char* kOutcomeColours[evaluation::kOutcomeCount] = {
    "#2ca02c", "#d62728", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};

void StabilityCharts(PlotWriter& writer, const std::vector<StabilityRow>& rows) {
  for (const std::string& map : InOrder(rows, MapOf, MapOrder())) {
    const std::vector<double> steps = SortedValues(rows, map, true);
    const std::vector<double> values = SortedValues(rows, map, false);
    std::vector<StabilityRow> of_map;
    for (const StabilityRow& r : rows) {
      if (r.map == map) of_map.push_back(r);
    }
    const std::vector<std::string> methods = InOrder(of_map, MethodOf<StabilityRow>, MethodOrder());
    // one panel per method and one for the key
    const int n = static_cast<int>(methods.size());
    const int cols = std::min(n + 1, 4);
    const int panel_rows = (n + 1 + cols - 1) / cols;
    writer.BeginPng(fmt::format("stability_{}.png", map), 360 * cols, 300 * panel_rows + 80);
    std::string xtics, ytics;
    for (size_t i = 0; i < steps.size(); ++i)
      xtics += fmt::format("{}'{:g}' {}", i ? ", " : "", steps[i], i);
    for (size_t j = 0; j < values.size(); ++j)
      ytics += fmt::format("{}'{:g}' {}", j ? ", " : "", values[j], j);
    writer.Line(fmt::format("set multiplot layout {},{} title {} noenhanced", panel_rows, cols,
                            GnuplotQuote(fmt::format("stability map: {}", map))));
    std::string palette;
    for (int k = 0; k < evaluation::kOutcomeCount; ++k) {
      palette += fmt::format("{}{} '{}'", k ? ", " : "", k, kOutcomeColours[k]);
    }
    writer.Line(fmt::format("set palette maxcolors {}\nset palette defined ({})",
                            evaluation::kOutcomeCount, palette));
    writer.Line(fmt::format("set cbrange [-0.5:{}]\nunset colorbox\nunset grid",
                            evaluation::kOutcomeCount - 0.5));
    writer.Line(fmt::format("set xtics ({}) rotate by 45 right\nset ytics ({})", xtics, ytics));
    writer.Line(fmt::format("set xrange [-0.5:{}]\nset yrange [-0.5:{}]", steps.size() - 0.5,
                            values.size() - 0.5));
    for (const evaluation::StabilityMapSpec& spec : evaluation::StabilityMaps("")) {
      if (spec.name == map) {
        writer.Line(fmt::format("set ylabel {} noenhanced", GnuplotQuote(spec.value_label)));
      }
    }
    writer.Line("set xlabel 'h (s)'");
    for (int m = 0; m < n; ++m) {
      std::string data;
      for (const StabilityRow& r : rows) {
        if (r.map != map || r.method != methods[m]) continue;
        const auto i = std::find(steps.begin(), steps.end(), r.h) - steps.begin();
        const auto j = std::find(values.begin(), values.end(), r.value) - values.begin();
        data += fmt::format("{} {} {}\n", i, j, static_cast<int>(r.outcome));
      }
      const std::string file = writer.Data(fmt::format("st_{}_{}", map, methods[m]), data);
      writer.Line(fmt::format("set title {} noenhanced", GnuplotQuote(methods[m])));
      writer.Line("unset key");
      writer.Line(fmt::format("plot {} using 1:2:3 with image notitle", file));
    }
    writer.Line(
        "unset title\nunset border\nunset xtics\nunset ytics\nunset xlabel\n"
        "unset ylabel\nset xrange [0:1]\nset yrange [0:1]\n"
        "set key center center vertical noenhanced");
    std::string key = "plot ";
    for (int k = 0; k < evaluation::kOutcomeCount; ++k) {
      key += fmt::format("{}NaN with boxes fs solid lc rgb '{}' title {}", k ? ", " : "",
                         kOutcomeColours[k],
                         GnuplotQuote(evaluation::OutcomeName(static_cast<Outcome>(k))));
    }
    writer.Line(key);
    writer.EndPng();
  }
}

// the columns "h = …" (largest first) of a scenario's table and a row per method that has a
// value: `cell(row)` formats a measured row, an unmeasured one is blank or "failed"
std::string MethodByStepTable(const std::vector<WorkPrecisionRow>& wp, const std::string& scenario,
                              const std::set<double>& steps,
                              const std::function<double(const WorkPrecisionRow&)>& value,
                              const std::function<std::string(const WorkPrecisionRow&)>& cell) {
  std::string md = "| method |";
  for (auto h = steps.rbegin(); h != steps.rend(); ++h) md += fmt::format(" h = {:g} |", *h);
  md += "\n|---|";
  for (size_t i = 0; i < steps.size(); ++i) md += "---|";
  md += "\n";
  for (const std::string& method : InOrder(wp, MethodOf<WorkPrecisionRow>, MethodOrder())) {
    std::string line;
    for (auto h = steps.rbegin(); h != steps.rend(); ++h) {
      std::string entry = " |";
      for (const WorkPrecisionRow& r : wp) {
        if (r.scenario != scenario || r.method != method || r.h != *h) continue;
        entry = value(r) < 0 ? (r.failed ? " failed |" : " |") : " " + cell(r) + " |";
      }
      line += entry;
    }
    if (line.find_first_not_of(" |") != std::string::npos) md += "| " + method + " |" + line + "\n";
  }
  return md + "\n";
}

// the step sizes at which `value` was measured for `scenario` (it is negative where not)
std::set<double> MeasuredSteps(const std::vector<WorkPrecisionRow>& wp, const std::string& scenario,
                               const std::function<double(const WorkPrecisionRow&)>& value) {
  std::set<double> steps;
  for (const WorkPrecisionRow& r : wp)
    if (r.scenario == scenario && value(r) >= 0) steps.insert(r.h);
  return steps;
}

// a push scenario's force against its closed form, per method at each step size (empty when
// the scenario has no push)
std::string PushForceTable(const std::vector<WorkPrecisionRow>& wp, const std::string& scenario) {
  const auto value = [](const WorkPrecisionRow& r) { return r.push_force_error; };
  const std::set<double> steps = MeasuredSteps(wp, scenario, value);
  if (steps.empty()) return "";
  return fmt::format(
             "The pusher's force on the body it touches after it settled ({:g} s after the first "
             "contact), each step against the closed form F = Σ μ m g, the ground friction of the "
             "bodies it pushes: max |f − F| / F, and in parentheses the share of steps in which "
             "the contact broke (f ≤ 0).\n\n",
             evaluation::kPushSettleTime) +
         MethodByStepTable(wp, scenario, steps, value, [](const WorkPrecisionRow& r) {
           return fmt::format("{} ({:.0f} %)", Sci(r.push_force_error),
                              100 * r.push_contact_breaks);
         });
}

// a scenario's drift (WorkPrecisionRow::drift) per method at each step size (empty when the
// scenario does not measure it)
std::string DriftTable(const std::vector<WorkPrecisionRow>& wp, const std::string& scenario) {
  const auto value = [](const WorkPrecisionRow& r) { return r.drift; };
  const std::set<double> steps = MeasuredSteps(wp, scenario, value);
  if (steps.empty()) return "";
  using evaluation::kClutterSettleTime, evaluation::kDominoesSettleTime;
  const std::string settled =
      kDominoesSettleTime == kClutterSettleTime
          ? fmt::format("{:g} s", kClutterSettleTime)
          : fmt::format("{:g} s and {:g} s", kDominoesSettleTime, kClutterSettleTime);
  return fmt::format(
             "Drift: the largest displacement (m) of any body's CM from its start over the run "
             "(for a push, across the push direction only; for the dominoes and the clutter "
             "bins, from its place at {}, when the pile has settled, to the run's end: its "
             "drift at rest).\n\n",
             settled) +
         MethodByStepTable(wp, scenario, steps, value,
                           [](const WorkPrecisionRow& r) { return Sci(r.drift); });
}

// auto against hull per scenario (evaluation/auto_cost.h); empty where no scenario ran both
std::string AutoCostMarkdown(const std::vector<WorkPrecisionRow>& wp) {
  const std::vector<evaluation::AutoCost> costs = evaluation::CompareAutoWithHull(wp);
  if (costs.empty()) return "";
  std::string md = fmt::format(
      "### auto against hull\n\nCPU per simulated second of `auto` over `hull`'s in this run, at "
      "each step size both completed: the median over the sweep and the largest. `auto` is "
      "dearer where the median exceeds {:g} (one run's noise).\n\n"
      "| scenario | steps | median | largest (at h) | verdict |\n|---|---|---|---|---|\n",
      evaluation::kMaxAutoOverHull);
  for (const evaluation::AutoCost& c : costs) {
    md += fmt::format("| {} | {} | {:.2f} | {:.2f} ({:g}) | {} |\n", c.scenario, c.steps, c.median,
                      c.largest, c.largest_h, c.Dearer() ? "**dearer**" : "ok");
  }
  return md + "\n";
}

std::string ResultsMarkdown(const std::vector<WorkPrecisionRow>& wp,
                            const std::vector<StabilityRow>& stability) {
  std::string md = "# ecpsim bench results\n\n";
  if (!wp.empty()) {
    md +=
        "## Work–precision\n\nState error max |Δp| + L·|Δθ| (m) against the reference; CPU s "
        "per simulated s; at the coarsest and finest step of the sweep; `fail` = failed runs "
        "of the sweep. `ref ±` estimates the reference's own error: 0 for a "
        "closed form; for a converged reference the state error between it and the same "
        "method at twice its step, below which an error is not resolved. For converged "
        "references, `vs hull` is the state error of the finest run against the hull model's "
        "converged solution (cross-model agreement).\n\n";
    for (const std::string& scenario :
         InOrder(wp, ScenarioOf, evaluation::WorkPrecisionScenarioNames())) {
      md += fmt::format(
          "### {}\n\n| method | h coarse | error | CPU s/s | h fine | error | CPU "
          "s/s | ref ± | max penetration (m) | wrong mode | vs hull | fail |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|\n",
          scenario);
      for (const std::string& method : InOrder(wp, MethodOf<WorkPrecisionRow>, MethodOrder())) {
        const WorkPrecisionRow *coarse = nullptr, *fine = nullptr;
        int failures = 0;
        double penetration = 0, wrong = 0;
        for (const WorkPrecisionRow& r : wp) {
          if (r.scenario != scenario || r.method != method) continue;
          if (!coarse || r.h > coarse->h) coarse = &r;
          if (!fine || r.h < fine->h) fine = &r;
          failures += r.failed;
          penetration = std::max(penetration, r.max_penetration);
          wrong = std::max(wrong, r.wrong_mode);
        }
        if (!coarse) continue;
        md += fmt::format(
            "| {} | {:g} | {} | {} | {:g} | {} | {} | {} | {} | {:.0f} % | {} | {} |\n", method,
            coarse->h, coarse->failed ? "failed" : Sci(coarse->error_state),
            Sci(coarse->cpu_per_sim_s), fine->h, fine->failed ? "failed" : Sci(fine->error_state),
            Sci(fine->cpu_per_sim_s), Sci(fine->reference_uncertainty), Sci(penetration),
            100 * wrong, Sci(fine->error_vs_hull), failures);
      }
      md += "\n" + PushForceTable(wp, scenario) + DriftTable(wp, scenario);
    }
    md += AutoCostMarkdown(wp);
  }
  if (!stability.empty()) {
    md += "## Stability maps\n\nRuns per outcome over every step size and parameter value.\n\n";
    for (const std::string& map : InOrder(stability, MapOf, MapOrder())) {
      md += fmt::format("### {}\n\n| method |", map);
      for (int k = 0; k < evaluation::kOutcomeCount; ++k) {
        md += fmt::format(" {} |", evaluation::OutcomeName(static_cast<Outcome>(k)));
      }
      md += "\n|---|";
      for (int k = 0; k < evaluation::kOutcomeCount; ++k) md += "---|";
      md += "\n";
      for (const std::string& method : InOrder(stability, MethodOf<StabilityRow>, MethodOrder())) {
        int counts[evaluation::kOutcomeCount] = {};
        int total = 0;
        for (const StabilityRow& r : stability) {
          if (r.map == map && r.method == method) ++counts[static_cast<int>(r.outcome)], ++total;
        }
        if (total == 0) continue;
        md += "| " + method + " |";
        for (int k = 0; k < evaluation::kOutcomeCount; ++k) md += fmt::format(" {} |", counts[k]);
        md += "\n";
      }
      md += "\n";
    }
  }
  return md;
}

std::string Ms(double seconds) { return fmt::format("{:.3g}", 1e3 * seconds); }

// the drop sweep: counts per kind × outcome, the slowest steps, every failure with its rerun
std::string DropMarkdown(const std::vector<evaluation::DropRow>& rows) {
  using evaluation::DropOutcome;
  using evaluation::DropRow;
  std::vector<std::string> kinds;
  for (evaluation::MeshKind k : evaluation::AllMeshKinds()) {
    kinds.push_back(evaluation::MeshKindName(k));
  }
  kinds.push_back(evaluation::kFileKind);
  int dropped = 0, skipped = 0, files = 0, failures = 0;
  std::set<std::string> dropped_files;
  for (const DropRow& r : rows) {
    if (r.outcome == DropOutcome::kSkipped) {
      ++skipped;
      continue;
    }
    ++dropped;
    failures += evaluation::IsDropFailure(r.outcome);
    if (r.kind == evaluation::kFileKind) ++files, dropped_files.insert(r.mesh);
  }
  std::string md = fmt::format(
      "## Drop sweep\n\n{} drops: {} of generated meshes and {} of the {} closed meshes found in "
      "the collection folders ({} more files skipped: they do not load or are not closed "
      "solids, drop_sweep.csv says why). Each "
      "mesh is scaled to a bounding-box diagonal (size) drawn log-uniformly in [{:g}, {:g}] m — "
      "collection meshes too, whatever their units — at {:g} kg/m³ with `ecpsim drop`'s friction, "
      "turned uniformly at random, its lowest point {:g}–{:g} × size above the ground, spinning "
      "at up to {:g} × sqrt(g / size) about a random axis, for max({:g} s, fall + {:g} sqrt(size "
      "/ g)), at two step sizes: `fixed` h = {:g} s whatever the size, and `scaled` h = {:g} s × "
      "sqrt(size / 1 m) (with the duration's {:g} s scaled alike), which makes every drop the "
      "dimensionless image of one at size 1 m. The bar: no failure, no mesh vertex deeper than "
      "{:g} × size. **{} of {} drops failed.**\n\n",
      dropped, dropped - files, files, dropped_files.size(), skipped, evaluation::kDropMinSize,
      evaluation::kDropMaxSize, evaluation::kDropDensity, evaluation::kDropMinHeight,
      evaluation::kDropMaxHeight, evaluation::kDropMaxSpin, evaluation::kDropMinDuration,
      evaluation::kDropSettleTimes, evaluation::kDropStep, evaluation::kDropStep,
      evaluation::kDropMinDuration, evaluation::kDropPenetrationBar, failures, dropped);

  md += "| kind | h | drops |";
  for (int k = 0; k < evaluation::kDropOutcomeCount; ++k) {
    if (static_cast<DropOutcome>(k) != DropOutcome::kSkipped) {
      md += fmt::format(" {} |", evaluation::DropOutcomeName(static_cast<DropOutcome>(k)));
    }
  }
  md +=
      " worst penetration ÷ size | max Newton iterations per step | retries | sub-stepped "
      "steps | slowest step (ms) | CPU s |\n|---|---|";
  for (int k = 0; k + 1 < evaluation::kDropOutcomeCount; ++k) md += "---|";
  md += "---|---|---|---|---|---|---|\n";
  const auto add_row = [&](const std::string& label, const std::string& kind,
                           evaluation::DropStep step) {
    int counts[evaluation::kDropOutcomeCount] = {};
    int total = 0, iterations = 0;
    long retries = 0, substepped = 0;
    double penetration = 0, slowest = 0, cpu = 0;
    for (const DropRow& r : rows) {
      if ((!kind.empty() && r.kind != kind) || r.step != step ||
          r.outcome == DropOutcome::kSkipped) {
        continue;
      }
      ++counts[static_cast<int>(r.outcome)], ++total;
      penetration = std::max(penetration, r.max_penetration_rel);
      iterations = std::max(iterations, r.iterations_max);
      retries += r.retries;
      substepped += r.substepped;
      slowest = std::max(slowest, r.max_step_cpu_s);
      cpu += r.cpu_s;
    }
    if (total == 0) return;
    md += fmt::format("| {} | {} | {} |", label, evaluation::DropStepName(step), total);
    for (int k = 0; k < evaluation::kDropOutcomeCount; ++k) {
      if (static_cast<DropOutcome>(k) != DropOutcome::kSkipped) {
        md += fmt::format(" {} |", counts[k]);
      }
    }
    md += fmt::format(" {:.2g} | {} | {} | {} | {} | {:.3g} |\n", penetration, iterations, retries,
                      substepped, Ms(slowest), cpu);
  };
  for (evaluation::DropStep step : {evaluation::DropStep::kFixed, evaluation::DropStep::kScaled}) {
    for (const std::string& kind : kinds) add_row(kind, kind, step);
    add_row("**all**", "", step);
  }

  std::vector<const DropRow*> slowest;
  for (const DropRow& r : rows) {
    if (r.outcome != DropOutcome::kSkipped && r.steps > 0) slowest.push_back(&r);
  }
  std::sort(slowest.begin(), slowest.end(), [](const DropRow* a, const DropRow* b) {
    return a->max_step_cpu_s > b->max_step_cpu_s;
  });
  slowest.resize(std::min<size_t>(slowest.size(), kSlowestDrops));
  if (!slowest.empty()) {
    md += fmt::format(
        "\n### The {} slowest steps\n\nCPU time of one `engine::Step` (thread CPU "
        "clock; the machine's load adds noise), with the case it belongs to.\n\n"
        "| case | mesh | size (m) | h (s) | mesh vertices | hull faces | slowest step "
        "(ms) | mean of its steps (ms) | steps | max Newton iterations |\n"
        "|---|---|---|---|---|---|---|---|---|---|\n",
        slowest.size());
    for (const DropRow* r : slowest) {
      md += fmt::format("| `{}` | {} | {:.3g} | {:.2g} | {} | {} | {} | {} | {} | {} |\n",
                        evaluation::DropCaseKey(r->Case()),
                        r->kind == evaluation::kFileKind ? "" : r->mesh, r->size, r->h, r->vertices,
                        r->hull_faces, Ms(r->max_step_cpu_s), Ms(r->cpu_s / r->steps), r->steps,
                        r->iterations_max);
    }
  }

  md += "\n### Failures\n\n";
  if (failures == 0) return md + "None.\n\n";
  md +=
      "Rerun one with `ecpsim bench --no-work-precision --no-stability --drop-case CASE`, or "
      "run the very files the sweep ran, kept in `drop_failures/` (the mesh as OBJ in metres, "
      "the scene for `ecpsim run`; named kind or file stem, seed and step).\n\n"
      "| case | outcome | mesh | size (m) | h (s) | lowest point (m) | quaternion (w, x, y, z) "
      "| ω (rad/s) | steps done | message |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const DropRow& r : rows) {
    if (!evaluation::IsDropFailure(r.outcome)) continue;
    std::string message = r.message;
    if (message.size() > kMessageLength) message = message.substr(0, kMessageLength) + " …";
    for (char& c : message) {
      if (c == '|') c = '/';
    }
    md += fmt::format(
        "| `{}` | {} | {} | {:.6g} | {:.3g} | {:.6g} | {:.4f}, {:.4f}, {:.4f}, "
        "{:.4f} | {:.4g}, {:.4g}, {:.4g} | {} | {} |\n",
        evaluation::DropCaseKey(r.Case()), evaluation::DropOutcomeName(r.outcome),
        r.kind == evaluation::kFileKind ? "" : r.mesh, r.size, r.h, r.height, r.q0.w(), r.q0.x(),
        r.q0.y(), r.q0.z(), r.w0.x(), r.w0.y(), r.w0.z(), r.steps, message);
  }
  return md + "\n";
}

}  // namespace

std::vector<std::string> WriteBenchReport(const std::string& dir,
                                          const std::vector<WorkPrecisionRow>& work_precision,
                                          const std::vector<StabilityRow>& stability,
                                          const std::vector<evaluation::DropRow>& drops,
                                          const std::vector<evaluation::ScalingRow>& scaling,
                                          bool charts) {
  std::vector<std::string> written;
  if (charts && (!work_precision.empty() || !stability.empty() || !scaling.empty())) {
    PlotWriter writer(dir);
    WorkPrecisionCharts(writer, work_precision);
    StabilityCharts(writer, stability);
    ScalingChart(writer, scaling);
    written = writer.Run();
  }
  const std::string results = (fs::path(dir) / "results.md").string();
  std::string markdown = ResultsMarkdown(work_precision, stability);
  if (!drops.empty()) markdown += DropMarkdown(drops);
  markdown += ScalingMarkdown(scaling);
  WriteFileAtomically(results, markdown);
  written.push_back(results);
  return written;
}

}  // namespace ecpsim::app
