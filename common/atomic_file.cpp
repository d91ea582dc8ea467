#include "common/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <regex>
#include <system_error>

#include <fmt/format.h>

#include "common/errors.h"

namespace ecpsim {
namespace {

namespace fs = std::filesystem;

// distinguishes the temporary files of one process (threads writing frames side by side)
std::atomic<unsigned long> temp_counter{0};

// the temporary form NAME.tmp-PID-N; the PID is group 1
const std::regex& TemporaryPattern() {
  static const std::regex pattern(R"(.+\.tmp-([0-9]{1,9})-[0-9]+)");
  return pattern;
}

// what lstat found at a path, in words for a message
std::string Describe(const std::string& path, const struct stat& info) {
  if (S_ISLNK(info.st_mode)) {
    std::error_code error;
    const fs::path target = fs::read_symlink(path, error);
    return error ? "symbolic link" : fmt::format("symbolic link (to {})", target.string());
  }
  if (S_ISFIFO(info.st_mode)) return "FIFO (named pipe)";
  if (S_ISDIR(info.st_mode)) return "folder";
  if (S_ISCHR(info.st_mode)) return "character device";
  if (S_ISBLK(info.st_mode)) return "block device";
  if (S_ISSOCK(info.st_mode)) return "socket";
  return "special file";
}

bool ProcessRunning(long pid) {
  return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM);
}

}  // namespace

void RequireReplaceable(const std::string& path) {
  struct stat info;
  if (::lstat(path.c_str(), &info) != 0) {
    if (errno == ENOENT) return;
    throw InputError(fmt::format("{}: cannot write it ({}); expected a path in a writable folder",
                                 path, std::strerror(errno)));
  }
  if (!S_ISREG(info.st_mode)) {
    throw InputError(
        fmt::format("{}: a {} is there; expected a regular file or nothing (an "
                    "output replaces only regular files)",
                    path, Describe(path, info)));
  }
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  RequireReplaceable(path_);
  temp_path_ = fmt::format("{}.tmp-{}-{}", path_, static_cast<long>(::getpid()), temp_counter++);
}

AtomicFile::AtomicFile(AtomicFile&& other) noexcept
    : path_(std::move(other.path_)),
      temp_path_(std::move(other.temp_path_)),
      committed_(other.committed_) {
  other.committed_ = true;  // the moved-from object owns no temporary file
}

AtomicFile::~AtomicFile() {
  if (!committed_) ::unlink(temp_path_.c_str());
}

std::FILE* AtomicFile::Create() {
  const int fd = ::open(temp_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  std::FILE* file = fd < 0 ? nullptr : ::fdopen(fd, "wb");
  if (file == nullptr) {
    const int error = errno;
    if (fd >= 0) ::close(fd);
    throw InputError(fmt::format("{}: cannot create it ({}); expected a writable folder",
                                 temp_path_, std::strerror(error)));
  }
  return file;
}

void AtomicFile::Commit() {
  ECPSIM_DEMAND(!committed_);
  try {
    // what is at the destination may have changed while the temporary file was written
    RequireReplaceable(path_);
    if (std::rename(temp_path_.c_str(), path_.c_str()) != 0) {
      throw InputError(
          fmt::format("{}: cannot rename it to {} ({})", temp_path_, path_, std::strerror(errno)));
    }
  } catch (...) {
    ::unlink(temp_path_.c_str());
    committed_ = true;
    throw;
  }
  committed_ = true;
}

void WriteFileAtomically(const std::string& path, std::string_view content) {
  AtomicFile file(path);
  std::FILE* out = file.Create();
  const bool written = std::fwrite(content.data(), 1, content.size(), out) == content.size();
  const bool closed = std::fclose(out) == 0;
  if (!written || !closed) {
    throw InputError(fmt::format("{}: cannot write it (disk full?)", file.temp_path()));
  }
  file.Commit();
}

bool IsTemporaryName(const std::string& file_name) {
  return std::regex_match(file_name, TemporaryPattern());
}

int RemoveStaleTemporaries(const std::string& dir) {
  std::error_code error;
  int removed = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    std::smatch match;
    if (!std::regex_match(name, match, TemporaryPattern())) continue;
    if (!entry.is_regular_file(error) || entry.is_symlink(error)) continue;
    if (ProcessRunning(std::stol(match[1].str()))) continue;
    if (fs::remove(entry.path(), error)) ++removed;
  }
  return removed;
}

}  // namespace ecpsim
