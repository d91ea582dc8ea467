#pragma once
// trajectory.csv: one row per written step with every body's state and every contact's solution.

#include <cstdio>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/atomic_file.h"
#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"

namespace ecpsim::app {

/// The rows of engine::TrajectoryColumns. Streams rows to a temporary file next to `path`
/// (common/atomic_file.h; flushed after every row) and renames it onto `path` in Finish(), so that
/// a run stopped by a solver failure or an interrupt still leaves a valid trajectory.csv holding
/// the rows written so far. Numbers are written in shortest round-trip form.
class TrajectoryWriter {
 public:
  /// Starts a new trajectory at `path`, or, with `keep_rows`, continues the one there: its
  /// header and first `keep_rows` rows are copied as they are and the rows after them dropped
  /// (a resumed run, app/checkpoint.h).
  /// @throws InputError if the file cannot be created, something other than a regular file is
  ///         at `path`, or the file to continue has another header or fewer rows.
  TrajectoryWriter(const engine::Scene& scene, const std::string& path,
                   std::optional<long> keep_rows = std::nullopt);
  ~TrajectoryWriter();
  TrajectoryWriter(const TrajectoryWriter&) = delete;
  TrajectoryWriter& operator=(const TrajectoryWriter&) = delete;

  /// Appends the row of `state` after a step that reported `report`.
  /// @throws engine::SolverFailure naming the column and time if any value is not finite (the
  ///         row is then not written: no NaN ever reaches the file).
  void Write(const engine::State& state, const engine::StepReport& report);

  /// Closes the file and renames it to its final name. Idempotent.
  /// @throws InputError if it cannot be written or renamed.
  void Finish();

  long rows() const { return rows_; }

 private:
  // writes `line` and a newline; a row is flushed at once so that it is on disk if the process dies
  void Append(std::string_view line, bool flush);

  const engine::Scene& scene_;  // outlives the writer
  std::vector<std::string> columns_;
  AtomicFile file_;
  std::FILE* stream_ = nullptr;
  long rows_ = 0;
};

}  // namespace ecpsim::app
