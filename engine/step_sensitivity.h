#pragma once
// Derivatives of one step (issue 32, item 5): the Jacobians of the state after a step with
// respect to the state before it and to a wrench applied over it, from the converged MNCP of
// each island by the implicit function theorem (engine/README.md, "Derivatives of a step").

#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"
#include "engine/step_workspace.h"

namespace ecpsim::engine {

/// Coordinates of one dynamic body's state, 12 per body in the order of
/// StepSensitivity::bodies: [c (m, 3), θ (rad, 3), v (m/s, 3), ω (rad/s, 3)], all in the world
/// frame. θ is a turn in the world frame applied to the state's orientation, Q = Exp(θ) ⊗ Q₀
/// (so the state itself is θ = 0); ω is the spatial angular velocity.
inline constexpr int kStateCoordinates = 12;
/// Coordinates of one dynamic body's input, 6 per body: a force (N, 3) at its CM and a torque
/// (N·m, 3), world frame, acting over the whole step on top of the scene's loads.
inline constexpr int kWrenchCoordinates = 6;

/// What one island contributed.
struct IslandSensitivity {
  std::vector<int> bodies;   // scene indices
  int unknowns = 0;          // of the re-assembled MNCP (0: free flight, Newton–Euler rows only)
  int rank = 0;              // numerical rank of its scaled Newton matrix (= unknowns: isolated)
  int degenerate_pairs = 0;  // complementarity pairs with both members ≈ 0 (incl. touching
                             // contacts without a normal impulse, which are left out)
  double residual = 0;       // the island's convergence measure at the re-assembled root
};

/// The derivatives of one step of `scene` from `state`, x⁺ = Φ(x, u) at u = 0.
struct StepSensitivity {
  std::vector<int> bodies;  // scene indices of the dynamic bodies, in the blocks' order
  Eigen::MatrixXd A;        // 12 n × 12 n: ∂x⁺/∂x
  Eigen::MatrixXd B;        // 12 n × 6 n: ∂x⁺/∂u
  // some complementarity pair had both members within kDegeneratePairFraction of their scales:
  // the step is not differentiable there, and A, B are one element of its Clarke generalized
  // Jacobian (each such pair kept on the side of its larger member; a touching contact without
  // a normal impulse is left out, as if apart)
  bool degenerate = false;
  // every island's Newton matrix had full numerical rank (kSensitivityRankTolerance): the
  // step's solution is locally unique. False: A, B are the minimum-norm solutions (in the scaled
  // unknowns) of the linearized equations; the parts of x⁺ the set of solutions leaves free are
  // not determined by them
  bool isolated = true;
  // where `isolated` is false: which entries of A and B the linearized equations determine
  // (all true otherwise): an entry is undetermined where its column of ∂Φ lies outside the
  // range of the singular Newton matrix (the linearized equations have no solution there) or
  // where the null space moves its body's ν⁺. The determined entries are derivatives of the
  // linearization; the step itself may still depend on where on its set of solutions the
  // solver lands (its path), beyond first order (engine/README.md, "Derivatives of a step")
  Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> A_determined, B_determined;
  // "implicit_function": H⁻¹ of every island; "implicit_function_minimum_norm": some island's
  // by the complete orthogonal decomposition's minimum-norm solution
  std::string method;
  double residual = 0;  // largest island measure at the re-assembled roots
  std::vector<IslandSensitivity> islands;
  State next;  // the step's result, exactly as Step's
  StepReport report;
};

/// A pair counts as degenerate when both its multiplier and its row are at most this fraction
/// of their scales: 1000 × the default solver tolerance (1e-12), which converged pairs reach,
/// so a pair that is merely converged is never taken for a degenerate one.
inline constexpr double kDegeneratePairFraction = 1e-9;
/// A pivot of the scaled Newton matrix's complete orthogonal decomposition at most this fraction
/// of the largest is a singular direction: the central differences of ∂Φ/∂x carry ≈ 1e-10 of
/// relative round-off, which a smaller pivot would amplify into an O(1) error.
inline constexpr double kSensitivityRankTolerance = 1e-10;

/// Steps `state` once as Step does (same path, bit for bit: `next` is Step's result) and forms
/// the step's Jacobians: per island, the MNCP is re-assembled at the converged unknowns z*
/// (EvaluateIslandMncp) in the hull model's form, its Newton matrix H taken at the active set,
/// ∂Φ/∂x and ∂Φ/∂u by central differences of the residual at fixed z* over problems rebuilt from
/// perturbed start states (no solves), dz/dx = −H⁻¹ ∂Φ/∂x, and then x⁺ = g(x, z):
/// c⁺ = c + h v⁺, θ⁺ = Exp(h ω⁺) θ + h J_l(h ω⁺) δω⁺. Islands do not couple within a step, so
/// A and B are block-diagonal over islands. Pending loads of the scene (a Python Simulation's
/// wrenches) are part of the linearization point.
/// @throws ModelInvalid where the scene's model is not the hull model or auto (or planar),
///         whose steps are the hull MNCP's solutions, or where the step needed sub-steps;
///         SolverFailure, ModelInvalid, InputError as Step.
StepSensitivity ComputeStepSensitivity(const Scene& scene, const State& state,
                                       StepWorkspace& workspace);

}  // namespace ecpsim::engine
