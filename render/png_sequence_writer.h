#pragma once
// Numbered PNG frames (DIR/frame_000000.png, ...) encoded on worker threads, so that rendering the
// next frame and encoding the last one overlap on two cores.

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "render/image.h"
#include "render/png_writer.h"

namespace ecpsim::render {

class PngSequenceWriter {
 public:
  /// Creates `directory` if missing. `threads` encoders (≥ 1); Add blocks while `max_queued`
  /// frames wait, bounding memory. The first frame added gets index `first_index` (> 0 continues
  /// a sequence whose earlier frames are there already).
  /// @throws InputError if the directory cannot be created (naming it and the reason) or a count
  ///         is out of range.
  explicit PngSequenceWriter(const std::string& directory, int threads = 1, int max_queued = 4,
                             int compression = kFastPngCompression, int first_index = 0);
  /// Waits for the queued frames; errors not collected by Finish() are dropped.
  ~PngSequenceWriter();
  PngSequenceWriter(const PngSequenceWriter&) = delete;
  PngSequenceWriter& operator=(const PngSequenceWriter&) = delete;

  /// Queues `frame` as the next file and returns its path.
  /// @throws the first error of an earlier write (InputError naming the file).
  std::string Add(Image frame);

  /// Waits until every queued frame is written.
  /// @throws the first write error, if any.
  void Finish();

  /// DIR/frame_NNNNNN.png for frame `index`.
  std::string FramePath(int index) const;

 private:
  void Work();
  void RethrowFirstError();

  std::string directory_;
  int max_queued_;
  int compression_;
  int next_index_ = 0;
  int busy_ = 0;  // frames taken by workers, not yet written
  bool stopping_ = false;
  std::deque<std::pair<int, Image>> queue_;
  std::exception_ptr first_error_;
  std::mutex mutex_;
  std::condition_variable work_ready_;
  std::condition_variable space_ready_;
  std::vector<std::thread> workers_;
};

}  // namespace ecpsim::render
