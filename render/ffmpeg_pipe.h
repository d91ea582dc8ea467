#pragma once
// MP4 video by piping raw RGB frames into the ffmpeg program (started with an argument vector,
// no shell): H.264, yuv420p, fast start, so browsers play it. A video can be continued: the new
// frames are encoded as a second segment and joined to the first without re-encoding.

#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "common/atomic_file.h"
#include "render/image.h"
#include "render/render_target.h"

namespace ecpsim::render {

/// What FfmpegPipe does with the video already at its path.
enum class VideoStart {
  kReplace,  // the frames make a new video, replacing what is there when finished
  kAppend,   // the frames continue the video there (same size and frame rate, made by FfmpegPipe)
};

/// Checks that `program` can be started (searched on PATH unless it contains a '/'), before
/// anything is written.
/// @throws InputError naming `video_path`, the program and the Debian package that has it.
void RequireVideoProgram(const std::string& video_path, const std::string& program = "ffmpeg");

/// The frames of the MP4 video at `path` (its first video stream's frame count as the file
/// records it, read by the ffprobe program).
/// @throws InputError if ffprobe is missing or `path` is not a readable video (naming it and
///         ffprobe's error output).
int CountVideoFrames(const std::string& path, const std::string& program = "ffprobe");

/// One ffmpeg process encoding frames of a fixed size into `path`. The video is written to a
/// temporary name (common/atomic_file.h) and renamed by Finish(), so `path` is never a
/// half-written file; without a successful Finish() the temporary file is removed and `path`
/// keeps what it held. Frames go to ffmpeg on a writer thread, so that the caller renders the
/// next frame while ffmpeg takes the last one.
class FfmpegPipe {
 public:
  /// Starts `program` (searched on PATH unless it contains a '/') for `width` × `height` frames at
  /// `fps` frames per second (odd sizes are padded by one pixel: yuv420p needs even sizes), whose
  /// bytes are in `order` (ChannelOrder::kBgr: ffmpeg's conversion to yuv420p costs ~1/3).
  /// With VideoStart::kAppend the video at `path` must be one that FfmpegPipe made with the same
  /// size and fps: Finish() joins it and the new frames (ffmpeg's concat demuxer, `-c copy`:
  /// lossless) into `path`.
  /// @throws InputError if the program is not found (naming it and the Debian package), the size
  ///         is not positive, fps is not finite in (0, 1000], something other than a regular
  ///         file is at `path`, or (kAppend) no video is there; std::runtime_error if the process
  ///         cannot be started.
  FfmpegPipe(const std::string& path, int width, int height, double fps,
             const std::string& program = "ffmpeg", VideoStart start = VideoStart::kReplace,
             ChannelOrder order = ChannelOrder::kRgb);
  ~FfmpegPipe();
  FfmpegPipe(const FfmpegPipe&) = delete;
  FfmpegPipe& operator=(const FfmpegPipe&) = delete;

  /// Queues one frame (must be width × height, in the order given at construction); blocks while
  /// two frames wait.
  /// @throws std::runtime_error with ffmpeg's own error output if ffmpeg has stopped.
  void Write(Image frame);

  /// Queues one frame as drawn (render_target.h): the writer thread downsamples it, so that the
  /// caller draws the next frame meanwhile (the downsample is ~1.5 ms of a 1280×720 frame's
  /// ~8 ms on the render thread). Same contract as Write(Image). A drawing is 2.25× to 16× the
  /// image's bytes (8 MB at 1280×720 with 1.5× supersampling); with SpareDrawing at most four
  /// are alive: one drawn into, two queued, one being sent.
  void Write(Drawing frame);

  /// A Drawing already sent, for its buffer to be drawn into again (Renderer::RenderDrawing's
  /// `spare`); an empty one if there is none yet.
  Drawing SpareDrawing();

  /// Sends the queued frames, closes the stream, waits for ffmpeg and renames the video to
  /// `path` (kAppend: joins the earlier video and the new frames into `path`; with no new frame,
  /// `path` is left as it is).
  /// @throws std::runtime_error with ffmpeg's error output if it failed.
  void Finish();

  /// Frames given to Write() so far.
  int frames() const { return frames_; }

 private:
  void Queue(std::variant<Image, Drawing> frame);
  void SendFrames();
  void StopWriter();
  void JoinOntoEarlierVideo();
  [[noreturn]] void Fail(const std::string& what);

  std::string path_, log_path_, program_;
  std::optional<AtomicFile> file_;  // the new frames' video under its temporary name
  VideoStart start_;
  ChannelOrder order_;
  int width_, height_;
  int pid_ = -1;
  int stdin_fd_ = -1;
  int frames_ = 0;

  // the writer thread's queue; write_error_ is the errno of a failed write (ffmpeg stopped)
  std::deque<std::variant<Image, Drawing>> queue_;
  std::vector<Drawing> spares_;  // Drawings sent, as many as may be in flight at once
  bool closing_ = false;
  int write_error_ = 0;
  std::mutex mutex_;
  std::condition_variable frame_ready_, space_ready_;
  std::thread writer_;
};

}  // namespace ecpsim::render
