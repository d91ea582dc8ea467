// The multi-patch model's balanced warm start (engine/models/multipatch_balance.h): a four-legged
// table sliding and turning flat on the ground, whose step under last step's loads is the warm
// start of a step under changed loads; balanced and polished, that start is the new step's solution
// to round-off, and where the balance does not apply the start is left as it came.

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "engine/mncp/mncp_scaling.h"
#include "engine/mncp/mncp_system.h"
#include "engine/models/multipatch_balance.h"
#include "engine/models/multipatch_model.h"
#include "engine/scene.h"
#include "engine/solver/complementarity_solver.h"
#include "geometry/convex_hull.h"
#include "geometry/convex_shape.h"

namespace ecpsim::engine {
namespace {

using Eigen::Vector3d;
using Eigen::VectorXd;

constexpr double kG = 9.8;                 // m/s²
constexpr double kMass = 15;               // kg, the paper's desk
constexpr double kCmHeight = 0.45;         // m, above the feet
constexpr double kSolveTolerance = 1e-14;  // the reference steps, solved past the default 1e-12
// a part's face carries it above this fraction of its largest multiplier (the model's)
constexpr double kActiveFraction = 1e-9;
// the proximal terms' sizes, in the scaled problem's units (multipatch_model.cpp's)
constexpr double kEcpDampingRel = 1e-5;
constexpr double kLoadDampingRel = 1e-7;
// the warm start's loads against the step's: the desk's push changes by up to 2π · 22.5 N · h
// ≈ 1.4 N a step, about 3 % of its mean; this is a few steps' change
constexpr double kLastLoads = 0.9;

// a 15 kg table at pose (R, c) whose four 0.06 × 0.06 m feet, centred 0.22 m off its CM along x
// and y, stand on the ground (z = 0), moving at (v, ω) under a push and a twist about z: the
// multi-patch problem of one step, its feet in the plane form with every face in the window
struct TableOnGround {
  std::shared_ptr<const geometry::ConvexShape> ground =
      geometry::MakeHalfSpace(Vector3d::UnitZ(), 0);
  std::vector<std::shared_ptr<const geometry::ConvexShape>> feet;
  std::vector<Vector3d> foot_centres;  // of the feet's soles, body frame
  MultiPatchProblem problem;
  MncpLayout layout;
  Scales scales;

  TableOnGround(const Vector3d& force, double torque_z) {
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.3, Vector3d::UnitZ()).toRotationMatrix();
    const Vector3d v(0.3, 0.2, 0), w(0, 0, 0.5);
    BodyProblem& body = problem.body;
    body.h = 0.01;
    body.mass = kMass;
    body.R = R;
    // a 0.5 × 0.5 × 0.1 m top's inertia, as the desk's is mostly
    const Vector3d inertia_body = kMass / 12 * Vector3d(0.26, 0.26, 0.5);
    body.inertia_world = R * inertia_body.asDiagonal() * R.transpose();
    body.c = Vector3d(0.1, -0.2, kCmHeight);
    body.v = v;
    body.w = w;
    body.p_gravity = Vector3d(0, 0, -kG * body.h * kMass);
    body.p_ext << body.p_gravity + body.h * force, Vector3d(0, 0, body.h * torque_z);
    body.free = {v, w};
    for (double x : {-0.22, 0.22}) {
      for (double y : {-0.22, 0.22}) {
        const auto box = geometry::MakeBox(Vector3d(0.03, 0.03, 0.05));
        feet.push_back(std::make_shared<geometry::PolyhedralShape>(
            geometry::TranslateHull(box->hull(), Vector3d(x, y, 0.05 - kCmHeight))));
        foot_centres.emplace_back(x, y, -kCmHeight);
        ContactProblem cp;
        cp.hull = feet.back().get();
        cp.obstacle = ground.get();
        for (int i = 0; i < cp.hull->NumConstraints(); ++i) cp.window.push_back(i);
        cp.friction = Friction{0.22, 1, 1, 0.1};
        cp.tangent_reference = Vector3d::UnitX();
        body.contacts.push_back(cp);
        problem.group.push_back(0);
      }
    }
    problem.num_groups = 1;
    const double length = std::sqrt(inertia_body.sum() / kMass);
    // (BodyScales' rule: the body's own speed, or what gravity adds over the step if larger)
    const double speed = std::max(v.norm() + w.norm() * length, kG * body.h);
    scales = Scales{length, speed, kMass * speed};
    problem.weight_floor = 1e-12 * scales.impulse;  // the model's
    problem.ecp_damping = kEcpDampingRel / scales.length;
    problem.load_damping = kLoadDampingRel * scales.length / scales.impulse;
    layout = MakeMultiPatchLayout(body);
  }

  double Measure(const VectorXd& z) const {
    VectorXd F(layout.size);
    EvaluateMultiPatch(problem, layout, z, &F, nullptr);
    return MncpResidual(layout, z, F, RowScales(problem.body, layout, scales),
                        VariableScales(problem.body, layout, scales),
                        {scales.length, kSolveTolerance, problem.body.c.cwiseAbs().maxCoeff()});
  }

  // the step solved to kSolveTolerance from `z` (as the model solves it, proximal terms and all)
  VectorXd Solve(VectorXd z) const {
    McpOptions options;
    options.tolerance = kSolveTolerance;
    const McpFunction f = [this](const VectorXd& zz, VectorXd* F, Eigen::MatrixXd* J) {
      EvaluateMultiPatch(problem, layout, zz, F, J, /*jacobian_is_zero=*/true);
      if (J != nullptr) AddProximalTerms(problem, layout, *J);
    };
    const McpResult result = SolveMcp(f, layout.num_free, RowScales(problem.body, layout, scales),
                                      VariableScales(problem.body, layout, scales), z, options);
    EXPECT_TRUE(result.converged) << result.residual;
    return z;
  }

  // sliding on the feet's centres, the weight shared evenly, friction against the motion
  VectorXd SlidingGuess() const {
    const BodyProblem& body = problem.body;
    VectorXd z = VectorXd::Zero(layout.size);
    z.head<3>() = body.v;
    z.segment<3>(3) = body.w;
    const EndPose end = PoseAfterStep(body, body.v, body.w);
    for (int i = 0; i < static_cast<int>(layout.contacts.size()); ++i) {
      const MncpLayout::Contact& L = layout.contacts[i];
      const Vector3d& centre = foot_centres[i];
      z.segment<3>(L.a1) = end.c + end.R * centre;
      z[L.p_n] = -body.p_gravity.z() / 4;
      z[L.p_t] = -0.22 * z[L.p_n] * body.v.x() / body.v.norm();
      z[L.p_o] = -0.22 * z[L.p_n] * body.v.y() / body.v.norm();
      z[L.sigma] = body.v.norm();
      z[L.l + MostOpposedWindowConstraint(body.contacts[i], end.R, centre, Vector3d::UnitZ())] = 1;
    }
    return z;
  }
};

const Vector3d kPush(22.5, 10, 0);  // N
constexpr double kTwist = 2.1;      // N·m

TEST(MultiPatchBalanceTest, TheBalancedWarmStartOfATableSlidingOnFourFeetIsItsStepsSolution) {
  // the warm start: the step solved under the last loads, a tenth smaller
  const TableOnGround last(kLastLoads * kPush, kLastLoads * kTwist);
  const VectorXd warm = last.Solve(last.SlidingGuess());
  const TableOnGround table(kPush, kTwist);
  const VectorXd solution = table.Solve(warm);
  VectorXd z = warm;
  const double before = table.Measure(z);
  ASSERT_EQ(BalanceMultiPatchSlidingStart(table.problem, table.layout, kActiveFraction, z),
            StartBalance::kPolished);
  const double balanced = table.Measure(z);
  std::printf("table on four feet: warm start %.3g, balanced %.3g\n", before, balanced);
  // the changed loads are in the warm start's residual to their own order (far above this) ...
  constexpr double kChangedLoadsShow = 1e-3;
  EXPECT_GT(before, kChangedLoadsShow);
  // ... and balanced away: polished, the start solves the step as the model takes it, under
  // kPolishedStartAcceptance of the default tolerance (the friction rows' scaled
  // residual is the sweeps' last change of the friction impulse, a fraction kPolishTolerance of
  // μ p_n, times μ e² σ / V ≤ 1; the other rows follow the friction, or are exact)
  EXPECT_LE(balanced, kPolishedStartAcceptance * SolverSettings{}.tolerance);
  // the motion is the step's, to the same order
  const Scales& s = table.scales;
  EXPECT_LE((z.head<3>() - solution.head<3>()).norm(), kMultiPatchBalanceTolerance * s.velocity);
  EXPECT_LE((z.segment<3>(3) - solution.segment<3>(3)).norm(),
            kMultiPatchBalanceTolerance * s.velocity / s.length);
  // the normal loads shared out anew: every foot still pressed, together the weight
  double total = 0;
  for (const MncpLayout::Contact& L : table.layout.contacts) {
    EXPECT_GT(z[L.p_n], 0);
    total += z[L.p_n];
  }
  constexpr double kWeightRoundOff = 1e-12;  // relative: four shares summed back
  EXPECT_NEAR(total, -table.problem.body.p_gravity.z(), kWeightRoundOff * total);
}

TEST(MultiPatchBalanceTest, AStartItDoesNotApplyToIsLeftAsItCame) {
  const TableOnGround table(kPush, kTwist);
  const VectorXd warm = table.Solve(table.SlidingGuess());
  const MncpLayout::Contact& first = table.layout.contacts[0];
  const auto left_alone = [&](const TableOnGround& t, VectorXd z) {
    const VectorXd before = z;
    return BalanceMultiPatchSlidingStart(t.problem, t.layout, kActiveFraction, z) ==
               StartBalance::kUnbalanced &&
           z == before;
  };
  // sticking: σ = 0, the friction a reaction the sweeps do not model
  VectorXd sticking = warm;
  sticking[first.sigma] = 0;
  EXPECT_TRUE(left_alone(table, sticking));
  // a foot off the ground
  VectorXd lifted = warm;
  lifted[first.p_n] = 0;
  EXPECT_TRUE(left_alone(table, lifted));
  // a foot on an edge: two of its faces carry it
  VectorXd edge = warm;
  for (int i = 0; i < first.l_count; ++i)
    if (edge[first.l + i] == 0) {
      edge[first.l + i] = 0.5;
      break;
    }
  EXPECT_TRUE(left_alone(table, edge));
  // one part (then the model is the hull model, whose balance applies instead)
  TableOnGround one_foot(kPush, kTwist);
  one_foot.problem.body.contacts.resize(1);
  one_foot.problem.group.resize(1);
  one_foot.layout = MakeMultiPatchLayout(one_foot.problem.body);
  EXPECT_TRUE(left_alone(one_foot, one_foot.SlidingGuess()));
}

}  // namespace
}  // namespace ecpsim::engine
