#include "common/child_process_call.h"

#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

namespace ecpsim::detail {
namespace {

// bytes of an exception's message the child hands back (longer ones are cut)
constexpr std::size_t kMessageBytes = 1024;
// the child's exit status when `work` threw (its message is in the shared message area)
constexpr int kThrewStatus = 3;

// the shared pages: the result, then the child's message, unmapped on every path
class SharedMemory {
 public:
  explicit SharedMemory(std::size_t bytes) : bytes_(bytes) {
    data_ = mmap(nullptr, bytes_, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (data_ == MAP_FAILED) {
      throw std::runtime_error(
          fmt::format("cannot map {} bytes of shared memory: {}", bytes_, std::strerror(errno)));
    }
  }
  ~SharedMemory() { munmap(data_, bytes_); }
  SharedMemory(const SharedMemory&) = delete;
  SharedMemory& operator=(const SharedMemory&) = delete;
  char* bytes() const { return static_cast<char*>(data_); }

 private:
  std::size_t bytes_;
  void* data_;
};

}  // namespace

std::string CallInChildProcess(void* result, std::size_t bytes,
                               const std::function<void(void* shared)>& work) {
  SharedMemory shared(bytes + kMessageBytes);
  std::memcpy(shared.bytes(), result, bytes);
  char* const message = shared.bytes() + bytes;
  const pid_t child = fork();
  if (child < 0) {
    throw std::runtime_error(fmt::format("cannot fork a child process: {}", std::strerror(errno)));
  }
  if (child == 0) {
    int status = 0;
    try {
      work(shared.bytes());
    } catch (const std::exception& e) {
      std::strncpy(message, e.what(), kMessageBytes - 1);
      status = kThrewStatus;
    } catch (...) {
      std::strncpy(message, "an exception that is not a std::exception", kMessageBytes - 1);
      status = kThrewStatus;
    }
    _exit(status);
  }
  int status = 0;
  while (waitpid(child, &status, 0) < 0) {
    if (errno != EINTR) {
      throw std::runtime_error(
          fmt::format("waiting for child process {}: {}", child, std::strerror(errno)));
    }
  }
  std::memcpy(result, shared.bytes(), bytes);
  if (WIFSIGNALED(status)) {
    return fmt::format("killed by signal {} ({})", WTERMSIG(status), strsignal(WTERMSIG(status)));
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == kThrewStatus) return std::string(message);
  if (WIFEXITED(status) && WEXITSTATUS(status) != 0) {
    return fmt::format("exit status {}", WEXITSTATUS(status));
  }
  return "";
}

}  // namespace ecpsim::detail
