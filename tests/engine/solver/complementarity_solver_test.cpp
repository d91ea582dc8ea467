#include "engine/solver/complementarity_solver.h"

#include <cmath>
#include <numeric>
#include <stdexcept>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace ecpsim::engine {
namespace {

// the measure the solves here run to (McpOptions::tolerance)
constexpr double kSolveTolerance = 1e-12;
// ‖z − z*‖∞ of a planted problem solved to kSolveTolerance: bounded by kSolveTolerance / 3 (see
// PlantedMcp), with room for round-off
constexpr double kPlantedError = 1e-12;

// a mixed linear complementarity problem F(z) = M z + q with a planted solution z*: the first
// `num_free` rows are equations, of the rest every third is strictly complementary with z* = 0,
// F* = 1 and the others have z* = 1 + i/n, F* = 0. M = 4 I + B with |B_ij| ≤ 1/n (a
// deterministic pseudo-random pattern with about 80 % structural zeros, as in the MNCP's Newton
// matrix): diagonally dominant, so z* is the unique solution and, once the active set is found,
// ‖z − z*‖∞ ≤ ‖M⁻¹‖∞ · residual ≤ residual / (4 − 1)
struct PlantedMcp {
  Eigen::MatrixXd M;
  Eigen::VectorXd q, z_star;
};

PlantedMcp MakePlantedMcp(int n, int num_free) {
  PlantedMcp p;
  p.M = 4 * Eigen::MatrixXd::Identity(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (i != j && (7 * i + 13 * j) % 5 == 0) p.M(i, j) = std::sin(1.0 + i + 2.0 * j) / n;
  p.z_star.resize(n);
  Eigen::VectorXd F_star(n);
  for (int i = 0; i < n; ++i) {
    const bool inactive = i >= num_free && i % 3 == 0;
    p.z_star[i] = inactive ? 0 : 1 + static_cast<double>(i) / n;
    F_star[i] = inactive ? 1 : 0;
  }
  p.q = F_star - p.M * p.z_star;
  return p;
}

void ExpectSolvesPlanted(int n, int num_free, bool sparse = false, bool replay = false,
                         const std::vector<int>& elimination_order = {}) {
  const PlantedMcp p = MakePlantedMcp(n, num_free);
  McpOptions options;
  options.tolerance = kSolveTolerance;
  options.replay_pivots = replay;
  options.elimination_order = elimination_order;
  Eigen::VectorXd z = Eigen::VectorXd::Constant(n, 0.5);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(n);
  McpResult result;
  if (sparse) {
    const SparseMatrix M = p.M.sparseView();
    const SparseMcpFunction f = [&](const Eigen::VectorXd& x, Eigen::VectorXd* F, SparseMatrix* J) {
      *F = M * x + p.q;
      if (J != nullptr) *J = M;
    };
    result = SolveMcp(f, num_free, ones, ones, z, options);
  } else {
    const McpFunction f = [&p](const Eigen::VectorXd& x, Eigen::VectorXd* F, Eigen::MatrixXd* J) {
      *F = p.M * x + p.q;
      if (J != nullptr) *J = p.M;
    };
    result = SolveMcp(f, num_free, ones, ones, z, options);
  }
  EXPECT_TRUE(result.converged) << "n = " << n;
  EXPECT_LE(result.residual, kSolveTolerance);
  // semismooth Newton from a nearby start: the active set is found in a few iterations
  EXPECT_LE(result.iterations, 10);
  EXPECT_LT((z - p.z_star).cwiseAbs().maxCoeff(), kPlantedError) << "n = " << n;
}

TEST(ComplementaritySolverTest, SolvesPlantedMixedLcpOfOneContactsSize) {
  // the size of one contact's MNCP (the unblocked LU)
  ExpectSolvesPlanted(25, 16);
}

TEST(ComplementaritySolverTest, SolvesPlantedMixedLcpAboveTheUnblockedSize) {
  // large enough for the blocked LU, then also for a workspace of the solve's own
  ExpectSolvesPlanted(150, 40);
  ExpectSolvesPlanted(300, 60);
  // and the shared workspace again afterwards
  ExpectSolvesPlanted(25, 16);
}

TEST(ComplementaritySolverTest, SolvesPlantedMixedLcpWithReplayedPivots) {
  // the Newton matrix factored by the pattern's replayed elimination (pattern_lu.h): the same
  // bounds, at one contact's size and the multi-patch desk's, twice each (the second replays)
  for (int pass = 0; pass < 2; ++pass) {
    ExpectSolvesPlanted(25, 16, /*sparse=*/false, /*replay=*/true);
    ExpectSolvesPlanted(82, 40, /*sparse=*/false, /*replay=*/true);
  }
}

TEST(ComplementaritySolverTest, SolvesPlantedMixedLcpInAnotherEliminationOrder) {
  // the dense LU on the Newton matrix permuted symmetrically (the multi-patch model's order:
  // complementarity unknowns, then free ones, the first six last), and in a reversed order: the
  // same bounds
  for (const auto& [n, num_free] : {std::pair{25, 16}, std::pair{62, 30}}) {
    std::vector<int> parts_first(n), reversed(n);
    std::iota(parts_first.begin(), parts_first.begin() + (n - num_free), num_free);
    std::iota(parts_first.begin() + (n - num_free), parts_first.end() - 6, 6);
    std::iota(parts_first.end() - 6, parts_first.end(), 0);
    std::iota(reversed.rbegin(), reversed.rend(), 0);
    ExpectSolvesPlanted(n, num_free, /*sparse=*/false, /*replay=*/false, parts_first);
    ExpectSolvesPlanted(n, num_free, /*sparse=*/false, /*replay=*/false, reversed);
  }
}

TEST(ComplementaritySolverTest, SolvesPlantedMixedLcpWithASparseJacobian) {
  // the sparse LU's path: the same bounds, small and large, and its pattern analysed again when
  // the next solve's size differs
  ExpectSolvesPlanted(25, 16, /*sparse=*/true);
  ExpectSolvesPlanted(300, 60, /*sparse=*/true);
  ExpectSolvesPlanted(150, 40, /*sparse=*/true);
}

// F(z) = ((z₀ − 1)², z₁ − 2): Newton's matrix is singular at the solution (1, 2) and
// near-singular next to it, where the line search and the Levenberg–Marquardt rescue act
TEST(ComplementaritySolverTest, SparseAndDenseFallbacksReachTheSameDoubleRoot) {
  // the residual's bar: (z₀ − 1)² below it bounds |z₀ − 1| by 1e-5
  constexpr double kDoubleRootTolerance = 1e-10;
  McpOptions options;
  options.tolerance = kDoubleRootTolerance;
  options.max_iterations = 100;
  options.levenberg_marquardt_rescue = true;
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(2);
  const auto residual = [](const Eigen::VectorXd& z, Eigen::VectorXd* F) {
    F->resize(2);
    (*F)[0] = (z[0] - 1) * (z[0] - 1);
    (*F)[1] = z[1] - 2;
  };
  const McpFunction dense = [&](const Eigen::VectorXd& z, Eigen::VectorXd* F, Eigen::MatrixXd* J) {
    residual(z, F);
    if (J) *J = Eigen::Vector2d(2 * (z[0] - 1), 1).asDiagonal();
  };
  const SparseMcpFunction sparse = [&](const Eigen::VectorXd& z, Eigen::VectorXd* F,
                                       SparseMatrix* J) {
    residual(z, F);
    if (!J) return;
    J->resize(2, 2);
    J->setIdentity();
    J->coeffRef(0, 0) = 2 * (z[0] - 1);
  };
  // Newton halves z₀ − 1 per step (a double root): the same path on both matrices
  Eigen::VectorXd z_dense = Eigen::Vector2d(3, 0), z_sparse = z_dense;
  const McpResult a = SolveMcp(dense, 2, ones, ones, z_dense, options);
  const McpResult b = SolveMcp(sparse, 2, ones, ones, z_sparse, options);
  EXPECT_TRUE(a.converged);
  EXPECT_TRUE(b.converged);
  EXPECT_EQ(a.iterations, b.iterations);
  // the double root: residual (z₀ − 1)² ≤ kDoubleRootTolerance bounds |z₀ − 1| by its root
  constexpr double kDoubleRootError = 1e-5;
  EXPECT_NEAR(z_sparse[0], 1, kDoubleRootError);
  // the linear row is solved exactly by the first full step, up to round-off of O(1) entries
  constexpr double kLinearRowRoundOff = 1e-12;
  EXPECT_NEAR(z_sparse[1], 2, kLinearRowRoundOff);
}

// F(z) = A z − b with A symmetric of rank 2 and b in its range: the solutions form the line
// (t, 2 − t, 3), and the Newton matrix is singular everywhere. From (5, −1, 0) the nearest
// solution is (4, −2, 3)
struct SolutionLine {
  SolutionLine() {
    A << 1, 1, 0, 1, 1, 0, 0, 0, 1;
    dense = [this](const Eigen::VectorXd& z, Eigen::VectorXd* F, Eigen::MatrixXd* J) {
      *F = A * z - b;
      if (J) *J = A;
    };
    sparse = [this](const Eigen::VectorXd& z, Eigen::VectorXd* F, SparseMatrix* J) {
      *F = A * z - b;
      if (J) *J = A.sparseView();
    };
  }
  SolutionLine(const SolutionLine&) = delete;
  SolutionLine& operator=(const SolutionLine&) = delete;
  Eigen::Matrix3d A;
  Eigen::Vector3d b{2, 2, 3};
  Eigen::Vector3d start{5, -1, 0};
  Eigen::Vector3d nearest{4, -2, 3};
  Eigen::VectorXd ones = Eigen::VectorXd::Ones(3);
  McpFunction dense;
  SparseMcpFunction sparse;
};

// On SolutionLine the minimum-norm Newton step from the start lands on the nearest solution in
// one iteration, moving nothing along the line (McpOptions::minimum_norm_steps), dense and sparse
// alike
TEST(ComplementaritySolverTest, MinimumNormStepsStayNearTheStartOnANonIsolatedSolutionSet) {
  const SolutionLine line;
  McpOptions options;
  options.tolerance = kSolveTolerance;
  options.minimum_norm_steps = true;
  Eigen::VectorXd z_dense = line.start, z_sparse = z_dense;
  const McpResult a = SolveMcp(line.dense, 3, line.ones, line.ones, z_dense, options);
  const McpResult c = SolveMcp(line.sparse, 3, line.ones, line.ones, z_sparse, options);
  for (const McpResult& result : {a, c}) {
    EXPECT_TRUE(result.converged);
    EXPECT_EQ(result.iterations, 1);
  }
  // one orthogonal decomposition's round-off on O(1) entries
  constexpr double kRoundOff = 1e-14;
  EXPECT_LT((z_dense - line.nearest).cwiseAbs().maxCoeff(), kRoundOff);
  EXPECT_LT((z_sparse - line.nearest).cwiseAbs().maxCoeff(), kRoundOff);
}

// SolutionLine with proximal terms instead (McpOptions::proximal_weight): each
// step solves (A + εI) d = −F, nonsingular, with no component along the line because A is
// symmetric, so the iteration lands on the same nearest solution; it converges at the rate
// ε / (2 + ε) in the range, which a few iterations take to the tolerance, dense and sparse alike
TEST(ComplementaritySolverTest, ProximalStepsStayNearTheStartOnANonIsolatedSolutionSet) {
  const SolutionLine line;
  McpOptions options;
  options.tolerance = kSolveTolerance;
  options.proximal_weight = 1e-6;
  Eigen::VectorXd z_dense = line.start, z_sparse = z_dense;
  const McpResult a = SolveMcp(line.dense, 3, line.ones, line.ones, z_dense, options);
  const McpResult c = SolveMcp(line.sparse, 3, line.ones, line.ones, z_sparse, options);
  // iterations: residual 3 → 3e-6 → 3e-12 → below the tolerance
  constexpr int kMaxProximalIterations = 3;
  for (const McpResult& result : {a, c}) {
    EXPECT_TRUE(result.converged);
    EXPECT_LE(result.iterations, kMaxProximalIterations);
  }
  // nothing moves along the line but round-off: (A + εI)'s smallest eigenvalue is ε, so each
  // step's LU round-off (1e-16 of the O(1) residual) is amplified 1/ε along it, ≈ 3e-10 a step
  constexpr double kNear = 1e-9;
  EXPECT_LT((z_dense - line.nearest).cwiseAbs().maxCoeff(), kNear);
  EXPECT_LT((z_sparse - line.nearest).cwiseAbs().maxCoeff(), kNear);

  // without either remedy the LU's matrix is singular: its step is refused and the solve falls
  // back on Levenberg–Marquardt steps, which stop short of the tolerance in as many iterations
  options.proximal_weight = 0;
  Eigen::VectorXd z_plain = line.start;
  options.max_iterations = kMaxProximalIterations;
  EXPECT_FALSE(SolveMcp(line.dense, 3, line.ones, line.ones, z_plain, options).converged);
}

// Where the root is isolated the proximal terms change the path only: a planted MCP with
// complementarity rows (active and inactive) solves to the same root, dense and sparse
TEST(ComplementaritySolverTest, ProximalStepsFindAnIsolatedRootExactly) {
  const PlantedMcp p = MakePlantedMcp(30, 12);
  McpOptions options;
  options.tolerance = kSolveTolerance;
  options.proximal_weight = 1e-6;
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(30);
  const McpFunction dense = [&](const Eigen::VectorXd& z, Eigen::VectorXd* F, Eigen::MatrixXd* J) {
    *F = p.M * z + p.q;
    if (J) *J = p.M;
  };
  const SparseMcpFunction sparse = [&](const Eigen::VectorXd& z, Eigen::VectorXd* F,
                                       SparseMatrix* J) {
    *F = p.M * z + p.q;
    if (J) *J = p.M.sparseView();
  };
  Eigen::VectorXd z_dense = Eigen::VectorXd::Ones(30), z_sparse = z_dense;
  EXPECT_TRUE(SolveMcp(dense, 12, ones, ones, z_dense, options).converged);
  EXPECT_TRUE(SolveMcp(sparse, 12, ones, ones, z_sparse, options).converged);
  // the tolerance 1e-12 on rows of M's size 4: the root to a few times that
  constexpr double kRootError = 1e-11;
  EXPECT_LT((z_dense - p.z_star).cwiseAbs().maxCoeff(), kRootError);
  EXPECT_LT((z_sparse - p.z_star).cwiseAbs().maxCoeff(), kRootError);
}

TEST(ComplementaritySolverTest, NestedSolveInTheCallbackKeepsTheOuterWorkspace) {
  // the outer callback solves an inner problem on every evaluation in the same workspace, which
  // the outer solve holds: the inner one works in storage of its own and both converge
  McpWorkspace workspace;
  const PlantedMcp outer = MakePlantedMcp(25, 16);
  const PlantedMcp inner = MakePlantedMcp(12, 3);
  const Eigen::VectorXd ones_inner = Eigen::VectorXd::Ones(12);
  int inner_failures = 0;
  const McpFunction f_inner = [&inner](const Eigen::VectorXd& z, Eigen::VectorXd* F,
                                       Eigen::MatrixXd* J) {
    *F = inner.M * z + inner.q;
    if (J != nullptr) *J = inner.M;
  };
  const McpFunction f = [&](const Eigen::VectorXd& z, Eigen::VectorXd* F, Eigen::MatrixXd* J) {
    Eigen::VectorXd z_inner = Eigen::VectorXd::Constant(12, 0.5);
    McpOptions options;
    options.tolerance = kSolveTolerance;
    const McpResult r = SolveMcp(f_inner, 3, ones_inner, ones_inner, z_inner, options, workspace);
    if (!r.converged || (z_inner - inner.z_star).cwiseAbs().maxCoeff() > kPlantedError)
      ++inner_failures;
    *F = outer.M * z + outer.q;
    if (J != nullptr) *J = outer.M;
  };
  McpOptions options;
  options.tolerance = kSolveTolerance;
  Eigen::VectorXd z = Eigen::VectorXd::Constant(25, 0.5);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(25);
  const McpResult result = SolveMcp(f, 16, ones, ones, z, options, workspace);
  EXPECT_TRUE(result.converged);
  EXPECT_EQ(inner_failures, 0);
  EXPECT_LT((z - outer.z_star).cwiseAbs().maxCoeff(), kPlantedError);
}

TEST(ComplementaritySolverTest, AKeptWorkspaceGivesTheBitsOfAFreshOne) {
  // storage left by solves of other sizes and kinds changes nothing: a workspace is memory,
  // never state
  McpWorkspace kept;
  for (const auto& [n, num_free] : {std::pair{25, 16}, std::pair{7, 2}, std::pair{40, 10}}) {
    for (bool sparse : {false, true}) {
      const PlantedMcp p = MakePlantedMcp(n, num_free);
      const Eigen::VectorXd ones = Eigen::VectorXd::Ones(n);
      McpOptions options;
      options.tolerance = kSolveTolerance;
      options.levenberg_marquardt_rescue = true;
      Eigen::VectorXd z_kept = Eigen::VectorXd::Constant(n, 0.5);
      Eigen::VectorXd z_fresh = z_kept;
      McpResult kept_result, fresh_result;
      if (sparse) {
        const SparseMatrix M = p.M.sparseView();
        const SparseMcpFunction f = [&](const Eigen::VectorXd& z, Eigen::VectorXd* F,
                                        SparseMatrix* J) {
          *F = p.M * z + p.q;
          if (J != nullptr) *J = M;
        };
        kept_result = SolveMcp(f, num_free, ones, ones, z_kept, options, kept);
        fresh_result = SolveMcp(f, num_free, ones, ones, z_fresh, options);
      } else {
        const McpFunction f = [&](const Eigen::VectorXd& z, Eigen::VectorXd* F,
                                  Eigen::MatrixXd* J) {
          *F = p.M * z + p.q;
          if (J != nullptr) *J = p.M;
        };
        kept_result = SolveMcp(f, num_free, ones, ones, z_kept, options, kept);
        fresh_result = SolveMcp(f, num_free, ones, ones, z_fresh, options);
      }
      EXPECT_TRUE(kept_result.converged) << "n = " << n << (sparse ? " sparse" : " dense");
      EXPECT_EQ(kept_result.iterations, fresh_result.iterations);
      EXPECT_EQ(z_kept, z_fresh) << "n = " << n << (sparse ? " sparse" : " dense");
    }
  }
}

TEST(ComplementaritySolverTest, HandsTheCallbackAZeroJacobianOfTheProblemsSize) {
  // the callback may add its entries into J (complementarity_solver.h): J arrives n × n and zero
  // at every evaluation, also when the shared workspace served another size in between, when an
  // evaluation left without its Jacobian (a converged trial point) and after a callback that
  // threw half-way through writing J
  {
    const PlantedMcp p = MakePlantedMcp(25, 16);
    const McpFunction throwing = [&](const Eigen::VectorXd& z, Eigen::VectorXd* F,
                                     Eigen::MatrixXd* J) {
      *F = p.M * z + p.q;
      if (J != nullptr) {
        *J += p.M;
        throw std::runtime_error("callback failed");
      }
    };
    Eigen::VectorXd z = Eigen::VectorXd::Constant(25, 0.5);
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(25);
    EXPECT_THROW(SolveMcp(throwing, 16, ones, ones, z), std::runtime_error);
  }
  int unclean = 0, evaluations = 0;
  for (const auto& [n, num_free] : {std::pair{25, 16}, {82, 40}, {25, 16}, {7, 2}}) {
    const PlantedMcp p = MakePlantedMcp(n, num_free);
    const McpFunction f = [&](const Eigen::VectorXd& z, Eigen::VectorXd* F, Eigen::MatrixXd* J) {
      *F = p.M * z + p.q;
      if (J == nullptr) return;
      ++evaluations;
      if (J->rows() != n || J->cols() != n || !(J->array() == 0).all()) ++unclean;
      *J += p.M;
    };
    McpOptions options;
    options.tolerance = kSolveTolerance;
    Eigen::VectorXd z = Eigen::VectorXd::Constant(n, 0.5);
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(n);
    const McpResult result = SolveMcp(f, num_free, ones, ones, z, options);
    EXPECT_TRUE(result.converged) << "n = " << n;
    EXPECT_LT((z - p.z_star).cwiseAbs().maxCoeff(), kPlantedError) << "n = " << n;
  }
  EXPECT_GT(evaluations, 8);
  EXPECT_EQ(unclean, 0);
}

}  // namespace
}  // namespace ecpsim::engine

namespace ecpsim::engine {
namespace {

// McpOptions::verify_start_first: a start that solves the problem is accepted on F alone (no
// Jacobian asked for); any other start is solved to the same doubles as without the option
TEST(ComplementaritySolverTest, AStartThatSolvesTheProblemIsVerifiedWithoutAJacobian) {
  const int n = 25, num_free = 10;
  const PlantedMcp p = MakePlantedMcp(n, num_free);
  int jacobians = 0;
  const McpFunction f = [&](const Eigen::VectorXd& z, Eigen::VectorXd* F, Eigen::MatrixXd* J) {
    *F = p.M * z + p.q;
    if (J != nullptr) {
      *J = p.M;
      ++jacobians;
    }
  };
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(n);
  McpOptions options;
  options.tolerance = kSolveTolerance;
  options.verify_start_first = true;
  Eigen::VectorXd z = p.z_star;
  McpResult result = SolveMcp(f, num_free, ones, ones, z, options);
  EXPECT_TRUE(result.converged);
  EXPECT_EQ(result.iterations, 0);
  EXPECT_EQ(jacobians, 0);
  EXPECT_EQ(z, p.z_star);

  // from a start that is no solution: the same iterates as the plain solve
  Eigen::VectorXd verified = Eigen::VectorXd::Constant(n, 0.5), plain = verified;
  result = SolveMcp(f, num_free, ones, ones, verified, options);
  options.verify_start_first = false;
  const McpResult plain_result = SolveMcp(f, num_free, ones, ones, plain, options);
  EXPECT_TRUE(result.converged);
  EXPECT_GT(jacobians, 0);
  EXPECT_EQ(result.iterations, plain_result.iterations);
  EXPECT_EQ(verified, plain);
}

}  // namespace
}  // namespace ecpsim::engine

namespace ecpsim::engine {
namespace {

TEST(ComplementaritySolverTest, AStopRequestedDuringASolveEndsItAtTheNextIteration) {
  // the planted problem from far away, the flag raised by the second evaluation (in use: another
  // thread or a signal handler): Cancelled before the solve's end, dense and sparse alike
  const PlantedMcp p = MakePlantedMcp(40, 10);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(40);
  const SparseMatrix M = p.M.sparseView();
  McpOptions options;
  options.tolerance = kSolveTolerance;
  for (bool sparse : {false, true}) {
    CancelFlag flag;
    int evaluations = 0, raise_at = -1;
    const auto evaluate = [&](const Eigen::VectorXd& x, Eigen::VectorXd* F) {
      if (++evaluations == raise_at) flag.Raise();
      *F = p.M * x + p.q;
    };
    const McpFunction dense_f = [&](const Eigen::VectorXd& x, Eigen::VectorXd* F,
                                    Eigen::MatrixXd* J) {
      evaluate(x, F);
      if (J != nullptr) *J = p.M;
    };
    const SparseMcpFunction sparse_f = [&](const Eigen::VectorXd& x, Eigen::VectorXd* F,
                                           SparseMatrix* J) {
      evaluate(x, F);
      if (J != nullptr) *J = M;
    };
    McpWorkspace workspace;
    workspace.StopOn(&flag);
    const auto solve = [&] {
      Eigen::VectorXd z = Eigen::VectorXd::Constant(40, 100.0);
      const McpResult result = sparse ? SolveMcp(sparse_f, 10, ones, ones, z, options, workspace)
                                      : SolveMcp(dense_f, 10, ones, ones, z, options, workspace);
      EXPECT_TRUE(result.converged);
      EXPECT_LT((z - p.z_star).cwiseAbs().maxCoeff(), kPlantedError);
    };
    // never raised: the solve as ever, over several iterations
    solve();
    const int whole_solve = evaluations;
    ASSERT_GE(whole_solve, 4) << (sparse ? "sparse" : "dense");
    evaluations = 0;
    raise_at = 2;
    EXPECT_THROW(solve(), Cancelled) << (sparse ? "sparse" : "dense");
    EXPECT_LT(evaluations, whole_solve) << (sparse ? "sparse" : "dense");
    // cleared, the workspace solves on
    flag.Clear();
    raise_at = -1;
    solve();
  }
}

TEST(ComplementaritySolverTest, NoStopRequestedLeavesTheSolveAlone) {
  // a workspace with a flag never raised solves as one without: the same iterates to the bit
  const PlantedMcp p = MakePlantedMcp(30, 12);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(30);
  const McpFunction f = [&p](const Eigen::VectorXd& x, Eigen::VectorXd* F, Eigen::MatrixXd* J) {
    *F = p.M * x + p.q;
    if (J != nullptr) *J = p.M;
  };
  McpOptions options;
  options.tolerance = kSolveTolerance;
  CancelFlag flag;
  McpWorkspace watched, plain;
  watched.StopOn(&flag);
  Eigen::VectorXd a = Eigen::VectorXd::Constant(30, 7.0), b = a;
  const McpResult ra = SolveMcp(f, 12, ones, ones, a, options, watched);
  const McpResult rb = SolveMcp(f, 12, ones, ones, b, options, plain);
  EXPECT_EQ(a, b);
  EXPECT_EQ(ra.iterations, rb.iterations);
  EXPECT_EQ(ra.residual, rb.residual);
}

}  // namespace
}  // namespace ecpsim::engine
