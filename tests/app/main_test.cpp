// The CLI's own conventions (app/main.cpp): exit code 1 and one line for every command-line error,
// 0 for --help and --version, the list of commands for an unknown one.

#include <string>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/cli_test.h"

namespace ecpsim {
namespace {

using ::testing::HasSubstr;
using ::testing::MatchesRegex;
using ::testing::StartsWith;

constexpr int kBadInput = 1;  // README.md: every bad input, the command line included
constexpr char kCommandList[] = "hull, meshes, compare, run, drop, render, plot, bench";

class MainTest : public testing::CliTest {
 protected:
  // a command-line error: exit code 1 and exactly one line of output
  void ExpectOneLineError(const std::string& arguments, const std::string& expected) {
    const testing::CliResult result = Run(arguments);
    EXPECT_EQ(result.exit_code, kBadInput) << arguments << ": " << result.output;
    EXPECT_THAT(result.output, HasSubstr(expected)) << arguments;
    ASSERT_FALSE(result.output.empty()) << arguments;
    EXPECT_EQ(result.output.find('\n'), result.output.size() - 1)
        << arguments << ": more than one line: " << result.output;
  }
};

TEST_F(MainTest, UnknownCommandListsTheCommands) {
  ExpectOneLineError(
      "frobnicate scenes/slide.yaml",
      fmt::format("unknown command 'frobnicate'; expected one of: {}", kCommandList));
}

TEST_F(MainTest, MissingCommandListsTheCommands) {
  ExpectOneLineError("", fmt::format("a command is required; expected one of: {}", kCommandList));
}

TEST_F(MainTest, MissingArgumentExitsOneNamingTheCommand) {
  ExpectOneLineError("hull", "ecpsim hull: error: MESH is required (see ecpsim hull --help)");
}

TEST_F(MainTest, BadOptionValueExitsOne) {
  // CLI11 itself would exit 105 (validation) here
  ExpectOneLineError(fmt::format("run scenes/slide.yaml -o '{}' --dt abc", (dir_ / "o").string()),
                     "ecpsim: error: --dt = abc: expected a finite time > 0 s");
}

TEST_F(MainTest, UnexpectedArgumentExitsOne) {
  // CLI11 itself would exit 109 (extras) here
  ExpectOneLineError(fmt::format("compare a.png b.png c.png"), "c.png");
}

TEST_F(MainTest, HelpExitsZero) {
  for (const char* arguments : {"--help", "run --help", "drop -h"}) {
    const testing::CliResult result = Run(arguments);
    EXPECT_EQ(result.exit_code, 0) << arguments << ": " << result.output;
    EXPECT_THAT(result.output, HasSubstr("Usage:")) << arguments;
  }
}

TEST_F(MainTest, VersionPrintsTheProjectVersionAndExitsZero) {
  const testing::CliResult result = Run("--version");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  // CMakeLists.txt project(VERSION), then the commit when built from a git checkout
  EXPECT_THAT(result.output, StartsWith(fmt::format("ecpsim {}", ECPSIM_VERSION)));
  EXPECT_THAT(result.output, MatchesRegex(R"(ecpsim [0-9]+\.[0-9]+\.[0-9]+( \(git [0-9a-f]+\))?
)"));
}

TEST_F(MainTest, CompareKeepsItsOwnExitCodes) {
  // compare's 2 (bad input) is its documented status, not a command-line error
  const testing::CliResult result = Run("compare /nonexistent/a.png /nonexistent/b.png");
  EXPECT_EQ(result.exit_code, 2) << result.output;
}

}  // namespace
}  // namespace ecpsim
