// Every trajectory of every shipped scene, bit for bit: each case's per-step hashes against the
// table tests/engine/trajectory_hashes.txt. A change that moves any state by one ulp fails here;
// where the change is meant, re-bless with `bash scripts/bless_trajectory_hashes.sh` and say why
// in the commit message.

#include <cmath>
#include <fstream>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/engine/trajectory_hash.h"

namespace ecpsim::engine::testing {

// ctest's test list names a case by its scene and model
void PrintTo(const TrajectoryCase& c, std::ostream* os) { *os << c.scene << " " << c.model; }

namespace {

const std::string kScenesDir = std::string(ECPSIM_SOURCE_DIR) + "/scenes";
const std::string kTablePath =
    std::string(ECPSIM_SOURCE_DIR) + "/tests/engine/trajectory_hashes.txt";

// the table's lines that are no comments
std::vector<std::string> TableLines() {
  std::ifstream in(kTablePath);
  EXPECT_TRUE(in) << "cannot read " << kTablePath;
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#') lines.push_back(line);
  }
  return lines;
}

std::string CasePrefix(const TrajectoryCase& c) { return c.scene + " " + c.model + " "; }

std::vector<std::string> TableLinesOf(const TrajectoryCase& c) {
  std::vector<std::string> lines;
  for (const std::string& line : TableLines()) {
    if (line.rfind(CasePrefix(c), 0) == 0) lines.push_back(line);
  }
  return lines;
}

class TrajectoryHash : public ::testing::TestWithParam<TrajectoryCase> {};

TEST_P(TrajectoryHash, MatchesTable) {
  const std::vector<std::string> expected = TableLinesOf(GetParam());
  ASSERT_FALSE(expected.empty()) << "no lines for '" << CasePrefix(GetParam()) << "' in "
                                 << kTablePath
                                 << ": a new scene? bash scripts/bless_trajectory_hashes.sh";
  const std::vector<std::string> actual = TrajectoryRecord(kScenesDir, GetParam());
  // the first line that differs says at which step the trajectory left the table's
  for (std::size_t i = 0; i < std::max(expected.size(), actual.size()); ++i) {
    const std::string want = i < expected.size() ? expected[i] : "(no line)";
    const std::string got = i < actual.size() ? actual[i] : "(no line)";
    ASSERT_EQ(got, want) << "line " << i + 1 << " of the case; if the change is meant: "
                         << "bash scripts/bless_trajectory_hashes.sh";
  }
}

std::string CaseName(const ::testing::TestParamInfo<TrajectoryCase>& info) {
  std::string name =
      info.param.scene.substr(0, info.param.scene.find('.')) + "_" + info.param.model;
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}

INSTANTIATE_TEST_SUITE_P(ShippedScenes, TrajectoryHash,
                         ::testing::ValuesIn(AllTrajectoryCases(kScenesDir)), CaseName);

// the hash sees one ulp of any body or contact value: the table pins every bit
TEST(TrajectoryHashOfState, ChangesWithOneUlp) {
  State state;
  state.t = 0.25;
  state.steps = 25;
  state.bodies.resize(2);
  state.bodies[1].p_WB = Eigen::Vector3d(0.1, -0.2, 0.05);
  state.contacts.resize(1);
  state.contacts[0].p_n = 0.049;
  StepReport report;
  report.converged = true;
  report.iterations = 3;
  const std::uint64_t reference = HashStep(state, report);
  const auto one_ulp_up = [](double& x) { x = std::nextafter(x, INFINITY); };

  State moved = state;
  one_ulp_up(moved.bodies[1].p_WB.z());
  EXPECT_NE(HashStep(moved, report), reference);
  moved = state;
  one_ulp_up(moved.bodies[0].w_WB.x());  // 0 → the smallest subnormal
  EXPECT_NE(HashStep(moved, report), reference);
  moved = state;
  one_ulp_up(moved.contacts[0].p_n);
  EXPECT_NE(HashStep(moved, report), reference);
  StepReport more = report;
  ++more.iterations;
  EXPECT_NE(HashStep(state, more), reference);
  EXPECT_EQ(HashStep(state, report), reference);
}

// a table line of a scene or model that no longer exists would pin nothing
TEST(TrajectoryHashTable, HasNoStaleCases) {
  std::set<std::string> prefixes;
  for (const TrajectoryCase& c : AllTrajectoryCases(kScenesDir)) prefixes.insert(CasePrefix(c));
  for (const std::string& line : TableLines()) {
    const std::size_t model_end = line.find(' ', line.find(' ') + 1);
    EXPECT_EQ(prefixes.count(line.substr(0, model_end + 1)), 1u) << "stale line: " << line;
  }
}

}  // namespace
}  // namespace ecpsim::engine::testing
