// ComputeStepSensitivity against central finite differences of whole steps: the state perturbed
// by ±ε in each coordinate (rotations by a turn in the world frame), stepped once, the resulting
// states differenced; and against the closed form of free flight.

#include "engine/step_sensitivity.h"

#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "engine/loads.h"
#include "engine/rotation.h"
#include "engine/scene.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/state.h"
#include "engine/time_step.h"

namespace ecpsim::engine {
namespace {

using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

std::string ScenePath(const std::string& name) {
  return std::string(ECPSIM_SOURCE_DIR) + "/scenes/" + name;
}

// the finite differences' step, as a fraction of each coordinate's scale (below): the steps'
// solutions carry ≈ 1e-13 of their scales in noise (the solver ends at round-off or a polished
// start below 1e-13), which 1e-6 turns into ≈ 1e-7 of error, while the truncation error is
// ≈ 1e-12; the modes stay put within it
constexpr double kStepFraction = 1e-6;
// the agreement asserted where the mode is stable, relative in the scaled norm (below)
constexpr double kAgreement = 1e-5;

// A body's natural scales: length L (radius of gyration), velocity V (its speed |v| + |ω| L, at
// least the g h a step of gravity gives), force m V / h (what changes its velocity by V in one
// step), torque m V L / h. A state coordinate is scaled by [L, 1 rad, V, V / L], an input by
// [force, torque].
struct NaturalScales {
  VectorXd state, input;  // 12 n, 6 n
};

NaturalScales ScalesOf(const Scene& scene, const State& state, const std::vector<int>& bodies) {
  NaturalScales s;
  const int n = static_cast<int>(bodies.size());
  s.state.resize(kStateCoordinates * n);
  s.input.resize(kWrenchCoordinates * n);
  for (int i = 0; i < n; ++i) {
    const Body& body = scene.bodies[bodies[i]];
    const BodyState& b = state.bodies[bodies[i]];
    const double L = std::sqrt(body.inertia.trace() / body.mass);
    const double V = std::max(b.v_WB.norm() + b.w_WB.norm() * L, scene.gravity.norm() * scene.h);
    const double unit[4] = {L, 1.0, V, V / L};
    for (int j = 0; j < kStateCoordinates; ++j) s.state[kStateCoordinates * i + j] = unit[j / 3];
    const double force = body.mass * V / scene.h;
    for (int j = 0; j < kWrenchCoordinates; ++j)
      s.input[kWrenchCoordinates * i + j] = j < 3 ? force : force * L;
  }
  return s;
}

// x⁺(perturbed) − x⁺ in the coordinates of kStateCoordinates
VectorXd Difference(const State& perturbed, const State& nominal, const std::vector<int>& bodies) {
  VectorXd d(kStateCoordinates * bodies.size());
  for (size_t i = 0; i < bodies.size(); ++i) {
    const BodyState& a = perturbed.bodies[bodies[i]];
    const BodyState& b = nominal.bodies[bodies[i]];
    d.segment<3>(12 * i) = a.p_WB - b.p_WB;
    d.segment<3>(12 * i + 3) = QuaternionLog(a.Q_WB * b.Q_WB.conjugate());
    d.segment<3>(12 * i + 6) = a.v_WB - b.v_WB;
    d.segment<3>(12 * i + 9) = a.w_WB - b.w_WB;
  }
  return d;
}

// a constant wrench on `body` over every step (as the Python Simulation's apply_wrench)
Load ConstantLoad(Load::Kind kind, int body, const Vector3d& value) {
  Load load;
  load.kind = kind;
  load.body = body;
  load.x = TimeFunction(value.x());
  load.y = TimeFunction(value.y());
  load.z = TimeFunction(value.z());
  return load;
}

struct FiniteDifferences {
  MatrixXd A, B;
};

// ∂x⁺/∂x and ∂x⁺/∂u by central differences of whole steps
FiniteDifferences StepDifferences(const Scene& scene, const State& state,
                                  const std::vector<int>& bodies) {
  const NaturalScales s = ScalesOf(scene, state, bodies);
  State nominal = state;
  Step(scene, nominal);
  const int n = static_cast<int>(bodies.size());
  FiniteDifferences fd{MatrixXd(12 * n, 12 * n), MatrixXd(12 * n, 6 * n)};
  for (int col = 0; col < 12 * n; ++col) {
    const double eps = kStepFraction * s.state[col];
    State plus = state, minus = state;
    for (auto [x, sign] : {std::pair<State*, double>{&plus, 1.0}, {&minus, -1.0}}) {
      BodyState& b = x->bodies[bodies[col / 12]];
      Vector3d e = Vector3d::Zero();
      e[col % 3] = sign * eps;
      switch (col % 12 / 3) {
        case 0:
          b.p_WB += e;
          break;
        case 1:
          b.Q_WB = (QuaternionExp(e) * b.Q_WB).normalized();
          break;
        case 2:
          b.v_WB += e;
          break;
        default:
          b.w_WB += e;
          break;
      }
      Step(scene, *x);
    }
    fd.A.col(col) =
        (Difference(plus, nominal, bodies) - Difference(minus, nominal, bodies)) / (2 * eps);
  }
  for (int col = 0; col < 6 * n; ++col) {
    const double eps = kStepFraction * s.input[col];
    VectorXd diff[2];
    for (int side = 0; side < 2; ++side) {
      Scene loaded = scene;
      Vector3d e = Vector3d::Zero();
      e[col % 3] = side == 0 ? eps : -eps;
      loaded.loads.push_back(
          ConstantLoad(col % 6 < 3 ? Load::Kind::kForce : Load::Kind::kTorque, bodies[col / 6], e));
      State x = state;
      Step(loaded, x);
      diff[side] = Difference(x, nominal, bodies);
    }
    fd.B.col(col) = (diff[0] - diff[1]) / (2 * eps);
  }
  return fd;
}

// the largest difference of the scaled Jacobians relative to the largest scaled entry (at least
// 1: A holds identity blocks)
double ScaledError(const MatrixXd& analytic, const MatrixXd& fd, const VectorXd& row_scale,
                   const VectorXd& col_scale) {
  const MatrixXd to_scaled =
      row_scale.cwiseInverse().asDiagonal() * (analytic - fd) * col_scale.asDiagonal();
  const MatrixXd fd_scaled = row_scale.cwiseInverse().asDiagonal() * fd * col_scale.asDiagonal();
  return to_scaled.cwiseAbs().maxCoeff() / std::max(1.0, fd_scaled.cwiseAbs().maxCoeff());
}

struct Errors {
  double a, b;
  StepSensitivity sensitivity;
};

Errors Compare(const Scene& scene, const State& state) {
  StepWorkspace workspace;
  Errors e{0, 0, ComputeStepSensitivity(scene, state, workspace)};
  const StepSensitivity& s = e.sensitivity;
  const NaturalScales scales = ScalesOf(scene, state, s.bodies);
  const FiniteDifferences fd = StepDifferences(scene, state, s.bodies);
  e.a = ScaledError(s.A, fd.A, scales.state, scales.state);
  e.b = ScaledError(s.B, fd.B, scales.state, scales.input);
  testing::Test::RecordProperty("A_error", fmt::format("{:.3g}", e.a));
  testing::Test::RecordProperty("B_error", fmt::format("{:.3g}", e.b));
  return e;
}

// `scene` stepped `steps` times from its initial state
State After(const Scene& scene, int steps) {
  State state = InitialState(scene);
  for (int i = 0; i < steps; ++i) Step(scene, state);
  return state;
}

TEST(StepSensitivityTest, NextStateIsStepsBitForBit) {
  const Scene scene = LoadScene(ScenePath("slide.yaml")).scene;
  const State state = After(scene, 3);
  StepWorkspace workspace;
  const StepSensitivity s = ComputeStepSensitivity(scene, state, workspace);
  State stepped = state;
  Step(scene, stepped);
  ASSERT_EQ(s.next.bodies.size(), stepped.bodies.size());
  EXPECT_EQ(s.next.bodies[0].p_WB, stepped.bodies[0].p_WB);
  EXPECT_EQ(s.next.bodies[0].Q_WB.coeffs(), stepped.bodies[0].Q_WB.coeffs());
  EXPECT_EQ(s.next.bodies[0].v_WB, stepped.bodies[0].v_WB);
  EXPECT_EQ(s.next.bodies[0].w_WB, stepped.bodies[0].w_WB);
}

TEST(StepSensitivityTest, FreeFlightIsTheClosedForm) {
  // a box tumbling in the air: v⁺ = v + h (g + F/m), so ∂p⁺/∂v = h I, ∂v⁺/∂F = h/m I,
  // ∂p⁺/∂F = h²/m I exactly, and ∂p⁺/∂p = I
  Scene scene = LoadScene(ScenePath("slide.yaml")).scene;
  State state = InitialState(scene);
  state.bodies[0].p_WB.z() = 1.0;
  state.bodies[0].w_WB = Vector3d(3, -2, 5);
  StepWorkspace workspace;
  const StepSensitivity s = ComputeStepSensitivity(scene, state, workspace);
  const double h = scene.h, m = scene.bodies[0].mass;
  EXPECT_FALSE(s.degenerate);
  EXPECT_TRUE(s.isolated);
  EXPECT_LT((s.A.block<3, 3>(0, 0) - Eigen::Matrix3d::Identity()).norm(), 1e-9);
  EXPECT_LT((s.A.block<3, 3>(0, 6) - h * Eigen::Matrix3d::Identity()).norm(), 1e-9 * h);
  EXPECT_LT((s.B.block<3, 3>(6, 0) - h / m * Eigen::Matrix3d::Identity()).norm(), 1e-9 * h / m);
  EXPECT_LT((s.B.block<3, 3>(0, 0) - h * h / m * Eigen::Matrix3d::Identity()).norm(),
            1e-9 * h * h / m);
  const Errors e = Compare(scene, state);
  EXPECT_LT(e.a, kAgreement);
  EXPECT_LT(e.b, kAgreement);
}

TEST(StepSensitivityTest, SlidingBoxMatchesFiniteDifferences) {
  const Scene scene = LoadScene(ScenePath("slide.yaml")).scene;
  const Errors e = Compare(scene, After(scene, 5));  // sliding at 0.39 m/s
  EXPECT_FALSE(e.sensitivity.degenerate);
  EXPECT_TRUE(e.sensitivity.isolated);
  EXPECT_LT(e.a, kAgreement);
  EXPECT_LT(e.b, kAgreement);
}

TEST(StepSensitivityTest, TheComparisonCatchesTheContactLeftOut) {
  // the sliding box's differences against the Jacobians of the same box in the air: the
  // friction's share of ∂v⁺/∂v (it turns with the slip) must show far above the agreement
  const Scene scene = LoadScene(ScenePath("slide.yaml")).scene;
  const State sliding = After(scene, 5);
  State flying = sliding;
  flying.bodies[0].p_WB.z() += 1.0;
  StepWorkspace workspace;
  const StepSensitivity in_air = ComputeStepSensitivity(scene, flying, workspace);
  const std::vector<int> bodies = {0};
  const NaturalScales s = ScalesOf(scene, sliding, bodies);
  const FiniteDifferences fd = StepDifferences(scene, sliding, bodies);
  EXPECT_GT(ScaledError(in_air.A, fd.A, s.state, s.state), 100 * kAgreement);
}

TEST(StepSensitivityTest, ATouchWithoutForceIsDegenerate) {
  // without gravity a box resting on the ground touches it with no normal impulse: p_n = 0 and
  // the gap 0, a degenerate pair. The contact is left out (the branch on which it stays apart),
  // so A is free flight's: ∂v⁺/∂v = I, ∂p⁺/∂v = h I
  Scene scene = LoadScene(ScenePath("slide.yaml")).scene;
  scene.gravity.setZero();
  State state = InitialState(scene);
  state.bodies[0].v_WB.setZero();
  StepWorkspace workspace;
  const StepSensitivity s = ComputeStepSensitivity(scene, state, workspace);
  EXPECT_TRUE(s.degenerate);
  ASSERT_EQ(s.islands.size(), 1u);
  EXPECT_EQ(s.islands[0].degenerate_pairs, 1);
  EXPECT_LT((s.A.block<3, 3>(6, 6) - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_LT((s.A.block<3, 3>(0, 6) - scene.h * Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(StepSensitivityTest, TippingBoxMatchesFiniteDifferences) {
  const Scene scene = LoadScene(ScenePath("tilted_box.yaml")).scene;
  const Errors e = Compare(scene, After(scene, 10));  // tipping about its edge
  EXPECT_TRUE(e.sensitivity.isolated);
  EXPECT_LT(e.a, kAgreement);
  EXPECT_LT(e.b, kAgreement);
}

TEST(StepSensitivityTest, DeskMatchesFiniteDifferences) {
  const Scene scene = LoadScene(ScenePath("desk.yaml")).scene;
  const Errors e = Compare(scene, After(scene, 20));  // sliding and turning on four feet
  EXPECT_TRUE(e.sensitivity.isolated);
  EXPECT_LT(e.a, kAgreement);
  EXPECT_LT(e.b, kAgreement);
}

TEST(StepSensitivityTest, RefusesModelsOtherThanTheHulls) {
  Scene scene = LoadScene(ScenePath("slide.yaml")).scene;
  scene.model = ContactModel::kPoint;
  StepWorkspace workspace;
  EXPECT_THROW(ComputeStepSensitivity(scene, InitialState(scene), workspace), ModelInvalid);
}

}  // namespace
}  // namespace ecpsim::engine
