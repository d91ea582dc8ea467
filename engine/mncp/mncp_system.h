#pragma once
// The mixed nonlinear complementarity problem of one body for one time step: the residual of the
// paper's "Summary of the discrete-time dynamic model" and its analytic Jacobian. Its parts are
// the body's step and contact-free Newton–Euler rows (body_step.h), the contact frame
// (contact_frame.h), one contact's rows (contact_rows.h), the unknowns' layout (mncp_layout.h),
// the assembly it shares with the island MNCP (mncp_assembly.h, island_mncp.h) and the
// convergence measure (mncp_measure.h); the equations, unknowns and the handling of the active
// facet are written out in engine/README.md.

#include <Eigen/Core>

#include "engine/mncp/body_step.h"
#include "engine/mncp/contact_frame.h"
#include "engine/mncp/contact_rows.h"
#include "engine/mncp/mncp_layout.h"
#include "engine/mncp/mncp_measure.h"
#include "engine/scene.h"

namespace ecpsim::engine {

/// Residual F(z) in physical units (rows as in MncpLayout). The friction cone row is written as
/// μ p_n − ‖(p_t/e_t, p_o/e_o, p_r/e_r)‖ instead of the paper's ζ = (μ p_n)² − ‖…‖²: for p_n ≥ 0
/// both have the same sign and the same zeros, so 0 ≤ σ ⊥ · ≥ 0 has the same solutions, but ζ has
/// a double root at p̂ = 0 (free flight: ζ = −‖p̂‖²), where Newton converges only linearly and
/// an error ε in p̂ shows in ζ as ε²; the norm form converges in one step there.
/// If `J` is not null also the analytic
/// Jacobian ∂F/∂z, including the dependence of the hull geometry on q⁺ = q + h G(q) ν⁺.
/// With `jacobian_is_zero` the caller promises J is already layout.size square and zero (as
/// SolveMcp hands it to its callback), and J is not cleared again.
/// AssembleMncp (mncp_assembly.h) over the body and its contacts, with DenseMncpRows.
void EvaluateMncp(const BodyProblem& problem, const MncpLayout& layout, const Eigen::VectorXd& z,
                  Eigen::VectorXd* F, Eigen::MatrixXd* J, bool jacobian_is_zero = false);

}  // namespace ecpsim::engine
