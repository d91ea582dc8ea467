#include "engine/lemke_solver.h"

#include <random>
#include <vector>

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
    const VectorXd w = M * z + q;
    if (z.minCoeff() >= -1e-12 && w.minCoeff() >= -1e-12) return z;
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
    EXPECT_LE((r.z - expected).cwiseAbs().maxCoeff(), 1e-11) << "trial " << trial;
    EXPECT_LE(r.residual, 1e-12) << "trial " << trial;
  }
}

}  // namespace
}  // namespace ecpsim::engine
