// `ecpsim hull` on every file of Debian's assimp-testmodels collection (447 scene files in 60
// formats, plus their textures): each run must exit 0 (a hull) or 1 (bad input, one message
// naming the file); never a signal, a hang or exit 4 (an internal error). Two runs at a time.

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

extern char** environ;

namespace ecpsim::app {
namespace {

const std::filesystem::path kCollection = "/usr/share/assimp/models";

// runs at a time: the machine's cores are shared with the rest of the suite
constexpr int kParallelRuns = 2;

// s: no file of the collection takes 4 s (the slowest, AC/sample_subdiv.ac, ~1 s on a busy
// machine); a run past this limit is a hang
constexpr double kRunSeconds = 60.0;

struct HullRun {
  std::string file;
  std::filesystem::path log;  // stdout and stderr
  std::chrono::steady_clock::time_point start;
};

// `ecpsim hull FILE`, output to `log`
pid_t StartHull(const std::string& file, const std::filesystem::path& log) {
  const std::string binary = std::string(ECPSIM_BINARY_DIR) + "/app/ecpsim";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<std::string> arguments = {binary, "hull", file};
  std::vector<char*> argv;
  for (std::string& a : arguments) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int error = posix_spawn(&pid, binary.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return error == 0 ? pid : -1;
}

std::string ReadLog(const std::filesystem::path& log) {
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(MeshCollectionTest, HullOfEveryFileExitsZeroOrOneNamingIt) {
  if (!std::filesystem::is_directory(kCollection)) {
    GTEST_SKIP() << kCollection << " is missing: install the Debian package assimp-testmodels "
                 << "(scripts/setup.sh does)";
  }
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(kCollection)) {
    if (entry.is_regular_file()) files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  ASSERT_GT(files.size(), 400u);

  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / fmt::format("ecpsim_collection_{}", ::getpid());
  std::filesystem::create_directories(folder);
  std::map<pid_t, HullRun> running;
  std::map<int, int> exit_codes;
  std::size_t next = 0;
  while (next < files.size() || !running.empty()) {
    // keep kParallelRuns going
    while (next < files.size() && static_cast<int>(running.size()) < kParallelRuns) {
      const std::filesystem::path log = folder / fmt::format("run{}.log", next);
      const pid_t pid = StartHull(files[next], log);
      ASSERT_GT(pid, 0) << "cannot start ecpsim for " << files[next];
      running[pid] = HullRun{files[next], log, std::chrono::steady_clock::now()};
      ++next;
    }
    int status = 0;
    const pid_t done = ::waitpid(-1, &status, WNOHANG);
    if (done <= 0) {
      // a run past its limit is killed (and reported below as a signal)
      for (const auto& [pid, run] : running) {
        const std::chrono::duration<double> age = std::chrono::steady_clock::now() - run.start;
        if (age.count() > kRunSeconds) ::kill(pid, SIGKILL);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      continue;
    }
    const HullRun run = running.at(done);
    running.erase(done);
    const std::string output = ReadLog(run.log);
    if (WIFSIGNALED(status)) {
      ADD_FAILURE() << run.file << ": ecpsim hull killed by signal " << WTERMSIG(status) << ": "
                    << output;
      continue;
    }
    const int code = WEXITSTATUS(status);
    ++exit_codes[code];
    EXPECT_TRUE(code == 0 || code == 1) << run.file << ": exit code " << code << ": " << output;
    if (code == 1) {
      EXPECT_NE(output.find("ecpsim: error: "), std::string::npos) << run.file << ": " << output;
      EXPECT_NE(output.find(run.file), std::string::npos) << run.file << ": " << output;
    }
  }
  std::filesystem::remove_all(folder);
  std::cout << files.size() << " files: " << exit_codes[0] << " with a hull (exit 0), "
            << exit_codes[1] << " rejected (exit 1)\n";
}

}  // namespace
}  // namespace ecpsim::app
