#include "render/png_sequence_writer.h"

#include <filesystem>
#include <system_error>
#include <utility>

#include <fmt/format.h>

#include "common/errors.h"

namespace ecpsim::render {
namespace {

// more encoders than this cannot help on any machine this runs on, and would hold many frames
constexpr int kMaxThreads = 64;

}  // namespace

PngSequenceWriter::PngSequenceWriter(const std::string& directory, int threads, int max_queued,
                                     int compression, int first_index)
    : directory_(directory),
      max_queued_(max_queued),
      compression_(compression),
      next_index_(first_index) {
  if (threads < 1 || threads > kMaxThreads || max_queued < 1 || first_index < 0) {
    throw InputError(
        fmt::format("frames '{}': {} threads, {} queued, first frame {}: expected 1 "
                    "to {} threads, at least 1 queued frame and a first frame >= 0",
                    directory, threads, max_queued, first_index, kMaxThreads));
  }
  std::error_code error;
  std::filesystem::create_directories(directory, error);
  if (error || !std::filesystem::is_directory(directory)) {
    throw InputError(fmt::format("frames '{}': cannot create the folder: {}", directory,
                                 error ? error.message() : "a file of that name exists"));
  }
  for (int i = 0; i < threads; ++i) workers_.emplace_back([this] { Work(); });
}

PngSequenceWriter::~PngSequenceWriter() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  work_ready_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

std::string PngSequenceWriter::FramePath(int index) const {
  return fmt::format("{}/frame_{:06d}.png", directory_, index);
}

std::string PngSequenceWriter::Add(Image frame) {
  std::unique_lock<std::mutex> lock(mutex_);
  RethrowFirstError();
  space_ready_.wait(
      lock, [this] { return static_cast<int>(queue_.size()) < max_queued_ || first_error_; });
  RethrowFirstError();
  const int index = next_index_++;
  queue_.emplace_back(index, std::move(frame));
  lock.unlock();
  work_ready_.notify_one();
  return FramePath(index);
}

void PngSequenceWriter::Finish() {
  std::unique_lock<std::mutex> lock(mutex_);
  space_ready_.wait(lock, [this] { return (queue_.empty() && busy_ == 0) || first_error_; });
  RethrowFirstError();
}

void PngSequenceWriter::RethrowFirstError() {
  if (first_error_) std::rethrow_exception(first_error_);
}

void PngSequenceWriter::Work() {
  for (;;) {
    std::pair<int, Image> job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      work_ready_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping, nothing left
      job = std::move(queue_.front());
      queue_.pop_front();
      ++busy_;
    }
    space_ready_.notify_all();
    std::exception_ptr error;
    try {
      WritePng(FramePath(job.first), job.second, compression_);
    } catch (...) {
      error = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      --busy_;
      if (error && !first_error_) first_error_ = error;
    }
    space_ready_.notify_all();
  }
}

}  // namespace ecpsim::render
