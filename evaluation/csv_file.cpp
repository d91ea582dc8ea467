#include "evaluation/csv_file.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "common/errors.h"

namespace ecpsim::evaluation {
namespace {

std::vector<std::string> SplitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

std::string Join(const std::vector<std::string>& fields) {
  std::string joined;
  for (const std::string& f : fields) joined += (joined.empty() ? "" : ",") + f;
  return joined;
}

}  // namespace

std::string CsvField(const std::string& text) {
  std::string field = text;
  for (char& c : field) {
    if (c == ',') c = ';';
    if (c == '"' || c == '\n' || c == '\r') c = ' ';
  }
  return field;
}

int CsvFile::Column(const std::string& name) const {
  for (size_t i = 0; i < header.size(); ++i) {
    if (header[i] == name) return static_cast<int>(i);
  }
  throw InputError(fmt::format("{}: no column '{}'", path, name));
}

double CsvFile::Number(size_t row, int column) const {
  const std::string& text = rows[row][column];
  try {
    size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size() && std::isfinite(value)) return value;
  } catch (const std::exception&) {
  }
  throw InputError(fmt::format("{}:{}: column '{}' = '{}': expected a finite number", path, row + 2,
                               header[column], text));
}

CsvFile ReadCsvFile(const std::string& path, const std::vector<std::string>& expected_header) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot open it for reading", path));
  CsvFile file;
  file.path = path;
  std::string line;
  if (!std::getline(in, line))
    throw InputError(fmt::format("{}: empty file, expected a header", path));
  file.header = SplitFields(line);
  if (file.header != expected_header) {
    throw InputError(
        fmt::format("{}:1: header '{}': expected '{}'", path, line, Join(expected_header)));
  }
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty()) continue;
    std::vector<std::string> fields = SplitFields(line);
    if (fields.size() != expected_header.size()) {
      throw InputError(fmt::format("{}:{}: {} fields, expected {}", path, line_number,
                                   fields.size(), expected_header.size()));
    }
    file.rows.push_back(std::move(fields));
  }
  return file;
}

}  // namespace ecpsim::evaluation
