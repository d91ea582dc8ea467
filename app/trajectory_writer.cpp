#include "app/trajectory_writer.h"

#include <cmath>
#include <fstream>

#include <fmt/format.h>

#include "common/errors.h"

namespace ecpsim::app {

std::vector<std::string> TrajectoryColumns(const engine::Scene& scene) {
  std::vector<std::string> columns = {"t"};
  const bool several_bodies = scene.bodies.size() > 1;
  for (const engine::Body& body : scene.bodies) {
    const std::string prefix = several_bodies ? body.name + "." : "";
    for (const char* c : {"px", "py", "pz", "qw", "qx", "qy", "qz", "vx", "vy", "vz", "wx", "wy",
                          "wz"}) {
      columns.push_back(prefix + c);
    }
  }
  const bool several_contacts = scene.contacts.size() > 1;
  for (const engine::ContactPair& pair : scene.contacts) {
    const std::string prefix =
        several_contacts
            ? scene.bodies[pair.body].name + "." +
                  (pair.WithBody() ? scene.bodies[pair.other_body].name
                                   : scene.obstacles[pair.obstacle].name) +
                  "."
            : "";
    for (const char* c : {"a1x", "a1y", "a1z", "a2x", "a2y", "a2z", "pn", "pt", "po", "pr",
                          "sigma"}) {
      columns.push_back(prefix + c);
    }
  }
  columns.push_back("iters");
  columns.push_back("residual");
  return columns;
}

TrajectoryWriter::TrajectoryWriter(const engine::Scene& scene, const std::string& path,
                                   std::optional<long> keep_rows)
    : columns_(TrajectoryColumns(scene)), file_(path) {
  std::string header;
  for (size_t i = 0; i < columns_.size(); ++i) {
    header += (i == 0 ? "" : ",") + columns_[i];
  }
  stream_ = file_.Create();
  try {
    Append(header, true);
    if (keep_rows) {
      // the earlier part of a resumed run, byte for byte, streamed
      std::ifstream earlier(path, std::ios::binary);
      std::string line;
      if (!std::getline(earlier, line) || line != header) {
        throw InputError(fmt::format("{}: {}; expected the header of this scene's trajectory",
                                     path, earlier ? "another header" : "missing or empty"));
      }
      for (long r = 0; r < *keep_rows; ++r) {
        // a last line without its newline is incomplete
        if (!std::getline(earlier, line) || earlier.eof()) {
          throw InputError(fmt::format("{}: {} complete rows; expected at least the {} rows that "
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
  std::vector<double> values = {state.t};
  values.reserve(columns_.size());
  for (const engine::BodyState& b : state.bodies) {
    values.insert(values.end(), {b.p_WB.x(), b.p_WB.y(), b.p_WB.z(), b.Q_WB.w(), b.Q_WB.x(),
                                 b.Q_WB.y(), b.Q_WB.z(), b.v_WB.x(), b.v_WB.y(), b.v_WB.z(),
                                 b.w_WB.x(), b.w_WB.y(), b.w_WB.z()});
  }
  for (const engine::ContactState& c : state.contacts) {
    values.insert(values.end(), {c.a1.x(), c.a1.y(), c.a1.z(), c.a2.x(), c.a2.y(), c.a2.z(),
                                 c.p_n, c.p_t, c.p_o, c.p_r, c.sigma});
  }
  values.push_back(report.iterations);
  values.push_back(report.residual);
  ECPSIM_DEMAND(values.size() == columns_.size());

  // never a NaN in an output: refuse the row and let the run stop as a failure
  for (size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      throw engine::SolverFailure(fmt::format("t = {} s: {} = {} is not finite; the trajectory "
                                              "stops at the last finite row",
                                              state.t, columns_[i], values[i]));
    }
  }
  fmt::memory_buffer row;
  for (size_t i = 0; i < values.size(); ++i) {
    fmt::format_to(std::back_inserter(row), i == 0 ? "{}" : ",{}", values[i]);
  }
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
