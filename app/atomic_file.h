#pragma once
// Writing an output file so that readers never see it half written (temporary file + rename).

#include <string>

namespace ecpsim::app {

/// Writes `content` to `path + ".partial"`, then renames it onto `path` (atomic on POSIX).
/// @throws InputError naming the path if the file cannot be written or renamed.
void WriteFileAtomically(const std::string& path, const std::string& content);

}  // namespace ecpsim::app
