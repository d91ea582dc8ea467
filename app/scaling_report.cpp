#include "app/scaling_report.h"

#include <algorithm>
#include <functional>
#include <set>

#include <fmt/format.h>

#include "app/method_style.h"
#include "evaluation/stack_grid.h"

namespace ecpsim::app {
namespace {

using evaluation::ScalingRow;

std::set<long> Sizes(const std::vector<ScalingRow>& rows) {
  std::set<long> sizes;
  for (const ScalingRow& r : rows) sizes.insert(r.bodies);
  return sizes;
}

std::string Slope(const std::vector<ScalingRow>& rows, const std::string& method, bool wall) {
  const auto fit = evaluation::FitScaling(rows, method, wall);
  return fit ? fmt::format("{:.2f}", fit->exponent) : "–";
}

// which time a table's last column fits: none (no column), CPU or wall-clock time
enum class SlopeColumn { kNone, kCpu, kWall };

// a table of a row per method and a column per N: `cell(row)` of the method's row at that N,
// "failed" for a failed run, blank where not run; then the fitted slope of `slope`'s time
std::string MethodBySizeTable(const std::vector<ScalingRow>& rows,
                              const std::function<std::string(const ScalingRow&)>& cell,
                              SlopeColumn slope) {
  const std::set<long> sizes = Sizes(rows);
  const bool slopes = slope != SlopeColumn::kNone;
  std::string md = "| method |";
  for (long n : sizes) md += fmt::format(" N = {} |", n);
  md += slopes ? " slope |\n|---|" : "\n|---|";
  for (size_t i = 0; i < sizes.size() + (slopes ? 1 : 0); ++i) md += "---|";
  md += "\n";
  for (const std::string& method : InOrder(rows, MethodOf<ScalingRow>, MethodOrder())) {
    md += "| " + method + " |";
    for (long n : sizes) {
      std::string entry = " |";
      for (const ScalingRow& r : rows) {
        if (r.method == method && r.bodies == n)
          entry = r.failed ? " failed |" : " " + cell(r) + " |";
      }
      md += entry;
    }
    if (slopes) md += " " + Slope(rows, method, slope == SlopeColumn::kWall) + " |";
    md += "\n";
  }
  return md + "\n";
}

std::string Mib(double mib) { return mib < 0 ? "–" : fmt::format("{:.1f}", mib); }

}  // namespace

void ScalingChart(PlotWriter& writer, const std::vector<ScalingRow>& rows) {
  std::string plot;
  for (const std::string& method : InOrder(rows, MethodOf<ScalingRow>, MethodOrder())) {
    std::string data = "# bodies cpu_ms_per_step\n";
    int points = 0;
    long largest_fitted = 0;
    for (long n : Sizes(rows)) {
      for (const ScalingRow& r : rows) {
        if (r.method == method && r.bodies == n && !r.failed) {
          data += fmt::format("{} {:.9g}\n", n, 1e3 * r.cpu_per_step);
          ++points;
          largest_fitted = n;
        }
      }
    }
    if (points == 0) continue;
    const auto fit = evaluation::FitScaling(rows, method, false);
    // a fit that stops short of the largest N says where (the larger runs failed)
    const std::string reach =
        largest_fitted < *Sizes(rows).rbegin() ? fmt::format(" to N = {}", largest_fitted) : "";
    const std::string title =
        fit ? fmt::format("{} (slope {:.2f}{})", method, fit->exponent, reach) : method;
    plot += fmt::format("{}{} using 1:2 with linespoints lw 2 {} title {}",
                        plot.empty() ? "plot " : ", \\\n  ", writer.Data("scaling_" + method, data),
                        MethodLineStyle(method), GnuplotQuote(title));
  }
  if (plot.empty()) return;
  writer.BeginPng("scaling.png", 1100, 750);
  writer.Line("set logscale xy\nset format y '10^{%L}'");
  writer.Line(fmt::format(
      "set title {} noenhanced",
      GnuplotQuote(fmt::format("cost per step against bodies: stacks of {} boxes at rest on a grid",
                               evaluation::kStackHeight))));
  writer.Line(fmt::format("set key title {} noenhanced",
                          GnuplotQuote(fmt::format("slope: log-log fit from N = {} (1 = linear)",
                                                   evaluation::kSlopeFitMinBodies))));
  writer.Line("set xlabel 'bodies N'");
  writer.Line("set ylabel 'CPU ms per step (median)'");
  writer.Line("set key outside right noenhanced");
  writer.Line(plot);
  writer.EndPng();
}

std::string ScalingMarkdown(const std::vector<ScalingRow>& rows) {
  if (rows.empty()) return "";
  // the protocol, read from a run that completed it (every row of one bench has the same)
  const ScalingRow* done = nullptr;
  for (const ScalingRow& r : rows) {
    if (!r.failed) done = &r;
  }
  std::string md = fmt::format(
      "## Scaling: cost per step against the number of bodies\n\n"
      "N boxes of {:g} m, {:g} kg, in stacks of {} at rest on a square grid {:g} m apart "
      "(`evaluation/stack_grid.h`; contact pairs: each box with the ground and the boxes of its "
      "stack), h = {:g} s. Each method and N is measured in rounds (all of them once per round, "
      "so that a group's rounds lie minutes apart), each in a process of its own (forked): ",
      evaluation::kGridBoxSize, evaluation::kGridBoxMass, evaluation::kStackHeight,
      evaluation::kStackSpacing, evaluation::kGridStep);
  if (done) {
    const long k = done->steps / 2;
    md += fmt::format(
        "{} warm-up steps, then {} timed blocks of {} steps (K = {} steps), then K steps more; "
        "times are the median over {} rounds of the median over the blocks of a block's time "
        "per step",
        k - done->timed_steps, done->repeats, done->timed_steps / done->repeats, k, done->rounds);
  } else {
    md += "every run failed";
  }
  md += fmt::format(
      ". The slope is the least-squares fit of log(time per step) against log N from N = {} (the "
      "first whole stack) on: 1 means the cost grows in proportion to the bodies (a constant cost "
      "per body), 2 with their square, below 1 a fixed cost per step still dominates.\n\n",
      evaluation::kSlopeFitMinBodies);
  md += "CPU time per step (ms; thread CPU time):\n\n" +
        MethodBySizeTable(
            rows, [](const ScalingRow& r) { return fmt::format("{:.3g}", 1e3 * r.cpu_per_step); },
            SlopeColumn::kCpu);
  md += "Wall-clock time per step (ms):\n\n" +
        MethodBySizeTable(
            rows, [](const ScalingRow& r) { return fmt::format("{:.3g}", 1e3 * r.wall_per_step); },
            SlopeColumn::kWall);
  md += "CPU time per body per step (µs):\n\n" +
        MethodBySizeTable(
            rows,
            [](const ScalingRow& r) {
              return fmt::format("{:.3g}", 1e6 * r.cpu_per_step / r.bodies);
            },
            SlopeColumn::kNone);
  md +=
      "Memory: the measuring process's peak resident set (MiB; VmHWM, the bench's own memory "
      "included, see the start below) and, in parentheses, how much its resident set grew from "
      "K to 2K steps (MiB; 0: bounded, no growth with the run's length):\n\n" +
      MethodBySizeTable(
          rows,
          [](const ScalingRow& r) {
            return fmt::format("{} ({:+.1f})", Mib(r.rss_peak_mib), r.rss_2k_mib - r.rss_k_mib);
          },
          SlopeColumn::kNone);
  double start = -1;
  for (const ScalingRow& r : rows) start = std::max(start, r.rss_start_mib);
  md += fmt::format(
      "Resident at a measurement's start (the bench before any scene): up to {} MiB.\n\n",
      Mib(start));
  std::string failures;
  for (const ScalingRow& r : rows) {
    if (!r.failed) continue;
    std::string message = r.failure;
    std::replace(message.begin(), message.end(), '|', '/');  // a table cell's delimiter
    failures += fmt::format("| {} | {} | {} | {} | {} |\n", r.method, r.bodies, r.steps,
                            Mib(r.rss_peak_mib), message);
  }
  if (!failures.empty()) {
    md +=
        "Failures (a round's; the peak resident set when it failed, – where not read):\n\n"
        "| method | N | steps done | peak RSS (MiB) | message |\n|---|---|---|---|---|\n" +
        failures + "\n";
  }
  return md;
}

}  // namespace ecpsim::app
