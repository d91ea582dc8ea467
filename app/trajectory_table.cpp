#include "app/trajectory_table.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "common/errors.h"
#include "engine/report/trajectory_columns.h"

namespace ecpsim::app {
namespace {

std::vector<std::string> SplitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  for (std::string field; std::getline(stream, field, ',');) fields.push_back(field);
  // a trailing comma is an empty last field
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

}  // namespace

bool TrajectoryTable::Has(const std::string& name) const {
  for (const std::string& n : names) {
    if (n == name) return true;
  }
  return false;
}

const std::vector<double>& TrajectoryTable::Column(const std::string& name) const {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return data[i];
  }
  throw InputError(
      fmt::format("{}: no column \"{}\"; expected a trajectory.csv of `ecpsim run` "
                  "(columns: {})",
                  path, name, fmt::join(names, ",")));
}

TrajectoryTable ReadTrajectoryTable(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    throw InputError(
        fmt::format("{}: cannot read it ({}); expected the trajectory.csv of an "
                    "`ecpsim run` output folder",
                    path, std::strerror(errno)));
  }
  TrajectoryTable table;
  table.path = path;
  std::string line;
  if (!std::getline(in, line) || line.empty()) {
    throw InputError(fmt::format("{}:1: empty file; expected a header row", path));
  }
  if (line.back() == '\r') line.pop_back();
  table.names = SplitFields(line);
  table.data.resize(table.names.size());
  table.text.resize(table.names.size());
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::vector<std::string> fields = SplitFields(line);
    if (fields.size() != table.names.size()) {
      throw InputError(fmt::format("{}:{}: {} fields; expected {} as in the header", path,
                                   line_number, fields.size(), table.names.size()));
    }
    for (std::size_t i = 0; i < fields.size(); ++i) {
      if (engine::IsModelColumn(table.names[i])) {
        table.text[i].push_back(fields[i]);
        continue;
      }
      // the whole field must parse, and to a finite number
      const char* begin = fields[i].c_str();
      char* end = nullptr;
      errno = 0;
      const double value = std::strtod(begin, &end);
      if (fields[i].empty() || end != begin + fields[i].size() || !std::isfinite(value)) {
        throw InputError(fmt::format("{}:{}: {} = \"{}\": expected a finite number", path,
                                     line_number, table.names[i], fields[i]));
      }
      table.data[i].push_back(value);
    }
  }
  if (table.rows() == 0) {
    throw InputError(fmt::format("{}: no data rows; expected at least one state", path));
  }
  return table;
}

}  // namespace ecpsim::app
