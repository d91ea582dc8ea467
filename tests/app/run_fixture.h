#pragma once
// A fixture for tests that run the built `ecpsim` and look into its output folder: reading the
// files, finding temporaries, interrupting a run once it has written rows.

#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/app/child_process.h"
#include "tests/cli_test.h"

namespace ecpsim::testing {

namespace fs = std::filesystem;

// how long a run may take to write its first rows before the test gives up (a loaded machine)
constexpr std::chrono::seconds kStartTimeout{60};

class RunFixture : public CliTest {
 protected:
  static nlohmann::json ReadJson(const fs::path& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
  }

  static std::vector<std::string> ReadLines(const fs::path& path) {
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  }

  // the names under `dir` (recursively) that are temporary or partial files
  static std::vector<std::string> Leftovers(const fs::path& dir) {
    std::vector<std::string> found;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      if (name.find(".tmp-") != std::string::npos || name.find(".partial") != std::string::npos) {
        found.push_back(entry.path().string());
      }
    }
    return found;
  }

  // lines in the trajectory a running process is writing (its temporary file), 0 if none yet
  static size_t RowsBeingWritten(const fs::path& out) {
    std::error_code error;
    for (const auto& entry : fs::directory_iterator(out, error)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind("trajectory.csv.tmp-", 0) == 0) return ReadLines(entry.path()).size();
    }
    return 0;
  }

  // starts `ecpsim ARGUMENTS` from the source tree (writing into `out`), waits until it has
  // written `rows` rows, stops it (SIGSTOP, so that it goes no further while the test signals),
  // sends `signals` one after the other, lets it go on (SIGCONT) and waits for it to end
  ChildExit InterruptAfterRows(const std::vector<std::string>& arguments, const fs::path& out,
                               size_t rows, const std::vector<int>& signals) {
    EcpsimProcess run(binary_, arguments, ECPSIM_SOURCE_DIR, dir_ / "log.txt");
    EXPECT_TRUE(run.started());
    const auto deadline = std::chrono::steady_clock::now() + kStartTimeout;
    while (RowsBeingWritten(out) < 1 + rows && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    run.Signal(SIGSTOP);
    EXPECT_GE(RowsBeingWritten(out), 1 + rows) << "the run wrote no rows in time";
    for (int signal : signals) run.Signal(signal);
    run.Signal(SIGCONT);
    const ChildExit exit = run.Wait();
    std::ifstream log(dir_ / "log.txt");
    std::stringstream text;
    text << log.rdbuf();
    log_ = text.str();
    return exit;
  }

  // the interrupted run's files agree: summary, trajectory rows, the last row's time
  void ExpectConsistentInterruptedRun(const fs::path& out, const std::string& signal) {
    const nlohmann::json summary = ReadJson(out / "summary.json");
    EXPECT_EQ(summary["interrupted"], true);
    EXPECT_EQ(summary["signal"], signal);
    EXPECT_EQ(summary["converged"], false);
    EXPECT_EQ(summary["failures"], 0);
    const long steps = summary["steps"].get<long>();
    EXPECT_GE(steps, 2);
    EXPECT_LT(steps, summary["planned_steps"].get<long>());
    // every = 1: the initial state and one row per step done, the last at t_end
    const std::vector<std::string> lines = ReadLines(out / "trajectory.csv");
    ASSERT_EQ(static_cast<long>(lines.size()), 1 + 1 + steps);
    EXPECT_EQ(summary["rows"].get<long>(), 1 + steps);
    EXPECT_EQ(std::stod(lines.back().substr(0, lines.back().find(','))),
              summary["t_end"].get<double>());
    EXPECT_THAT(Leftovers(out), ::testing::IsEmpty());
  }

  std::string log_;  // output of the last InterruptAfterRows
};

}  // namespace ecpsim::testing
