#pragma once
// Checks an analytic Jacobian against central finite differences, entry by entry.

#include <algorithm>
#include <cmath>
#include <functional>

#include <gtest/gtest.h>
#include <Eigen/Core>

namespace ecpsim::engine::testing {

/// A residual F(z) and, when J is not null, its analytic Jacobian.
using ResidualWithJacobian =
    std::function<void(const Eigen::VectorXd& z, Eigen::VectorXd* F, Eigen::MatrixXd* J)>;

/// The bar on |J_analytic − J_numeric| / max(1, |J|) per entry: JacobianError's differences are
/// Richardson-extrapolated central ones with steps eps = 1e-6 and eps/2, whose truncation
/// O(eps⁴·F⁽⁵⁾) and round-off O(1e-16/eps) ≈ 1e-10 stay far below it. (Plain central differences
/// leave eps²·F'''/6, which reached 2.4e-7 on a friction cone row ‖(p_t/e_t, p_o/e_o, p_r/e_r)‖
/// with e_r = 0.05, where F''' ~ 1/(e_r³ ‖p̂‖²).)
inline constexpr double kJacobianTolerance = 1e-7;

/// max over entries of |J_analytic − J_numeric| / max(1, |J|) at z, with an
/// EXPECT_LT(·, kJacobianTolerance) per entry naming row and column.
inline double JacobianError(const ResidualWithJacobian& f, const Eigen::VectorXd& z) {
  constexpr double kEps = 1e-6;
  Eigen::VectorXd F;
  Eigen::MatrixXd J;
  f(z, &F, &J);
  const auto central = [&](int k, double eps) {
    Eigen::VectorXd zp = z, zm = z, Fp, Fm;
    zp[k] += eps;
    zm[k] -= eps;
    f(zp, &Fp, nullptr);
    f(zm, &Fm, nullptr);
    return Eigen::VectorXd((Fp - Fm) / (2 * eps));
  };
  double worst = 0;
  for (int k = 0; k < z.size(); ++k) {
    const Eigen::VectorXd numeric = (4 * central(k, kEps / 2) - central(k, kEps)) / 3;
    for (int i = 0; i < F.size(); ++i) {
      const double error = std::abs(numeric[i] - J(i, k)) / std::max(1.0, std::abs(J(i, k)));
      EXPECT_LT(error, kJacobianTolerance) << "row " << i << " column " << k << ": analytic "
                                           << J(i, k) << ", numeric " << numeric[i];
      worst = std::max(worst, error);
    }
  }
  return worst;
}

}  // namespace ecpsim::engine::testing
