#include "evaluation/work_precision.h"

#include <filesystem>
#include <fstream>
#include <tuple>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "engine/models/hull_model.h"

namespace ecpsim::evaluation {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

std::vector<Scenario> CheapScenarios() {
  std::vector<Scenario> chosen;
  for (Scenario& s : WorkPrecisionScenarios(std::string(ECPSIM_SOURCE_DIR) + "/scenes", 0.5)) {
    if (s.name == "slide" || s.name == "spin" || s.name == "rest") chosen.push_back(s);
  }
  return chosen;
}

std::string WriteTemporary(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / (name + std::to_string(getpid()));
  std::ofstream(path) << text;
  return path.string();
}

TEST(WorkPrecisionTest, ShardsPartitionTheSweepAndReproduceItsErrors) {
  const std::vector<Scenario> scenarios = CheapScenarios();
  const std::vector<Method> methods = {FindMethod("hull"), FindMethod("planar")};
  SweepOptions options;
  options.steps = {0.01, 0.005};
  const std::vector<WorkPrecisionRow> whole = RunWorkPrecision(scenarios, methods, options);
  ASSERT_EQ(whole.size(), 3u * 2 * 2);
  std::vector<WorkPrecisionRow> joined;
  for (int shard = 1; shard <= 2; ++shard) {
    options.shard_index = shard;
    options.shard_count = 2;
    for (const auto& row : RunWorkPrecision(scenarios, methods, options)) joined.push_back(row);
  }
  ASSERT_EQ(joined.size(), whole.size());
  for (const WorkPrecisionRow& row : whole) {
    int matches = 0;
    for (const WorkPrecisionRow& other : joined) {
      if (other.scenario == row.scenario && other.method == row.method && other.h == row.h) {
        ++matches;
        // deterministic: the same run gives the same errors bit for bit
        EXPECT_EQ(other.error_state, row.error_state);
      }
    }
    EXPECT_EQ(matches, 1) << row.scenario << " " << row.method << " " << row.h;
    EXPECT_FALSE(row.failed) << row.failure;
    EXPECT_EQ(row.reference_uncertainty, 0);  // closed-form references
    EXPECT_EQ(row.error_vs_hull, -1);         // only measured against converged references
  }
}

TEST(WorkPrecisionTest, AShortRunIsTimedAgainAndALongOneOnce) {
  const Scenario slide = CheapScenarios().front();
  ASSERT_EQ(slide.name, "slide");
  const Method hull = FindMethod("hull");
  // the slide at h = 0.02 s: some 50 steps, well under a millisecond of CPU
  const RunRecord first = RunTrajectory(hull, slide, 0.02);
  ASSERT_FALSE(first.failed) << first.failure;
  ASSERT_LT(first.cpu_seconds, kMinTimedCpuSeconds);
  const TimedCpu timed = TimedCpuSeconds(hull, slide, 0.02, first, 60);
  EXPECT_GE(timed.runs, 2);
  EXPECT_LE(timed.runs, kMaxTimedRuns);
  EXPECT_GT(timed.cpu_seconds, 0);
  // a run that took long enough is its own time
  RunRecord long_run = first;
  long_run.cpu_seconds = 2 * kMinTimedCpuSeconds;
  const TimedCpu once = TimedCpuSeconds(hull, slide, 0.02, long_run, 60);
  EXPECT_EQ(once.runs, 1);
  EXPECT_EQ(once.cpu_seconds, long_run.cpu_seconds);
}

TEST(WorkPrecisionTest, PlanarAndHullAgreeWhereBothApply) {
  SweepOptions options;
  options.steps = {0.01};
  const auto rows =
      RunWorkPrecision(CheapScenarios(), {FindMethod("hull"), FindMethod("planar")}, options);
  for (size_t i = 0; i < rows.size(); i += 2) {
    // the same implicit scheme on a flat body: the models agree to the solver tolerance (1e-12
    // of the state's scales) summed over the run's steps
    constexpr double kModelAgreement = 1e-10;
    EXPECT_NEAR(rows[i].error_state, rows[i + 1].error_state, kModelAgreement) << rows[i].scenario;
  }
}

TEST(WorkPrecisionTest, TheHullModelsPushForceIsMuMgAtEveryStepAndNeverBreaks) {
  Scenario push;
  for (Scenario& s : WorkPrecisionScenarios(std::string(ECPSIM_SOURCE_DIR) + "/scenes", 0.5)) {
    if (s.name == "push_box") push = s;
  }
  ASSERT_EQ(push.name, "push_box");
  ASSERT_GE(push.pusher, 0);
  EXPECT_DOUBLE_EQ(push.push_force, 0.3 * 1 * 9.8);  // μ m g of the scene's 1 kg box
  SweepOptions options;
  options.steps = {0.01};
  const auto rows = RunWorkPrecision({push}, {FindMethod("hull")}, options);
  ASSERT_EQ(rows.size(), 1u);
  // relative: the box slides on the ground with μ p_n exactly; the pusher's own friction on it
  // (vertical, sticking with the creep) is known to μ τ / kStickCreepFraction of its normal force
  // (tests/engine/island_gripper_test.cpp) and moves the ground's p_n by that: μ_g μ_pair 1e-7,
  // times 10 for the rows it sums
  constexpr double kMu = 0.3, kSolverTolerance = 1e-12;  // push_box.yaml's, both pairs
  constexpr double kPushForceRel = 10 * kMu * kMu * kSolverTolerance / engine::kStickCreepFraction;
  EXPECT_LE(rows[0].push_force_error, kPushForceRel);
  EXPECT_EQ(rows[0].push_contact_breaks, 0);
}

// the scenario `name` of the sweep, cut to `duration` s
Scenario ScenarioCut(const std::string& name, double duration) {
  for (Scenario& s : WorkPrecisionScenarios(std::string(ECPSIM_SOURCE_DIR) + "/scenes", 0.5)) {
    if (s.name != name) continue;
    s.scene.duration = duration;
    return s;
  }
  ADD_FAILURE() << "no scenario " << name;
  return {};
}

TEST(WorkPrecisionTest, TheHullModelHoldsThePyramidAtRest) {
  // 0.5 s at h = 0.01 s: 50 steps of ten boxes in 15 contacts
  const Scenario pyramid = ScenarioCut("pyramid", 0.5);
  SweepOptions options;
  options.steps = {0.01};
  const auto rows = RunWorkPrecision({pyramid}, {FindMethod("hull")}, options);
  ASSERT_EQ(rows.size(), 1u);
  ASSERT_FALSE(rows[0].failed) << rows[0].failure;
  EXPECT_EQ(rows[0].steps, 50);
  // m: the exact rest is a solution of every step, found to the solver's 1e-12 tolerance; 1e-9
  // of the 0.1 m box leaves room for round-off over the steps, far below any sag or creep
  constexpr double kRestDrift = 1e-9 * 0.1;
  EXPECT_GE(rows[0].drift, 0);
  EXPECT_LE(rows[0].drift, kRestDrift);
  EXPECT_LE(rows[0].error_position, kRestDrift);  // the top box against the initial pose
  EXPECT_LE(rows[0].max_penetration, kRestDrift);
}

TEST(WorkPrecisionTest, TheHullModelsTrainPushForceIsMuSumMg) {
  // 0.5 s at h = 0.01 s: the whole row moves from the first step, its force compared from 0.1 s
  const Scenario train = ScenarioCut("train", 0.5);
  EXPECT_DOUBLE_EQ(train.push_force, 0.3 * 6 * 9.8);  // μ Σ m g of the scene's six 1 kg boxes
  SweepOptions options;
  options.steps = {0.01};
  const auto rows = RunWorkPrecision({train}, {FindMethod("hull")}, options);
  ASSERT_EQ(rows.size(), 1u);
  ASSERT_FALSE(rows[0].failed) << rows[0].failure;
  // relative: the boxes slide on the ground with μ p_n exactly, and Σ p_n is Σ m g but for the
  // pusher's own vertical friction on the first box (sticking with the creep), known to
  // μ τ / kStickCreepFraction of its normal force: μ_g μ_pair 1e-7, times 10 for the rows it
  // sums (as push_box's test)
  constexpr double kMuGround = 0.3, kMuPair = 0.22, kSolverTolerance = 1e-12;  // train.yaml's
  constexpr double kPushForceRel =
      10 * kMuGround * kMuPair * kSolverTolerance / engine::kStickCreepFraction;
  EXPECT_LE(rows[0].push_force_error, kPushForceRel);
  EXPECT_EQ(rows[0].push_contact_breaks, 0);
  // m: the row neither skews nor climbs (the push is along it, through the CMs), to the rest's
  // bar: 1e-9 of the box
  constexpr double kTransverseDrift = 1e-9 * 0.1;
  EXPECT_GE(rows[0].drift, 0);
  EXPECT_LE(rows[0].drift, kTransverseDrift);
}

TEST(WorkPrecisionTest, DriftFromASettleTimeIsTheRestAfterItAndNoReferenceMeasuresNoError) {
  // the slide stops at v0/(μg) = 0.34 s, 0.17 m from its start: measured from 0.4 s, the hull
  // model's box sticks exactly, and its drift is the round-off of sticking steps
  Scenario slide = ScenarioCut("slide", 0.5);
  slide.measure_drift = true;
  SweepOptions options;
  options.steps = {0.01};
  const auto from_start = RunWorkPrecision({slide}, {FindMethod("hull")}, options);
  slide.drift_from = 0.4;
  slide.has_reference = false;
  const auto at_rest = RunWorkPrecision({slide}, {FindMethod("hull")}, options);
  ASSERT_EQ(from_start.size(), 1u);
  ASSERT_EQ(at_rest.size(), 1u);
  ASSERT_FALSE(at_rest[0].failed) << at_rest[0].failure;
  constexpr double kSlideDistance = 1.0 / (2 * 0.3 * 9.8);  // m, v0² / (2 μ g)
  // (to within the discrete scheme's first-order stop: one step's travel at most)
  EXPECT_NEAR(from_start[0].drift, kSlideDistance, 0.01 * 1.0);
  // m: 1e-12 of the 0.2 m box, the solver's relative tolerance on a sticking velocity
  constexpr double kStuckDrift = 1e-12 * 0.2;
  EXPECT_GE(at_rest[0].drift, 0);
  EXPECT_LE(at_rest[0].drift, kStuckDrift);
  // no reference: nothing to compare with, the cost and the rest still measured
  EXPECT_EQ(at_rest[0].error_state, -1);
  EXPECT_EQ(at_rest[0].error_vs_hull, -1);
  EXPECT_EQ(at_rest[0].reference_uncertainty, -1);
  EXPECT_EQ(at_rest[0].wrong_mode, -1);
  EXPECT_GT(at_rest[0].cpu_per_sim_s, 0);
  EXPECT_GE(from_start[0].error_state, 0);
}

TEST(WorkPrecisionTest, AScenarioSweptOnlyAtSomeStepsSkipsTheOthersAndSaysWhereNoneIsLeft) {
  Scenario slide = ScenarioCut("slide", 0.1);
  slide.only_steps = {0.01};
  SweepOptions options;
  options.steps = {0.02, 0.01};
  std::vector<std::string> said;
  options.progress = [&](const std::string& line) { said.push_back(line); };
  const auto rows = RunWorkPrecision({slide}, {FindMethod("hull")}, options);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].h, 0.01);
  options.steps = {0.02};
  said.clear();
  EXPECT_TRUE(RunWorkPrecision({slide}, {FindMethod("hull")}, options).empty());
  ASSERT_EQ(said.size(), 1u);
  EXPECT_THAT(said[0], HasSubstr("slide / hull: not run, it is swept only at h = 0.01 s"));
}

// the bug: a run that failed in its first step reported its CPU time over 1e-300 simulated
// seconds, ~1e296 CPU s per simulated s, in the CSV and results.md (ODE on the pyramid)
TEST(WorkPrecisionTest, AFailedRunHasNoCpuPerSimulatedSecond) {
  Scenario stack = ScenarioCut("stack", 0.02);
  SweepOptions options;
  options.steps = {0.01};
  // the planar model throws in the first step: the boxes touch each other
  stack.planar_applies = true;
  const auto at_once = RunWorkPrecision({stack}, {FindMethod("planar")}, options);
  ASSERT_EQ(at_once.size(), 1u);
  ASSERT_TRUE(at_once[0].failed);
  EXPECT_THAT(at_once[0].failure, HasSubstr("planar model"));
  EXPECT_EQ(at_once[0].steps, 0);
  EXPECT_EQ(at_once[0].cpu_per_sim_s, -1);
  // a run stopped by the CPU limit after its first step: a cost, but of an unfinished run
  options.cpu_limit_s = 0;
  const auto stopped = RunWorkPrecision({stack}, {FindMethod("hull")}, options);
  ASSERT_EQ(stopped.size(), 1u);
  ASSERT_TRUE(stopped[0].failed);
  EXPECT_THAT(stopped[0].failure, HasSubstr("CPU limit"));
  EXPECT_EQ(stopped[0].steps, 1);
  EXPECT_EQ(stopped[0].cpu_per_sim_s, -1);
  // the same run completed has its cost: positive, and under the 300 s default limit per
  // simulated 0.02 s
  options.cpu_limit_s = SweepOptions().cpu_limit_s;
  const auto completed = RunWorkPrecision({stack}, {FindMethod("hull")}, options);
  ASSERT_EQ(completed.size(), 1u);
  ASSERT_FALSE(completed[0].failed) << completed[0].failure;
  EXPECT_EQ(completed[0].steps, 2);
  EXPECT_GT(completed[0].cpu_per_sim_s, 0);
  EXPECT_LT(completed[0].cpu_per_sim_s, options.cpu_limit_s / 0.02);
}

TEST(WorkPrecisionTest, CsvRoundTripKeepsNineDigits) {
  WorkPrecisionRow row;
  row.scenario = "slide";
  row.method = "hull";
  row.h = 0.002;
  row.steps = 250;
  row.cpu_per_sim_s = 0.00383123456;
  row.error_state = 1.00000000123e-3;
  row.failure = "solver failed, at t = 1";
  row.push_force_error = 0.25;
  row.push_contact_breaks = 0.125;
  row.drift = 3.5e-15;
  const std::string path = WriteTemporary("wp.csv", WorkPrecisionCsv({row, row}));
  const std::vector<WorkPrecisionRow> back = ReadWorkPrecisionCsv(path);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].scenario, "slide");
  EXPECT_EQ(back[0].steps, 250);
  // nine significant digits: within half a unit of the ninth, 5e-9 relative
  constexpr double kNineDigits = 5e-9;
  EXPECT_NEAR(back[0].error_state, row.error_state, kNineDigits * row.error_state);
  EXPECT_EQ(back[0].error_angle, -1);
  EXPECT_EQ(back[0].failure, "solver failed; at t = 1");  // commas cannot split the row
  EXPECT_EQ(back[0].push_force_error, 0.25);
  EXPECT_EQ(back[0].push_contact_breaks, 0.125);
  EXPECT_EQ(back[0].drift, 3.5e-15);
  std::filesystem::remove(path);
}

TEST(WorkPrecisionTest, MalformedCsvNamesFileLineAndColumn) {
  const std::string header = WorkPrecisionCsv({}).substr(0, WorkPrecisionCsv({}).find('\n'));
  const std::string path =
      WriteTemporary("bad.csv", header + "\nslide,hull,abc,1,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,\n");
  EXPECT_THAT(
      [&] { ReadWorkPrecisionCsv(path); },
      ThrowsMessage<InputError>(HasSubstr(path + ":2: column `h`: 'abc' is not a finite number")));
  std::filesystem::remove(path);
}

// two rows whose every number has at most nine significant digits: the table's own
std::vector<WorkPrecisionRow> TwoRows() {
  WorkPrecisionRow a;
  a.scenario = "slide";
  a.method = "hull";
  a.h = 0.002;
  a.steps = 250;
  a.cpu_per_sim_s = 0.00383123456;
  a.error_state = 1.5e-12;
  a.error_position = 2.5e-07;
  a.error_angle = 123456789;
  a.error_velocity = 1e20;
  a.wrong_mode = 0.125;
  a.error_vs_hull = 3.14159265;
  a.reference_uncertainty = 0;
  a.max_penetration = 1e-300;
  a.iterations_mean = 4.75;
  a.iterations_max = 12;
  WorkPrecisionRow b;
  b.scenario = "push_slide";
  b.method = "mujoco-default";
  b.h = 0.0005;
  b.steps = 1000;
  b.failed = true;
  b.cpu_per_sim_s = 12.5;
  b.max_penetration = 0.00012;
  b.push_force_error = 0.25;
  b.push_contact_breaks = 0.0625;
  b.failure = "solver failed; at t = 1 s";
  return {a, b};
}

auto Fields(const WorkPrecisionRow& r) {
  return std::make_tuple(r.scenario, r.method, r.h, r.steps, r.failed, r.cpu_per_sim_s,
                         r.error_state, r.error_position, r.error_angle, r.error_velocity,
                         r.wrong_mode, r.stop_time_error, r.error_vs_hull, r.reference_uncertainty,
                         r.max_penetration, r.iterations_mean, r.iterations_max, r.push_force_error,
                         r.push_contact_breaks, r.drift, r.failure);
}

TEST(WorkPrecisionTest, CsvRowsReadBackEqual) {
  const std::vector<WorkPrecisionRow> rows = TwoRows();
  const std::string path = WriteTemporary("wp_rows.csv", WorkPrecisionCsv(rows));
  const std::vector<WorkPrecisionRow> back = ReadWorkPrecisionCsv(path);
  ASSERT_EQ(back.size(), rows.size());
  for (size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(Fields(back[i]), Fields(rows[i])) << i;
  std::filesystem::remove(path);
}

// TwoRows() as the writer of the hand-written schema wrote them (before the columns were
// declared once, and before the drift column): shards written then still read, drift −1
const char* const kEarlierCsv =
    "scenario,method,h,steps,failed,cpu_per_sim_s,error_state,error_position,error_angle,"
    "error_velocity,wrong_mode,stop_time_error,error_vs_hull,reference_uncertainty,"
    "max_penetration,iterations_mean,iterations_max,push_force_error,push_contact_breaks,failure\n"
    "slide,hull,0.002,250,0,0.00383123456,1.5e-12,2.5e-07,123456789,1e+20,0.125,-1,3.14159265,0,"
    "1e-300,4.75,12,-1,-1,\n"
    "push_slide,mujoco-default,0.0005,1000,1,12.5,-1,-1,-1,-1,-1,-1,-1,-1,0.00012,0,0,0.25,0.0625,"
    "solver failed; at t = 1 s\n";

// TwoRows() as this writer writes them: the earlier table with `drift` before `failure`
const char* const kCsvWithDrift =
    "scenario,method,h,steps,failed,cpu_per_sim_s,error_state,error_position,error_angle,"
    "error_velocity,wrong_mode,stop_time_error,error_vs_hull,reference_uncertainty,"
    "max_penetration,iterations_mean,iterations_max,push_force_error,push_contact_breaks,drift,"
    "failure\n"
    "slide,hull,0.002,250,0,0.00383123456,1.5e-12,2.5e-07,123456789,1e+20,0.125,-1,3.14159265,0,"
    "1e-300,4.75,12,-1,-1,-1,\n"
    "push_slide,mujoco-default,0.0005,1000,1,12.5,-1,-1,-1,-1,-1,-1,-1,-1,0.00012,0,0,0.25,0.0625,"
    "-1,solver failed; at t = 1 s\n";

TEST(WorkPrecisionTest, CsvOfTheEarlierWriterReadsTheSame) {
  const std::vector<WorkPrecisionRow> rows = TwoRows();
  const std::string path = WriteTemporary("wp_earlier.csv", kEarlierCsv);
  const std::vector<WorkPrecisionRow> back = ReadWorkPrecisionCsv(path);
  ASSERT_EQ(back.size(), rows.size());
  for (size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(Fields(back[i]), Fields(rows[i])) << i;
  EXPECT_EQ(WorkPrecisionCsv(rows), kCsvWithDrift);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace ecpsim::evaluation
