// stability.csv: its rows read back, a table of the earlier writer reads the same, and a bad
// outcome is named.

#include "evaluation/stability_map.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <tuple>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"

namespace ecpsim::evaluation {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

std::string WriteTemporary(const std::string& name, const std::string& text) {
  const fs::path path = fs::temp_directory_path() / (name + std::to_string(getpid()));
  std::ofstream(path) << text;
  return path.string();
}

// two rows whose every number has at most nine significant digits: the table's own
std::vector<StabilityRow> TwoRows() {
  StabilityRow a;
  a.map = "impact";
  a.method = "point";
  a.h = 0.02;
  a.value = 30;
  a.outcome = Outcome::kPenetration;
  a.max_penetration = 0.0123;
  a.energy_gain = -2.5e-05;
  a.max_speed_late = 1.75;
  a.drift_late = 0.000333;
  a.final_mode = "edge";
  StabilityRow b;
  b.map = "push_speed";
  b.method = "hull";
  b.h = 0.002;
  b.value = 0.03;
  b.outcome = Outcome::kOffSpeed;
  b.energy_gain = 1e-10;
  b.max_speed_late = 0.03;
  b.drift_late = 4.5e-09;
  b.final_mode = "face";
  b.failure = "Newton stalled at t = 0.5 s";
  return {a, b};
}

auto Fields(const StabilityRow& r) {
  return std::make_tuple(r.map, r.method, r.h, r.value, r.outcome, r.max_penetration, r.energy_gain,
                         r.max_speed_late, r.drift_late, r.final_mode, r.failure);
}

TEST(StabilityCsvTest, RowsReadBackEqual) {
  std::vector<StabilityRow> rows = TwoRows();
  for (int k = 0; k < kOutcomeCount; ++k) {
    rows.push_back(rows.front());
    rows.back().outcome = static_cast<Outcome>(k);
  }
  const std::string path = WriteTemporary("st_rows.csv", StabilityCsv(rows));
  const std::vector<StabilityRow> back = ReadStabilityCsv(path);
  ASSERT_EQ(back.size(), rows.size());
  for (size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(Fields(back[i]), Fields(rows[i])) << i;
  fs::remove(path);
}

// TwoRows() as the writer of the hand-written schema wrote them (before the columns were
// declared once): shards written then still read, and the table is written byte for byte alike
const char* const kEarlierCsv =
    "map,method,h,value,outcome,max_penetration,energy_gain,max_speed_late,drift_late,final_mode,"
    "failure\n"
    "impact,point,0.02,30,penetration,0.0123,-2.5e-05,1.75,0.000333,edge,\n"
    "push_speed,hull,0.002,0.03,off_speed,0,1e-10,0.03,4.5e-09,face,Newton stalled at t = 0.5 s\n";

TEST(StabilityCsvTest, TheEarlierWritersTableReadsTheSame) {
  const std::vector<StabilityRow> rows = TwoRows();
  const std::string path = WriteTemporary("st_earlier.csv", kEarlierCsv);
  const std::vector<StabilityRow> back = ReadStabilityCsv(path);
  ASSERT_EQ(back.size(), rows.size());
  for (size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(Fields(back[i]), Fields(rows[i])) << i;
  EXPECT_EQ(StabilityCsv(rows), kEarlierCsv);
  fs::remove(path);
}

TEST(StabilityCsvTest, AnUnknownOutcomeIsNamedWithTheOutcomes) {
  std::string text = kEarlierCsv;
  text.replace(text.find("off_speed"), 9, "exploded");
  const std::string path = WriteTemporary("st_bad.csv", text);
  EXPECT_THAT([&] { ReadStabilityCsv(path); },
              ThrowsMessage<InputError>(
                  HasSubstr(path + ":3: column `outcome`: 'exploded' is not ok, solver_failure, "
                                   "penetration, energy_gain, wrong_mode, jitter or off_speed")));
  fs::remove(path);
}

}  // namespace
}  // namespace ecpsim::evaluation
