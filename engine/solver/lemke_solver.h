#pragma once
// A dense linear complementarity problem solver: Lemke's complementary pivoting method.

#include <Eigen/Core>

#include "common/cancel_flag.h"

namespace ecpsim::engine {

/// How Lemke's method ended.
enum class LcpStatus {
  kSolved,          // z found with w = M z + q ≥ 0, z ≥ 0, wᵀz = 0 (up to round-off)
  kRayTermination,  // the entering column had no positive entry: no solution found (for a
                    // copositive-plus M this proves the LCP infeasible)
  kPivotLimit,      // LemkeOptions::max_pivots pivots without reaching a solution
};
const char* LcpStatusName(LcpStatus status);

struct LemkeOptions {
  /// Pivot limit; ≤ 0 means 50 × (n + 1) for an n × n problem (Lemke needs about n to 2n pivots
  /// on the contact LCPs; the lexicographic rule cannot cycle, so the limit only bounds work).
  int max_pivots = 0;
  /// A tableau entry (i, j) must exceed this times its round-off scale ‖B⁻¹_i‖₁ max_k |A_kj| to
  /// be a pivot candidate (B⁻¹ the basis inverse, A_j the variable's column of [I, −M, −d]).
  /// Round-off is ≈ 1e-16 × that scale, amplified by nearly singular bases; on the contact LCPs
  /// of the desk, T-bar and dumbbell (h = 0.0002 to 0.01 s) every pivot taken was ≥ 1e-8 of its
  /// scale and the noise reached 1e-10, so 1e-9 separates them. Entries below it are treated as
  /// zero: a backward perturbation of M of that relative size.
  double pivot_tolerance = 1e-9;
  /// Once raised, the next pivot throws Cancelled (null: never; common/cancel_flag.h).
  const CancelFlag* cancel = nullptr;
};

struct LcpResult {
  LcpStatus status = LcpStatus::kRayTermination;
  Eigen::VectorXd z;  // the solution when solved (zeros otherwise); size n
  Eigen::VectorXd w;  // M z + q
  int pivots = 0;     // complementary pivots, including the first one that brings in z0
  /// max_i max(−z_i, −w_i, |min(z_i, w_i)|) at the returned z (in q's units); 0 when q ≥ 0.
  double residual = 0;
};

/// Solves w = M z + q, w ≥ 0, z ≥ 0, wᵀz = 0 by Lemke's method with the covering vector
/// d = (1, …, 1) and a lexicographic ratio test (ties in the minimum ratio, up to a relative
/// 1e-12, are broken by the rows of the basis inverse, which excludes cycling on degenerate
/// problems; z0 leaves whenever it ties). M is n × n (dense, any sign pattern), q has size n.
/// Lemke's method finds a solution whenever M is copositive-plus and the LCP is feasible, or
/// M is a P-matrix, and terminates on a ray otherwise. The problem should be scaled so that its
/// entries are O(1): the tolerances are relative.
/// ECPSIM_DEMAND fails for mismatched sizes or non-finite entries.
LcpResult SolveLcpLemke(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                        const LemkeOptions& options = {});

}  // namespace ecpsim::engine
