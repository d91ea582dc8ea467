#pragma once
// The built `ecpsim` as a child process the test can signal while it runs, and whose exit status
// and peak memory it reads (tests/cli_test.h waits for the command through a shell instead).

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

namespace ecpsim::testing {

struct ChildExit {
  int exit_code = -1;   // the status passed to exit(), or -1 if a signal ended the process
  int signal = 0;       // the signal that ended it, 0 if it exited
  long max_rss_kb = 0;  // peak resident set size, kB (getrusage's ru_maxrss)
};

class EcpsimProcess {
 public:
  /// Starts `binary ARGUMENTS` in `working_dir` with stdout and stderr going to `log`, and
  /// SIGINT and SIGTERM at their default action (a test runner may start tests with them ignored).
  EcpsimProcess(const std::filesystem::path& binary, const std::vector<std::string>& arguments,
                const std::filesystem::path& working_dir, const std::filesystem::path& log) {
    std::vector<std::string> words = {binary.string()};
    words.insert(words.end(), arguments.begin(), arguments.end());
    std::vector<char*> argv;
    for (std::string& word : words) argv.push_back(word.data());
    argv.push_back(nullptr);
    pid_ = ::fork();
    if (pid_ == 0) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd < 0 || ::chdir(working_dir.c_str()) != 0) ::_exit(127);
      ::dup2(fd, STDOUT_FILENO);
      ::dup2(fd, STDERR_FILENO);
      ::signal(SIGINT, SIG_DFL);
      ::signal(SIGTERM, SIG_DFL);
      sigset_t none;
      sigemptyset(&none);
      ::sigprocmask(SIG_SETMASK, &none, nullptr);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
  }
  ~EcpsimProcess() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  EcpsimProcess(const EcpsimProcess&) = delete;
  EcpsimProcess& operator=(const EcpsimProcess&) = delete;

  bool started() const { return pid_ > 0; }
  void Signal(int signal) const { ::kill(pid_, signal); }

  /// Waits for the process to end.
  ChildExit Wait() {
    ChildExit result;
    int status = 0;
    struct rusage usage = {};
    if (::wait4(pid_, &status, 0, &usage) != pid_) return result;
    pid_ = -1;
    if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) result.signal = WTERMSIG(status);
    result.max_rss_kb = usage.ru_maxrss;
    return result;
  }

 private:
  pid_t pid_ = -1;
};

}  // namespace ecpsim::testing
