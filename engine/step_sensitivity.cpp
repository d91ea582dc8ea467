#include "engine/step_sensitivity.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>

#include <fmt/format.h>
#include <Eigen/QR>
#include <Eigen/SVD>

#include "common/errors.h"
#include "engine/contact_model.h"
#include "engine/islands.h"
#include "engine/mncp/contact_frame.h"
#include "engine/mncp/island_mncp.h"
#include "engine/mncp/island_scaling.h"
#include "engine/models/hull_problem.h"
#include "engine/models/hull_warm_start.h"
#include "engine/obstacle_queries.h"
#include "engine/rotation.h"
#include "engine/time_step.h"

namespace ecpsim::engine {
namespace {

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Other = IslandContact::Other;

// ∂Φ/∂x and ∂Φ/∂u by central differences of the residual at fixed z: Φ is smooth in x there
// (poses, inertia, loads, the creep's scale), so a step of 1e-6 of each coordinate's scale
// leaves a truncation error of ≈ 1e-12 and a round-off error of ≈ 1e-16 / 1e-6 = 1e-10, relative
constexpr double kResidualDifferenceFraction = 1e-6;

// the island's part of `state`, in the island's orders
IslandState Gather(const Island& island, const State& state) {
  IslandState local;
  for (int b : island.bodies) local.bodies.push_back(state.bodies[b]);
  for (int k : island.contacts) local.contacts.push_back(state.contacts[k]);
  return local;
}

// the sorted union of two windows
std::vector<int> Union(const std::vector<int>& a, const std::vector<int>& b) {
  std::vector<int> sorted_a = a, sorted_b = b, out;
  std::sort(sorted_a.begin(), sorted_a.end());
  std::sort(sorted_b.begin(), sorted_b.end());
  std::set_union(sorted_a.begin(), sorted_a.end(), sorted_b.begin(), sorted_b.end(),
                 std::back_inserter(out));
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// `values` over `from` (face indices) written over `to` from z[at] on, 0 for a face not in `from`
void PlaceByFace(const std::vector<int>& from, const VectorXd& values, const std::vector<int>& to,
                 VectorXd& z, int at) {
  for (size_t i = 0; i < to.size(); ++i) {
    const auto it = std::find(from.begin(), from.end(), to[i]);
    z[at + static_cast<int>(i)] =
        it != from.end() ? values[static_cast<int>(it - from.begin())] : 0.0;
  }
}

// A state perturbation of island body b: coordinate j of [c, θ, v, ω] by `delta`.
void Perturb(int j, double delta, BodyState& body) {
  Vector3d e = Vector3d::Zero();
  e[j % 3] = delta;
  switch (j / 3) {
    case 0:
      body.p_WB += e;
      break;
    case 1:
      body.Q_WB = (QuaternionExp(e) * body.Q_WB).normalized();
      break;
    case 2:
      body.v_WB += e;
      break;
    case 3:
      body.w_WB += e;
      break;
    default:
      ECPSIM_DEMAND(false);
  }
}

// A column of ∂Φ whose least-squares misfit exceeds this fraction of its norm lies outside the
// range of a singular H: far above the central differences' ≈ 1e-10 relative round-off, far
// below the O(1) misfit of a direction the set of solutions cannot follow
constexpr double kConsistencyFraction = 1e-6;
// a unit null vector of the scaled H whose ν⁺ part is at most this moves no body: round-off of
// the SVD (≈ 1e-15) on a direction that leaves the velocities alone
constexpr double kNullMotionFraction = 1e-8;

// One island's step as the re-assembly needs it: the island, its start (with the pairs'
// normals as the hull model orients them, SeparatePairs) and the contacts it keeps, each with its
// windows and tangent reference, which stay fixed under perturbations of x and u as the step
// holds them fixed for its solve.
struct IslandAtStart {
  const Scene& scene;
  const Island& island;
  double t, h;
  IslandState start;
  std::vector<int> kept;                // island contact indices with a normal impulse
  std::vector<IslandContact> contacts;  // the kept contacts' windows and tangent references
  bool exact_friction = false;          // least-energy selection: the creep-free MNCP's root
};

// The island's problem at `start` with `extra` (per island body: N·s, N·m·s, world) added to
// its applied impulses, as the hull model builds it (bodies, kinematic bodies, grippers, scales
// and the sticking creep from this start), with the kept contacts of `at` only.
IslandProblem ProblemAt(const IslandAtStart& at, const IslandState& start,
                        const std::vector<Eigen::Matrix<double, 6, 1>>& extra,
                        IslandScales& scales) {
  IslandProblem full = hull::MakeHullProblem(at.scene, at.island, at.t, at.h, start);
  for (size_t b = 0; b < full.bodies.size(); ++b) full.bodies[b].p_ext += extra[b];
  std::vector<FailedAttempt> tried;
  ECPSIM_DEMAND(hull::MakeIslandScales(at.scene, at.island, full, start, scales, tried));
  hull::SetStickCreep(scales, full);
  IslandProblem problem = full;
  problem.contacts.clear();
  for (size_t i = 0; i < at.kept.size(); ++i) {
    IslandContact cp = at.contacts[i];
    cp.stick_creep = at.exact_friction ? 0.0 : full.contacts[at.kept[i]].stick_creep;
    problem.contacts.push_back(std::move(cp));
  }
  return problem;
}

// The root z* of the kept contacts' MNCP as the step left it in `after`: ν⁺ the bodies' new
// velocities; per contact its ECPs, impulses and σ, the gap and the multipliers of its hull warm
// start carried by face index to the problem's windows, the friction impulses in the problem's
// frame (the same as the step's, but for round-off).
VectorXd RootOf(const IslandProblem& problem, const IslandLayout& layout, const IslandAtStart& at,
                const IslandState& after) {
  VectorXd z = VectorXd::Zero(layout.size);
  for (int b = 0; b < layout.num_bodies; ++b) {
    z.segment<3>(IslandLayout::Velocity(b)) = after.bodies[b].v_WB;
    z.segment<3>(IslandLayout::Velocity(b) + 3) = after.bodies[b].w_WB;
  }
  for (size_t i = 0; i < at.kept.size(); ++i) {
    const ContactState& c = after.contacts[at.kept[i]];
    const auto* warm = c.warm_start.Get<HullWarmStart>();
    ECPSIM_DEMAND(warm != nullptr);
    const MncpLayout::Contact& L = layout.contacts[i];
    const IslandContact& cp = problem.contacts[i];
    z.segment<3>(L.a1) = c.a1;
    if (!L.on_plane()) {
      z.segment<3>(L.a2) = c.a2;
      z[L.s] = warm->s;
      if (cp.other_kind == Other::kFixed) {
        z.segment(L.l_g, L.l_g_count) = warm->l_g;
      } else {
        PlaceByFace(warm->other_window, warm->l_g, cp.other_window, z, L.l_g);
      }
    }
    PlaceByFace(warm->window, warm->l, cp.window, z, L.l);
    z[L.p_n] = c.p_n;
    z[L.sigma] = c.sigma;
    z[L.p_r] = c.p_r;
    const ContactFrame frame = MakeContactFrame(
        IslandContactNormal(problem, layout, z, static_cast<int>(i)), cp.tangent_reference);
    const Vector3d force = c.n * c.p_n + c.t * c.p_t + c.o * c.p_o;
    z[L.p_t] = frame.t.dot(force);
    z[L.p_o] = frame.o.dot(force);
  }
  return z;
}

// The derivatives of island `at`'s ν⁺ and the solve's diagnostics.
struct IslandDerivatives {
  MatrixXd dnu_dx;  // 6 nb × 12 nb
  MatrixXd dnu_du;  // 6 nb × 6 nb
  // per column of [∂Φ/∂x ∂Φ/∂u] (12 nb + 6 nb): the linearized equations have a solution
  std::vector<char> column_determined;
  // per island body: its ν⁺ is the same for every solution of the linearized equations
  std::vector<char> body_determined;
  IslandSensitivity info;
};

IslandDerivatives DifferentiateIsland(const IslandAtStart& at, const IslandState& after,
                                      double tolerance) {
  const int nb = static_cast<int>(at.island.bodies.size());
  const std::vector<Eigen::Matrix<double, 6, 1>> no_extra(nb, Eigen::Matrix<double, 6, 1>::Zero());
  IslandScales scales;
  const IslandProblem problem = ProblemAt(at, at.start, no_extra, scales);
  const IslandLayout layout = MakeIslandLayout(problem);
  const VectorXd z = RootOf(problem, layout, at, after);
  const int n = layout.size;

  // the residual and its Jacobian at z*, with the solver's scales and measure
  VectorXd F(n);
  MatrixXd J;
  EvaluateIslandMncp(problem, layout, z, &F, &J);
  const VectorXd row_scale = IslandRowScales(problem, layout, scales);
  const VectorXd var_scale = IslandVariableScales(problem, layout, scales);
  const IslandResidualUnits units = MakeIslandResidualUnits(problem, scales, tolerance);
  IslandDerivatives out;
  out.info.bodies = at.island.bodies;
  out.info.unknowns = n;
  out.info.residual = IslandMncpResidual(problem, layout, z, F, row_scale, var_scale, units);

  // the Newton matrix at the active set: free rows and pairs whose multiplier is the larger
  // member (z_i > 0 ⊥ F_i = 0) keep their row of J; pairs whose row is the larger (z_i = 0)
  // hold z_i. That is the semismooth Newton matrix of the Fischer–Burmeister reformulation at a
  // strictly complementary root up to a non-zero factor per row, which dz/dx does not see.
  // Where both members are ≈ 0 the pair is degenerate and the same rule picks one element of
  // the generalized Jacobian.
  std::vector<char> held(n, 0);
  VectorXd scale_row = row_scale;  // a held row z_i in the unit of z_i
  for (int i = layout.num_free; i < n; ++i) {
    const double x = z[i] / var_scale[i];
    const double f = F[i] * row_scale[i];
    if (std::abs(x) <= kDegeneratePairFraction && std::abs(f) <= kDegeneratePairFraction)
      ++out.info.degenerate_pairs;
    if (x < f) {
      held[i] = 1;
      scale_row[i] = 1 / var_scale[i];
    }
  }
  MatrixXd H = J;
  for (int i = 0; i < n; ++i) {
    if (!held[i]) continue;
    H.row(i).setZero();
    H(i, i) = 1;
  }

  // ∂Φ/∂x, ∂Φ/∂u by central differences of F at fixed z over perturbed starts (no solve)
  const int columns = nb * (kStateCoordinates + kWrenchCoordinates);
  MatrixXd dF = MatrixXd::Zero(n, columns);
  VectorXd F_plus(n), F_minus(n);
  IslandScales unused;
  for (int b = 0; b < nb; ++b) {
    const Scales& s = scales.bodies[b];
    const double state_scale[4] = {s.length, 1.0, s.velocity, s.velocity / s.length};
    for (int j = 0; j < kStateCoordinates; ++j) {
      const double delta = kResidualDifferenceFraction * state_scale[j / 3];
      IslandState plus = at.start, minus = at.start;
      Perturb(j, delta, plus.bodies[b]);
      Perturb(j, -delta, minus.bodies[b]);
      EvaluateIslandMncp(ProblemAt(at, plus, no_extra, unused), layout, z, &F_plus, nullptr);
      EvaluateIslandMncp(ProblemAt(at, minus, no_extra, unused), layout, z, &F_minus, nullptr);
      dF.col(kStateCoordinates * b + j) = (F_plus - F_minus) / (2 * delta);
    }
    // u enters as the impulse h u; the force in the unit of the body's impulse per step, the
    // torque in that times its length
    const double wrench_scale[2] = {s.impulse / at.h, s.impulse * s.length / at.h};
    for (int j = 0; j < kWrenchCoordinates; ++j) {
      const double delta = kResidualDifferenceFraction * wrench_scale[j / 3];
      std::vector<Eigen::Matrix<double, 6, 1>> plus = no_extra, minus = no_extra;
      plus[b][j] = at.h * delta;
      minus[b][j] = -at.h * delta;
      EvaluateIslandMncp(ProblemAt(at, at.start, plus, unused), layout, z, &F_plus, nullptr);
      EvaluateIslandMncp(ProblemAt(at, at.start, minus, unused), layout, z, &F_minus, nullptr);
      dF.col(nb * kStateCoordinates + kWrenchCoordinates * b + j) =
          (F_plus - F_minus) / (2 * delta);
    }
  }
  for (int i = 0; i < n; ++i) {
    if (held[i]) dF.row(i).setZero();
  }

  // dz = −H⁻¹ dF in the scaled unknowns (rows and unknowns in their units, so the rank test
  // compares like with like); the minimum-norm solution where H is singular
  const MatrixXd H_scaled = scale_row.asDiagonal() * H * var_scale.asDiagonal();
  Eigen::CompleteOrthogonalDecomposition<MatrixXd> cod(H_scaled);
  cod.setThreshold(kSensitivityRankTolerance);
  out.info.rank = static_cast<int>(cod.rank());
  const MatrixXd rhs = -(scale_row.asDiagonal() * dF);
  const MatrixXd y = cod.solve(rhs);
  const MatrixXd dz = var_scale.asDiagonal() * y;
  out.dnu_dx = dz.topLeftCorner(6 * nb, nb * kStateCoordinates);
  out.dnu_du = dz.topRightCorner(6 * nb, nb * kWrenchCoordinates);
  out.column_determined.assign(columns, 1);
  out.body_determined.assign(nb, 1);
  if (out.info.rank == n) return out;

  // a singular H: a column of ∂Φ that H's range does not hold has no solution of the linearized
  // equations (the step's solution moves along its set by more than ε: not differentiable
  // there), and a body whose ν⁺ the null space moves has its rows of x⁺ undetermined
  const MatrixXd misfit = H_scaled * y - rhs;
  for (int j = 0; j < columns; ++j) {
    if (misfit.col(j).norm() > kConsistencyFraction * rhs.col(j).norm())
      out.column_determined[j] = 0;
  }
  Eigen::JacobiSVD<MatrixXd> svd(H_scaled, Eigen::ComputeFullV);
  const VectorXd sv = svd.singularValues();
  for (int k = 0; k < n; ++k) {
    if (sv[k] > kSensitivityRankTolerance * sv[0]) continue;
    for (int b = 0; b < nb; ++b) {
      if (svd.matrixV().col(k).segment<6>(IslandLayout::Velocity(b)).norm() > kNullMotionFraction)
        out.body_determined[b] = 0;
    }
  }
  return out;
}

}  // namespace

StepSensitivity ComputeStepSensitivity(const Scene& scene, const State& state,
                                       StepWorkspace& workspace) {
  if (scene.model != ContactModel::kHull && scene.model != ContactModel::kAuto &&
      scene.model != ContactModel::kPlanar) {
    throw ModelInvalid(fmt::format(
        "derivatives of a step: model '{}': expected hull, auto or planar (the derivatives are "
        "those of the hull model's MNCP)",
        ContactModelName(scene.model)));
  }
  StepSensitivity out;
  out.next = state;
  out.report = Step(scene, out.next, workspace);
  if (out.report.substeps > 1) {
    throw ModelInvalid(fmt::format(
        "derivatives of a step: the step at t = {} s needed {} sub-steps of h/{}; derivatives "
        "are formed only for steps solved at h",
        state.t, out.report.substeps, out.report.substeps));
  }
  // the dynamic bodies' blocks
  std::vector<int> block(scene.bodies.size(), -1);
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    if (scene.bodies[b].IsKinematic()) continue;
    block[b] = static_cast<int>(out.bodies.size());
    out.bodies.push_back(static_cast<int>(b));
  }
  const int n = static_cast<int>(out.bodies.size());
  out.A = MatrixXd::Zero(kStateCoordinates * n, kStateCoordinates * n);
  out.B = MatrixXd::Zero(kStateCoordinates * n, kWrenchCoordinates * n);
  // (the zero blocks between islands are exact)
  out.A_determined.setOnes(kStateCoordinates * n, kStateCoordinates * n);
  out.B_determined.setOnes(kStateCoordinates * n, kWrenchCoordinates * n);

  // the islands as the step formed them: a pair that stays apart was kept in the step where the
  // driver found it not apart at the step's end, and only such a pair has a warm start after it
  const double h = scene.h;
  IslandScratch island_scratch;
  island_scratch.kept.resize(scene.contacts.size());
  for (size_t k = 0; k < scene.contacts.size(); ++k)
    island_scratch.kept[k] = !out.next.contacts[k].warm_start.empty();
  std::vector<Island> islands;
  FormIslandsInto(scene, state, island_scratch, islands);
  for (const Island& island : islands) {
    IslandAtStart at{scene, island, state.t, h, Gather(island, state), {}, {}, false};
    const IslandState after = Gather(island, out.next);
    // the problem the hull model builds for the step: scales, the pairs' normals, windows and
    // tangent references
    IslandProblem full = hull::MakeHullProblem(scene, island, state.t, h, at.start);
    IslandScales scales;
    std::vector<FailedAttempt> tried;
    ECPSIM_DEMAND(hull::MakeIslandScales(scene, island, full, at.start, scales, tried));
    std::vector<double> overlaps;
    hull::SeparatePairs(full, scales, at.start, overlaps);
    hull::SelectWindows(scene.solver, at.start, full);
    at.exact_friction = scene.solver.selection == Selection::kLeastEnergy && hull::Coupled(full);
    int dropped_degenerate = 0;
    for (size_t k = 0; k < island.contacts.size(); ++k) {
      IslandContact& cp = full.contacts[k];
      cp.tangent_reference = TangentReference(at.start.contacts[k].n);
      const ContactState& c = after.contacts[k];
      const auto* warm = c.warm_start.Get<HullWarmStart>();
      if (!(c.p_n > 0)) {
        // apart: the contact does not act on the step's solution nearby; touching without an
        // impulse (gap ≈ 0 too) is a degenerate pair, left out as if apart
        const double length = ContactScales(full, scales, static_cast<int>(k)).length;
        if (warm != nullptr && std::abs(warm->s) <= kDegeneratePairFraction * length)
          ++dropped_degenerate;
        continue;
      }
      ECPSIM_DEMAND(warm != nullptr);
      cp.window = Union(cp.window, warm->window);
      if (cp.other_kind != Other::kFixed)
        cp.other_window = Union(cp.other_window, warm->other_window);
      at.kept.push_back(static_cast<int>(k));
      at.contacts.push_back(cp);
    }
    IslandDerivatives d = DifferentiateIsland(at, after, scene.solver.tolerance);
    d.info.degenerate_pairs += dropped_degenerate;

    // x⁺ = g(x, z): c⁺ = c + h v⁺, θ⁺ = Exp(h ω⁺) θ + h J_l(h ω⁺) δω⁺, v⁺, ω⁺
    const int nb = static_cast<int>(island.bodies.size());
    for (int b = 0; b < nb; ++b) {
      const int row = kStateCoordinates * block[island.bodies[b]];
      const Vector3d w_plus = after.bodies[b].w_WB;
      const Matrix3d turn = ExpMap(h * w_plus);
      const Matrix3d Jl = LeftJacobian(h * w_plus);
      for (int b2 = 0; b2 < nb; ++b2) {
        const int col_x = kStateCoordinates * block[island.bodies[b2]];
        const int col_u = kWrenchCoordinates * block[island.bodies[b2]];
        const auto dv_dx = d.dnu_dx.block(6 * b, kStateCoordinates * b2, 3, kStateCoordinates);
        const auto dw_dx = d.dnu_dx.block(6 * b + 3, kStateCoordinates * b2, 3, kStateCoordinates);
        out.A.block(row, col_x, 3, kStateCoordinates) = h * dv_dx;
        out.A.block(row + 3, col_x, 3, kStateCoordinates) = h * Jl * dw_dx;
        out.A.block(row + 6, col_x, 3, kStateCoordinates) = dv_dx;
        out.A.block(row + 9, col_x, 3, kStateCoordinates) = dw_dx;
        const auto dv_du = d.dnu_du.block(6 * b, kWrenchCoordinates * b2, 3, kWrenchCoordinates);
        const auto dw_du =
            d.dnu_du.block(6 * b + 3, kWrenchCoordinates * b2, 3, kWrenchCoordinates);
        out.B.block(row, col_u, 3, kWrenchCoordinates) = h * dv_du;
        out.B.block(row + 3, col_u, 3, kWrenchCoordinates) = h * Jl * dw_du;
        out.B.block(row + 6, col_u, 3, kWrenchCoordinates) = dv_du;
        out.B.block(row + 9, col_u, 3, kWrenchCoordinates) = dw_du;
      }
      out.A.block<3, 3>(row, row) += Matrix3d::Identity();
      out.A.block<3, 3>(row + 3, row + 3) += turn;
    }
    for (int b = 0; b < nb; ++b) {
      const int row = kStateCoordinates * block[island.bodies[b]];
      for (int b2 = 0; b2 < nb; ++b2) {
        for (int j = 0; j < kStateCoordinates; ++j) {
          out.A_determined
              .block<kStateCoordinates, 1>(row, kStateCoordinates * block[island.bodies[b2]] + j)
              .setConstant(d.body_determined[b] && d.column_determined[kStateCoordinates * b2 + j]);
        }
        for (int j = 0; j < kWrenchCoordinates; ++j) {
          out.B_determined
              .block<kStateCoordinates, 1>(row, kWrenchCoordinates * block[island.bodies[b2]] + j)
              .setConstant(
                  d.body_determined[b] &&
                  d.column_determined[nb * kStateCoordinates + kWrenchCoordinates * b2 + j]);
        }
      }
    }
    out.degenerate |= d.info.degenerate_pairs > 0;
    out.isolated &= d.info.rank == d.info.unknowns;
    out.residual = std::max(out.residual, d.info.residual);
    out.islands.push_back(std::move(d.info));
  }
  out.method = out.isolated ? "implicit_function" : "implicit_function_minimum_norm";
  return out;
}

}  // namespace ecpsim::engine
