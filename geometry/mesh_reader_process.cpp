#include "geometry/mesh_reader_process.h"

#include <fcntl.h>
#include <limits.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "common/errors.h"
#include "geometry/mesh_stream.h"

extern char** environ;

namespace ecpsim::geometry {
namespace {

namespace ms = mesh_stream;
using Clock = std::chrono::steady_clock;

// bytes of address space every reader gets: its own code and libraries take ~20 MB, and small
// files can expand a lot legitimately (Blender's subdivision modifier: SuzanneSubdiv_252.blend
// of assimp-testmodels grows from 86 kB to 107 MB); a runaway allocation stops here within a
// fraction of a second instead of taking the machine's memory
constexpr std::uint64_t kReaderMemoryFloor = std::uint64_t{1} << 30;

// more bytes of address space per byte of file: assimp peaks at 3.7×, 3.8× and 4.0× the file for
// a 1M-triangle binary STL, OBJ and binary PLY (184, 328 and 76 MB for 50, 86 and 19 MB); 16×
// leaves a factor 4 for formats that inflate compressed data (FBX arrays, zipped .zae/.3mf)
constexpr std::uint64_t kReaderMemoryPerFileByte = 16;

// seconds every reader gets: the slowest file of assimp-testmodels reads in ~0.5 s, so 5 s is
// ample on a loaded machine and still stops a reader caught in a loop within seconds
constexpr double kReaderSecondsFloor = 5.0;

// more seconds per byte of file: assimp reads the 86 MB 1M-triangle OBJ in 0.6 s (140 MB/s);
// 10 MB/s leaves a factor 14 for slower formats and a busy machine
constexpr double kReaderSecondsPerFileByte = 1e-7;

// the pipe buffer asked for: fewer wake-ups than the default 64 KiB while a large mesh streams
// (1 MiB is Linux's default /proc/sys/fs/pipe-max-size for unprivileged processes)
constexpr int kPipeBytes = 1 << 20;

// the descriptor the stream is written to inside the reader (0–2 go to /dev/null)
constexpr int kReaderOutputFd = 3;

[[noreturn]] void Fail(const std::string& path, const std::string& reason) {
  throw InputError(fmt::format("{}: cannot read the mesh: {}", path, reason));
}

std::string Megabytes(std::uint64_t bytes) {
  return fmt::format("{:.4g} MB", static_cast<double>(bytes) / 1e6);
}

bool IsExecutableFile(const std::string& path) {
  struct stat info;
  return ::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode) &&
         ::access(path.c_str(), X_OK) == 0;
}

// $ECPSIM_MESH_READER, else beside the running executable (an installed bin/), else the build
// tree's copy
std::string ReaderProgram() {
  if (const char* chosen = std::getenv("ECPSIM_MESH_READER"); chosen != nullptr && *chosen) {
    return chosen;
  }
  char self[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof(self) - 1);
  if (n > 0) {
    std::string beside(self, static_cast<std::size_t>(n));
    beside = beside.substr(0, beside.rfind('/') + 1) + "ecpsim-mesh-reader";
    if (IsExecutableFile(beside)) return beside;
  }
  return ECPSIM_MESH_READER_PATH;
}

// the wait status of `pid`, retrying after signals; nullopt if the status is lost (SIGCHLD
// ignored by the application, so the kernel reaped the child itself)
std::optional<int> WaitForExit(pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return std::nullopt;
  }
  return status;
}

// a started reader: on every way out of ReadMeshInReaderProcess, exceptions included, its pipe
// is closed and it is killed if still running and reaped (no zombie, no orphan)
class ReaderChild {
 public:
  ReaderChild(pid_t pid, int fd) : pid_(pid), fd_(fd) {}
  ReaderChild(const ReaderChild&) = delete;
  ReaderChild& operator=(const ReaderChild&) = delete;
  ~ReaderChild() {
    if (pid_ > 0) Kill();
    CloseFd();
  }

  int fd() const { return fd_; }

  // waits for the reader to end by itself; closing the pipe first means a reader still writing
  // gets EPIPE and ends instead of blocking forever
  std::optional<int> Wait() {
    CloseFd();
    if (pid_ <= 0) return std::nullopt;
    const pid_t pid = pid_;
    pid_ = -1;
    return WaitForExit(pid);
  }

  // never signals anything once the reader is reaped (kill(-1, …) would reach every process)
  std::optional<int> Kill() {
    if (pid_ > 0) ::kill(pid_, SIGKILL);
    return Wait();
  }

 private:
  void CloseFd() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

  pid_t pid_;
  int fd_;
};

struct DeadlinePassed {};

// reads up to `size` bytes into `data`, stopping early only at end of stream; returns the bytes
// read. Throws DeadlinePassed when `deadline` passes first.
std::size_t ReadUntil(int fd, void* data, std::size_t size, Clock::time_point deadline) {
  char* p = static_cast<char*>(data);
  std::size_t done = 0;
  while (done < size) {
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) throw DeadlinePassed{};
    pollfd request{fd, POLLIN, 0};
    const int ready =
        ::poll(&request, 1, static_cast<int>(std::min<long long>(left.count(), INT_MAX)));
    if (ready < 0 && errno != EINTR) {
      throw std::runtime_error(
          fmt::format("mesh reader pipe: poll failed: {}", std::strerror(errno)));
    }
    if (ready <= 0) continue;
    const ssize_t n = ::read(fd, p + done, size - done);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN) continue;
      throw std::runtime_error(
          fmt::format("mesh reader pipe: read failed: {}", std::strerror(errno)));
    }
    done += static_cast<std::size_t>(n);
  }
  return done;
}

// after an error record: waits, within the deadline, for the reader to close its end (it exits
// right after the record), kills it otherwise, and reaps it
void FinishAfterError(ReaderChild& child, Clock::time_point deadline) {
  char rest[256];
  try {
    while (ReadUntil(child.fd(), rest, sizeof(rest), deadline) == sizeof(rest)) {
    }
  } catch (const DeadlinePassed&) {
    child.Kill();
  }
  child.Wait();
}

// why the reader ended without a complete stream, from its wait status
std::string DescribeEnd(const std::optional<int>& status, const MeshReaderLimits& limits) {
  if (!status) return "the reader ended without sending the mesh (its exit status is unavailable)";
  if (WIFSIGNALED(*status)) {
    const int signal = WTERMSIG(*status);
    if (signal == SIGXCPU) {
      return fmt::format("assimp used more than the {:.3g} s CPU-time limit for this file",
                         limits.seconds);
    }
    const char* name = ::sigabbrev_np(signal);
    const char* description = ::sigdescr_np(signal);
    if (signal == SIGKILL) {
      return "the reader was killed by SIGKILL (e.g. by the system's out-of-memory killer)";
    }
    return fmt::format(
        "assimp crashed on it (signal SIG{}, {}); the file is corrupt or uses a feature assimp "
        "mishandles",
        name ? name : std::to_string(signal).c_str(), description ? description : "unknown");
  }
  return fmt::format("the reader exited with status {} without sending the mesh",
                     WIFEXITED(*status) ? WEXITSTATUS(*status) : -1);
}

// the reader's environment: ours, plus glibc's transparent-huge-page tunable for malloc. assimp's
// OBJ importer zero-fills a 16 MB read buffer for every file; in a fresh process that costs 4096
// page faults, with huge pages a handful (reading desk.obj in a fresh process: median 23 ms →
// 4.8 ms on a busy machine)
std::vector<std::string> ReaderEnvironment() {
  constexpr const char* kHugePages = "glibc.malloc.hugetlb=1";
  std::vector<std::string> environment;
  bool tunables_set = false;
  for (char** e = environ; e != nullptr && *e != nullptr; ++e) {
    std::string entry = *e;
    if (entry.rfind("GLIBC_TUNABLES=", 0) == 0) {
      entry += std::string(entry.size() > 15 ? ":" : "") + kHugePages;
      tunables_set = true;
    }
    environment.push_back(std::move(entry));
  }
  if (!tunables_set) environment.push_back(std::string("GLIBC_TUNABLES=") + kHugePages);
  return environment;
}

// starts the reader on `path` writing into `write_fd` (which must not be kReaderOutputFd);
// returns its pid
pid_t SpawnReader(const std::string& program, const std::string& path, int write_fd,
                  const MeshReaderLimits& limits) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  // dup2 clears close-on-exec on the copy; every other descriptor of ours is close-on-exec
  posix_spawn_file_actions_adddup2(&actions, write_fd, kReaderOutputFd);

  // an own process group keeps the terminal's Ctrl-C for the application (the reader dies with
  // its parent through PR_SET_PDEATHSIG); no signal blocked, signals the application ignores
  // back to their defaults
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t none, defaults;
  sigemptyset(&none);
  sigemptyset(&defaults);
  for (int s : {SIGPIPE, SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGXCPU, SIGXFSZ})
    sigaddset(&defaults, s);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  posix_spawnattr_setpgroup(&attributes, 0);
  posix_spawnattr_setflags(&attributes,
                           POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETPGROUP);

  const auto cpu_seconds = static_cast<unsigned long long>(std::ceil(limits.seconds)) + 1;
  std::vector<std::string> arguments = {program,
                                        std::to_string(kReaderOutputFd),
                                        std::to_string(limits.memory_bytes),
                                        std::to_string(cpu_seconds),
                                        std::to_string(::getpid()),
                                        path};
  std::vector<char*> argv;
  for (std::string& a : arguments) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> environment = ReaderEnvironment();
  std::vector<char*> envp;
  for (std::string& e : environment) envp.push_back(e.data());
  envp.push_back(nullptr);

  pid_t pid = 0;
  const int error =
      ::posix_spawn(&pid, program.c_str(), &actions, &attributes, argv.data(), envp.data());
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) {
    throw std::runtime_error(fmt::format(
        "cannot start the mesh reader {}: {} (build the target ecpsim-mesh-reader, or set "
        "ECPSIM_MESH_READER to its path)",
        program, std::strerror(error)));
  }
  return pid;
}

}  // namespace

MeshReaderLimits MeshReaderLimitsForFile(std::uint64_t file_bytes) {
  MeshReaderLimits limits;
  const std::uint64_t max = std::numeric_limits<std::uint64_t>::max();
  limits.memory_bytes = file_bytes > (max - kReaderMemoryFloor) / kReaderMemoryPerFileByte
                            ? max
                            : kReaderMemoryFloor + kReaderMemoryPerFileByte * file_bytes;
  limits.seconds =
      kReaderSecondsFloor + kReaderSecondsPerFileByte * static_cast<double>(file_bytes);
  return limits;
}

ImportedMesh ReadMeshInReaderProcess(const std::string& path, const MeshReaderLimits& limits) {
  ECPSIM_DEMAND(limits.memory_bytes > 0 && limits.seconds > 0.0 && std::isfinite(limits.seconds));
  const Clock::time_point deadline =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(
                         std::chrono::duration<double>(std::min(limits.seconds, 1e9)));

  // close-on-exec on both ends, so a reader started by another thread at the same moment does
  // not inherit our write end (our end-of-stream would then never come)
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    throw std::runtime_error(
        fmt::format("mesh reader: cannot create a pipe: {}", std::strerror(errno)));
  }
  const int read_fd = fds[0];
  int write_fd = fds[1];
  if (write_fd == kReaderOutputFd) {
    // dup2 onto itself would keep close-on-exec set: move it out of the way
    write_fd = ::fcntl(fds[1], F_DUPFD_CLOEXEC, kReaderOutputFd + 1);
    ::close(fds[1]);
  }
  ::fcntl(read_fd, F_SETPIPE_SZ, kPipeBytes);  // a hint: a smaller pipe only costs speed

  pid_t pid = -1;
  try {
    if (write_fd < 0) {
      throw std::runtime_error(
          fmt::format("mesh reader: cannot duplicate a descriptor: {}", std::strerror(errno)));
    }
    pid = SpawnReader(ReaderProgram(), path, write_fd, limits);
  } catch (...) {
    ::close(read_fd);
    if (write_fd >= 0) ::close(write_fd);
    throw;
  }
  ::close(write_fd);
  ReaderChild child(pid, read_fd);

  try {
    ms::Header header;
    if (ReadUntil(child.fd(), &header, sizeof(header), deadline) < sizeof(header)) {
      Fail(path, DescribeEnd(child.Wait(), limits));
    }
    if (std::memcmp(header.magic, ms::kMagic, sizeof(ms::kMagic)) != 0) {
      throw std::runtime_error(fmt::format(
          "mesh reader {}: unexpected output (not an ecpsim mesh stream)", ReaderProgram()));
    }
    if (header.kind == ms::Kind::kOutOfMemory) {
      FinishAfterError(child, deadline);
      Fail(path, fmt::format("assimp needs more than the {} memory limit for this file (a "
                             "corrupt header declaring huge counts?)",
                             Megabytes(limits.memory_bytes)));
    }
    if (header.kind == ms::Kind::kError) {
      std::string message(std::min(header.message_bytes, ms::kMaxMessageBytes), '\0');
      message.resize(ReadUntil(child.fd(), message.data(), message.size(), deadline));
      FinishAfterError(child, deadline);
      Fail(path, message);
    }
    if (header.kind != ms::Kind::kMesh) {
      throw std::runtime_error(fmt::format("mesh reader: unknown record kind {}",
                                           static_cast<std::uint32_t>(header.kind)));
    }

    // the decoded mesh is bounded like the reader: node instancing can multiply a small file
    const std::uint64_t max_vertices = std::numeric_limits<std::int32_t>::max();
    const std::uint64_t vertex_bytes = sizeof(Eigen::Vector3d);
    const std::uint64_t triangle_bytes = sizeof(Eigen::Vector3i);
    const std::uint64_t budget = limits.memory_bytes;
    if (header.num_vertices > max_vertices || header.num_vertices > budget / vertex_bytes ||
        header.num_triangles > (budget - header.num_vertices * vertex_bytes) / triangle_bytes) {
      child.Kill();
      Fail(path,
           fmt::format("the scene expands to {} vertices and {} triangles, more than the "
                       "{} memory limit for this file",
                       header.num_vertices, header.num_triangles, Megabytes(limits.memory_bytes)));
    }

    // straight into the mesh's own arrays: no second copy of a large mesh
    static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double));
    static_assert(sizeof(Eigen::Vector3i) == 3 * sizeof(std::int32_t));
    ImportedMesh imported;
    imported.num_meshes = header.num_meshes;
    imported.other_faces = header.other_faces;
    TriangleMesh& mesh = imported.mesh;
    mesh.vertices.resize(header.num_vertices);
    mesh.triangles.resize(header.num_triangles);
    const std::size_t vertex_size = mesh.vertices.size() * sizeof(Eigen::Vector3d);
    const std::size_t triangle_size = mesh.triangles.size() * sizeof(Eigen::Vector3i);
    if (ReadUntil(child.fd(), mesh.vertices.data(), vertex_size, deadline) < vertex_size ||
        ReadUntil(child.fd(), mesh.triangles.data(), triangle_size, deadline) < triangle_size) {
      Fail(path, DescribeEnd(child.Wait(), limits));
    }

    // the stream ends here; the reader then exits 0 (its status may be lost, see WaitForExit)
    char extra = 0;
    const bool trailing = ReadUntil(child.fd(), &extra, 1, deadline) != 0;
    const std::optional<int> status = child.Wait();
    if (trailing) throw std::runtime_error("mesh reader: data after the end of the mesh stream");
    if (status && !(WIFEXITED(*status) && WEXITSTATUS(*status) == ms::kExitOk)) {
      Fail(path, DescribeEnd(status, limits));
    }
    const int num_vertices = static_cast<int>(mesh.vertices.size());
    for (const Eigen::Vector3i& t : mesh.triangles) {
      ECPSIM_DEMAND(t.minCoeff() >= 0 && t.maxCoeff() < num_vertices);
    }
    return imported;
  } catch (const DeadlinePassed&) {
    child.Kill();
    Fail(path, fmt::format("assimp took longer than the {:.3g} s limit for this file (a valid "
                           "file of this size reads in a fraction of that)",
                           limits.seconds));
  }
}

}  // namespace ecpsim::geometry
