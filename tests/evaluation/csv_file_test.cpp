// The one writer and reader of the benchmark's tables, on a small table with a column of each
// kind: what they write, that it reads back, and the messages for what does not.

#include "evaluation/csv_file.h"

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <tuple>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"

namespace ecpsim::evaluation {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

enum class Colour { kRed = 0, kGreen, kBlue };
const char* ColourName(Colour colour) {
  switch (colour) {
    case Colour::kRed:
      return "red";
    case Colour::kGreen:
      return "green";
    case Colour::kBlue:
      return "blue";
  }
  return "unknown";
}

struct Sample {
  std::string name;
  double exact = 0;
  double rough = 0;
  std::uint64_t count = 0;
  int small = 0;
  bool flag = false;
  Colour colour = Colour::kRed;
  double pair[2] = {0, 0};
};

auto Fields(const Sample& s) {
  return std::make_tuple(s.name, s.exact, s.rough, s.count, s.small, s.flag, s.colour, s.pair[0],
                         s.pair[1]);
}

const std::vector<CsvColumn<Sample>> kColumns = {
    TextColumn<Sample>("name", &Sample::name),
    NumberColumn<Sample>("exact", 17, &Sample::exact),
    NumberColumn<Sample>("rough", 3, &Sample::rough),
    WholeColumn<Sample>("count", &Sample::count),
    WholeColumn<Sample>("small", &Sample::small),
    FlagColumn<Sample>("flag", &Sample::flag),
    EnumColumn<Sample>("colour", ColourName, 3, &Sample::colour),
    NumberColumn<Sample>("first", 17, [](auto& s) -> decltype(auto) { return s.pair[0]; }),
    NumberColumn<Sample>("second", 17, [](auto& s) -> decltype(auto) { return s.pair[1]; }),
};
const char* const kHeader = "name,exact,rough,count,small,flag,colour,first,second";

// a fresh temporary folder per test, removed afterwards
class CsvFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / fmt::format("ecpsim_csv_file_{}_{}", getpid(), info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // `text` as the file table.csv; its path
  std::string File(const std::string& text) const {
    const fs::path path = dir_ / "table.csv";
    std::ofstream(path) << text;
    return path.string();
  }

  fs::path dir_;
};

TEST_F(CsvFileTest, WritesEachKindOfColumn) {
  Sample s;
  s.name = "a, \"quoted\"\nname";
  s.exact = 0.1;
  s.rough = 1234.5;
  s.count = 7;
  s.small = 0;
  s.flag = true;
  s.colour = Colour::kBlue;
  s.pair[0] = -2.5e-300;
  s.pair[1] = 1e20;
  EXPECT_EQ(WriteCsv(kColumns, {s}),
            std::string(kHeader) +
                "\na;  quoted  name,0.10000000000000001,1.23e+03,7,0,1,blue,-2.5e-300,"
                "1e+20\n");
  EXPECT_EQ(WriteCsv(kColumns, {}), std::string(kHeader) + "\n");
}

TEST_F(CsvFileTest, RowsReadBackEqual) {
  Sample a;
  a.name = "first row";
  a.exact = 1.0 / 3;
  a.rough = 0.125;
  a.count = std::numeric_limits<std::uint64_t>::max();  // beyond a double's 53 bits
  a.small = std::numeric_limits<int>::max();
  a.flag = true;
  a.colour = Colour::kGreen;
  a.pair[0] = 4.9406564584124654e-324;  // the least subnormal: strtod sets ERANGE, stod throws
  a.pair[1] = -1.7976931348623157e308;
  Sample b;  // every default, the empty name
  const std::vector<Sample> back = ReadCsv(File(WriteCsv(kColumns, {a, b})), kColumns);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(Fields(back[0]), Fields(a));
  EXPECT_EQ(Fields(back[1]), Fields(b));
}

TEST_F(CsvFileTest, EmptyLinesArePassedOverAndLinesCountedInTheFile) {
  const std::string row = "x,1,2,3,4,0,red,5,6\n";
  const std::string path =
      File(std::string(kHeader) + "\n" + row + "\n\n" + row + "x,1,2,3,4,0,red,5,oops\n");
  EXPECT_THAT([&] { ReadCsv(path, kColumns); },
              ThrowsMessage<InputError>(HasSubstr(path + ":6: column `second`: 'oops'")));
  const std::string good = File(std::string(kHeader) + "\n" + row + "\n\n" + row);
  EXPECT_EQ(ReadCsv(good, kColumns).size(), 2u);
}

TEST_F(CsvFileTest, ABadFieldNamesFileLineColumnValueAndWhatWasExpected) {
  // each column's bad values, in the order of the header's fields
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"x,abc,2,3,4,0,red,5,6", "column `exact`: 'abc' is not a finite number"},
      {"x,,2,3,4,0,red,5,6", "column `exact`: '' is not a finite number"},
      {"x,1,inf,3,4,0,red,5,6", "column `rough`: 'inf' is not a finite number"},
      {"x,1,nan,3,4,0,red,5,6", "column `rough`: 'nan' is not a finite number"},
      {"x,1,1e999,3,4,0,red,5,6", "column `rough`: '1e999' is not a finite number"},
      {"x,1,2 m,3,4,0,red,5,6", "column `rough`: '2 m' is not a finite number"},
      {"x,1,2,-3,4,0,red,5,6", "column `count`: '-3' is not a whole number ≥ 0"},
      {"x,1,2,3.5,4,0,red,5,6", "column `count`: '3.5' is not a whole number ≥ 0"},
      {"x,1,2,18446744073709551616,4,0,red,5,6",
       "column `count`: '18446744073709551616' is not a whole number ≥ 0"},
      {"x,1,2,3,2147483648,0,red,5,6", "column `small`: '2147483648' is not a whole number ≥ 0"},
      {"x,1,2,3,4,2,red,5,6", "column `flag`: '2' is not 1 or 0"},
      {"x,1,2,3,4,0,Red,5,6", "column `colour`: 'Red' is not red, green or blue"},
  };
  for (const auto& [row, message] : cases) {
    const std::string path = File(std::string(kHeader) + "\n" + row + "\n");
    EXPECT_THAT([&] { ReadCsv(path, kColumns); },
                ThrowsMessage<InputError>(HasSubstr(path + ":2: " + message)));
  }
}

TEST_F(CsvFileTest, ARowOfAnotherLengthNamesWhereItEnds) {
  std::string path = File(std::string(kHeader) + "\nx,1,2,3\n");
  EXPECT_THAT([&] { ReadCsv(path, kColumns); },
              ThrowsMessage<InputError>(HasSubstr(
                  path + ":2: 4 fields, expected 9: the row ends before column `small`")));
  path = File(std::string(kHeader) + "\nx,1,2,3,4,0,red,5,6,7,\n");
  EXPECT_THAT([&] { ReadCsv(path, kColumns); },
              ThrowsMessage<InputError>(HasSubstr(
                  path + ":2: 11 fields, expected 9: 2 more after the last column, `second`")));
}

TEST_F(CsvFileTest, AWrongHeaderNamesTheColumn) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"name,exact,rough,count,small,flag,colour,first", "no column `second`"},
      {"name,exact,rough,count,small,flag,colour,first,second,third", "an extra column `third`"},
      {"name,exact,rough,count,small,flag,color,first,second",
       "no column `colour`, an extra column `color`"},
      {"exact,name,rough,count,small,flag,colour,first,second",
       "column 1 is `exact` where `name` belongs"},
      {"name,exact,rough,count,small,flag,colour,first,second,name", "column `name` twice"},
  };
  for (const auto& [header, problem] : cases) {
    const std::string path = File(header + "\n");
    EXPECT_THAT([&] { ReadCsv(path, kColumns); },
                ThrowsMessage<InputError>(HasSubstr(path + ":1: " + problem +
                                                    "; expected the header '" + kHeader + "'")));
  }
}

TEST_F(CsvFileTest, AMissingOrEmptyFileIsNamed) {
  const std::string missing = (dir_ / "nosuch.csv").string();
  EXPECT_THAT([&] { ReadCsv(missing, kColumns); },
              ThrowsMessage<InputError>(HasSubstr(missing + ": cannot open it for reading")));
  const std::string empty = File("");
  EXPECT_THAT([&] { ReadCsv(empty, kColumns); },
              ThrowsMessage<InputError>(HasSubstr(empty + ": empty file, expected the header")));
}

TEST(CsvFieldTest, CommasQuotesAndLineBreaksCannotSplitARow) {
  EXPECT_EQ(CsvField("a,b \"c\"\r\nd"), "a;b  c   d");
  EXPECT_EQ(CsvField("plain text"), "plain text");
}

}  // namespace
}  // namespace ecpsim::evaluation
