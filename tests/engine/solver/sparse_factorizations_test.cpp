// The sparse Newton matrix's factorizations: KLU's LU, the damped least squares by the augmented
// system and its fallback, and the pattern a factorization keeps its analysis for.

#include "engine/solver/sparse_factorizations.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

namespace ecpsim::engine {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

// relative residual of a solve on a well-conditioned matrix: round-off of a few hundred
// unknowns' elimination, with room
constexpr double kSolveRelError = 1e-12;

// an island-like matrix: `blocks` diagonal blocks of 6 (a body's rows), each coupled to the next
// through `coupling` entries, with a dominant diagonal; `skip` drops every skip-th coupling entry
// (a pattern inside the full one)
SparseMatrix BlockChain(int blocks, double shift, int skip = 0) {
  const int n = 6 * blocks;
  std::vector<Eigen::Triplet<double>> entries;
  int count = 0;
  for (int b = 0; b < blocks; ++b)
    for (int i = 0; i < 6; ++i) {
      const int row = 6 * b + i;
      entries.emplace_back(row, row, 4 + shift + std::sin(row));
      for (int j = 0; j < 6; ++j)
        if (j != i) entries.emplace_back(row, 6 * b + j, 0.3 * std::cos(row + 2.0 * j));
      if (b + 1 < blocks) {
        ++count;
        if (skip > 0 && count % skip == 0) continue;
        entries.emplace_back(row, 6 * (b + 1) + (i + 1) % 6, 0.5 * std::sin(3.0 * row));
        entries.emplace_back(6 * (b + 1) + i, row, -0.4 * std::cos(row));
      }
    }
  SparseMatrix A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  A.makeCompressed();
  return A;
}

Eigen::VectorXd Ramp(int n) {
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) b[i] = 1 + std::sin(0.7 * i);
  return b;
}

// `lu` in a new solve, having factored `first` and then `then` (of the same solve)
void FactorInOneSolve(SparseLu& lu, const SparseMatrix& first, const SparseMatrix& then) {
  lu.BeginSolve();
  ASSERT_TRUE(lu.Factor(first));
  ASSERT_TRUE(lu.Factor(then));
}

// A⁻¹ b by `lu`'s last factors
Eigen::VectorXd Solved(SparseLu& lu, const Eigen::VectorXd& b) {
  Eigen::VectorXd x = b;
  lu.SolveInPlace(x);
  return x;
}

TEST(SparseLuTest, SolvesAnIslandLikeMatrixToRoundOff) {
  const SparseMatrix A = BlockChain(50, 0);
  SparseLu lu;
  lu.BeginSolve();
  ASSERT_TRUE(lu.Factor(A));
  const Eigen::VectorXd b = Ramp(static_cast<int>(A.rows()));
  Eigen::VectorXd x = b;
  lu.SolveInPlace(x);
  EXPECT_LE((A * x - b).norm(), kSolveRelError * b.norm());
}

TEST(SparseLuTest, ASingularMatrixIsReportedNotFactored) {
  SparseMatrix A = BlockChain(4, 0);
  A = A.transpose() * A;
  // a zero column: singular to a zero pivot whatever the order
  A = A * Eigen::VectorXd::Ones(A.cols()).asDiagonal();
  A.prune([](int, int col, double) { return col != 5; });
  A.makeCompressed();
  SparseLu lu;
  lu.BeginSolve();
  EXPECT_FALSE(lu.Factor(A));
}

TEST(SparseLuTest, AMatrixWithinTheAnalysedPatternIsSolvedWithTheAnalysisKept) {
  const SparseMatrix full = BlockChain(30, 0), inside = BlockChain(30, 1, 3);
  SparseLu lu;
  ASSERT_NO_FATAL_FAILURE(FactorInOneSolve(lu, full, inside));
  const Eigen::VectorXd b = Ramp(static_cast<int>(inside.rows()));
  EXPECT_LE((inside * Solved(lu, b) - b).norm(), kSolveRelError * b.norm());
}

TEST(SparseLuTest, ALaterMatrixOfTheSolveIsSolvedToRoundOffWithTheReusedPivots) {
  // the same pattern with other values, as a Newton iteration's next matrix
  const SparseMatrix first = BlockChain(50, 0), next = BlockChain(50, 0.7);
  SparseLu lu;
  ASSERT_NO_FATAL_FAILURE(FactorInOneSolve(lu, first, next));
  const Eigen::VectorXd b = Ramp(static_cast<int>(next.rows()));
  EXPECT_LE((next * Solved(lu, b) - b).norm(), kSolveRelError * b.norm());
}

TEST(SparseLuTest, PivotsThatNoLongerFitTheMatrixAreChosenAgain) {
  // the first matrix pivots column 0 on row 1; on the next, that entry is 1e-20 of its row's,
  // and eliminating with it would lose the solution (x = (0, 1) for (1, 1))
  const auto two_by_two = [](double a00, double a10) {
    SparseMatrix A(2, 2);
    const std::vector<Eigen::Triplet<double>> entries = {
        {0, 0, a00}, {1, 0, a10}, {0, 1, 1}, {1, 1, 1}};
    A.setFromTriplets(entries.begin(), entries.end());
    A.makeCompressed();
    return A;
  };
  const SparseMatrix first = two_by_two(1e-3, 1), next = two_by_two(1, 1e-20);
  SparseLu lu;
  ASSERT_NO_FATAL_FAILURE(FactorInOneSolve(lu, first, next));
  const Eigen::VectorXd b = Eigen::Vector2d(2, 1 + 1e-20);
  const Eigen::VectorXd x = Solved(lu, b);
  EXPECT_LE((next * x - b).norm(), kSolveRelError * b.norm());
  EXPECT_NEAR(x[0], 1, kSolveRelError);
}

TEST(SparseLuTest, ASolvesFactorsDoNotDependOnTheSolveBefore) {
  // `inside`'s factors after a solve that analysed the fuller pattern are those of a fresh LU:
  // a new solve keeps the last analysis only for exactly its pattern
  const SparseMatrix full = BlockChain(30, 0), inside = BlockChain(30, 1, 3);
  const Eigen::VectorXd b = Ramp(static_cast<int>(inside.rows()));
  SparseLu fresh, used;
  fresh.BeginSolve();
  ASSERT_TRUE(fresh.Factor(inside));
  Eigen::VectorXd x_fresh = b;
  fresh.SolveInPlace(x_fresh);
  used.BeginSolve();
  ASSERT_TRUE(used.Factor(full));
  used.BeginSolve();
  ASSERT_TRUE(used.Factor(inside));
  Eigen::VectorXd x_used = b;
  used.SolveInPlace(x_used);
  EXPECT_EQ(x_fresh, x_used);
}

TEST(PatternCoverTest, KeepsItsAnalysisForMatricesWithinItAndAnalysesTheUnionOtherwise) {
  // every third coupling dropped lies within every sixth dropped, and both within the full
  const SparseMatrix full = BlockChain(10, 0), third = BlockChain(10, 1, 3),
                     sixth = BlockChain(10, 2, 6);
  PatternCover cover;
  cover.BeginSolve();
  bool analyse = false;
  cover.Cover(third, &analyse);
  EXPECT_TRUE(analyse);
  cover.Cover(sixth, &analyse);
  EXPECT_TRUE(analyse) << "a coupling outside the pattern";
  // within a solve: a matrix inside the analysed pattern is laid on it, zeros where it has none
  const SparseMatrix& laid = cover.Cover(third, &analyse);
  EXPECT_FALSE(analyse);
  EXPECT_EQ(laid.nonZeros(), sixth.nonZeros());
  EXPECT_EQ(Eigen::MatrixXd(laid), Eigen::MatrixXd(third));
  cover.Cover(full, &analyse);
  EXPECT_TRUE(analyse);
  EXPECT_EQ(Eigen::MatrixXd(cover.Cover(sixth, &analyse)), Eigen::MatrixXd(sixth));
  EXPECT_FALSE(analyse);
  // a new solve keeps the analysis only for exactly its pattern
  cover.BeginSolve();
  cover.Cover(third, &analyse);
  EXPECT_TRUE(analyse);
  cover.BeginSolve();
  cover.Cover(third, &analyse);
  EXPECT_FALSE(analyse);
}

// the diagonal of n and a dense k × k block at `first` (row and column)
SparseMatrix DiagonalAndBlock(int n, int k, int first) {
  Eigen::MatrixXd dense = Eigen::MatrixXd::Identity(n, n);
  dense.block(first, first, k, k).setConstant(1.0);
  dense.diagonal().setConstant(k + 1.0);
  SparseMatrix A = dense.sparseView();
  A.makeCompressed();
  return A;
}

TEST(PatternCoverTest, AUnionMuchLargerThanTheMatrixIsNotKept) {
  // two dense blocks at opposite corners: their union holds 800 non-zeros, either alone 420
  const SparseMatrix upper = DiagonalAndBlock(40, 20, 0), lower = DiagonalAndBlock(40, 20, 20);
  PatternCover cover;
  cover.BeginSolve();
  bool analyse = false;
  cover.Cover(upper, &analyse);
  const SparseMatrix& alone = cover.Cover(lower, &analyse);
  EXPECT_TRUE(analyse);
  EXPECT_EQ(alone.nonZeros(), lower.nonZeros());
  // a matrix of another size is analysed alone too
  const SparseMatrix larger = DiagonalAndBlock(41, 20, 0);
  EXPECT_EQ(cover.Cover(larger, &analyse).nonZeros(), larger.nonZeros());
  EXPECT_TRUE(analyse);
}

// (HᵀH + μI) d + g relative to g, of a direction from DampedLeastSquares
double NormalResidual(const SparseMatrix& H, double mu, const Eigen::VectorXd& g,
                      const Eigen::VectorXd& d) {
  const Eigen::VectorXd r = H.transpose() * (H * d) + mu * d + g;
  return r.norm() / g.norm();
}

TEST(DampedLeastSquaresTest, SolvesTheNormalEquationsWithoutFormingThem) {
  const SparseMatrix H = BlockChain(40, 0);
  const Eigen::VectorXd g = H.transpose() * Ramp(static_cast<int>(H.rows()));
  DampedLeastSquares damped;
  damped.BeginSolve();
  for (double mu : {1.0, 1e-4, 1e-8}) {
    Eigen::VectorXd d;
    damped.Solve(H, mu, g, d);
    ASSERT_TRUE(d.allFinite()) << mu;
    EXPECT_LE(NormalResidual(H, mu, g, d), DampedLeastSquares::kAugmentedRelTolerance) << mu;
    const Eigen::MatrixXd dense = Eigen::MatrixXd(H);
    const Eigen::VectorXd reference =
        (dense.transpose() * dense + mu * Eigen::MatrixXd::Identity(H.cols(), H.cols()))
            .ldlt()
            .solve(-g);
    EXPECT_LE((d - reference).norm(), 1e-10 * reference.norm()) << mu;
  }
}

TEST(DampedLeastSquaresTest, ASingularMatrixIsSolvedDampedAndGivesADescentDirectionUndamped) {
  // two equal columns: H is singular. Damped, the augmented system solves it; with μ = 1e-20
  // its pivots are round-off and the normal matrix is factored instead, which gives the
  // direction the line search needs: downhill, and the linear model's residual smaller
  SparseMatrix H = BlockChain(20, 0);
  Eigen::MatrixXd dense(H);
  dense.col(7) = dense.col(3);
  H = dense.sparseView();
  H.makeCompressed();
  const Eigen::VectorXd phi = Ramp(static_cast<int>(H.rows()));
  const Eigen::VectorXd g = H.transpose() * phi;
  DampedLeastSquares damped;
  damped.BeginSolve();
  Eigen::VectorXd d;
  damped.Solve(H, 1e-6, g, d);
  EXPECT_LE(NormalResidual(H, 1e-6, g, d), DampedLeastSquares::kAugmentedRelTolerance);
  damped.Solve(H, 1e-20, g, d);
  ASSERT_TRUE(d.allFinite());
  EXPECT_LT(g.dot(d), 0);
  EXPECT_LT((H * d + phi).norm(), phi.norm());
}

}  // namespace
}  // namespace ecpsim::engine
