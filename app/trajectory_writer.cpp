#include "app/trajectory_writer.h"

#include <cmath>
#include <fstream>

#include <fmt/format.h>

#include "common/errors.h"
#include "engine/report/trajectory_columns.h"

namespace ecpsim::app {

TrajectoryWriter::TrajectoryWriter(const engine::Scene& scene, const std::string& path,
                                   std::optional<long> keep_rows)
    : scene_(scene), columns_(engine::TrajectoryColumns(scene)), file_(path) {
  std::string header;
  for (size_t i = 0; i < columns_.size(); ++i) {
    header += (i == 0 ? "" : ",") + columns_[i];
  }
  for (const std::string& column : engine::TrajectoryModelColumns(scene)) header += "," + column;
  stream_ = file_.Create();
  try {
    Append(header, true);
    if (keep_rows) {
      // the earlier part of a resumed run, byte for byte, streamed
      std::ifstream earlier(path, std::ios::binary);
      std::string line;
      if (!std::getline(earlier, line) || line != header) {
        throw InputError(fmt::format("{}: {}; expected the header of this scene's trajectory", path,
                                     earlier ? "another header" : "missing or empty"));
      }
      for (long r = 0; r < *keep_rows; ++r) {
        // a last line without its newline is incomplete
        if (!std::getline(earlier, line) || earlier.eof()) {
          throw InputError(
              fmt::format("{}: {} complete rows; expected at least the {} rows that "
                          "the checkpoint counts",
                          path, r, *keep_rows));
        }
        Append(line, false);
      }
      rows_ = *keep_rows;
    }
  } catch (...) {
    std::fclose(stream_);  // file_ then removes the temporary file
    throw;
  }
}

TrajectoryWriter::~TrajectoryWriter() {
  // without Finish() the AtomicFile removes the temporary file
  if (stream_ != nullptr) {
    std::fclose(stream_);
  }
}

void TrajectoryWriter::Write(const engine::State& state, const engine::StepReport& report) {
  const std::vector<double> values = engine::TrajectoryValues(scene_, state, report);
  ECPSIM_DEMAND(values.size() == columns_.size());

  // never a NaN in an output: refuse the row and let the run stop as a failure
  for (size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      throw engine::SolverFailure(
          fmt::format("t = {} s: {} = {} is not finite; the trajectory "
                      "stops at the last finite row",
                      state.t, columns_[i], values[i]));
    }
  }
  fmt::memory_buffer row;
  for (size_t i = 0; i < values.size(); ++i) {
    fmt::format_to(std::back_inserter(row), i == 0 ? "{}" : ",{}", values[i]);
  }
  for (const std::string& model : engine::TrajectoryModels(scene_, report))
    fmt::format_to(std::back_inserter(row), ",{}", model);
  Append(std::string_view(row.data(), row.size()), true);
  ++rows_;
}

void TrajectoryWriter::Append(std::string_view line, bool flush) {
  if (std::fwrite(line.data(), 1, line.size(), stream_) != line.size() ||
      std::fputc('\n', stream_) == EOF || (flush && std::fflush(stream_) != 0)) {
    throw InputError(fmt::format("{}: cannot write it (disk full?)", file_.temp_path()));
  }
}

void TrajectoryWriter::Finish() {
  if (stream_ == nullptr) {
    return;
  }
  const bool closed = std::fclose(stream_) == 0;
  stream_ = nullptr;
  if (!closed) {
    throw InputError(fmt::format("{}: cannot write it (disk full?)", file_.temp_path()));
  }
  file_.Commit();
}

}  // namespace ecpsim::app
