// The directions of a set of solutions and the least-energy point on it, on small problems whose
// sets and minimizers are known in closed form.

#include "engine/solver/solution_set.h"

#include <cmath>

#include <gtest/gtest.h>

namespace ecpsim::engine {
namespace {

using Eigen::MatrixXd;
using Eigen::Vector2d;
using Eigen::VectorXd;

// the measure the solves and the selection run to (McpOptions::tolerance)
constexpr double kSolveTolerance = 1e-12;
// a selected point against its closed form: the selection stops when its step is below the
// tolerance, and Gauss–Newton converges at least linearly there, so a few tolerances
constexpr double kSelectedError = 1e-11;
// directions against their closed form: orthonormal singular vectors to round-off
constexpr double kDirectionRoundOff = 1e-14;

const VectorXd kOnes2 = VectorXd::Ones(2);

McpOptions Options() {
  McpOptions options;
  options.tolerance = kSolveTolerance;
  return options;
}

// two unknowns that must sum to 1, stated twice: the solutions are a line
void SumIsOne(const VectorXd& z, VectorXd* F, MatrixXd* J) {
  *F = Vector2d(z[0] + z[1] - 1, 2 * (z[0] + z[1] - 1));
  if (J != nullptr) *J << 1, 1, 2, 2;
}

// two unknowns on the unit circle, stated twice
void OnUnitCircle(const VectorXd& z, VectorXd* F, MatrixXd* J) {
  const double c = z.squaredNorm() - 1;
  *F = Vector2d(c, c);
  if (J != nullptr) *J << 2 * z[0], 2 * z[1], 2 * z[0], 2 * z[1];
}

// E = ½ |z − target|²
EnergyResiduals DistanceTo(const Vector2d& target) {
  return [target](const VectorXd& z, VectorXd* r, MatrixXd* R) {
    *r = z - target;
    if (R != nullptr) *R = MatrixXd::Identity(2, 2);
  };
}

TEST(SolutionSetTest, AnIsolatedSolutionHasNoDirectionsAndIsLeftBitForBit) {
  // z0 + z1 = 1, z0 − z1 = 0.5, z1 ≥ 0 ⊥ (second row): one solution (0.75, 0.25)
  const McpFunction f = [](const VectorXd& z, VectorXd* F, MatrixXd* J) {
    *F = Vector2d(z[0] + z[1] - 1, z[0] - z[1] - 0.5);
    if (J != nullptr) *J << 1, 1, 1, -1;
  };
  VectorXd z = Vector2d(0.7, 0.2);
  McpWorkspace workspace;
  ASSERT_TRUE(SolveMcp(f, 1, kOnes2, kOnes2, z, Options(), workspace).converged);
  const VectorXd solved = z;
  const SelectionResult result =
      SelectLeastEnergySolution(f, 1, kOnes2, kOnes2, DistanceTo({0, 0}), z, Options(), workspace);
  EXPECT_TRUE(result.converged);
  EXPECT_EQ(result.directions, 0);
  EXPECT_EQ(result.steps, 0);
  EXPECT_EQ(z[0], solved[0]);
  EXPECT_EQ(z[1], solved[1]);
}

TEST(SolutionSetTest, ALineOfSolutionsHasItsDirection) {
  VectorXd F(2);
  MatrixXd J(2, 2);
  const VectorXd z = Vector2d(0.3, 0.7);
  SumIsOne(z, &F, &J);
  const MatrixXd N = SolutionSetDirections(J, z, F, 2, kOnes2, kOnes2, kSolveTolerance);
  ASSERT_EQ(N.cols(), 1);
  EXPECT_NEAR(std::abs(N.col(0).dot(Vector2d(1, -1) / std::sqrt(2.0))), 1, kDirectionRoundOff);
}

TEST(SolutionSetTest, DirectionsAreThoseOfTheScaledUnknowns) {
  // x = z / (1, 4): the line z0 + z1 = 1 runs along (4, −1) in x
  VectorXd F(2);
  MatrixXd J(2, 2);
  const VectorXd z = Vector2d(0.3, 0.7), var_scale = Vector2d(1, 4);
  SumIsOne(z, &F, &J);
  const MatrixXd N = SolutionSetDirections(J, z, F, 2, kOnes2, var_scale, kSolveTolerance);
  ASSERT_EQ(N.cols(), 1);
  EXPECT_NEAR(std::abs(N.col(0).dot(Vector2d(4, -1) / std::sqrt(17.0))), 1, kDirectionRoundOff);
}

TEST(SolutionSetTest, AnInactivePairHoldsItsUnknownAndADegenerateOneBoth) {
  // rows: z0 + z1 = 1 twice as a free row and a pair (z1 ≥ 0 ⊥ 2(z0 + z1 − 1) + 1 at z1 = 0)
  const MatrixXd J = (MatrixXd(2, 2) << 1, 1, 2, 2).finished();
  // inactive: z1 = 0, F1 = 1 > 0 — z1 held, the line's direction gone
  MatrixXd N =
      SolutionSetDirections(J, Vector2d(1, 0), Vector2d(0, 1), 1, kOnes2, kOnes2, kSolveTolerance);
  EXPECT_EQ(N.cols(), 0);
  // degenerate: z1 = 0, F1 = 0 — both held, nothing left either
  N = SolutionSetDirections(J, Vector2d(1, 0), Vector2d(0, 0), 1, kOnes2, kOnes2, kSolveTolerance);
  EXPECT_EQ(N.cols(), 0);
  // active: z1 > 0, F1 = 0 — only the row, the line stays
  N = SolutionSetDirections(J, Vector2d(0.5, 0.5), Vector2d(0, 0), 1, kOnes2, kOnes2,
                            kSolveTolerance);
  EXPECT_EQ(N.cols(), 1);
}

TEST(SolutionSetTest, ATiedRowCountsInTheRankWhateverItsScale) {
  // z0 + z1 + z2 = 1 and s (z1 − z2) = 0, the second row tied to z0 (a loaded contact's friction
  // row, whose entries go with its load and σ): a line along (2, −1, −1) for a row 1e-14 or 1e15
  // times the first, not a plane (the small row dropped, or the first row taken for 0)
  const VectorXd ones = VectorXd::Ones(3);
  for (const double s : {1e-14, 1e15}) {
    const MatrixXd J = (MatrixXd(3, 3) << 1, 1, 1, 0, s, -s, 0, 0, 0).finished();
    const MatrixXd N = SolutionSetDirections(J, VectorXd::Constant(3, 1.0 / 3), VectorXd::Zero(3),
                                             3, ones, ones, kSolveTolerance, {-1, 0, -1});
    ASSERT_EQ(N.cols(), 1) << s;
    EXPECT_NEAR(std::abs(N.col(0).dot(Eigen::Vector3d(2, -1, -1) / std::sqrt(6.0))), 1,
                kDirectionRoundOff)
        << s;
    // untied, the row is taken against the largest: a plane either way
    EXPECT_EQ(SolutionSetDirections(J, VectorXd::Constant(3, 1.0 / 3), VectorXd::Zero(3), 3, ones,
                                    ones, kSolveTolerance)
                  .cols(),
              2)
        << s;
  }
}

TEST(SolutionSetTest, AnUnknownTiedToOneHeldAtZeroIsHeldWithItAndItsRowLeftOut) {
  // a contact in miniature, (v, p) free and p_n ≥ 0 ⊥ its gap 1: v + p = 1, and the friction row
  // p_n v = 0, which holds for any v and p while p_n = 0. Untied, v and p trade along a line; p
  // tied to p_n (the cone holds p at 0 to second order) is held, and its row left out with it
  const VectorXd z = Eigen::Vector3d(1, 0, 0);
  const VectorXd F = Eigen::Vector3d(0, 0, 1);
  const MatrixXd J = (MatrixXd(3, 3) << 1, 1, 0, 0, 0, 1, 0, 0, 0).finished();
  const VectorXd ones = VectorXd::Ones(3);
  EXPECT_EQ(SolutionSetDirections(J, z, F, 2, ones, ones, kSolveTolerance).cols(), 1);
  EXPECT_EQ(SolutionSetDirections(J, z, F, 2, ones, ones, kSolveTolerance, {-1, 2, -1}).cols(), 0);
  // loaded (p_n > 0, its gap closed, rows that v + p = 1 alone constrains), the tie holds nothing
  const VectorXd loaded = Eigen::Vector3d(1, 0, 0.5);
  const MatrixXd J_loaded = (MatrixXd(3, 3) << 1, 1, 0, 0, 0, 0, 0, 0, 0).finished();
  const MatrixXd untied =
      SolutionSetDirections(J_loaded, loaded, VectorXd::Zero(3), 2, ones, ones, kSolveTolerance);
  const MatrixXd tied = SolutionSetDirections(J_loaded, loaded, VectorXd::Zero(3), 2, ones, ones,
                                              kSolveTolerance, {-1, 2, -1});
  EXPECT_EQ(untied.cols(), 2);
  EXPECT_EQ(tied, untied);
}

TEST(SolutionSetTest, ADegeneratePairIsLetGoWhereItsUnknownMustGrow) {
  // SumIsOne with its second row a pair, z1 ≥ 0 ⊥ 2 (z0 + z1 − 1) (0 on the line): the set is the
  // line's half z1 ≥ 0, and at (1, 0) the pair is degenerate. E = ½ |z − (0, 2)|² is least at (−½,
  // 3/2), which the selection reaches only by letting z1 grow
  VectorXd z = Vector2d(1, 0);
  McpWorkspace workspace;
  const SelectionResult result = SelectLeastEnergySolution(
      SumIsOne, 1, kOnes2, kOnes2, DistanceTo({0, 2}), z, Options(), workspace);
  EXPECT_TRUE(result.converged);
  EXPECT_EQ(result.directions, 0);  // both held at the start
  EXPECT_NEAR(z[0], -0.5, kSelectedError);
  EXPECT_NEAR(z[1], 1.5, kSelectedError);
}

TEST(SolutionSetTest, ADegeneratePairIsLetGoWhereItsRowMustOpen) {
  // z1 = 0 (a free row) with z1 ≥ 0 ⊥ z0 − 1: the set is z0 ≥ 1, z1 = 0, degenerate at (1, 0).
  // E = ½ (z0 − 3)² is least at (3, 0), where the row is open (z0 − 1 = 2)
  const McpFunction f = [](const VectorXd& z, VectorXd* F, MatrixXd* J) {
    *F = Vector2d(z[1], z[0] - 1);
    if (J != nullptr) *J << 0, 1, 1, 0;
  };
  const EnergyResiduals energy = [](const VectorXd& z, VectorXd* r, MatrixXd* R) {
    *r = VectorXd::Constant(1, z[0] - 3);
    if (R != nullptr) *R = (MatrixXd(1, 2) << 1, 0).finished();
  };
  VectorXd z = Vector2d(1, 0);
  McpWorkspace workspace;
  const SelectionResult result =
      SelectLeastEnergySolution(f, 1, kOnes2, kOnes2, energy, z, Options(), workspace);
  EXPECT_TRUE(result.converged);
  EXPECT_EQ(result.directions, 0);
  EXPECT_NEAR(z[0], 3, kSelectedError);
  EXPECT_EQ(z[1], 0);
}

TEST(SolutionSetTest, APairThatOpensOnlyADirectionTheEnergyBarelySeesStaysHeld) {
  // the set of ADegeneratePairIsLetGoWhereItsUnknownMustGrow, with E = ½ (1e-12 z1 − 1)²: letting
  // z1 grow lowers E, but its least point lies 1e12 of z1's scale away, far past any step a
  // contact takes along its set (kMaxReleasedStep): the pair stays held and z where it is
  const EnergyResiduals energy = [](const VectorXd& z, VectorXd* r, MatrixXd* R) {
    *r = VectorXd::Constant(1, 1e-12 * z[1] - 1);
    if (R != nullptr) *R = (MatrixXd(1, 2) << 0, 1e-12).finished();
  };
  VectorXd z = Vector2d(1, 0);
  McpWorkspace workspace;
  const SelectionResult result =
      SelectLeastEnergySolution(SumIsOne, 1, kOnes2, kOnes2, energy, z, Options(), workspace);
  EXPECT_TRUE(result.converged);
  EXPECT_EQ(result.steps, 0);
  EXPECT_EQ(z, Vector2d(1, 0));
}

TEST(SolutionSetTest, TheLeastNormPointOfALineWhateverTheStart) {
  McpWorkspace workspace;
  for (const Vector2d& start : {Vector2d(1, 0), Vector2d(-3, 4), Vector2d(0.5, 0.5)}) {
    VectorXd z = start;
    const SelectionResult result = SelectLeastEnergySolution(
        SumIsOne, 2, kOnes2, kOnes2, DistanceTo({0, 0}), z, Options(), workspace);
    EXPECT_TRUE(result.converged);
    EXPECT_EQ(result.directions, 1);
    EXPECT_NEAR(z[0], 0.5, kSelectedError) << start.transpose();
    EXPECT_NEAR(z[1], 0.5, kSelectedError) << start.transpose();
    EXPECT_NEAR(result.energy, 0.25, kSelectedError);
  }
}

TEST(SolutionSetTest, TheNearestPointOfACurvedSet) {
  // the point of the unit circle nearest (2, 1) is (2, 1)/√5; the steps leave the circle and the
  // minimum-norm Newton steps take them back
  McpWorkspace workspace;
  for (const Vector2d& start : {Vector2d(0, 1), Vector2d(-0.6, 0.8), Vector2d(0.6, -0.8)}) {
    VectorXd z = start;
    const SelectionResult result = SelectLeastEnergySolution(
        OnUnitCircle, 2, kOnes2, kOnes2, DistanceTo({2, 1}), z, Options(), workspace);
    EXPECT_TRUE(result.converged);
    EXPECT_NEAR(z[0], 2 / std::sqrt(5.0), kSelectedError) << start.transpose();
    EXPECT_NEAR(z[1], 1 / std::sqrt(5.0), kSelectedError) << start.transpose();
    EXPECT_LT(result.energy, result.start_energy);
  }
}

TEST(SolutionSetTest, TheLeastEnergyPointStopsAtAnActivePairsBound) {
  // z0 + z1 = 1 with z1 ≥ 0 ⊥ 0 (any z1 ≥ 0): E = ½ ((z0 − 2)² + z1²) is least on the line at
  // z1 = −½, outside the set; on the set at its end z1 = 0, z0 = 1
  const McpFunction f = [](const VectorXd& z, VectorXd* F, MatrixXd* J) {
    *F = Vector2d(z[0] + z[1] - 1, 0);
    if (J != nullptr) *J << 1, 1, 0, 0;
  };
  VectorXd z = Vector2d(0.5, 0.5);
  McpWorkspace workspace;
  const SelectionResult result =
      SelectLeastEnergySolution(f, 1, kOnes2, kOnes2, DistanceTo({2, 0}), z, Options(), workspace);
  EXPECT_TRUE(result.converged);
  EXPECT_EQ(result.directions, 1);
  EXPECT_EQ(z[1], 0);  // the step is cut at the bound, which then holds the pair
  EXPECT_NEAR(z[0], 1, kSelectedError);
}

TEST(SolutionSetTest, AStartThatIsNoSolutionIsLeftAsItIs) {
  VectorXd z = Vector2d(0.2, 0.2);
  McpWorkspace workspace;
  const SelectionResult result = SelectLeastEnergySolution(
      SumIsOne, 2, kOnes2, kOnes2, DistanceTo({0, 0}), z, Options(), workspace);
  EXPECT_FALSE(result.converged);
  EXPECT_EQ(z, Vector2d(0.2, 0.2));
}

}  // namespace
}  // namespace ecpsim::engine
