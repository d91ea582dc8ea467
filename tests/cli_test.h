#pragma once
// A test fixture that runs the built `ecpsim` binary in a fresh temporary folder per test.

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

namespace ecpsim::testing {

struct CliResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           fmt::format("ecpsim_{}_{}_{}", info->test_suite_name(), getpid(), info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    binary_ = std::filesystem::path(ECPSIM_BINARY_DIR) / "app" / "ecpsim";
    ASSERT_TRUE(std::filesystem::exists(binary_)) << binary_ << " is missing: build target ecpsim";
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  /// Runs `ecpsim ARGUMENTS` from the source tree (so scenes/... paths work), with an optional
  /// environment prefix such as "PATH=/nonexistent".
  CliResult Run(const std::string& arguments, const std::string& environment = "") {
    const std::filesystem::path log = dir_ / "log.txt";
    const std::string command = fmt::format("cd '{}' && {} '{}' {} > '{}' 2>&1", ECPSIM_SOURCE_DIR,
                                            environment, binary_.string(), arguments, log.string());
    const int status = std::system(command.c_str());
    CliResult result;
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(log);
    std::stringstream text;
    text << in.rdbuf();
    result.output = text.str();
    return result;
  }

  std::filesystem::path dir_;     // empty folder of this test, removed afterwards
  std::filesystem::path binary_;  // the built ecpsim
};

}  // namespace ecpsim::testing
