#pragma once
// Output files replaced atomically: written under a temporary name next to the destination, then
// renamed onto it, so a reader sees the old file or the whole new one, never half of one. Only a
// regular file (or nothing) at the destination is replaced; a symbolic link, a FIFO, a directory
// or a device node there is refused and left untouched.
//
// The one temporary-name scheme of ecpsim: DEST.tmp-PID-N, in DEST's folder (so the rename stays
// on one file system), PID the writing process and N a counter within it. A process that dies
// before its rename (SIGKILL, power loss) leaves such a file; RemoveStaleTemporaries finds it.

#include <cstdio>
#include <string>
#include <string_view>

namespace ecpsim {

/// Checks that writing `path` may replace what is there: nothing, or a regular file.
/// @throws InputError naming the path and what is there, e.g. `out/summary.json: a FIFO (named
///         pipe) is there; expected a regular file or nothing (an output replaces only regular
///         files)`, or if `path` cannot be inspected (a parent that is not a folder, no access).
void RequireReplaceable(const std::string& path);

/// One output file under its temporary name until Commit() renames it onto `path`. Without a
/// successful Commit() the destructor removes the temporary file.
class AtomicFile {
 public:
  /// Chooses the temporary name; creates nothing yet.
  /// @throws InputError if `path` is there and is not a regular file (RequireReplaceable).
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(AtomicFile&& other) noexcept;
  AtomicFile& operator=(AtomicFile&& other) = delete;
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::string& path() const { return path_; }
  /// PATH.tmp-PID-N: for programs that write the file themselves (ffmpeg, gnuplot).
  const std::string& temp_path() const { return temp_path_; }

  /// Creates the temporary file (exclusively: never through an existing name) and opens it for
  /// binary writing; the caller closes it before Commit().
  /// @throws InputError naming the path and the system's reason.
  std::FILE* Create();

  /// Renames the temporary file onto `path`, checking RequireReplaceable again just before.
  /// @throws InputError if the destination is no longer replaceable or the rename fails; the
  ///         temporary file is then removed.
  void Commit();

 private:
  std::string path_;
  std::string temp_path_;
  bool committed_ = false;
};

/// Writes `content` to `path` through an AtomicFile.
/// @throws InputError naming the path: not replaceable, not writable (with the system's reason),
///         disk full.
void WriteFileAtomically(const std::string& path, std::string_view content);

/// Whether `file_name` (no folder) has the temporary form NAME.tmp-PID-N.
bool IsTemporaryName(const std::string& file_name);

/// Removes the temporary files in `dir` (regular files named NAME.tmp-PID-N) whose writing
/// process is no longer running; returns how many. A missing `dir` has none.
int RemoveStaleTemporaries(const std::string& dir);

}  // namespace ecpsim
