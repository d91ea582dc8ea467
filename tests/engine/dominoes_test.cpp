// scenes/dominoes.yaml (a row of nine 1 cm × 5 cm × 10 cm blocks, the first tipped): the cascade
// through islands that grow as the blocks fall onto each other, solved sparse from 200 unknowns
// (engine/README.md, "The island's linear algebra"). The first 0.5 s: six blocks fall (the
// seventh is reached at ≈ 0.52 s), past the step at 0.455 s where falling blocks sticking to
// each other once stalled on their friction's round-off (island_mncp.cpp, CreepFrictionRoundOff);
// the whole cascade runs in `ecpsim run scenes/dominoes.yaml` (0.7 s).

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "engine/models/hull_warm_start.h"
#include "engine/report/penetration.h"
#include "engine/scene.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/state.h"
#include "engine/time_step.h"

namespace ecpsim::engine {
namespace {

// s: the blocks that fall within it (see the file's comment)
constexpr double kDuration = 0.5;
constexpr int kFallen = 6;
// rad: a block has started tipping when it turned this far (the first block starts at once,
// the others only when struck: before that they rest, turned by round-off only)
constexpr double kTippingAngle = 1e-3;
// rad: atan(thickness / height) = atan(0.01 / 0.1), the angle past which a block's centre of
// mass is beyond its front edge and it falls on its own
constexpr double kFallingAngle = 0.0997;
// m: deepest overlap allowed, with the ground or between blocks: the gap rows converge to the
// solver's tolerance (1e-12) in the contact's length (≈ 0.03 m) and carry the coordinates'
// round-off (64 ulps of 0.7 m ≈ 1e-14 m); 1e-9 m is far above both and far below any overlap
// a missed contact would leave (a block moves ~1 mm per step)
constexpr double kMaxPenetration = 1e-9;
// J: the largest energy gain of one step the engine accepts (hull_model.cpp, kMaxEnergyGainRel:
// 1e-3 of each body's energy scale, whose potential part is m g L, L its radius of gyration,
// here sqrt((0.01² + 0.1²) / 12) = 0.029 m): the first-order step gains O(h²) energy while a
// block pivots on its edge (≈ 2e-6 J per step here), and nothing else may add any. The run as
// a whole must lose energy: contacts only dissipate, and every impact of a block on the next
// takes some
constexpr double kMaxStepEnergyGain = 1e-3 * 9 * 0.05 * 9.8 * 0.029;

std::string ScenePath() { return std::string(ECPSIM_SOURCE_DIR) + "/scenes/dominoes.yaml"; }

// rad: the block's tilt from upright (the angle of its body z axis to the world's)
double Tilt(const BodyState& body) {
  const Eigen::Vector3d up = body.Q_WB * Eigen::Vector3d::UnitZ();
  return std::acos(std::clamp(up.z(), -1.0, 1.0));
}

// J: kinetic (translational and rotational) plus gravitational energy of every body
double TotalEnergy(const Scene& scene, const State& state) {
  double energy = 0;
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    const BodyState& s = state.bodies[b];
    const Eigen::Matrix3d R = s.Q_WB.toRotationMatrix();
    const Eigen::Matrix3d inertia_world = R * body.inertia * R.transpose();
    energy += 0.5 * body.mass * s.v_WB.squaredNorm() + 0.5 * s.w_WB.dot(inertia_world * s.w_WB) -
              body.mass * scene.gravity.dot(s.p_WB);
  }
  return energy;
}

// Steps the blocks, asserting each step converged and gained no more than kMaxStepEnergyGain,
// and keeps the deepest overlap seen: with the ground and, through each contact's gap s,
// between blocks
class CheckedRun {
 public:
  explicit CheckedRun(const Scene& scene)
      : scene_(scene),
        state_(InitialState(scene)),
        probe_(scene),
        energy_(TotalEnergy(scene, state_)) {}
  // false (with a failure recorded) if the step did not converge; Step throws SolverFailure
  // where no guess solves it
  bool Step() {
    const StepReport report = engine::Step(scene_, state_);
    EXPECT_TRUE(report.converged) << "t = " << state_.t;
    if (!report.converged) return false;
    deepest_ = std::max(deepest_, probe_.MaxDepth(scene_, state_));
    for (const ContactState& c : state_.contacts)
      if (const auto* warm = c.warm_start.Get<HullWarmStart>())
        deepest_ = std::max(deepest_, -warm->s);
    const double next_energy = TotalEnergy(scene_, state_);
    EXPECT_LE(next_energy, energy_ + kMaxStepEnergyGain) << "t = " << state_.t;
    energy_ = next_energy;
    return true;
  }
  const State& state() const { return state_; }
  double energy() const { return energy_; }
  double deepest() const { return deepest_; }

 private:
  const Scene& scene_;
  State state_;
  const PenetrationProbe probe_;
  double energy_;
  double deepest_ = 0;
};

TEST(DominoesTest, BlocksFallInOrderWithoutPenetrationAndLoseEnergy) {
  const Scene scene = LoadScene(ScenePath()).scene;
  ASSERT_EQ(scene.bodies.size(), 9u);
  CheckedRun run(scene);
  const State& state = run.state();
  std::vector<double> tipping_time(scene.bodies.size(), INFINITY);
  const double initial_energy = run.energy();
  const int steps = static_cast<int>(std::lround(kDuration / scene.h));
  for (int k = 0; k < steps; ++k) {
    ASSERT_TRUE(run.Step());
    for (size_t b = 0; b < scene.bodies.size(); ++b)
      if (tipping_time[b] == INFINITY && Tilt(state.bodies[b]) > kTippingAngle)
        tipping_time[b] = state.t;
  }
  EXPECT_LE(run.deepest(), kMaxPenetration);
  EXPECT_LT(run.energy(), initial_energy);
  // the first kFallen blocks fall, each starting after the one before; the rest still stand
  for (int b = 0; b < kFallen; ++b) {
    EXPECT_GT(Tilt(state.bodies[b]), kFallingAngle) << scene.bodies[b].name;
    if (b > 0) {
      EXPECT_GT(tipping_time[b], tipping_time[b - 1]) << scene.bodies[b].name;
    }
  }
  for (size_t b = kFallen; b < scene.bodies.size(); ++b)
    EXPECT_LT(Tilt(state.bodies[b]), kTippingAngle) << scene.bodies[b].name;
}

// The first five blocks alone (the last four moved out of reach): d5 slams flat onto the table
// at 19 rad/s under the four leaning on it, steps whose solutions are not isolated (each
// leaning block's ECPs along its edge on the table and along its neighbour's face share one
// moment equation; engine/README.md, "Non-isolated solutions"). By 0.7 s the pile has landed:
// d5 flat, the others leaning on each other. Whether it then rests or creeps depends on the
// Newton path: the leaning blocks' contacts hold at the friction limit, where resting and a
// slow slip both solve the step, and the sticking creep may take the slip — d2–d4 at
// 2.5–4.6e-6 m/s on every path measured, until 0.68 s on 283ad07's, to the run's end since the
// island's LU is KLU's, as the whole nine's pile creeps on both. Which one is issue 33's
// selection to decide; until then the test bounds the creep.
TEST(DominoesTest, PileOfFiveLandsOnTheBlockThatLandsFlatAndAtMostCreeps) {
  constexpr int kPile = 5;
  // s: d5 lands at ≈ 0.52 s; from kSettled to kUntil every step must end at most creeping
  constexpr double kSettled = 0.7;
  constexpr double kUntil = 1.0;
  // m/s: twice the largest slip measured on a set (4.6e-6); a block still falling into the pile
  // moves at 1e-2 m/s 0.15 s before kSettled
  constexpr double kMaxCreep = 1e-5;
  // m: d5's centre of mass lying flat, half its 1 cm thickness above the table
  constexpr double kFlatHeight = 0.005;
  std::vector<std::string> overrides;
  for (int b = kPile; b < 9; ++b)
    overrides.push_back(fmt::format("bodies.{}.position=[{}, 0, 0.05]", b, 10.0 + b));
  const Scene scene = LoadScene(ScenePath(), overrides).scene;
  CheckedRun run(scene);
  const int settled = static_cast<int>(std::lround(kSettled / scene.h));
  const int steps = static_cast<int>(std::lround(kUntil / scene.h));
  const State& state = run.state();
  for (int k = 0; k < steps; ++k) {
    ASSERT_TRUE(run.Step());
    if (k + 1 < settled) continue;
    for (int b = 0; b < kPile; ++b) {
      ASSERT_LE(state.bodies[b].v_WB.norm(), kMaxCreep)
          << scene.bodies[b].name << " at " << state.t;
    }
  }
  EXPECT_LE(run.deepest(), kMaxPenetration);
  const BodyState& last = state.bodies[kPile - 1];
  EXPECT_NEAR(Tilt(last), M_PI / 2, kMaxPenetration / kFlatHeight);
  EXPECT_NEAR(last.p_WB.z(), kFlatHeight, kMaxPenetration);
  for (int b = 0; b + 1 < kPile; ++b) {
    const BodyState& block = state.bodies[b];
    // leaning: past the angle where it falls on its own, held above lying flat
    EXPECT_GT(Tilt(block), kFallingAngle) << scene.bodies[b].name;
    EXPECT_GT(block.p_WB.z(), kFlatHeight + kMaxPenetration) << scene.bodies[b].name;
  }
}

}  // namespace
}  // namespace ecpsim::engine
