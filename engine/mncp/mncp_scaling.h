#pragma once
// Characteristic sizes of one body's step and the row/unknown scaling of its MNCP
// (FORMULATION.md trap 6), shared by the hull and multi-patch models.

#include <vector>

#include <Eigen/Core>

#include <boost/container/static_vector.hpp>

#include "engine/mncp/mncp_system.h"
#include "engine/scene.h"
#include "engine/state.h"

namespace ecpsim::engine {

struct Scales {
  double length;    // m: radius of gyration
  double velocity;  // m/s: of the body, or what the step's applied impulse adds to it
  double impulse;   // N·s: mass × velocity
};

/// The body's scales for a step of length `h` from `state`, with `p_applied` (N·s; N·m·s, world
/// frame) the impulse of gravity and loads over the step (BodyProblem::p_ext): the velocity scale
/// is the larger of the body's own speed (|v| + |ω| L) and the velocity change the applied impulse
/// alone would cause (|p| / m + |τ| / (m L)), so a body at rest under gravity gets g h; only a
/// body at rest with nothing acting on it falls back on a thousandth of its length per step.
Scales BodyScales(const Body& body, const BodyState& state,
                  const Eigen::Matrix<double, 6, 1>& p_applied, double h);

/// J: m V² + |p_ext| L / h for the body's velocity scale V and length L: its kinetic energy and
/// the applied force's work over its own length.
double EnergyScale(const BodyProblem& problem, const Scales& scales);

/// Unknowns are divided by these: velocities by V (angular by V/L), points and gaps by L,
/// impulses by P (torsion by P e_r), σ by V; multipliers are dimensionless.
Eigen::VectorXd VariableScales(const BodyProblem& problem, const MncpLayout& layout,
                               const Scales& s);

/// Rows are multiplied by these: Newton–Euler by 1/P (1/(P L)), lengths by 1/L, friction rows by
/// 1/(P V) (1/(P V e_r)), the cone by 1/P; the normal-cone rows are dimensionless.
Eigen::VectorXd RowScales(const BodyProblem& problem, const MncpLayout& layout, const Scales& s);

/// The parts of VariableScales and RowScales, shared with the island's scaling
/// (island_scaling.h): one body's ν⁺ at z[index … index + 5] and its Newton–Euler rows, and one
/// contact block with `friction`, all in the units of `s`.
void SetVelocityScales(int index, const Scales& s, Eigen::VectorXd& scale);
void SetNewtonEulerRowScales(int index, const Scales& s, Eigen::VectorXd& scale);
void SetContactVariableScales(const MncpLayout::Contact& L, const Friction& friction,
                              const Scales& s, Eigen::VectorXd& scale);
void SetContactRowScales(const MncpLayout::Contact& L, const Friction& friction, const Scales& s,
                         Eigen::VectorXd& scale);

/// Whether the body moves at more than a small fraction of its velocity scale (the restart ladder
/// starts from the sliding guess then, else from the resting one).
bool IsMoving(const BodyState& state, const Scales& scales);

/// Which initial guess a solve starts from (FORMULATION.md, the restart ladder; the predicted
/// start: the warm start extrapolated along its trend, engine/README.md).
enum class Guess { kWarm, kSeparated, kResting, kSliding, kPredicted };
const char* GuessName(Guess guess);

/// The guesses of one step in the order they are tried (each at most once).
using GuessLadder = boost::container::static_vector<Guess, 5>;

/// The order to try them in: the warm start first when the body was in contact, else after the
/// guesses that fit its motion (a free-flight warm start is a poor guess for an impact).
GuessLadder RestartLadder(bool have_warm_start, bool was_in_contact, bool moving);

/// The same for a body in `state` whose contacts ended the last step as `contacts`: in contact
/// if any carried a normal impulse, moving as IsMoving says.
GuessLadder RestartLadder(bool have_warm_start, const std::vector<ContactState>& contacts,
                          const BodyState& state, const Scales& scales);

/// A sliding guess's friction on contact L: for the slip (v_t, v_o, v_r) at the ECP (m/s, m/s,
/// rad/s) the slip multiplier σ = ‖(e_t v_t, e_o v_o, e_r v_r)‖ and the impulses that oppose it on
/// the edge of the cone μ p_n (the Fritz-John rows' solution); nothing when σ ≤ sigma_floor (the
/// guess keeps its own σ: no slip to oppose).
void SetSlidingFriction(const Friction& fr, double p_n, double v_t, double v_o, double v_r,
                        double sigma_floor, const MncpLayout::Contact& L, Eigen::VectorXd& z);

/// For a guess: the index into cp.window of the hull constraint whose world normal at y_B (body
/// frame, end-of-step rotation R) is most opposed to the obstacle's N — it carries the normal cone.
int MostOpposedWindowConstraint(const ContactProblem& cp, const Eigen::Matrix3d& R,
                                const Eigen::Vector3d& y_B, const Eigen::Vector3d& N);
/// The same for the constraints `window` of `shape`.
int MostOpposedWindowConstraint(const geometry::ConvexShape& shape, const std::vector<int>& window,
                                const Eigen::Matrix3d& R, const Eigen::Vector3d& y_B,
                                const Eigen::Vector3d& N);

}  // namespace ecpsim::engine
