#pragma once
// Sub-commands of the ecpsim CLI; each adds itself to the CLI11 app and runs when selected.

#include <CLI/CLI.hpp>

namespace ecpsim::app {

/// `ecpsim hull MESH [--json] [--scale S] [--mass M | --density RHO]`
void AddHullCommand(CLI::App& app);

/// `ecpsim meshes [DIR]`: regenerates the paper's desk, T-bar and dumbbell meshes.
void AddMeshesCommand(CLI::App& app);

}  // namespace ecpsim::app
