#pragma once
// Reading a trajectory.csv written by `ecpsim run` back into named columns of numbers.

#include <string>
#include <vector>

namespace ecpsim::app {

/// The numbers of a CSV file with a header row, by column.
struct TrajectoryTable {
  std::string path;                       // the file, for messages
  std::vector<std::string> names;         // header, in file order
  std::vector<std::vector<double>> data;  // data[column][row]; empty for a text column
  // text[column][row] for the text columns (engine::IsModelColumn: `model`, `<body>.model`),
  // empty for the others
  std::vector<std::vector<std::string>> text;

  std::size_t rows() const { return data.empty() ? 0 : data.front().size(); }  // t is a number
  bool Has(const std::string& name) const;
  /// @throws InputError naming the file and the missing column (and the columns it has).
  const std::vector<double>& Column(const std::string& name) const;
};

/// Reads `path` (comma-separated, a header row, then rows of the header's length: finite numbers,
/// and text in the model columns).
/// @throws InputError `path:line: ...` for a missing/unreadable file, an empty file, a row of the
///         wrong length, or a field that is not a finite number (naming its column and value).
TrajectoryTable ReadTrajectoryTable(const std::string& path);

}  // namespace ecpsim::app
