// The patch energy the least-energy selection minimizes, on a box lying on the ground: its
// residuals against the compliant patch's closed form, and their Jacobian against central
// differences.

#include "engine/models/hull_selection.h"

#include <cmath>

#include <gtest/gtest.h>

#include "tests/engine/models/hull_islands.h"

namespace ecpsim::engine::hull {
namespace {

using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

// the residuals' closed forms: a few products of exact patch moments, to round-off
constexpr double kEnergyRoundOff = 1e-12;
// central differences of residuals at most quadratic in z, step 1e-6 of O(1) unknowns: the
// round-off of the differences, 1e-16 / 1e-6, with margin
constexpr double kJacobianTolerance = 1e-8;

// the island's unknowns with the box at rest (its end pose its start) and the contact's impulses
// and ECP as given
VectorXd BoxAtRest(const IslandLayout& layout, const Vector3d& a1, double p_n, double p_t,
                   double p_o, double p_r) {
  VectorXd z = VectorXd::Zero(layout.size);
  const MncpLayout::Contact& L = layout.contacts[0];
  z.segment<3>(L.a1) = a1;
  z[L.p_n] = p_n;
  z[L.p_t] = p_t;
  z[L.p_o] = p_o;
  z[L.p_r] = p_r;
  return z;
}

TEST(PatchEnergyTest, AFaceLoadedAtItsCentroidCostsItsLoadOverItsArea) {
  // the 0.2 × 0.1 m bottom face: A = 0.02 m², I = 0.1 · 0.2³/12 and 0.2 · 0.1³/12
  const HullIsland c = PrepareHullIsland(BoxScene(0.025), InitialState(BoxScene(0.025)));
  const IslandLayout layout = MakeIslandLayout(c.problem);
  const double p_n = 0.2;
  VectorXd z = BoxAtRest(layout, Vector3d::Zero(), p_n, 0, 0, 0);
  const EnergyResiduals energy = PatchEnergy(c.scene, c.island, c.problem, layout, z);
  VectorXd r;
  energy(z, &r, nullptr);
  ASSERT_EQ(r.size(), 6);
  EXPECT_NEAR(r[0], p_n / std::sqrt(0.02), kEnergyRoundOff);
  EXPECT_NEAR(r.tail(5).norm(), 0, kEnergyRoundOff);
  // the ECP 1 cm along the long side: p_n e / √I1; a friction 0.05 N·s along x there adds its
  // moment about the centroid to the torsion's row
  const double I1 = 0.1 * std::pow(0.2, 3) / 12, J = I1 + 0.2 * std::pow(0.1, 3) / 12;
  z = BoxAtRest(layout, Vector3d(0.01, 0, 0), p_n, 0, 0, 0);
  energy(z, &r, nullptr);
  EXPECT_NEAR(std::abs(r[1]), p_n * 0.01 / std::sqrt(I1), kEnergyRoundOff);
  EXPECT_NEAR(r[2], 0, kEnergyRoundOff);
  const double p_along_y = 0.05;  // o or t: whichever the frame's tangent along world y is
  const MncpLayout::Contact& L = layout.contacts[0];
  const ContactFrame frame =
      MakeContactFrame(Vector3d::UnitZ(), c.problem.contacts[0].tangent_reference);
  z[L.p_t] = p_along_y * frame.t.y();
  z[L.p_o] = p_along_y * frame.o.y();
  energy(z, &r, nullptr);
  // a force along y at x = 0.01: the moment 0.01 · 0.05 about the normal
  EXPECT_NEAR(std::abs(r[5]), 0.01 * p_along_y / std::sqrt(J), kEnergyRoundOff);
}

TEST(PatchEnergyTest, TheJacobianMatchesCentralDifferences) {
  const HullIsland c = PrepareHullIsland(BoxScene(0.025), InitialState(BoxScene(0.025)));
  const IslandLayout layout = MakeIslandLayout(c.problem);
  const VectorXd z = BoxAtRest(layout, Vector3d(0.03, -0.02, 0), 0.2, 0.03, -0.04, 0.002);
  const EnergyResiduals energy = PatchEnergy(c.scene, c.island, c.problem, layout, z);
  VectorXd r;
  MatrixXd R;
  energy(z, &r, &R);
  constexpr double kStep = 1e-6;
  for (int i = 0; i < layout.size; ++i) {
    VectorXd plus = z, minus = z, r_plus, r_minus;
    plus[i] += kStep;
    minus[i] -= kStep;
    energy(plus, &r_plus, nullptr);
    energy(minus, &r_minus, nullptr);
    EXPECT_LT(((r_plus - r_minus) / (2 * kStep) - R.col(i)).lpNorm<Eigen::Infinity>(),
              kJacobianTolerance)
        << "column " << i;
  }
}

}  // namespace
}  // namespace ecpsim::engine::hull
