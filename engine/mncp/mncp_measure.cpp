#include "engine/mncp/mncp_measure.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace ecpsim::engine {

ScaledRowResidual::ScaledRowResidual(int num_free, const Eigen::VectorXd& z,
                                     const Eigen::VectorXd& F, const Eigen::VectorXd& row_scale,
                                     const Eigen::VectorXd& var_scale)
    : num_free_(num_free), z_(z), F_(F), row_scale_(row_scale), var_scale_(var_scale) {}

void ScaledRowResidual::AddRow(int i, double divisor) {
  const double f = row_scale_[i] * F_[i] / divisor;
  const double e = i < num_free_ ? std::abs(f) : std::abs(std::min(z_[i] / var_scale_[i], f));
  value_ = std::max(value_, std::isfinite(e) ? e : INFINITY);
}

void ScaledRowResidual::AddContact(const MncpLayout::Contact& L, double factor) {
  // rows in metres (row_scale 1/L), moments and slips: floored by the round-off length; the
  // cone rows (a2's, or a1's on a plane) and the normalization are dimensionless
  if (L.on_plane()) {
    for (int i = 0; i < 3; ++i) AddRow(L.a1 + i, 1);
  } else {
    for (int i = 0; i < 3; ++i) {
      AddRow(L.a1 + i, factor);
      AddRow(L.a2 + i, 1);
    }
    AddRow(L.s, 1);
  }
  for (int i : {L.p_t, L.p_o}) AddRow(i, factor);
  for (int i : {L.p_r, L.sigma}) AddRow(i, 1);
  for (int i = 0; i < L.l_count; ++i) AddRow(L.l + i, factor);
  for (int i = 0; i < L.l_g_count; ++i) AddRow(L.l_g + i, factor);
  AddRow(L.p_n, factor);
}

double ContactRoundOffLength(const MncpLayout::Contact& L, const Eigen::VectorXd& z,
                             double coordinates, double tolerance) {
  // (on a plane a2 and s are a1's projection and distance: |a1| bounds them)
  double magnitude = std::max(z.segment<3>(L.a1).cwiseAbs().maxCoeff(), coordinates);
  if (!L.on_plane())
    magnitude = std::max({magnitude, z.segment<3>(L.a2).cwiseAbs().maxCoeff(), std::abs(z[L.s])});
  return kCoordinateRoundOffUlps * DBL_EPSILON * magnitude / tolerance;
}

double MncpResidual(const MncpLayout& layout, const Eigen::VectorXd& z, const Eigen::VectorXd& F,
                    const Eigen::VectorXd& row_scale, const Eigen::VectorXd& var_scale,
                    const ResidualUnits& units) {
  // row by row (each row of the layout once), without a scaled copy of F: called every iterate
  ScaledRowResidual r(layout.num_free, z, F, row_scale, var_scale);
  double moment_factor = 1;
  for (const MncpLayout::Contact& L : layout.contacts) {
    // a length below which the coordinates' own round-off hides it (see the header)
    const double factor = std::max(
        1.0, ContactRoundOffLength(L, z, units.coordinates, units.tolerance) / units.length);
    moment_factor = std::max(moment_factor, factor);
    r.AddContact(L, factor);
  }
  // Newton–Euler: the moment rows carry r × p with r = a1 − c⁺
  for (int i = 0; i < 3; ++i) {
    r.AddRow(i, 1);
    r.AddRow(3 + i, moment_factor);
  }
  return r.value();
}

}  // namespace ecpsim::engine
