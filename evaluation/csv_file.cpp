#include "evaluation/csv_file.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
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

bool Contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// what is wrong with a header `found` that is not `expected`, column by column
std::string HeaderProblem(const std::vector<std::string>& found,
                          const std::vector<std::string>& expected) {
  std::vector<std::string> problems;
  for (const std::string& name : expected) {
    if (!Contains(found, name)) problems.push_back(fmt::format("no column `{}`", name));
  }
  for (const std::string& name : found) {
    if (!Contains(expected, name)) problems.push_back(fmt::format("an extra column `{}`", name));
  }
  if (problems.empty()) {
    // the same names: one twice, or in another order
    for (size_t i = 0; i < found.size(); ++i) {
      if (std::count(found.begin(), found.end(), found[i]) > 1) {
        return fmt::format("column `{}` twice", found[i]);
      }
      if (found[i] != expected[i]) {
        return fmt::format("column {} is `{}` where `{}` belongs", i + 1, found[i], expected[i]);
      }
    }
  }
  std::string joined;
  for (const std::string& p : problems) joined += (joined.empty() ? "" : ", ") + p;
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

namespace csv_internal {

std::string FormatNumber(double value, int digits) { return fmt::format("{:.{}g}", value, digits); }

bool ParseNumber(const std::string& text, double& value) {
  // strtod, not stod: a subnormal number (ERANGE on underflow) reads back as written
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(value);
}

bool ParseWhole(const std::string& text, std::uint64_t most, std::uint64_t& value) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return false;
  errno = 0;
  const unsigned long long parsed = std::strtoull(text.c_str(), nullptr, 10);
  if (errno == ERANGE || parsed > most) return false;
  value = parsed;
  return true;
}

std::string Alternatives(const std::vector<std::string>& names) {
  std::string text;
  for (size_t k = 0; k < names.size(); ++k) {
    text += (k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + names[k];
  }
  return text;
}

std::vector<Line> ReadLines(const std::string& path, const std::vector<std::string>& names) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot open it for reading", path));
  std::string text;
  if (!std::getline(in, text)) {
    throw InputError(fmt::format("{}: empty file, expected the header '{}'", path, Join(names)));
  }
  const std::vector<std::string> header = SplitFields(text);
  if (header != names) {
    throw InputError(fmt::format("{}:1: {}; expected the header '{}'", path,
                                 HeaderProblem(header, names), Join(names)));
  }
  std::vector<Line> lines;
  for (int number = 2; std::getline(in, text); ++number) {
    if (text.empty()) continue;
    Line line{number, SplitFields(text)};
    const size_t count = line.fields.size();
    if (count < names.size()) {
      throw InputError(fmt::format("{}:{}: {} fields, expected {}: the row ends before column `{}`",
                                   path, number, count, names.size(), names[count]));
    }
    if (count > names.size()) {
      throw InputError(
          fmt::format("{}:{}: {} fields, expected {}: {} more after the last column, `{}`", path,
                      number, count, names.size(), count - names.size(), names.back()));
    }
    lines.push_back(std::move(line));
  }
  return lines;
}

void ThrowBadField(const std::string& path, int line, const std::string& column,
                   const std::string& text, const std::string& expected) {
  throw InputError(
      fmt::format("{}:{}: column `{}`: '{}' is not {}", path, line, column, text, expected));
}

}  // namespace csv_internal
}  // namespace ecpsim::evaluation
