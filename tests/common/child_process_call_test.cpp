// A call in a forked child: its result comes back, and so does what ended it (an exception's
// message, a signal), with what it wrote before.

#include "common/child_process_call.h"

#include <unistd.h>
#include <csignal>
#include <stdexcept>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace ecpsim {
namespace {

struct Numbers {
  long count = 0;
  double value = -1;
  pid_t pid = 0;
};

TEST(CallInChildProcess, ReturnsTheChildsResult) {
  Numbers numbers;
  const std::string failure = CallInChildProcess<Numbers>(numbers, [](Numbers& n) {
    n.count = 42;
    n.value = 0.5;
    n.pid = getpid();
  });
  EXPECT_EQ(failure, "");
  EXPECT_EQ(numbers.count, 42);
  EXPECT_EQ(numbers.value, 0.5);
  // it ran elsewhere: this process's memory changed only by the copy back
  EXPECT_NE(numbers.pid, getpid());
}

TEST(CallInChildProcess, AnExceptionIsItsMessageWithWhatWasWrittenBefore) {
  Numbers numbers;
  const std::string failure = CallInChildProcess<Numbers>(numbers, [](Numbers& n) {
    n.count = 7;
    throw std::runtime_error("solver failed at t = 0.01 s");
  });
  EXPECT_EQ(failure, "solver failed at t = 0.01 s");
  EXPECT_EQ(numbers.count, 7);
}

TEST(CallInChildProcess, ACrashEndsTheChildNotTheCaller) {
  Numbers numbers;
  const std::string failure = CallInChildProcess<Numbers>(numbers, [](Numbers& n) {
    n.count = 3;
    std::raise(SIGABRT);
  });
  EXPECT_THAT(failure, ::testing::HasSubstr(fmt::format("killed by signal {}", SIGABRT)));
  EXPECT_EQ(numbers.count, 3);
}

}  // namespace
}  // namespace ecpsim
