#pragma once
// Sub-commands of the ecpsim CLI; each adds itself to the CLI11 app and runs when selected.

#include <CLI/CLI.hpp>

#include "engine/scene_io/loaded_scene.h"

namespace ecpsim::app {

/// `ecpsim hull MESH [--json] [--scale S] [--mass M | --density RHO]`
void AddHullCommand(CLI::App& app);

/// `ecpsim meshes [DIR]`: regenerates the paper's desk, T-bar and dumbbell meshes.
void AddMeshesCommand(CLI::App& app);

/// `ecpsim run SCENE -o DIR [--dt H] [--duration T] [--set key=value]...`, and
/// `ecpsim run --resume DIR` to continue a run (or drop) that stopped early.
void AddRunCommand(CLI::App& app);

/// `ecpsim drop MESH -o DIR [--height H] [--tilt DEG] [--spin W] [--duration T] [--mass M]`
void AddDropCommand(CLI::App& app);

/// Prints the scene's warnings (LoadedScene::warnings), one line each on stderr.
void PrintWarnings(const engine::LoadedScene& loaded);

/// `ecpsim compare EXPECTED.png ACTUAL.png [--diff OUT.png] [--threshold N] [--max-fraction F]`
/// (exit 0 same, 1 different, 2 bad input).
void AddCompareCommand(CLI::App& app);

/// `ecpsim plot DIR [--scene desk|tbar|dumbbell|generic|auto]`: PNG plots of a run via gnuplot.
void AddPlotCommand(CLI::App& app);

/// `ecpsim render SCENE --time T -o frame.png`: one frame, simulated up to T.
void AddRenderCommand(CLI::App& app);

/// `ecpsim bench [-o DIR] [--quick] [--scenarios …] [--methods …] [--shard i/N] [--merge DIR…]`:
/// work–precision charts and stability maps (docs/benchmarks.md).
void AddBenchCommand(CLI::App& app);

}  // namespace ecpsim::app
