#include "engine/solver/lemke_solver.h"

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <gtest/gtest.h>

namespace ecpsim::engine {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

// a solve of O(1) data is exact up to a few ulps per pivot
constexpr double kExact = 1e-14;

VectorXd Vec(std::initializer_list<double> values) {
  VectorXd v(values.size());
  int i = 0;
  for (double x : values) v[i++] = x;
  return v;
}

TEST(LemkeSolverTest, NonNegativeQNeedsNoPivot) {
  const MatrixXd M = MatrixXd::Identity(3, 3);
  const LcpResult r = SolveLcpLemke(M, Vec({1, 0, 2}));
  EXPECT_EQ(r.status, LcpStatus::kSolved);
  EXPECT_EQ(r.pivots, 0);
  EXPECT_EQ(r.z.norm(), 0);
}

TEST(LemkeSolverTest, BothUnknownsPositive) {
  // 2 z1 + z2 = 5, z1 + 2 z2 = 6: z = (4/3, 7/3), w = 0; three pivots (z0, z2, z1 enter)
  MatrixXd M(2, 2);
  M << 2, 1, 1, 2;
  const LcpResult r = SolveLcpLemke(M, Vec({-5, -6}));
  ASSERT_EQ(r.status, LcpStatus::kSolved);
  EXPECT_NEAR(r.z[0], 4.0 / 3, kExact);
  EXPECT_NEAR(r.z[1], 7.0 / 3, kExact);
  EXPECT_NEAR(r.w.cwiseAbs().maxCoeff(), 0, kExact);
  EXPECT_EQ(r.pivots, 3);
  EXPECT_LE(r.residual, kExact);
}

TEST(LemkeSolverTest, OneActiveOneSlack) {
  // z1 = 1/2 (w1 = 0), z2 = 0 with w2 = 1/2 + 3 = 3.5
  MatrixXd M(2, 2);
  M << 2, 1, 1, 2;
  const LcpResult r = SolveLcpLemke(M, Vec({-1, 3}));
  ASSERT_EQ(r.status, LcpStatus::kSolved);
  EXPECT_NEAR(r.z[0], 0.5, kExact);
  EXPECT_EQ(r.z[1], 0);
  EXPECT_NEAR(r.w[0], 0, kExact);
  EXPECT_NEAR(r.w[1], 3.5, kExact);
}

TEST(LemkeSolverTest, DegenerateTiesInTheRatioTest) {
  // every q_i ties in the first ratio test, and each later pivot ties z0 with another row:
  // M = I, q = −1 has the solution z = 1 with w = 0 (three tied pivots)
  const LcpResult r = SolveLcpLemke(MatrixXd::Identity(3, 3), Vec({-1, -1, -1}));
  ASSERT_EQ(r.status, LcpStatus::kSolved);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r.z[i], 1, kExact);
  EXPECT_LE(r.residual, kExact);
}

TEST(LemkeSolverTest, DegenerateSingularMatrixWithAFamilyOfSolutions) {
  // M = [[1, 1], [1, 1]] (PSD, singular), q = −1: every z ≥ 0 with z1 + z2 = 1 solves it, and
  // the basis of any solution is degenerate (a basic variable at 0 or w = z = 0 in some pair)
  MatrixXd M(2, 2);
  M << 1, 1, 1, 1;
  const LcpResult r = SolveLcpLemke(M, Vec({-1, -1}));
  ASSERT_EQ(r.status, LcpStatus::kSolved);
  EXPECT_NEAR(r.z.sum(), 1, kExact);
  EXPECT_GE(r.z.minCoeff(), 0);
  EXPECT_NEAR(r.w.cwiseAbs().maxCoeff(), 0, kExact);
}

TEST(LemkeSolverTest, StaticallyIndeterminateContactLcp) {
  // four equal contact points under a unit mass, unit impulse needed at each of the 4 rows of
  // a rank-1 M = 1 1ᵀ (a translating body on four coplanar points): Σ z = 1, any split
  const MatrixXd M = MatrixXd::Ones(4, 4);
  const LcpResult r = SolveLcpLemke(M, Vec({-1, -1, -1, -1}));
  ASSERT_EQ(r.status, LcpStatus::kSolved);
  EXPECT_NEAR(r.z.sum(), 1, kExact);
  EXPECT_GE(r.z.minCoeff(), 0);
  EXPECT_LE(r.residual, kExact);
}

// one desk LCP: step h (s), the desk's yaw θ (rad) and its inertia about z (kg·m²)
struct DeskLcpCase {
  double h, theta, izz;
};

// the point-contact LCP of a 15 kg desk sliding on four coplanar feet (at (±0.25, ±0.25, −0.45) m
// from the CM in its frame, yawed by θ; normal z, 8 friction directions from x, μ = 0.22) under
// gravity, a 45 N push along y and a 2.1 N·m twist, from v = (0.3, 0.2, 0) m/s, ω_z = 0.5 rad/s,
// built and scaled as point_model.cpp does: the 36 × 36 (p_n, β) block is Wᵀ M⁻¹ W of
// rank 6 and its normal part of rank 3 (statically indeterminate). Returns the velocity scale V.
double DeskContactLcp(const DeskLcpCase& c, MatrixXd& M, VectorXd& q) {
  constexpr int k = 4, d = 8, m = (1 + d) * k, size = m + k;
  constexpr double mass = 15, mu = 0.22, ixx = 0.9176;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(c.theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d inertia = R * Eigen::Vector3d(ixx, ixx, c.izz).asDiagonal() * R.transpose();
  Eigen::Matrix<double, 6, Eigen::Dynamic> W(6, m), AW(6, m);
  const double corners[k][2] = {{-0.25, -0.25}, {0.25, -0.25}, {0.25, 0.25}, {-0.25, 0.25}};
  const auto column = [](const Eigen::Vector3d& u, const Eigen::Vector3d& r) {
    Eigen::Matrix<double, 6, 1> w;
    w << u, r.cross(u);
    return w;
  };
  for (int i = 0; i < k; ++i) {
    const Eigen::Vector3d r = R * Eigen::Vector3d(corners[i][0], corners[i][1], -0.45);
    W.col(i) = column(Eigen::Vector3d::UnitZ(), r);
    for (int j = 0; j < d; ++j) {
      const double a = 2 * M_PI * j / d;
      W.col(k + d * i + j) = column(Eigen::Vector3d(std::cos(a), std::sin(a), 0), r);
    }
  }
  AW.topRows<3>() = W.topRows<3>() / mass;
  AW.bottomRows<3>() = inertia.ldlt().solve(W.bottomRows<3>());
  Eigen::Matrix<double, 6, 1> nu;
  nu << 0.3, 0.2 + 45 * c.h / mass, -9.8 * c.h, 0, 0, 0.5 + 2.1 * c.h / c.izz;
  M = MatrixXd::Zero(size, size);
  q = VectorXd::Zero(size);
  M.topLeftCorner(m, m) = W.transpose() * AW;
  q.head(m) = W.transpose() * nu;
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j < d; ++j) {
      M(k + d * i + j, m + i) = 1;
      M(m + i, k + d * i + j) = -1;
    }
    M(m + i, i) = mu;
  }
  const double V = q.head(m).cwiseAbs().maxCoeff(), P = mass * V;
  for (int i = 0; i < size; ++i)
    for (int j = 0; j < size; ++j) M(i, j) *= (i < m ? 1 / V : 1 / P) * (j < m ? P : V);
  q.head(m) /= V;
  return V;
}

class LemkeSingularContactTest : public ::testing::TestWithParam<DeskLcpCase> {};

TEST_P(LemkeSingularContactTest, DeskOnFourCoplanarFeetIsSolvedExactly) {
  // with the pivot threshold relative to the column's largest entry (the old rule), each of these
  // cases pivoted on a round-off entry (≈ 1e-16 of its scale ‖B⁻¹_i‖₁ max|A_j|) and returned
  // "solved" with a scaled residual of 0.45, 0.63 and 3.6
  MatrixXd M;
  VectorXd q;
  const double V = DeskContactLcp(GetParam(), M, q);
  const LcpResult r = SolveLcpLemke(M, q);
  ASSERT_EQ(r.status, LcpStatus::kSolved);
  // w recomputed here, not taken from the solver. O(1) data, but the nearly singular bases of the
  // rank-deficient block carry ‖B⁻¹‖ ≈ 1e3: round-off ≈ 1e3 × n ε ≈ 1e-11 (measured ≤ 1.4e-12),
  // far below the 0.45–3.6 of the old rule and the model's 1e-9 acceptance
  constexpr double kDeskExact = 1e-11;
  const VectorXd w = M * r.z + q;
  EXPECT_GE(r.z.minCoeff(), 0);
  EXPECT_GE(w.minCoeff(), -kDeskExact);
  EXPECT_LE(r.z.cwiseProduct(w).cwiseAbs().maxCoeff(), kDeskExact);
  EXPECT_LE(r.residual, kDeskExact);
  // all four feet stay on the ground (w_n = 0), so v_z⁺ = 0 and ω_x⁺ = ω_y⁺ = 0: the normal
  // impulses carry the weight over the step, Σ p_n = m g h, i.e. Σ z_n = g h / V scaled
  EXPECT_LE(w.head(4).cwiseAbs().maxCoeff(), kDeskExact);
  EXPECT_NEAR(r.z.head(4).sum(), 9.8 * GetParam().h / V, kDeskExact);
}

INSTANTIATE_TEST_SUITE_P(LemkeSmallSteps, LemkeSingularContactTest,
                         ::testing::Values(DeskLcpCase{2.5e-4, 1e-4, 0.6},
                                           DeskLcpCase{1.25e-4, 3e-4, 0.6},
                                           DeskLcpCase{1.25e-4, 2e-4, 0.9}));

TEST(LemkeSolverTest, InfeasibleProblemEndsOnARay) {
  // w1 = −z1 − 1 < 0 for every z1 ≥ 0: no solution, Lemke must stop on a ray
  MatrixXd M(2, 2);
  M << -1, 0, 0, 1;
  const LcpResult r = SolveLcpLemke(M, Vec({-1, 1}));
  EXPECT_EQ(r.status, LcpStatus::kRayTermination);
  EXPECT_EQ(r.z.norm(), 0);
}

TEST(LemkeSolverTest, InfeasibleCopositivePlusProblemEndsOnARay) {
  // M = 0 (copositive-plus) with q1 < 0: w1 = q1 for all z, infeasible
  const LcpResult r = SolveLcpLemke(MatrixXd::Zero(2, 2), Vec({-1, 2}));
  EXPECT_EQ(r.status, LcpStatus::kRayTermination);
}

TEST(LemkeSolverTest, PivotLimitIsReported) {
  // the 2 × 2 problem above needs 3 pivots
  MatrixXd M(2, 2);
  M << 2, 1, 1, 2;
  LemkeOptions options;
  options.max_pivots = 2;
  const LcpResult r = SolveLcpLemke(M, Vec({-5, -6}), options);
  EXPECT_EQ(r.status, LcpStatus::kPivotLimit);
  EXPECT_EQ(r.pivots, 2);
}

// the unique solution of a P-matrix LCP by enumerating all 2ⁿ complementary bases
VectorXd BruteForce(const MatrixXd& M, const VectorXd& q) {
  const int n = static_cast<int>(q.size());
  for (int mask = 0; mask < (1 << n); ++mask) {
    std::vector<int> active;
    for (int i = 0; i < n; ++i)
      if (mask & (1 << i)) active.push_back(i);
    VectorXd z = VectorXd::Zero(n);
    if (!active.empty()) {
      MatrixXd A(active.size(), active.size());
      VectorXd b(active.size());
      for (size_t a = 0; a < active.size(); ++a) {
        b[a] = -q[active[a]];
        for (size_t c = 0; c < active.size(); ++c) A(a, c) = M(active[a], active[c]);
      }
      const VectorXd x = A.lu().solve(b);
      for (size_t a = 0; a < active.size(); ++a) z[active[a]] = x[a];
    }
    // z ≥ 0 and w ≥ 0 up to the round-off of a small LU solve of O(1) data
    constexpr double kFeasibleRoundOff = 1e-12;
    const VectorXd w = M * z + q;
    if (z.minCoeff() >= -kFeasibleRoundOff && w.minCoeff() >= -kFeasibleRoundOff) return z;
  }
  return VectorXd();
}

TEST(LemkeSolverTest, MatchesEnumerationOnRandomPMatrixProblems) {
  // M = AᵀA + I + S (S skew) is positive definite hence a P-matrix: the solution is unique
  std::mt19937 random(7);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 50; ++trial) {
    const int n = 2 + trial % 6;
    MatrixXd A(n, n), S(n, n);
    VectorXd q(n);
    for (int i = 0; i < n; ++i) {
      q[i] = normal(random);
      for (int j = 0; j < n; ++j) {
        A(i, j) = normal(random);
        S(i, j) = normal(random);
      }
    }
    const MatrixXd M = A.transpose() * A + MatrixXd::Identity(n, n) + (S - S.transpose());
    const LcpResult r = SolveLcpLemke(M, q);
    ASSERT_EQ(r.status, LcpStatus::kSolved) << "trial " << trial;
    const VectorXd expected = BruteForce(M, q);
    ASSERT_EQ(expected.size(), n);
    // M's condition number here is ≤ 1e3: 1e-11 covers the round-off of both solves
    constexpr double kConditionedRoundOff = 1e-11;
    // the residual itself: round-off of O(10) entries of M over at most 7 rows
    constexpr double kResidualRoundOff = 1e-12;
    EXPECT_LE((r.z - expected).cwiseAbs().maxCoeff(), kConditionedRoundOff) << "trial " << trial;
    EXPECT_LE(r.residual, kResidualRoundOff) << "trial " << trial;
  }
}

}  // namespace
}  // namespace ecpsim::engine

namespace ecpsim::engine {
namespace {

TEST(LemkeSolverTest, AStopRequestedEndsTheSolveAtTheNextPivot) {
  // the three-pivot problem of BothUnknownsPositive with the flag raised: Cancelled; cleared,
  // the same solve as without a flag
  Eigen::MatrixXd M(2, 2);
  M << 2, 1, 1, 2;
  const Eigen::VectorXd q = (Eigen::VectorXd(2) << -5, -6).finished();
  CancelFlag flag;
  LemkeOptions options;
  options.cancel = &flag;
  flag.Raise();
  EXPECT_THROW(SolveLcpLemke(M, q, options), Cancelled);
  flag.Clear();
  const LcpResult watched = SolveLcpLemke(M, q, options);
  const LcpResult plain = SolveLcpLemke(M, q);
  ASSERT_EQ(watched.status, LcpStatus::kSolved);
  EXPECT_EQ(watched.z, plain.z);
  EXPECT_EQ(watched.pivots, plain.pivots);
}

}  // namespace
}  // namespace ecpsim::engine
