#pragma once
// MP4 video by piping raw RGB frames into the ffmpeg program (started with an argument vector,
// no shell): H.264, yuv420p, fast start, so browsers play it.

#include <optional>
#include <string>

#include "common/atomic_file.h"
#include "render/image.h"

namespace ecpsim::render {

/// One ffmpeg process encoding frames of a fixed size into `path`. The video is written to a
/// temporary name (common/atomic_file.h) and renamed by Finish(), so `path` is never a
/// half-written file; without a successful Finish() the temporary file is removed.
class FfmpegPipe {
 public:
  /// Starts `program` (searched on PATH unless it contains a '/') for `width` × `height` frames at
  /// `fps` frames per second (odd sizes are padded by one pixel: yuv420p needs even sizes).
  /// @throws InputError if the program is not found (naming it and the Debian package), the size
  ///         is not positive, fps is not finite in (0, 1000], or something other than a regular
  ///         file is at `path`; std::runtime_error if the process cannot be started.
  FfmpegPipe(const std::string& path, int width, int height, double fps,
             const std::string& program = "ffmpeg");
  ~FfmpegPipe();
  FfmpegPipe(const FfmpegPipe&) = delete;
  FfmpegPipe& operator=(const FfmpegPipe&) = delete;

  /// Sends one frame (must be width × height).
  /// @throws std::runtime_error with ffmpeg's own error output if ffmpeg has stopped.
  void Write(const Image& frame);

  /// Closes the stream, waits for ffmpeg and renames the video to `path`.
  /// @throws std::runtime_error with ffmpeg's error output if it failed.
  void Finish();

  int frames() const { return frames_; }

 private:
  [[noreturn]] void Fail(const std::string& what);
  std::string path_, log_path_;
  std::optional<AtomicFile> file_;  // the video under its temporary name
  int width_, height_;
  int pid_ = -1;
  int stdin_fd_ = -1;
  int frames_ = 0;
};

}  // namespace ecpsim::render
