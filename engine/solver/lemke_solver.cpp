#include "engine/solver/lemke_solver.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/errors.h"

namespace ecpsim::engine {
namespace {

// ratios within this fraction of the minimum (or of 1, whichever is larger) tie: the tableau
// carries round-off of ≈ 1e-16 × its entries after each pivot, so exact ties of a degenerate
// problem show up as ratios that differ by a few ulps
constexpr double kTieRelTol = 1e-12;
// the default pivot limit per unknown (see LemkeOptions::max_pivots)
constexpr int kDefaultPivotsPerUnknown = 50;

double Residual(const Eigen::VectorXd& z, const Eigen::VectorXd& w) {
  double r = 0;
  for (int i = 0; i < z.size(); ++i)
    r = std::max({r, -z[i], -w[i], std::abs(std::min(z[i], w[i]))});
  return r;
}

}  // namespace

const char* LcpStatusName(LcpStatus status) {
  switch (status) {
    case LcpStatus::kSolved:
      return "solved";
    case LcpStatus::kRayTermination:
      return "ray termination";
    case LcpStatus::kPivotLimit:
      return "pivot limit";
  }
  return "unknown";
}

LcpResult SolveLcpLemke(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                        const LemkeOptions& options) {
  const int n = static_cast<int>(q.size());
  ECPSIM_DEMAND(M.rows() == n && M.cols() == n);
  ECPSIM_DEMAND(M.allFinite() && q.allFinite());
  LcpResult result;
  result.z = Eigen::VectorXd::Zero(n);
  result.w = q;

  // q ≥ 0: z = 0 is a solution, no pivot needed
  if (n == 0 || q.minCoeff() >= 0) {
    result.status = LcpStatus::kSolved;
    return result;
  }
  const int max_pivots =
      options.max_pivots > 0 ? options.max_pivots : kDefaultPivotsPerUnknown * (n + 1);

  // tableau [B⁻¹ | −B⁻¹M | −B⁻¹d | B⁻¹q] of I w − M z − d z0 = q; variables 0..n−1 are w,
  // n..2n−1 are z, 2n is z0; the first n columns hold the basis inverse for the lexicographic
  // ratio test
  const int z0 = 2 * n, rhs = 2 * n + 1;
  Eigen::MatrixXd T(n, 2 * n + 2);
  T.leftCols(n).setIdentity();
  T.middleCols(n, n) = -M;
  T.col(z0).setConstant(-1);
  T.col(rhs) = q;
  std::vector<int> basis(n);
  for (int i = 0; i < n; ++i) basis[i] = i;

  const auto pivot = [&](int row, int column) {
    T.row(row) /= T(row, column);
    Eigen::VectorXd factors = T.col(column);
    factors[row] = 0;
    const Eigen::RowVectorXd pivot_row = T.row(row);
    T.noalias() -= factors * pivot_row;
  };
  const auto complement = [n](int variable) { return variable < n ? variable + n : variable - n; };

  // first pivot: z0 enters at the most negative q_i, so that every basic variable becomes ≥ 0;
  // among ties the largest index keeps the rows lexicographically positive
  int row = 0;
  const double q_min = q.minCoeff();
  const double q_tie = kTieRelTol * std::max(1.0, q.cwiseAbs().maxCoeff());
  for (int i = 0; i < n; ++i)
    if (q[i] <= q_min + q_tie) row = i;
  int leaving = basis[row];
  pivot(row, z0);
  basis[row] = z0;
  result.pivots = 1;

  // the largest |entry| of each variable's column in the initial tableau: 1 for w (identity) and
  // z0 (covering vector), max_i |M_ij| for z_j
  Eigen::VectorXd column_scale = Eigen::VectorXd::Ones(2 * n + 1);
  column_scale.segment(n, n) = M.cwiseAbs().colwise().maxCoeff().transpose();

  std::vector<int> ties;
  ties.reserve(n);
  std::vector<char> candidate(n);
  while (true) {
    ThrowIfCancelled(options.cancel, "Lemke's method");
    const int entering = complement(leaving);
    const Eigen::VectorXd column = T.col(entering);
    // an entry is a pivot candidate only when it stands out of its own round-off: entry (i, j)
    // is row i of B⁻¹ times the initial column j, so its error is ≈ ε ‖B⁻¹_i‖₁ max|A_j| (the
    // first n tableau columns hold B⁻¹). A threshold relative to the column's largest entry
    // instead accepts round-off whenever the whole column is ill-determined (a singular M, as
    // four coplanar feet give) and the tableau then blows up (a zero column: no candidate, a ray)
    const double scale = options.pivot_tolerance * column_scale[entering];
    for (int i = 0; i < n; ++i)
      candidate[i] = column[i] > 0 && column[i] > scale * T.row(i).head(n).cwiseAbs().sum();

    // minimum ratio over the candidate rows; basic values are ≥ 0 in exact arithmetic, so a
    // slightly negative one from round-off counts as 0 (a degenerate row, not a negative ratio)
    const auto ratio = [&](int i) { return std::max(T(i, rhs), 0.0) / column[i]; };
    double theta = INFINITY;
    for (int i = 0; i < n; ++i)
      if (candidate[i]) theta = std::min(theta, ratio(i));
    if (!std::isfinite(theta)) {
      result.status = LcpStatus::kRayTermination;
      result.z.setZero();
      result.w = q;
      return result;
    }
    ties.clear();
    const double ratio_tie = kTieRelTol * std::max(1.0, std::abs(theta));
    for (int i = 0; i < n; ++i)
      if (candidate[i] && ratio(i) <= theta + ratio_tie) ties.push_back(i);

    // z0 leaves whenever it can (that ends the method); otherwise the lexicographic rule on the
    // rows of the basis inverse, column by column, until one row remains
    row = -1;
    for (int i : ties)
      if (basis[i] == z0) row = i;
    for (int j = 0; row < 0 && j < n && ties.size() > 1; ++j) {
      double best = INFINITY;
      for (int i : ties) best = std::min(best, T(i, j) / column[i]);
      const double tie = kTieRelTol * std::max(1.0, std::abs(best));
      ties.erase(std::remove_if(ties.begin(), ties.end(),
                                [&](int i) { return T(i, j) / column[i] > best + tie; }),
                 ties.end());
    }
    if (row < 0) row = ties.front();

    leaving = basis[row];
    pivot(row, entering);
    basis[row] = entering;
    ++result.pivots;
    if (leaving == z0) break;
    if (result.pivots >= max_pivots) {
      result.status = LcpStatus::kPivotLimit;
      result.z.setZero();
      result.w = q;
      return result;
    }
  }

  // read z off the basis; basic values are ≥ 0 up to round-off
  for (int i = 0; i < n; ++i)
    if (basis[i] >= n && basis[i] < 2 * n) result.z[basis[i] - n] = std::max(T(i, rhs), 0.0);
  result.w = M * result.z + q;
  result.residual = Residual(result.z, result.w);
  result.status = LcpStatus::kSolved;
  return result;
}

}  // namespace ecpsim::engine
