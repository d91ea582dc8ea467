#include "app/output_folder.h"

#include <filesystem>
#include <regex>
#include <system_error>

#include <fmt/format.h>

#include "common/atomic_file.h"
#include "common/errors.h"

namespace ecpsim::app {
namespace {

namespace fs = std::filesystem;

// the names a run writes directly in its folder
constexpr const char* kOutputNames[] = {"trajectory.csv", "summary.json", "video.mp4",
                                        "checkpoint.json"};

// removes `path` if it is a regular file (never what a symlink points to)
void RemoveRegularFile(const fs::path& path) {
  std::error_code error;
  if (fs::is_regular_file(fs::symlink_status(path, error))) fs::remove(path, error);
}

}  // namespace

bool IsFrameName(const std::string& file_name) {
  // PngSequenceWriter::FramePath: frame_{:06d}.png, so 6 digits or more
  static const std::regex pattern(R"(frame_[0-9]{6,}\.png)");
  return std::regex_match(file_name, pattern);
}

void PrepareOutputFolder(const std::string& out_dir, bool resume) {
  std::error_code error;
  fs::create_directories(out_dir, error);
  if (error || !fs::is_directory(out_dir)) {
    throw InputError(
        fmt::format("output folder {}: cannot create it ({}); expected a writable "
                    "path",
                    out_dir, error ? error.message() : "a file of that name exists"));
  }
  for (const char* name : kOutputNames) RequireReplaceable((fs::path(out_dir) / name).string());

  const fs::path frames = fs::path(out_dir) / "frames";
  RemoveStaleTemporaries(out_dir);
  RemoveStaleTemporaries(frames.string());
  if (resume) return;
  for (const fs::directory_entry& entry : fs::directory_iterator(frames, error)) {
    if (IsFrameName(entry.path().filename().string())) RemoveRegularFile(entry.path());
  }
  // a folder the frames leave empty goes too (a run with a video alone makes none); never a
  // symbolic link to one
  if (fs::is_directory(fs::symlink_status(frames, error)) && fs::is_empty(frames, error)) {
    fs::remove(frames, error);
  }
  RemoveRegularFile(fs::path(out_dir) / "video.mp4");
  RemoveRegularFile(fs::path(out_dir) / "checkpoint.json");
}

}  // namespace ecpsim::app
