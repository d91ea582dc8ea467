#pragma once
// The benchmark's CSV tables (work_precision.csv, stability.csv, drop_sweep.csv): a table is its
// list of columns, each declared once with how a row's field is written and read back
// (CsvColumn), and every table is written by WriteCsv and read by ReadCsv. Fields are plain,
// never quoted: a text field has its commas, quotes and line breaks replaced (CsvField).

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace ecpsim::evaluation {

/// `text` as one CSV field: commas become semicolons, quotes and line breaks spaces.
std::string CsvField(const std::string& text);

/// One column of a table of `Row`s: its name in the header and its field's text in a row.
template <typename Row>
struct CsvColumn {
  std::string name;
  std::string expected;  // what `read` accepts, for messages: "a finite number", "fixed or scaled"
  std::function<std::string(const Row& row)> write;
  std::function<bool(const std::string& text, Row& row)> read;  // false: `text` is not `expected`
};

// The kinds of column. `field` reaches a row's field: a pointer to a data member (&Row::h), or a
// callable that returns a reference to the field of a const and of a mutable row alike
// ([](auto& row) -> decltype(auto) { return row.q0.w(); }).

/// Text, written through CsvField and read as it stands.
template <typename Row, typename Field>
CsvColumn<Row> TextColumn(std::string name, Field field);

/// A finite double with `digits` significant digits ({:.<digits>g}); at 17 it reads back exactly.
template <typename Row, typename Field>
CsvColumn<Row> NumberColumn(std::string name, int digits, Field field);

/// A whole number ≥ 0 of an integer field, in decimal.
template <typename Row, typename Field>
CsvColumn<Row> WholeColumn(std::string name, Field field);

/// A bool as 1 or 0.
template <typename Row, typename Field>
CsvColumn<Row> FlagColumn(std::string name, Field field);

/// An enum whose values are 0 … count − 1, by the names `name_of` gives them.
template <typename Row, typename Field, typename Enum>
CsvColumn<Row> EnumColumn(std::string name, const char* (*name_of)(Enum), int count, Field field);

/// The table's text: a header line of the columns' names, then a line per row.
template <typename Row>
std::string WriteCsv(const std::vector<CsvColumn<Row>>& columns, const std::vector<Row>& rows);

/// The rows of a file that WriteCsv wrote with `columns`; empty lines are passed over.
/// @throws InputError naming the file when it cannot be read; the file, line 1 and the column
///         when the header lacks a column, has one too many or has them in another order; the
///         file and line when a row has another number of fields; the file, line, column, value
///         and what was expected when a field does not parse.
template <typename Row>
std::vector<Row> ReadCsv(const std::string& path, const std::vector<CsvColumn<Row>>& columns);

// ---------------------------------------------------------------------------------------------
// implementation: the templates reach a row's fields; the text work is in csv_file.cpp

namespace csv_internal {

std::string FormatNumber(double value, int digits);
bool ParseNumber(const std::string& text, double& value);  // finite, whole text
bool ParseWhole(const std::string& text, std::uint64_t most, std::uint64_t& value);  // ≤ most
std::string Alternatives(const std::vector<std::string>& names);                     // "a, b or c"

struct Line {
  int number = 0;  // 1-based, in the file
  std::vector<std::string> fields;
};
/// The data lines of `path` once its header is checked to be `names`; as ReadCsv throws.
std::vector<Line> ReadLines(const std::string& path, const std::vector<std::string>& names);
[[noreturn]] void ThrowBadField(const std::string& path, int line, const std::string& column,
                                const std::string& text, const std::string& expected);

// the type of the field that `field` reaches in a Row, by reference: `read` sets it
template <typename Row, typename Field>
struct FieldOf {
  using Reference = std::invoke_result_t<const Field&, Row&>;
  static_assert(std::is_lvalue_reference_v<Reference>, "a column's field must return a reference");
  using Type = std::decay_t<Reference>;
};
template <typename Row, typename Field>
using FieldType = typename FieldOf<Row, Field>::Type;

}  // namespace csv_internal

template <typename Row, typename Field>
CsvColumn<Row> TextColumn(std::string name, Field field) {
  static_assert(std::is_same_v<csv_internal::FieldType<Row, Field>, std::string>);
  return {std::move(name), "text",
          [field](const Row& row) { return CsvField(std::invoke(field, row)); },
          [field](const std::string& text, Row& row) {
            std::invoke(field, row) = text;
            return true;
          }};
}

template <typename Row, typename Field>
CsvColumn<Row> NumberColumn(std::string name, int digits, Field field) {
  static_assert(std::is_same_v<csv_internal::FieldType<Row, Field>, double>);
  return {std::move(name), "a finite number",
          [field, digits](const Row& row) {
            return csv_internal::FormatNumber(std::invoke(field, row), digits);
          },
          [field](const std::string& text, Row& row) {
            return csv_internal::ParseNumber(text, std::invoke(field, row));
          }};
}

template <typename Row, typename Field>
CsvColumn<Row> WholeColumn(std::string name, Field field) {
  using Whole = csv_internal::FieldType<Row, Field>;
  static_assert(std::is_integral_v<Whole> && !std::is_same_v<Whole, bool>);
  return {std::move(name), "a whole number ≥ 0",
          [field](const Row& row) { return std::to_string(std::invoke(field, row)); },
          [field](const std::string& text, Row& row) {
            std::uint64_t value = 0;
            if (!csv_internal::ParseWhole(text, std::numeric_limits<Whole>::max(), value))
              return false;
            std::invoke(field, row) = static_cast<Whole>(value);
            return true;
          }};
}

template <typename Row, typename Field>
CsvColumn<Row> FlagColumn(std::string name, Field field) {
  static_assert(std::is_same_v<csv_internal::FieldType<Row, Field>, bool>);
  return {std::move(name), "1 or 0",
          [field](const Row& row) { return std::string(std::invoke(field, row) ? "1" : "0"); },
          [field](const std::string& text, Row& row) {
            if (text != "1" && text != "0") return false;
            std::invoke(field, row) = text == "1";
            return true;
          }};
}

template <typename Row, typename Field, typename Enum>
CsvColumn<Row> EnumColumn(std::string name, const char* (*name_of)(Enum), int count, Field field) {
  static_assert(std::is_same_v<csv_internal::FieldType<Row, Field>, Enum>);
  std::vector<std::string> names;
  for (int k = 0; k < count; ++k) names.push_back(name_of(static_cast<Enum>(k)));
  return {
      std::move(name), csv_internal::Alternatives(names),
      [field, name_of](const Row& row) { return std::string(name_of(std::invoke(field, row))); },
      [field, names](const std::string& text, Row& row) {
        for (size_t k = 0; k < names.size(); ++k) {
          if (text == names[k]) {
            std::invoke(field, row) = static_cast<Enum>(k);
            return true;
          }
        }
        return false;
      }};
}

template <typename Row>
std::string WriteCsv(const std::vector<CsvColumn<Row>>& columns, const std::vector<Row>& rows) {
  std::string csv;
  for (size_t c = 0; c < columns.size(); ++c) csv += (c ? "," : "") + columns[c].name;
  csv += '\n';
  for (const Row& row : rows) {
    for (size_t c = 0; c < columns.size(); ++c) csv += (c ? "," : "") + columns[c].write(row);
    csv += '\n';
  }
  return csv;
}

template <typename Row>
std::vector<Row> ReadCsv(const std::string& path, const std::vector<CsvColumn<Row>>& columns) {
  std::vector<std::string> names;
  for (const CsvColumn<Row>& column : columns) names.push_back(column.name);
  std::vector<Row> rows;
  for (const csv_internal::Line& line : csv_internal::ReadLines(path, names)) {
    Row row;
    for (size_t c = 0; c < columns.size(); ++c) {
      if (!columns[c].read(line.fields[c], row)) {
        csv_internal::ThrowBadField(path, line.number, columns[c].name, line.fields[c],
                                    columns[c].expected);
      }
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace ecpsim::evaluation
