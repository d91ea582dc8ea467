// ecpsim: the command-line front end. Each sub-command lives in its own *_command.cpp.

#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "app/commands.h"
#include "engine/planar_model.h"
#include "engine/step_report.h"
#include "common/errors.h"

int main(int argc, char** argv) {
  CLI::App app{"ecpsim: rigid bodies with planar non-convex contact (equivalent contact points)"};
  app.require_subcommand(1);
  ecpsim::app::AddHullCommand(app);
  ecpsim::app::AddMeshesCommand(app);
  ecpsim::app::AddCompareCommand(app);
  ecpsim::app::AddRunCommand(app);
  ecpsim::app::AddDropCommand(app);
  ecpsim::app::AddRenderCommand(app);
  ecpsim::app::AddPlotCommand(app);
  ecpsim::app::AddBenchCommand(app);

  // exit codes: 0 ok, 1 bad input (one line on stderr), 3 solver failure, 4 internal error,
  // 5 the selected contact model does not apply (the outputs so far stay valid)
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const ecpsim::engine::SolverFailure& e) {
    std::fprintf(stderr, "ecpsim: solver failure: %s\n", e.what());
    return 3;
  } catch (const ecpsim::engine::ModelInvalid& e) {
    std::fprintf(stderr, "ecpsim: model invalid: %s\n", e.what());
    return 5;
  } catch (const ecpsim::InputError& e) {
    std::fprintf(stderr, "ecpsim: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ecpsim: error: %s\n", e.what());
    return 4;
  }
  return 0;
}
