#include "render/ffmpeg_pipe.h"

#include <cerrno>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <fcntl.h>
#include <pthread.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <fmt/format.h>

#include "common/errors.h"

namespace ecpsim::render {
namespace {

// frame-rate limits: anything above is a unit mistake (frames per second, not per step)
constexpr double kMaxFps = 1000;
// how much of ffmpeg's error output goes into a message
constexpr size_t kMaxLogChars = 600;

bool IsExecutable(const std::string& path) {
  struct stat info;
  return ::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode) && ::access(path.c_str(), X_OK) == 0;
}

// execvp's own search, done beforehand so that a missing program is a clear error, not a child
// that exits 127
bool FindProgram(const std::string& program) {
  if (program.find('/') != std::string::npos) return IsExecutable(program);
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "/usr/bin:/bin");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    if (IsExecutable((dir.empty() ? "." : dir) + "/" + program)) return true;
  }
  return false;
}

// writes all of `data`; a closed pipe returns EPIPE instead of killing the process with SIGPIPE
int WriteAll(int fd, const std::uint8_t* data, size_t size) {
  sigset_t pipe_signal, old_mask;
  sigemptyset(&pipe_signal);
  sigaddset(&pipe_signal, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_signal, &old_mask);
  int error = 0;
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      error = errno;
      break;
    }
    data += n;
    size -= static_cast<size_t>(n);
  }
  if (error == EPIPE) {
    // consume the SIGPIPE raised for this thread before unblocking it
    const timespec zero = {0, 0};
    sigtimedwait(&pipe_signal, nullptr, &zero);
  }
  pthread_sigmask(SIG_SETMASK, &old_mask, nullptr);
  return error;
}

std::string ReadTail(const std::string& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  std::string log = text.str();
  while (!log.empty() && (log.back() == '\n' || log.back() == '\r')) log.pop_back();
  if (log.size() > kMaxLogChars) log = "..." + log.substr(log.size() - kMaxLogChars);
  for (char& c : log) {
    if (c == '\n') c = ' ';
  }
  return log.empty() ? "(no error output)" : log;
}

}  // namespace

FfmpegPipe::FfmpegPipe(const std::string& path, int width, int height, double fps,
                       const std::string& program)
    : path_(path), width_(width), height_(height) {
  if (width <= 0 || height <= 0) {
    throw InputError(fmt::format("video '{}': frame size {}x{}: expected positive sizes", path,
                                 width, height));
  }
  if (!std::isfinite(fps) || fps <= 0 || fps > kMaxFps) {
    throw InputError(fmt::format("video '{}': fps = {}: expected a frame rate in (0, {}] frames/s",
                                 path, fps, kMaxFps));
  }
  if (!FindProgram(program)) {
    throw InputError(fmt::format("cannot write video '{}': the program '{}' is not on PATH; "
                                 "install the Debian package ffmpeg (PNG frames do not need it)",
                                 path, program));
  }
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  if (!folder.empty() && !std::filesystem::is_directory(folder)) {
    throw InputError(fmt::format("cannot write video '{}': the folder '{}' does not exist", path,
                                 folder.string()));
  }
  file_.emplace(path);
  // ffmpeg's error output goes to a private temporary file, read back for messages
  std::string log_template =
      (std::filesystem::temp_directory_path() / "ecpsim-ffmpeg-XXXXXX").string();
  const int log_fd = ::mkostemp(log_template.data(), O_CLOEXEC);
  if (log_fd < 0) {
    throw std::runtime_error(fmt::format("video '{}': cannot create a log file in {}: {}", path,
                                         std::filesystem::temp_directory_path().string(),
                                         std::strerror(errno)));
  }
  log_path_ = log_template;

  // the whole argument vector before fork: the child only rewires descriptors and execs
  const std::vector<std::string> args = {
      program, "-hide_banner", "-loglevel", "error", "-y",
      "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", fmt::format("{}x{}", width, height),
      "-framerate", fmt::format("{}", fps), "-i", "pipe:0",
      // yuv420p halves the chroma resolution, so both sides must be even
      "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2",
      "-c:v", "libx264", "-preset", "veryfast", "-crf", "18", "-pix_fmt", "yuv420p",
      "-movflags", "+faststart", "-f", "mp4", file_->temp_path()};
  std::vector<char*> argv;
  for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
  argv.push_back(nullptr);

  int fds[2] = {-1, -1};
  const int null_fd = ::open("/dev/null", O_RDWR | O_CLOEXEC);
  if (null_fd < 0 || ::pipe2(fds, O_CLOEXEC) != 0) {
    const std::string reason = std::strerror(errno);
    if (null_fd >= 0) ::close(null_fd);
    ::close(log_fd);
    std::remove(log_path_.c_str());
    throw std::runtime_error(fmt::format("video '{}': cannot create a pipe: {}", path, reason));
  }
  pid_ = ::fork();
  if (pid_ == 0) {
    // child: stdin from the pipe, stdout discarded, stderr to the log; dup2 clears close-on-exec.
    // Its own process group keeps a terminal's Ctrl-C away from it: ecpsim decides when the
    // video ends (an interrupted run finishes it with the frames so far)
    ::setpgid(0, 0);
    ::dup2(fds[0], STDIN_FILENO);
    ::dup2(null_fd, STDOUT_FILENO);
    ::dup2(log_fd, STDERR_FILENO);
    ::execvp(argv[0], argv.data());
    ::_exit(127);
  }
  const int fork_errno = errno;
  ::close(fds[0]);
  ::close(log_fd);
  ::close(null_fd);
  if (pid_ < 0) {
    ::close(fds[1]);
    std::remove(log_path_.c_str());
    throw std::runtime_error(fmt::format("video '{}': cannot start {}: {}", path, program,
                                         std::strerror(fork_errno)));
  }
  stdin_fd_ = fds[1];
}

FfmpegPipe::~FfmpegPipe() {
  if (pid_ > 0) {
    // not finished: stop ffmpeg; file_ then removes what it wrote
    if (stdin_fd_ >= 0) ::close(stdin_fd_);
    ::kill(pid_, SIGTERM);
    int status = 0;
    ::waitpid(pid_, &status, 0);
  }
  std::remove(log_path_.c_str());
}

void FfmpegPipe::Fail(const std::string& what) {
  if (stdin_fd_ >= 0) ::close(stdin_fd_);
  stdin_fd_ = -1;
  int status = 0;
  if (pid_ > 0) ::waitpid(pid_, &status, 0);
  pid_ = -1;
  const std::string log = ReadTail(log_path_);
  file_.reset();  // removes the temporary video
  std::string exit;
  if (WIFEXITED(status)) exit = fmt::format("exit status {}", WEXITSTATUS(status));
  if (WIFSIGNALED(status)) exit = fmt::format("signal {}", WTERMSIG(status));
  throw std::runtime_error(fmt::format("video '{}': {} ({}): {}", path_, what, exit, log));
}

void FfmpegPipe::Write(const Image& frame) {
  ECPSIM_DEMAND(frame.width == width_ && frame.height == height_);
  ECPSIM_DEMAND(frame.rgb.size() == static_cast<size_t>(width_) * height_ * 3);
  ECPSIM_DEMAND(stdin_fd_ >= 0);
  // raw rgb24 rows top first, as Image holds them
  if (WriteAll(stdin_fd_, frame.rgb.data(), frame.rgb.size()) != 0) {
    Fail(fmt::format("ffmpeg stopped reading after {} frames", frames_));
  }
  ++frames_;
}

void FfmpegPipe::Finish() {
  ECPSIM_DEMAND(pid_ > 0);
  ::close(stdin_fd_);
  stdin_fd_ = -1;
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  pid_ = -1;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const std::string log = ReadTail(log_path_);
    file_.reset();  // removes the temporary video
    throw std::runtime_error(fmt::format("video '{}': ffmpeg failed ({}): {}", path_,
                                         WIFEXITED(status)
                                             ? fmt::format("exit status {}", WEXITSTATUS(status))
                                             : std::string("killed"),
                                         log));
  }
  try {
    file_->Commit();
  } catch (const InputError& e) {
    throw InputError(fmt::format("cannot write video '{}': {}", path_, e.what()));
  }
}

}  // namespace ecpsim::render
