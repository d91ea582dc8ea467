#include "engine/models/point_model.h"

#include <cmath>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/rotation.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/time_step.h"
#include "tests/engine/test_bodies.h"
#include "tests/tolerances.h"

namespace ecpsim::engine {
namespace {

using Eigen::Vector3d;

constexpr double kG = 9.8;  // m/s², the scenes' gravity
// m, m/s, rad/s: a quantity of size ≲ 1 that Lemke's pivots determine exactly (a resting or
// landed body's drift and velocity, its centre of pressure), to round-off over the run
constexpr double kRoundOff = 1e-12;
// N·s: a box's impulses of size m g h ≈ 0.1 N·s from a handful of pivots: a few dozen ulps
constexpr double kImpulseRoundOff = 1e-14;
// the point model's LCP residual bar (point_model.cpp's kLcpResidualTol), relative to velocity
// and impulse scales of O(1): what a step reproduces of a quantity the LCP fixes (a sliding
// step's Δv = −a h, a resting desk's height and weight)
constexpr double kLcpResidualBar = 1e-9;

// a 0.2 × 0.1 × 0.05 m, 1 kg box resting flat on the ground at the origin, stepped by the model
Scene BoxScene() {
  Body box = testing::MakeBoxBody(Vector3d(0.2, 0.1, 0.05), 1);
  box.p0 = Vector3d(0, 0, 0.025);
  Scene scene = testing::MakeGroundScene({box});
  scene.model = ContactModel::kPoint;
  return scene;
}

TEST(PointModelTest, BoxAtRestStaysPut) {
  const Scene scene = BoxScene();
  State state = InitialState(scene);
  for (int i = 0; i < 100; ++i) {
    const StepReport report = Step(scene, state);
    ASSERT_TRUE(report.converged);
    ASSERT_EQ(report.substeps, 1);
  }
  // the LCP is solved exactly: the box does not drift (round-off only) over 1 s
  EXPECT_LE((state.bodies[0].p_WB - Vector3d(0, 0, 0.025)).norm(), kRoundOff);
  EXPECT_LE(state.bodies[0].v_WB.norm(), kRoundOff);
  EXPECT_LE(state.bodies[0].w_WB.norm(), kRoundOff);
  // the four bottom corners carry the weight m g h with their centre of pressure under the CM
  const ContactState& c = state.contacts[0];
  EXPECT_NEAR(c.p_n, kG * scene.h, kImpulseRoundOff);
  EXPECT_LE((c.a1 - Vector3d::Zero()).norm(), kRoundOff);
  EXPECT_LE(std::hypot(c.p_t, c.p_o), kImpulseRoundOff);
  EXPECT_NEAR(c.n.z(), 1, kUnitRoundOff);
}

TEST(PointModelTest, SmoothHullStandingOnItsDiscStaysPut) {
  // a cylinder hull (radius 0.1 m, length 0.3 m, axis z) standing on an end disc: its 48-segment
  // tessellation puts 49 vertices on the ground, a highly degenerate LCP of size 490
  Body body = testing::MakeBoxBody(Vector3d(0.2, 0.2, 0.3), 3, "drum");
  body.hull = geometry::MakeCylinder(0.1, 0.3, 2);
  body.p0 = Vector3d(0, 0, 0.15);
  Scene scene = testing::MakeGroundScene({body});
  scene.model = ContactModel::kPoint;
  State state = InitialState(scene);
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(Step(scene, state).converged);
  EXPECT_LE((state.bodies[0].p_WB - Vector3d(0, 0, 0.15)).norm(), kRoundOff);
  EXPECT_LE(state.bodies[0].w_WB.norm(), kRoundOff);
  // N·s: 3 m g h shared by the 49 vertices on the ground and summed back
  constexpr double kDrumImpulseRoundOff = 1e-13;
  EXPECT_NEAR(state.contacts[0].p_n, 3 * kG * scene.h, kDrumImpulseRoundOff);
  EXPECT_LE(state.contacts[0].a1.norm(), kRoundOff);  // centre of pressure under the CM
}

// slides the box from v0 until it stops; checks the deceleration of every sliding step
// against `decel` (m/s²) and returns the distance travelled
double SlideUntilStop(const Scene& scene, const Vector3d& v0, double decel) {
  State state = InitialState(scene);
  state.bodies[0].v_WB = v0;
  const Vector3d direction = v0.normalized();
  // m: the active normal constraint holds the height to the LCP's bar times h (1e-11 m)
  constexpr double kHeightTol = 1e-10;
  for (int i = 0; i < 1000 && state.bodies[0].v_WB.norm() > 0; ++i) {
    const double speed = state.bodies[0].v_WB.norm();
    EXPECT_TRUE(Step(scene, state).converged);
    const Vector3d v = state.bodies[0].v_WB;
    if (speed > decel * scene.h) {
      // Δv = −a h exactly while sliding (round-off of the pivots is ≈ 1e-15 m/s), along the
      // initial direction, without tipping, lifting or turning
      EXPECT_NEAR(speed - v.norm(), decel * scene.h, kLcpResidualBar) << "step " << i;
      EXPECT_LE((v - v.norm() * direction).norm(), kLcpResidualBar) << "step " << i;
    } else {
      EXPECT_LE(v.norm(), kLcpResidualBar) << "step " << i;
      state.bodies[0].v_WB.setZero();
    }
    EXPECT_LE(state.bodies[0].w_WB.norm(), kLcpResidualBar);
    EXPECT_NEAR(state.bodies[0].p_WB.z(), 0.025, kHeightTol);
  }
  return state.bodies[0].p_WB.head<2>().norm();
}

TEST(PointModelTest, SlidingAlongAFrictionDirectionDeceleratesAtMuG) {
  const Scene scene = BoxScene();
  const double mu = scene.contacts[0].friction.mu, a = mu * kG, v0 = 1, h = scene.h;
  // the first step's contact state: the whole friction impulse −μ p_n along t = x, no torsion
  State state = InitialState(scene);
  state.bodies[0].v_WB = Vector3d(v0, 0, 0);
  ASSERT_TRUE(Step(scene, state).converged);
  const ContactState& c = state.contacts[0];
  EXPECT_NEAR(c.p_n, kG * h, kImpulseRoundOff);
  EXPECT_NEAR(c.p_t, -mu * kG * h, kImpulseRoundOff);
  EXPECT_NEAR(c.p_o, 0, kImpulseRoundOff);
  EXPECT_NEAR(c.p_r, 0, kImpulseRoundOff);
  EXPECT_NEAR(c.sigma, v0 - a * h, kRoundOff);  // λ: the sliding speed at the end of the step
  // the centre of pressure moves ahead of the CM by μ × the CM height (friction's tipping moment)
  EXPECT_NEAR(c.a1.x() - state.bodies[0].p_WB.x(), mu * 0.025, kRoundOff);

  const double distance = SlideUntilStop(scene, Vector3d(v0, 0, 0), a);
  // the discrete solution: v_n = v0 − n a h for n ≤ N = ⌊v0/(a h)⌋, then 0
  const int N = static_cast<int>(std::floor(v0 / (a * h)));
  const double discrete = h * (N * v0 - a * h * N * (N + 1) / 2.0);
  EXPECT_NEAR(distance, discrete, kLcpResidualBar);  // m: ≤ 1 s of velocities each within it
  // and the continuous one to O(h): the step's velocity is the end-of-step one
  EXPECT_NEAR(distance, v0 * v0 / (2 * a), v0 * h);
}

TEST(PointModelTest, SlidingBetweenTwoDirectionsUnderestimatesFrictionByCosPiOverD) {
  // at 22.5° the sliding velocity bisects two of the d = 8 directions: the polyhedral cone's
  // edge is perpendicular to it at the distance μ p_n cos(π/d) from the apex
  const Scene scene = BoxScene();
  const double mu = scene.contacts[0].friction.mu;
  const double angle = M_PI / kPointContactFrictionDirections;  // 22.5°
  const double a = mu * kG * std::cos(angle);
  State state = InitialState(scene);
  state.bodies[0].v_WB = Vector3d(std::cos(angle), std::sin(angle), 0);
  const double speed0 = state.bodies[0].v_WB.norm();
  ASSERT_TRUE(Step(scene, state).converged);
  const double ratio = (speed0 - state.bodies[0].v_WB.norm()) / (mu * kG * scene.h);
  EXPECT_NEAR(ratio, std::cos(M_PI / kPointContactFrictionDirections), kLcpResidualBar);
  // and every later sliding step too, down to the stop
  SlideUntilStop(scene, Vector3d(std::cos(angle), std::sin(angle), 0), a);
}

// the lowest hull vertex's height over a run, and the largest per-step explicit-geometry bound
// ½ h² |ω⁺|² r (the end pose rotates by Exp(hω⁺); the LCP constrains only its linearization)
struct DropResult {
  double deepest = 0;  // m, the most negative lowest-vertex height (0 when never below)
  double margin = 0;   // m, max over steps of (penetration − that step's bound)
  State final;
};

DropResult Drop(const Scene& scene, int steps) {
  const Body& body = scene.bodies[0];
  double radius = 0;
  for (const Vector3d& y : body.mesh.vertices) radius = std::max(radius, y.norm());
  DropResult result;
  result.final = InitialState(scene);
  result.margin = -INFINITY;
  for (int i = 0; i < steps; ++i) {
    EXPECT_TRUE(Step(scene, result.final).converged);
    const BodyState& b = result.final.bodies[0];
    const double penetration = std::max(0.0, -testing::LowestVertexHeight(body, b));
    const double bound = 0.5 * scene.h * scene.h * b.w_WB.squaredNorm() * radius;
    result.deepest = std::max(result.deepest, penetration);
    result.margin = std::max(result.margin, penetration - bound);
  }
  return result;
}

TEST(PointModelTest, FlatBoxDroppedFrom5cmLandsWithoutPenetration) {
  Scene scene = BoxScene();
  scene.bodies[0].p0.z() += 0.05;
  const DropResult r = Drop(scene, 50);
  // without rotation the constraint ψ + h nᵀv⁺ ≥ 0 is exact: round-off only
  EXPECT_LE(r.deepest, kRoundOff);
  // inelastic landing, then at rest on its face
  EXPECT_NEAR(r.final.bodies[0].p_WB.z(), 0.025, kRoundOff);
  EXPECT_LE(r.final.bodies[0].v_WB.norm(), kRoundOff);
}

TEST(PointModelTest, TumblingBoxPenetratesOnlyByTheExplicitGeometryBound) {
  Scene scene = BoxScene();
  Body& box = scene.bodies[0];
  box.q0 = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Vector3d(1, 1, 0).normalized()));
  box.p0 = Vector3d(0, 0, 0.05 + 0.07);  // lowest corner ≈ 5 cm up
  box.w0 = Vector3d(20, 0, 0);           // rad/s: it lands spinning, so the explicit geometry shows
  const DropResult r = Drop(scene, 150);
  // each step's penetration stays within ½ h² |ω⁺|² r (round-off on top)
  EXPECT_LE(r.margin, kRoundOff);
  // the bound is not vacuous: the explicit geometry does penetrate (1.0e-4 m measured), by far
  // less than the 5 mm the box's corners move per step; m, a decade either side of that
  constexpr double kLeastPenetration = 1e-5, kMostPenetration = 1e-3;
  EXPECT_GT(r.deepest, kLeastPenetration);
  EXPECT_LT(r.deepest, kMostPenetration);
  // it comes to rest on a face
  EXPECT_LE(r.final.bodies[0].v_WB.norm(), kLcpResidualBar);
}

TEST(PointModelTest, PaperDeskRunsWithoutSolverFailure) {
  const Scene scene = testing::PaperDeskScene(ContactModel::kPoint);
  State state = InitialState(scene);
  for (int i = 0; i < 50; ++i) {
    const StepReport report = Step(scene, state);
    ASSERT_TRUE(report.converged);
    ASSERT_EQ(report.substeps, 1);
    ASSERT_GT(report.iterations, 0);  // Lemke pivots
    // the feet stay on the ground: the normal impulse carries the weight over the step
    ASSERT_NEAR(state.contacts[0].p_n, 15 * kG * scene.h, kLcpResidualBar);
    ASSERT_NEAR(state.bodies[0].p_WB.z(), 0.45, kLcpResidualBar);
  }
  EXPECT_GT(state.bodies[0].p_WB.head<2>().norm(), 0.05);
}

// the desk at small steps: its four coplanar feet make the normal block of the LCP singular
// (statically indeterminate), and at h ≤ 1.25e-4 s the Lemke solver once pivoted on round-off
// there ("solved" with a scaled residual of 0.26); it must run, keep its height and follow the
// hull model over 0.05 s
class PointContactSmallStepTest : public ::testing::TestWithParam<double> {};

TEST_P(PointContactSmallStepTest, PaperDeskFollowsTheHullModel) {
  const double h = GetParam();
  Scene point = testing::PaperDeskScene(ContactModel::kPoint);
  Scene hull = testing::PaperDeskScene(ContactModel::kHull);
  point.h = hull.h = h;
  State sp = InitialState(point), sh = InitialState(hull);
  const int steps = static_cast<int>(std::lround(0.05 / h));
  double dv = 0, dw = 0;
  for (int i = 0; i < steps; ++i) {
    const StepReport report = Step(point, sp);
    ASSERT_TRUE(report.converged) << "step " << i;
    ASSERT_EQ(report.substeps, 1) << "step " << i;
    ASSERT_TRUE(Step(hull, sh).converged);
    // the feet stay on the ground (the hull model's height test uses the same 1e-9)
    ASSERT_NEAR(sp.bodies[0].p_WB.z(), 0.45, kLcpResidualBar) << "step " << i;
    dv = std::max(dv, (sp.bodies[0].v_WB - sh.bodies[0].v_WB).norm());
    dw = std::max(dw, (sp.bodies[0].w_WB - sh.bodies[0].w_WB).norm());
  }
  // the models differ in friction, not in the LCP's accuracy: either one's friction impulse
  // changes v by at most μ g t = 0.108 m/s over t = 0.05 s (measured difference 0.0232 m/s at
  // both h), and the four feet's Coulomb torque stops the 0.5 rad/s twist much sooner than the
  // ellipsoid's e_r = 0.1 m (measured 0.127 rad/s; README "The point-contact baseline")
  constexpr double kFrictionSpeedGap = 0.03;  // m/s, over the measured 0.0232
  constexpr double kFrictionTwistGap = 0.15;  // rad/s, over the measured 0.127
  EXPECT_LE(dv, kFrictionSpeedGap);
  EXPECT_LE(dw, kFrictionTwistGap);
}

INSTANTIATE_TEST_SUITE_P(PointContactSmallSteps, PointContactSmallStepTest,
                         ::testing::Values(1.25e-4, 6.25e-5));

// --- contacts between bodies (issue 13) ---

// relative: what Lemke's solution reproduces of a quantity the LCP determines exactly (a
// velocity set by an active constraint, an impulse balance): its bar kLcpResidualTol = 1e-9 on
// the scaled LCP (velocities by the largest |q|, impulses by m V), with a margin of 10 for the
// sums over a body's points
constexpr double kLcpRel = 1e-8;
// m: the stack's drift bar over 10 s (the issue's); a resting stack's points sit at ψ = 0 and
// the LCP keeps them there to round-off, 1e-16 m per step
constexpr double kStackDrift = 1e-9;

Scene StackScene(double h) {
  Scene scene = LoadScene(ECPSIM_SOURCE_DIR "/scenes/stack.yaml").scene;
  scene.model = ContactModel::kPoint;
  scene.h = h;
  return scene;
}

TEST(PointContactBodiesTest, StackOfThreeBoxesRestsTenSecondsWithoutDrift) {
  const Scene scene = StackScene(0.01);
  State state = InitialState(scene);
  const State start = state;
  double mass_above[3] = {0, 0, 0};  // kg on top of box b, itself included
  for (int b = 2; b >= 0; --b)
    mass_above[b] = scene.bodies[b].mass + (b < 2 ? mass_above[b + 1] : 0);
  for (int step = 0; step < 1000; ++step) {
    const StepReport report = Step(scene, state);
    ASSERT_TRUE(report.converged) << "t = " << state.t;
    ASSERT_EQ(report.substeps, 1) << "t = " << state.t;
    for (int b = 0; b < 3; ++b) {
      ASSERT_LE((state.bodies[b].p_WB - start.bodies[b].p_WB).norm(), kStackDrift)
          << scene.bodies[b].name << " at t = " << state.t;
    }
  }
  // each contact under a box carries the weight of it and the boxes above it over the step
  const double h = scene.h;
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const ContactPair& pair = scene.contacts[k];
    const ContactState& c = state.contacts[k];
    double carried = 0;
    if (!pair.WithBody()) {
      carried = pair.body == 0 ? mass_above[0] : 0;
    } else if (pair.other_body == pair.body + 1) {
      carried = mass_above[pair.other_body];
      EXPECT_NEAR(c.n.z(), -1, kRoundOff) << "the normal points from G (above) into F (below)";
    }
    EXPECT_NEAR(c.p_n, carried * kG * h, kLcpRel * mass_above[0] * kG * h)
        << "contact " << k << " (" << scene.bodies[pair.body].name << ")";
  }
}

TEST(PointContactBodiesTest, StackFirstStepDoesNotDropAsEnginesWithoutBodyContactDo) {
  // MuJoCo and ODE find no box–box contact on the first step and each level drops g h² (issue
  // 13); the point model's vertices resting at ψ = 0 hold every box from the first step on
  for (double h : {0.02, 0.01, 0.001}) {
    const Scene scene = StackScene(h);
    State state = InitialState(scene);
    ASSERT_TRUE(Step(scene, state).converged);
    for (int b = 0; b < 3; ++b)
      EXPECT_LE(std::abs(state.bodies[b].p_WB.z() - scene.bodies[b].p0.z()), kStackDrift)
          << "h = " << h << ", " << scene.bodies[b].name;
  }
}

TEST(PointContactBodiesTest, TwoFreeCubesExchangeMomentumExactlyAndNeverGainKineticEnergy) {
  // no gravity, no ground: a spinning cube hits another off its centre line, with friction.
  // Cubes have isotropic inertia: free flight keeps ω, only the contact changes momentum
  Body a = testing::MakeBoxBody(Vector3d(0.2, 0.2, 0.2), 2, "a");
  a.v0 = Vector3d(1.5, 0, 0);
  a.w0 = Vector3d(0.3, -0.2, 1.0);
  a.friction = Friction{0.6, 1, 1, 0.05};
  Body b = testing::MakeBoxBody(Vector3d(0.25, 0.25, 0.25), 1, "b");
  b.p0 = Vector3d(0.4, 0.08, 0.03);
  b.friction = a.friction;
  Scene scene;
  scene.source = "test";
  scene.gravity = Vector3d::Zero();
  scene.h = 0.01;
  scene.bodies = {a, b};
  scene.model = ContactModel::kPoint;
  AddBodyPairs(scene);
  State state = InitialState(scene);

  // N·s: the impulses enter the two bodies as +J and −J exactly, so linear momentum changes by
  // round-off of the velocity updates only (ε of the momentum scale m V = 3 N·s, × 100)
  const double kMomentumTol = 100 * 2.2e-16 * 3.0;
  const auto kinetic = [&](const State& s) {
    double e = 0;
    for (int i = 0; i < 2; ++i) {
      const Eigen::Matrix3d R = s.bodies[i].Q_WB.toRotationMatrix();
      const Eigen::Matrix3d I = R * scene.bodies[i].inertia * R.transpose();
      e += 0.5 * scene.bodies[i].mass * s.bodies[i].v_WB.squaredNorm() +
           0.5 * s.bodies[i].w_WB.dot(I * s.bodies[i].w_WB);
    }
    return e;
  };
  const auto linear = [&](const State& s) {
    return Vector3d(2 * s.bodies[0].v_WB + 1 * s.bodies[1].v_WB);
  };
  // angular momentum about the origin with the centres at the start of the step: the impulse
  // J at x acts with the moment arms x − c of the start pose, so Σ c × m v⁺ + I ω⁺ equals
  // Σ c × m v + I ω exactly (c × J + (x − c) × J − c' × J − (x − c') × J = 0)
  const auto angular = [&](const State& at, const State& velocities) {
    Vector3d L = Vector3d::Zero();
    for (int i = 0; i < 2; ++i) {
      const Eigen::Matrix3d R = velocities.bodies[i].Q_WB.toRotationMatrix();
      const Eigen::Matrix3d I = R * scene.bodies[i].inertia * R.transpose();
      L += at.bodies[i].p_WB.cross(scene.bodies[i].mass * velocities.bodies[i].v_WB) +
           I * velocities.bodies[i].w_WB;
    }
    return L;
  };
  const Vector3d p0 = linear(state);
  bool touched = false;
  for (int step = 0; step < 60; ++step) {
    const State before = state;
    ASSERT_TRUE(Step(scene, state).converged) << "t = " << state.t;
    touched |= state.contacts[0].p_n > 0;
    EXPECT_LE((linear(state) - p0).norm(), kMomentumTol) << "t = " << state.t;
    EXPECT_LE((angular(before, state) - angular(before, before)).norm(), kMomentumTol)
        << "t = " << state.t;
    // with every point's gap ψ ≥ 0 the LCP's impulses do work ≤ 0 at the end velocities
    constexpr double kEnergyRoundOff = 1e-12;  // relative, of the kinetic energy's sums
    EXPECT_LE(kinetic(state), kinetic(before) * (1 + kEnergyRoundOff)) << "t = " << state.t;
  }
  EXPECT_TRUE(touched);
  EXPECT_GT(state.bodies[1].v_WB.x(), 0.5);  // b moves off in +x
}

TEST(PointContactBodiesTest, ConstantSpeedPusherCarriesTheBoxAtItsSpeed) {
  Scene scene = LoadScene(ECPSIM_SOURCE_DIR "/scenes/push_box.yaml").scene;
  scene.model = ContactModel::kPoint;
  ASSERT_EQ(scene.contacts.size(), 2u);  // box–ground, box–pusher (F the box, G the pusher)
  const double speed = 0.1, mu = scene.contacts[0].friction.mu, mass = scene.bodies[0].mass;
  State state = InitialState(scene);
  for (int step = 0; step < 200; ++step) {
    const double v_before = state.bodies[0].v_WB.x();
    ASSERT_TRUE(Step(scene, state).converged) << "t = " << state.t;
    const KinematicPose pose = scene.bodies[1].motion->PoseAt(state.t);
    ASSERT_EQ(state.bodies[1].p_WB, pose.p);
    // never inside the pusher: the box's −x face stays ahead of the pusher's +x face (a
    // translation: the explicit geometry is exact)
    ASSERT_GE((state.bodies[0].p_WB.x() - 0.1) - (pose.p.x() + 0.01), -kLcpRel * speed * scene.h)
        << "t = " << state.t;
    if (state.t < 0.5) continue;
    const ContactState& ground = state.contacts[0];
    const ContactState& push = state.contacts[1];
    EXPECT_NEAR(state.bodies[0].v_WB.x(), speed, kLcpRel * speed) << "t = " << state.t;
    EXPECT_NEAR(push.n.x(), 1, kRoundOff);  // from G (the pusher) into F (the box)
    // the box slides with Coulomb friction along a cone edge (x is one of the 8 directions)
    const Vector3d push_impulse = push.p_n * push.n + push.p_t * push.t + push.p_o * push.o;
    const Vector3d ground_friction = ground.p_t * ground.t + ground.p_o * ground.o;
    EXPECT_NEAR(ground_friction.x(), -mu * ground.p_n, kLcpRel * mass * kG * scene.h);
    EXPECT_NEAR(push_impulse.x() + ground_friction.x(),
                mass * (state.bodies[0].v_WB.x() - v_before), kLcpRel * mass * speed);
    EXPECT_NEAR(state.bodies[0].v_WB.y(), 0, kLcpRel * speed);
  }
}

}  // namespace
}  // namespace ecpsim::engine
