#include "app/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include <fmt/format.h>

#include "common/errors.h"

namespace ecpsim::app {

void WriteFileAtomically(const std::string& path, const std::string& content) {
  const std::string partial = path + ".partial";
  std::FILE* file = std::fopen(partial.c_str(), "wb");
  if (file == nullptr) {
    throw InputError(fmt::format("{}: cannot create it ({}); expected a writable folder", partial,
                                 std::strerror(errno)));
  }
  const bool written = std::fwrite(content.data(), 1, content.size(), file) == content.size();
  const bool closed = std::fclose(file) == 0;
  if (!written || !closed) {
    std::remove(partial.c_str());
    throw InputError(fmt::format("{}: cannot write it (disk full?)", partial));
  }
  if (std::rename(partial.c_str(), path.c_str()) != 0) {
    throw InputError(fmt::format("{}: cannot rename it to {} ({})", partial, path,
                                 std::strerror(errno)));
  }
}

}  // namespace ecpsim::app
