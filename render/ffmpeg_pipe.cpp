#include "render/ffmpeg_pipe.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fcntl.h>
#include <fmt/format.h>
#include <pthread.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "common/errors.h"

namespace ecpsim::render {
namespace {

// frame-rate limits: anything above is a unit mistake (frames per second, not per step)
constexpr double kMaxFps = 1000;
// how much of ffmpeg's error output goes into a message
constexpr size_t kMaxLogChars = 600;
// frames waiting for the writer thread: one to render into while one is sent is all the overlap
// there is; more would only hold memory (6 MB per 1920×1080 frame)
constexpr size_t kMaxQueuedFrames = 2;
// bytes of the pipe into ffmpeg: Linux's default /proc/sys/fs/pipe-max-size
constexpr int kPipeBytes = 1 << 20;

bool IsExecutable(const std::string& path) {
  struct stat info;
  return ::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode) &&
         ::access(path.c_str(), X_OK) == 0;
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

std::string ExitText(int status) {
  if (WIFEXITED(status)) return fmt::format("exit status {}", WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return fmt::format("signal {}", WTERMSIG(status));
  return "killed";
}

int WaitForExit(int pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return status;
}

// a private temporary file (for a program's error output or ffmpeg's concat list), removed with
// this object
class TempFile {
 public:
  explicit TempFile(const std::string& what) {
    std::string name = (std::filesystem::temp_directory_path() / "ecpsim-ffmpeg-XXXXXX").string();
    fd_ = ::mkostemp(name.data(), O_CLOEXEC);
    if (fd_ < 0) {
      throw std::runtime_error(fmt::format("{}: cannot create a temporary file in {}: {}", what,
                                           std::filesystem::temp_directory_path().string(),
                                           std::strerror(errno)));
    }
    path_ = name;
  }
  ~TempFile() {
    Close();
    if (!path_.empty()) std::remove(path_.c_str());
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  /// The path, kept by the caller: this object no longer removes the file.
  std::string Release() {
    Close();
    return std::exchange(path_, std::string());
  }
  void Close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }
  int fd() const { return fd_; }
  const std::string& path() const { return path_; }

 private:
  int fd_ = -1;
  std::string path_;
};

// starts `args` (no shell) with the given standard descriptors, in its own process group so that
// a terminal's Ctrl-C reaches only ecpsim, which decides when a video ends (an interrupted run
// finishes it with the frames so far); returns its pid
int Spawn(const std::vector<std::string>& args, int stdin_fd, int stdout_fd, int stderr_fd,
          const std::string& what) {
  std::vector<char*> argv;
  for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawnattr_t attributes;
  posix_spawn_file_actions_init(&actions);
  posix_spawnattr_init(&attributes);
  posix_spawn_file_actions_adddup2(&actions, stdin_fd, STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&actions, stdout_fd, STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, stderr_fd, STDERR_FILENO);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attributes, 0);
  pid_t pid = -1;
  const int error = ::posix_spawnp(&pid, argv[0], &actions, &attributes, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (error != 0) {
    throw std::runtime_error(
        fmt::format("{}: cannot start {}: {}", what, args.front(), std::strerror(error)));
  }
  return pid;
}

struct ProgramResult {
  int status = 0;      // waitpid's
  std::string output;  // standard output
  std::string log;     // the tail of the error output (ReadTail)
  bool ok() const { return WIFEXITED(status) && WEXITSTATUS(status) == 0; }
};

// runs `args` to its end: no input, its output collected, its error output kept for messages
ProgramResult RunProgram(const std::vector<std::string>& args, const std::string& what) {
  TempFile log(what);
  const int null_fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  int fds[2] = {-1, -1};
  if (null_fd < 0 || ::pipe2(fds, O_CLOEXEC) != 0) {
    const std::string reason = std::strerror(errno);
    if (null_fd >= 0) ::close(null_fd);
    throw std::runtime_error(fmt::format("{}: cannot create a pipe: {}", what, reason));
  }
  int pid = -1;
  try {
    pid = Spawn(args, null_fd, fds[1], log.fd(), what);
  } catch (...) {
    ::close(null_fd);
    ::close(fds[0]);
    ::close(fds[1]);
    throw;
  }
  ::close(null_fd);
  ::close(fds[1]);
  ProgramResult result;
  char buffer[4096];
  for (;;) {
    const ssize_t n = ::read(fds[0], buffer, sizeof(buffer));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    result.output.append(buffer, static_cast<size_t>(n));
  }
  ::close(fds[0]);
  result.status = WaitForExit(pid);
  result.log = ReadTail(log.path());
  return result;
}

// `path` as a line of ffmpeg's concat list: quoted, a quote inside written as '\''
std::string ConcatLine(const std::string& path) {
  std::string quoted;
  for (char c : std::filesystem::absolute(path).string()) {
    if (c == '\'') {
      quoted += "'\\''";
    } else {
      quoted += c;
    }
  }
  return "file '" + quoted + "'\n";
}

std::string MissingProgram(const std::string& video_path, const std::string& program) {
  return fmt::format(
      "cannot write video '{}': the program '{}' is not on PATH; install the "
      "Debian package ffmpeg (PNG frames do not need it)",
      video_path, program);
}

}  // namespace

void RequireVideoProgram(const std::string& video_path, const std::string& program) {
  if (!FindProgram(program)) throw InputError(MissingProgram(video_path, program));
}

int CountVideoFrames(const std::string& path, const std::string& program) {
  if (!FindProgram(program)) {
    throw InputError(
        fmt::format("cannot read video '{}': the program '{}' is not on PATH; "
                    "install the Debian package ffmpeg",
                    path, program));
  }
  const std::string what = fmt::format("video '{}'", path);
  const ProgramResult probe =
      RunProgram({program, "-v", "error", "-select_streams", "v:0", "-show_entries",
                  "stream=nb_frames", "-of", "csv=p=0", path},
                 what);
  std::string text = probe.output;
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  int frames = -1;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), frames);
  if (!probe.ok() || error != std::errc() || end != text.data() + text.size() || frames < 0) {
    throw InputError(fmt::format("{}: not a readable video ({} says '{}', {}): {}", what, program,
                                 text, ExitText(probe.status), probe.log));
  }
  return frames;
}

FfmpegPipe::FfmpegPipe(const std::string& path, int width, int height, double fps,
                       const std::string& program, VideoStart start, ChannelOrder order)
    : path_(path), program_(program), start_(start), order_(order), width_(width), height_(height) {
  if (width <= 0 || height <= 0) {
    throw InputError(
        fmt::format("video '{}': frame size {}x{}: expected positive sizes", path, width, height));
  }
  if (!std::isfinite(fps) || fps <= 0 || fps > kMaxFps) {
    throw InputError(fmt::format("video '{}': fps = {}: expected a frame rate in (0, {}] frames/s",
                                 path, fps, kMaxFps));
  }
  RequireVideoProgram(path, program);
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  if (!folder.empty() && !std::filesystem::is_directory(folder)) {
    throw InputError(fmt::format("cannot write video '{}': the folder '{}' does not exist", path,
                                 folder.string()));
  }
  file_.emplace(path);
  if (start == VideoStart::kAppend && !std::filesystem::is_regular_file(path)) {
    throw InputError(
        fmt::format("cannot continue video '{}': there is no video to continue", path));
  }
  // ffmpeg's error output goes to a private temporary file, read back for messages
  TempFile log(fmt::format("video '{}'", path));

  const std::vector<std::string> args = {
      program, "-hide_banner", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt",
      order == ChannelOrder::kBgr ? "bgr24" : "rgb24", "-s", fmt::format("{}x{}", width, height),
      "-framerate", fmt::format("{}", fps), "-i", "pipe:0",
      // yuv420p halves the chroma resolution, so both sides must be even
      "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-preset", "veryfast", "-crf",
      "18", "-pix_fmt", "yuv420p", "-movflags", "+faststart", "-f", "mp4", file_->temp_path()};
  int fds[2] = {-1, -1};
  const int null_fd = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
  if (null_fd < 0 || ::pipe2(fds, O_CLOEXEC) != 0) {
    const std::string reason = std::strerror(errno);
    if (null_fd >= 0) ::close(null_fd);
    throw std::runtime_error(fmt::format("video '{}': cannot create a pipe: {}", path, reason));
  }
  try {
    pid_ = Spawn(args, fds[0], null_fd, log.fd(), fmt::format("video '{}'", path));
  } catch (...) {
    ::close(fds[0]);
    ::close(fds[1]);
    ::close(null_fd);
    throw;
  }
  ::close(fds[0]);
  ::close(null_fd);
  stdin_fd_ = fds[1];
  // a pipe as large as an unprivileged process may ask for: a frame crosses in fewer wake-ups
  // (the default 64 kB is 42 of them for a 1280×720 frame); without it the pipe still works
  ::fcntl(stdin_fd_, F_SETPIPE_SZ, kPipeBytes);
  log_path_ = log.Release();
  writer_ = std::thread([this] { SendFrames(); });
}

FfmpegPipe::~FfmpegPipe() {
  // not finished: drop the queued frames, stop ffmpeg; file_ then removes what it wrote
  {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.clear();
  }
  StopWriter();
  if (stdin_fd_ >= 0) ::close(stdin_fd_);
  if (pid_ > 0) {
    ::kill(pid_, SIGTERM);
    WaitForExit(pid_);
  }
  std::remove(log_path_.c_str());
}

void FfmpegPipe::SendFrames() {
  for (;;) {
    std::variant<Image, Drawing> queued;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      frame_ready_.wait(lock, [this] { return closing_ || !queue_.empty(); });
      if (queue_.empty()) return;  // closing, every frame sent
      queued = std::move(queue_.front());
      queue_.pop_front();
    }
    space_ready_.notify_all();
    Image frame;
    if (Drawing* drawing = std::get_if<Drawing>(&queued)) {
      frame = Downsample(*drawing);
      std::lock_guard<std::mutex> lock(mutex_);
      if (spares_.size() <= kMaxQueuedFrames) spares_.push_back(std::move(*drawing));
    } else {
      frame = std::move(std::get<Image>(queued));
    }
    // raw rgb24 or bgr24 rows top first, as Image holds them
    const int error = WriteAll(stdin_fd_, frame.pixels.data(), frame.pixels.size());
    if (error != 0) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        write_error_ = error;
        queue_.clear();
      }
      space_ready_.notify_all();
      return;
    }
  }
}

void FfmpegPipe::StopWriter() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closing_ = true;
  }
  frame_ready_.notify_all();
  if (writer_.joinable()) writer_.join();
}

void FfmpegPipe::Fail(const std::string& what) {
  StopWriter();
  if (stdin_fd_ >= 0) ::close(stdin_fd_);
  stdin_fd_ = -1;
  const int status = pid_ > 0 ? WaitForExit(pid_) : 0;
  pid_ = -1;
  const std::string log = ReadTail(log_path_);
  file_.reset();  // removes the temporary video
  throw std::runtime_error(
      fmt::format("video '{}': {} ({}): {}", path_, what, ExitText(status), log));
}

void FfmpegPipe::Write(Image frame) {
  ECPSIM_DEMAND(frame.width == width_ && frame.height == height_);
  ECPSIM_DEMAND(frame.order == order_);
  ECPSIM_DEMAND(frame.pixels.size() == static_cast<size_t>(width_) * height_ * 3);
  Queue(std::move(frame));
}

void FfmpegPipe::Write(Drawing frame) {
  ECPSIM_DEMAND(frame.width == width_ && frame.height == height_);
  ECPSIM_DEMAND(frame.order == order_);
  Queue(std::move(frame));
}

Drawing FfmpegPipe::SpareDrawing() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (spares_.empty()) return Drawing();
  Drawing spare = std::move(spares_.back());
  spares_.pop_back();
  return spare;
}

void FfmpegPipe::Queue(std::variant<Image, Drawing> frame) {
  ECPSIM_DEMAND(pid_ > 0);
  int error = 0;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    space_ready_.wait(lock, [this] { return queue_.size() < kMaxQueuedFrames || write_error_; });
    error = write_error_;
    if (error == 0) queue_.push_back(std::move(frame));
  }
  if (error != 0) Fail(fmt::format("ffmpeg stopped reading after {} frames", frames_));
  frame_ready_.notify_one();
  ++frames_;
}

void FfmpegPipe::Finish() {
  ECPSIM_DEMAND(pid_ > 0);
  StopWriter();  // after sending every queued frame
  if (write_error_ != 0) Fail("ffmpeg stopped reading before the last frame");
  ::close(stdin_fd_);
  stdin_fd_ = -1;
  const int status = WaitForExit(pid_);
  pid_ = -1;
  if (start_ == VideoStart::kAppend && frames_ == 0) {
    file_.reset();  // nothing to add: the earlier video stays as it is
    return;
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const std::string log = ReadTail(log_path_);
    file_.reset();  // removes the temporary video
    throw std::runtime_error(
        fmt::format("video '{}': ffmpeg failed ({}): {}", path_, ExitText(status), log));
  }
  try {
    if (start_ == VideoStart::kAppend) {
      JoinOntoEarlierVideo();
    } else {
      file_->Commit();
    }
  } catch (const InputError& e) {
    throw InputError(fmt::format("cannot write video '{}': {}", path_, e.what()));
  }
}

void FfmpegPipe::JoinOntoEarlierVideo() {
  // the concat demuxer reads both videos' packets in turn and shifts the second's timestamps by
  // the first's duration; -c copy keeps every frame's bits (no second encoding)
  const std::string what = fmt::format("video '{}'", path_);
  TempFile list(what);
  const std::string lines = ConcatLine(path_) + ConcatLine(file_->temp_path());
  if (::write(list.fd(), lines.data(), lines.size()) != static_cast<ssize_t>(lines.size())) {
    throw std::runtime_error(fmt::format("{}: cannot write the concat list {}: {}", what,
                                         list.path(), std::strerror(errno)));
  }
  list.Close();
  AtomicFile joined(path_);
  const ProgramResult join = RunProgram(
      {program_, "-hide_banner", "-loglevel", "error", "-y", "-f", "concat", "-safe", "0", "-i",
       list.path(), "-c", "copy", "-movflags", "+faststart", "-f", "mp4", joined.temp_path()},
      what);
  if (!join.ok()) {
    throw std::runtime_error(
        fmt::format("{}: joining the earlier video and the {} new frames "
                    "failed ({}): {}",
                    what, frames_, ExitText(join.status), join.log));
  }
  joined.Commit();
  file_.reset();  // the new frames' own video, now part of `path`
}

}  // namespace ecpsim::render
