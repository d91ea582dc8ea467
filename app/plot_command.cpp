// `ecpsim plot DIR [--scene desk|tbar|dumbbell|generic|auto]`: the paper's figures from a run.

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/paper_plots.h"

namespace ecpsim::app {
namespace {

struct PlotOptions {
  std::string dir;
  std::string scene = "auto";
};

}  // namespace

void AddPlotCommand(CLI::App& app) {
  auto options = std::make_shared<PlotOptions>();
  CLI::App* plot = app.add_subcommand(
      "plot",
      "Draw PNG plots of a run (DIR/trajectory.csv) with gnuplot: the paper's figures "
      "for the desk, T-bar and dumbbell scenes, with contact-patch snapshots");
  plot->add_option("dir", options->dir, "output folder of `ecpsim run`")->required();
  plot->add_option("--scene", options->scene,
                   "which figures: desk, tbar, dumbbell, generic, or auto (from the scene file "
                   "named in DIR/summary.json)")
      ->capture_default_str();
  plot->callback([options] {
    const std::vector<std::string> pngs = PlotRun(options->dir, ParsePlotKind(options->scene));
    for (const std::string& png : pngs) std::printf("wrote %s\n", png.c_str());
  });
}

}  // namespace ecpsim::app
