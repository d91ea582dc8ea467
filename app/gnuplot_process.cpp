#include "app/gnuplot_process.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "common/errors.h"

extern char** environ;

namespace ecpsim::app {
namespace {

// the last `max_chars` characters of the file, for an error message
std::string TailOf(const std::string& path, std::size_t max_chars) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  std::string all = text.str();
  if (all.size() > max_chars) all = "..." + all.substr(all.size() - max_chars);
  while (!all.empty() && (all.back() == '\n' || all.back() == ' ')) all.pop_back();
  for (char& c : all) {
    if (c == '\n') c = ' ';
  }
  return all;
}

}  // namespace

void RunGnuplot(const std::string& script_path, const std::string& log_path) {
  // stdout and stderr of gnuplot go to the log; stdin is /dev/null so it never waits for input
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);

  std::string program = "gnuplot";
  std::string script = script_path;
  std::vector<char*> argv = {program.data(), script.data(), nullptr};
  pid_t pid = 0;
  const int spawn_error =
      posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawn_error == ENOENT) {
    throw InputError(
        "gnuplot: not found on PATH; expected the gnuplot program (Debian package gnuplot-nox, "
        "installed by scripts/setup.sh)");
  }
  if (spawn_error != 0) {
    throw InputError(fmt::format("gnuplot: cannot start it ({})", std::strerror(spawn_error)));
  }

  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      throw InputError(fmt::format("gnuplot: cannot wait for it ({})", std::strerror(errno)));
    }
  }
  // posix_spawnp reports a missing program as exit code 127 on some C libraries
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127) {
    throw InputError(
        "gnuplot: not found on PATH; expected the gnuplot program (Debian package gnuplot-nox, "
        "installed by scripts/setup.sh)");
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw InputError(fmt::format("gnuplot {}: failed (exit status {}); its log {} ends: {}",
                                 script_path, WIFEXITED(status) ? WEXITSTATUS(status) : -1,
                                 log_path, TailOf(log_path, 400)));
  }
}

}  // namespace ecpsim::app
