#include "engine/solver/pattern_lu.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/LU>

#include "engine/mncp/island_mncp.h"
#include "geometry/convex_shape.h"
#include "tests/engine/island_test_problems.h"

namespace ecpsim::engine {
namespace {

// a residual of A x = b relative to ‖A‖ ‖x‖ + ‖b‖ that backward-stable partial pivoting keeps
// within a small multiple of n ε; 1e-13 is ≈ 20 n ε at n = 25
constexpr double kBackwardErrorTol = 1e-13;
// the solutions' difference from Eigen's LU relative to |x|: the condition number of these random
// matrices (≲ 1e3) times the backward error
constexpr double kForwardErrorTol = 1e-9;

// random values on a fixed pattern: one body's Newton matrix pattern at the desk's size (a
// Jacobian's non-zeros plus the diagonal, from the island MNCP of a box on the ground), or a
// random sparse pattern
Eigen::MatrixXd RandomOnPattern(const Eigen::MatrixXd& pattern, std::mt19937& rng) {
  std::uniform_real_distribution<double> value(-1, 1);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(pattern.rows(), pattern.cols());
  for (Eigen::Index j = 0; j < A.cols(); ++j)
    for (Eigen::Index i = 0; i < A.rows(); ++i)
      if (pattern(i, j) != 0 || i == j) A(i, j) = value(rng);
  return A;
}

Eigen::MatrixXd NewtonMatrixPattern() {
  const auto box = geometry::MakeBox(Eigen::Vector3d(0.2, 0.15, 0.1));
  const auto ground = geometry::MakeHalfSpace(Eigen::Vector3d::UnitZ(), 0);
  std::mt19937 rng(2);
  // a case whose window is the whole box: 20 unknowns, as the desk's (the plane form)
  testing::RandomBodyCase c = testing::MakeRandomBodyCase(*box, {ground.get()}, false, rng);
  while (c.problem.contacts[0].window.size() != 6)
    c = testing::MakeRandomBodyCase(*box, {ground.get()}, false, rng);
  const IslandProblem island = testing::OneBodyIsland(c.problem);
  const IslandLayout layout = MakeIslandLayout(island);
  Eigen::VectorXd F;
  Eigen::MatrixXd J;
  EvaluateIslandMncp(island, layout, c.z, &F, &J);
  return J;
}

double BackwardError(const Eigen::MatrixXd& A, const Eigen::VectorXd& x, const Eigen::VectorXd& b) {
  return (A * x - b).norm() / (A.norm() * x.norm() + b.norm());
}

// each factorization of a new matrix on the pattern (replayed from the first one's schedule
// while its pivots pass the threshold) solves as Eigen's dense LU does, to backward stability
TEST(PatternLuTest, ReplayedFactorizationsSolveLikeEigensDenseLu) {
  const Eigen::MatrixXd pattern = NewtonMatrixPattern();
  ASSERT_GE(pattern.rows(), 20);
  std::mt19937 rng(11);
  PatternLu replaying;
  int replays = 0;
  // Newton matrices of successive iterations differ by little: a base matrix and perturbations
  // of a tenth of it (now and then enough to fail a pivot's threshold)
  const Eigen::MatrixXd base = RandomOnPattern(pattern, rng);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::MatrixXd A = base + 0.1 * RandomOnPattern(pattern, rng);
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1, 2);
    replaying.Compute(A);
    replays += replaying.replayed();
    Eigen::VectorXd x = b;
    replaying.SolveInPlace(x);
    const Eigen::VectorXd x_eigen = A.partialPivLu().solve(b);
    EXPECT_LE(BackwardError(A, x, b), kBackwardErrorTol) << "trial " << trial;
    EXPECT_LE((x - x_eigen).norm(), kForwardErrorTol * x_eigen.norm()) << "trial " << trial;
  }
  EXPECT_GT(replays, 150);
}

// with the pivots the dense elimination chooses (the same matrix again), a replay does its
// operations exactly: bit-identical solutions
TEST(PatternLuTest, ReplayWithTheDensePivotsIsBitIdentical) {
  const Eigen::MatrixXd pattern = NewtonMatrixPattern();
  std::mt19937 rng(4);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::MatrixXd A = RandomOnPattern(pattern, rng);
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -2, 1);
    PatternLu lu;
    lu.Compute(A);
    ASSERT_FALSE(lu.replayed());
    Eigen::VectorXd x_dense = b;
    lu.SolveInPlace(x_dense);
    lu.Compute(A);
    ASSERT_TRUE(lu.replayed());
    Eigen::VectorXd x = b;
    lu.SolveInPlace(x);
    for (Eigen::Index i = 0; i < x.size(); ++i) ASSERT_EQ(x[i], x_dense[i]) << "trial " << trial;
    // and without replay the dense elimination again
    lu.Compute(A, false);
    EXPECT_FALSE(lu.replayed());
  }
}

// a matrix with a near-zero diagonal entry, whose pivot must come from another row: a replay
// recorded on a matrix that pivoted on the diagonal detects the changed choice and falls back
TEST(PatternLuTest, NearSingularPivotFallsBackToDenseElimination) {
  const Eigen::MatrixXd pattern = NewtonMatrixPattern();
  std::mt19937 rng(5);
  Eigen::MatrixXd A = RandomOnPattern(pattern, rng);
  for (Eigen::Index i = 0; i < A.rows(); ++i) A(i, i) += 10;  // diagonal pivots throughout
  PatternLu lu;
  lu.Compute(A);
  lu.Compute(A);
  EXPECT_TRUE(lu.replayed());
  // column 0's diagonal becomes tiny: another row of column 0 must be the pivot
  Eigen::MatrixXd B = A;
  B(0, 0) = 1e-14;
  Eigen::Index other = 1;
  while (B(other, 0) == 0) ++other;
  lu.Compute(B);
  EXPECT_FALSE(lu.replayed());
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(B.rows());
  Eigen::VectorXd x = b;
  lu.SolveInPlace(x);
  EXPECT_LE(BackwardError(B, x, b), kBackwardErrorTol);
  // and the new pivot sequence is replayed from then on
  B(0, 0) = 2e-14;
  lu.Compute(B);
  EXPECT_TRUE(lu.replayed());
  x = b;
  lu.SolveInPlace(x);
  EXPECT_LE(BackwardError(B, x, b), kBackwardErrorTol);
}

// an entry outside the recorded pattern is a new pattern: eliminated densely, then replayed
TEST(PatternLuTest, NewNonZeroOutsideThePatternIsFactoredExactly) {
  std::mt19937 rng(3);
  const Eigen::MatrixXd pattern = NewtonMatrixPattern();
  Eigen::MatrixXd A = RandomOnPattern(pattern, rng);
  PatternLu lu;
  lu.Compute(A);
  Eigen::Index i = 0, j = 1;
  while (A(i, j) != 0) ++i;
  A(i, j) = 0.5;
  lu.Compute(A);
  EXPECT_FALSE(lu.replayed());
  lu.Compute(A);
  EXPECT_TRUE(lu.replayed());
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), 1, 3);
  Eigen::VectorXd x = b;
  lu.SolveInPlace(x);
  EXPECT_LE(BackwardError(A, x, b), kBackwardErrorTol);
}

// with an elimination order the factors are P A Pᵀ's and the solve is A's: the dense elimination,
// the replay (its second factorization), and the blocked one above kMaxUnblockedSize, each in a
// reversed order and in runs (the multi-patch model's: the last unknowns first)
TEST(PatternLuTest, AnEliminationOrderSolvesTheMatrixInItsOwnOrder) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> unit(0, 1);
  for (const Eigen::Index n :
       {Eigen::Index{20}, Eigen::Index{62}, PatternLu::kMaxUnblockedSize + 5}) {
    Eigen::MatrixXd pattern(n, n);
    for (Eigen::Index j = 0; j < n; ++j)
      for (Eigen::Index i = 0; i < n; ++i) pattern(i, j) = unit(rng) < 0.2 ? 1.0 : 0.0;
    const Eigen::MatrixXd A = RandomOnPattern(pattern, rng);
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1, 2);
    const Eigen::VectorXd x_eigen = A.partialPivLu().solve(b);
    std::vector<int> reversed(n), last_first(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      reversed[i] = static_cast<int>(n - 1 - i);
      last_first[i] = static_cast<int>((i + 6) % n);
    }
    for (const auto& order : {reversed, last_first}) {
      for (const bool replay : {false, true}) {
        PatternLu lu;
        lu.Compute(A, replay, order);
        lu.Compute(A, replay, order);
        Eigen::VectorXd x = b;
        lu.SolveInPlace(x);
        EXPECT_LE(BackwardError(A, x, b), kBackwardErrorTol * n / 25) << "n = " << n;
        EXPECT_LE((x - x_eigen).norm(), kForwardErrorTol * x_eigen.norm()) << "n = " << n;
      }
    }
  }
}

// an exactly singular matrix (a zero column) gives a non-finite solution, never a finite wrong one
TEST(PatternLuTest, SingularMatrixGivesNonFiniteSolution) {
  std::mt19937 rng(8);
  Eigen::MatrixXd A = RandomOnPattern(NewtonMatrixPattern(), rng);
  PatternLu lu;
  lu.Compute(A);
  A.col(3).setZero();
  for (int pass = 0; pass < 2; ++pass) {
    lu.Compute(A);
    Eigen::VectorXd x = Eigen::VectorXd::Ones(A.rows());
    lu.SolveInPlace(x);
    EXPECT_FALSE(x.allFinite()) << "pass " << pass;
  }
}

// the AVX2 and the portable dense elimination of large matrices (from 32 unknowns; smaller ones
// always take a portable version) do the same operations in the same roundings: bit-identical
// factors, whatever the processor picks (random sparse matrices, whose long columns run the wide
// loop's body and its tail)
TEST(PatternLuTest, Avx2AndPortableEliminationsAreBitIdentical) {
  if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "no AVX2 on this processor";
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Eigen::MatrixXd> patterns;
  for (const int n : {37, 82, 127}) {
    Eigen::MatrixXd random(n, n);
    for (Eigen::Index j = 0; j < n; ++j)
      for (Eigen::Index i = 0; i < n; ++i) random(i, j) = unit(rng) < 0.1 ? 1.0 : 0.0;
    patterns.push_back(random);
  }
  for (const Eigen::MatrixXd& pattern : patterns) {
    for (int trial = 0; trial < 10; ++trial) {
      const Eigen::MatrixXd A = RandomOnPattern(pattern, rng);
      const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1, 1);
      PatternLu portable(PatternLu::Kernel::kPortable), wide(PatternLu::Kernel::kAvx2);
      portable.Compute(A, false);
      wide.Compute(A, false);
      Eigen::VectorXd x_portable = b, x_wide = b;
      portable.SolveInPlace(x_portable);
      wide.SolveInPlace(x_wide);
      ASSERT_LE(BackwardError(A, x_wide, b), kBackwardErrorTol * A.rows() / 25);
      for (Eigen::Index i = 0; i < b.size(); ++i)
        ASSERT_EQ(x_wide[i], x_portable[i]) << "n = " << A.rows() << ", trial " << trial;
    }
  }
}

}  // namespace
}  // namespace ecpsim::engine
