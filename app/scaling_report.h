#pragma once
// The scaling benchmark's part of `ecpsim bench`'s report: its chart (cost per step against the
// number of bodies, log–log, the fitted slope in the legend) and its section of results.md.

#include <string>
#include <vector>

#include "app/plot_writer.h"
#include "evaluation/scaling.h"

namespace ecpsim::app {

/// Adds scaling.png to `writer`: CPU time per step against bodies on log–log axes, a line per
/// method whose runs did not all fail, its fitted slope (evaluation::FitScaling) in its title.
/// Nothing when `rows` is empty.
void ScalingChart(PlotWriter& writer, const std::vector<evaluation::ScalingRow>& rows);

/// results.md's section "Scaling": how it was measured, the CPU and wall time per step, the CPU
/// time per body per step and the memory, each a table of a row per method and a column per N,
/// and every failure with its message; "" when `rows` is empty.
std::string ScalingMarkdown(const std::vector<evaluation::ScalingRow>& rows);

}  // namespace ecpsim::app
