#pragma once
// What `ecpsim bench` draws and writes from its rows: work–precision charts (one per scenario),
// stability maps (one per map, a panel per method), the scaling chart and results.md with the
// tables (the drop sweep's and the scaling benchmark's too).

#include <string>
#include <vector>

#include "evaluation/drop_sweep.h"
#include "evaluation/scaling.h"
#include "evaluation/stability_map.h"
#include "evaluation/work_precision.h"

namespace ecpsim::app {

/// Writes into `dir`: work_precision_<scenario>.png, stability_<map>.png, scaling.png (gnuplot)
/// and results.md (atomically). Returns the paths written.
/// @throws InputError if gnuplot fails or a file cannot be written.
std::vector<std::string> WriteBenchReport(
    const std::string& dir, const std::vector<evaluation::WorkPrecisionRow>& work_precision,
    const std::vector<evaluation::StabilityRow>& stability,
    const std::vector<evaluation::DropRow>& drops,
    const std::vector<evaluation::ScalingRow>& scaling, bool charts);

}  // namespace ecpsim::app
