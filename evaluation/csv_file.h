#pragma once
// The comma-separated files of the benchmark: plain fields (no quoting), a header line.

#include <string>
#include <vector>

namespace ecpsim::evaluation {

/// `text` as one CSV field: commas, quotes and line breaks become spaces/semicolons.
std::string CsvField(const std::string& text);

/// A parsed CSV file: its header and the rows, each with as many fields as the header.
struct CsvFile {
  std::string path;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  /// Index of column `name`. @throws InputError naming the file and the column.
  int Column(const std::string& name) const;
  /// Row `row`'s field `column` as a number. @throws InputError naming file, line, column, value.
  double Number(size_t row, int column) const;
};

/// Reads `path` and checks that its header is `expected_header`.
/// @throws InputError naming the file (and line) when it cannot be read, the header differs, or a
///         row has the wrong number of fields.
CsvFile ReadCsvFile(const std::string& path, const std::vector<std::string>& expected_header);

}  // namespace ecpsim::evaluation
