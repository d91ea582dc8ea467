#pragma once
// Checks an analytic Jacobian against central finite differences, entry by entry.

#include <algorithm>
#include <cmath>
#include <functional>

#include <Eigen/Core>
#include <gtest/gtest.h>

namespace ecpsim::engine::testing {

/// A residual F(z) and, when J is not null, its analytic Jacobian.
using ResidualWithJacobian =
    std::function<void(const Eigen::VectorXd& z, Eigen::VectorXd* F, Eigen::MatrixXd* J)>;

/// max over entries of |J_analytic − J_central| / max(1, |J|) at z, with an EXPECT_LT(·, 1e-7)
/// per entry naming row and column. Central differences with eps = 1e-6: truncation
/// O(eps²·F''') ≈ 1e-12 and round-off O(1e-16/eps) ≈ 1e-10, far below the 1e-7 bar.
inline double JacobianError(const ResidualWithJacobian& f, const Eigen::VectorXd& z) {
  constexpr double kEps = 1e-6;
  Eigen::VectorXd F;
  Eigen::MatrixXd J;
  f(z, &F, &J);
  double worst = 0;
  for (int k = 0; k < z.size(); ++k) {
    Eigen::VectorXd zp = z, zm = z, Fp, Fm;
    zp[k] += kEps;
    zm[k] -= kEps;
    f(zp, &Fp, nullptr);
    f(zm, &Fm, nullptr);
    const Eigen::VectorXd numeric = (Fp - Fm) / (2 * kEps);
    for (int i = 0; i < F.size(); ++i) {
      const double error = std::abs(numeric[i] - J(i, k)) / std::max(1.0, std::abs(J(i, k)));
      EXPECT_LT(error, 1e-7) << "row " << i << " column " << k << ": analytic " << J(i, k)
                             << ", numeric " << numeric[i];
      worst = std::max(worst, error);
    }
  }
  return worst;
}

}  // namespace ecpsim::engine::testing
