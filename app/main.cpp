// ecpsim: the command-line front end. Each sub-command lives in its own *_command.cpp.

#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "app/commands.h"
#include "app/interrupt.h"
#include "app/version.h"
#include "common/errors.h"
#include "engine/step_report.h"

namespace {

// exit codes (README.md): 0 ok, 1 bad input, 3 solver failure, 4 internal error, 5 the selected
// contact model does not apply; a run stopped by a signal exits 128 + its number
constexpr int kBadInput = 1;
constexpr int kSolverFailure = 3;
constexpr int kInternalError = 4;
constexpr int kModelInvalid = 5;

// the sub-commands in the order they were added
std::vector<std::string> CommandNames(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; })) {
    names.push_back(command->get_name());
  }
  return names;
}

// one line for any command-line error, and the exit code of bad input
int CommandLineError(const CLI::App& app, const CLI::ParseError& error, int argc, char** argv) {
  std::string message = error.what();
  std::replace(message.begin(), message.end(), '\n', ' ');
  const std::vector<CLI::App*> chosen = app.get_subcommands();
  if (!chosen.empty()) {
    const std::string name = chosen.back()->get_name();
    std::fprintf(stderr, "ecpsim %s: error: %s (see ecpsim %s --help)\n", name.c_str(),
                 message.c_str(), name.c_str());
    return kBadInput;
  }
  // no command recognised: the first word that is not an option is the unknown command
  const std::vector<std::string> names = CommandNames(app);
  const std::string expected = fmt::format("{}", fmt::join(names, ", "));
  const auto word = std::find_if(argv + 1, argv + argc, [](const char* a) { return a[0] != '-'; });
  if (word != argv + argc && std::find(names.begin(), names.end(), *word) == names.end()) {
    std::fprintf(stderr, "ecpsim: error: unknown command '%s'; expected one of: %s\n", *word,
                 expected.c_str());
  } else if (word == argv + argc && message.find("subcommand is required") != std::string::npos) {
    std::fprintf(stderr,
                 "ecpsim: error: a command is required; expected one of: %s (see ecpsim "
                 "--help)\n",
                 expected.c_str());
  } else {
    std::fprintf(stderr, "ecpsim: error: %s (see ecpsim --help)\n", message.c_str());
  }
  return kBadInput;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ecpsim: rigid bodies with planar non-convex contact (equivalent contact points)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", ecpsim::app::kVersionText, "print the version and exit");
  ecpsim::app::AddHullCommand(app);
  ecpsim::app::AddMeshesCommand(app);
  ecpsim::app::AddCompareCommand(app);
  ecpsim::app::AddRunCommand(app);
  ecpsim::app::AddDropCommand(app);
  ecpsim::app::AddRenderCommand(app);
  ecpsim::app::AddPlotCommand(app);
  ecpsim::app::AddBenchCommand(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --help-all, --version: printed, exit 0
  } catch (const CLI::RuntimeError& e) {
    return e.get_exit_code();  // a command's own status (`compare`), its message already printed
  } catch (const CLI::ParseError& e) {
    return CommandLineError(app, e, argc, argv);
  } catch (const ecpsim::app::Interrupted& e) {
    std::fprintf(stderr, "ecpsim: %s\n", e.what());
    return e.exit_code();
  } catch (const ecpsim::engine::SolverFailure& e) {
    std::fprintf(stderr, "ecpsim: solver failure: %s\n", e.what());
    return kSolverFailure;
  } catch (const ecpsim::engine::ModelInvalid& e) {
    std::fprintf(stderr, "ecpsim: model invalid: %s\n", e.what());
    return kModelInvalid;
  } catch (const ecpsim::InputError& e) {
    std::fprintf(stderr, "ecpsim: error: %s\n", e.what());
    return kBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ecpsim: error: %s\n", e.what());
    return kInternalError;
  }
  return 0;
}
