#include "evaluation/power_law_fit.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "common/errors.h"

namespace ecpsim::evaluation {

std::optional<PowerLaw> FitPowerLaw(const std::vector<double>& x, const std::vector<double>& y) {
  ECPSIM_DEMAND(x.size() == y.size());
  std::vector<double> log_x, log_y;
  for (size_t i = 0; i < x.size(); ++i) {
    // a log axis holds only positive finite values: failed or unmeasured costs are −1
    if (std::isfinite(x[i]) && std::isfinite(y[i]) && x[i] > 0 && y[i] > 0) {
      log_x.push_back(std::log(x[i]));
      log_y.push_back(std::log(y[i]));
    }
  }
  const auto [low, high] = std::minmax_element(log_x.begin(), log_x.end());
  if (log_x.size() < 2 || *low == *high) return std::nullopt;
  // log y = log c + k log x, in least squares (QR: no normal equations)
  const int n = static_cast<int>(log_x.size());
  Eigen::MatrixXd a(n, 2);
  a.col(0).setOnes();
  a.col(1) = Eigen::Map<const Eigen::VectorXd>(log_x.data(), n);
  const Eigen::Vector2d fit =
      a.colPivHouseholderQr().solve(Eigen::Map<const Eigen::VectorXd>(log_y.data(), n));
  return PowerLaw{fit(1), std::exp(fit(0)), n};
}

}  // namespace ecpsim::evaluation
