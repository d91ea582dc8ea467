#pragma once
// The paper's figures from a run's output folder: time plots and contact-patch snapshots as PNG,
// drawn by gnuplot (`ecpsim plot DIR`).

#include <string>
#include <vector>

namespace ecpsim::app {

/// Which figures to draw: the paper's, by scenario, or generic position/velocity plots.
enum class PlotKind { kAuto, kDesk, kTBar, kDumbbell, kGeneric };

/// "auto", "desk", "tbar", "dumbbell", "generic" → PlotKind.
/// @throws InputError naming `--scene` and the value for anything else.
PlotKind ParsePlotKind(const std::string& name);

/// Reads DIR/trajectory.csv (and DIR/summary.json, whose "scene" key names the scene file for
/// kAuto and for the snapshots) and writes, in DIR, each PNG atomically:
/// - desk: desk_velocity.png (v_x and ω_z vs t; with DIR/trajectory_planar.csv and/or
///   DIR/trajectory_multipatch.csv, their curves and the differences from trajectory.csv) and
///   desk_patches.png (contact-patch snapshots at six times);
/// - T-bar: tbar_ecp.png (a_x, a_y, a_z vs t), tbar_qz.png, tbar_vz_ax.png (v_z above a_x, the
///   contact-mode changes marked) and tbar_patches.png (snapshots at mode changes);
/// - dumbbell: dumbbell_cm.png (CM position vs t) and dumbbell_patches.png (snapshots at the
///   paper's times 0.01, 0.25, 0.5, 1.75, 2.5 s);
/// - generic: position.png and velocity.png.
/// A snapshot is the top-down view of ExtractContactPatch on the body's mesh at that row's pose:
/// polygons, segments and points, the patch's convex hull (dashed), the ECP (×) and the CM's
/// projection (○). kAuto picks the kind from the scene file's name (desk/tbar/dumbbell.yaml).
/// Returns the PNG paths written.
/// @throws InputError for a missing/bad CSV or summary.json, a scene file that cannot be found
///         (a relative "scene" is taken from the current folder, as `ecpsim run` was given it),
///         a sibling trajectory whose times differ, or a missing/failing gnuplot.
std::vector<std::string> PlotRun(const std::string& dir, PlotKind kind);

}  // namespace ecpsim::app
