#include "engine/hull_model.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <variant>

#include <fmt/format.h>

#include "engine/complementarity_solver.h"
#include "engine/contact_window.h"
#include "engine/mncp_scaling.h"
#include "engine/mncp_system.h"
#include "engine/obstacle_queries.h"
#include "engine/rotation.h"
#include "common/errors.h"

namespace ecpsim::engine {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;

// a guess's slip multiplier starts slightly positive: (σ, ζ) = (0, 0) is the kink of φ_FB
constexpr double kInitialSigmaFraction = 1e-3;  // of the velocity scale
// the window check tolerance relative to the body size: far below any face, far above round-off
constexpr double kWindowCheckRelTol = 1e-9;
// rad: the largest rotation h|ω⁺| of one step; beyond π the end pose Exp(hω⁺) R is reached by a
// smaller rotation too, so the step's solution is not unique (an alias)
constexpr double kMaxStepRotation = M_PI;
// a converged step may gain at most this fraction of the body's energy scale m V² + |p_ext| L / h
// (kinetic, and the potential over its own length) beyond the applied loads' work: the implicit
// step dissipates O(h²) where it is resolved, and the spurious roots the drop sweep found at
// coarse dimensionless steps (a 3 cm plate whose |ω| jumped from 3.7 to 193 rad/s in one step)
// gained 1.6e-2 to 0.94 of it
constexpr double kMaxEnergyGainRel = 1e-3;
// the solver's Jacobian smoothing per unit of ‖Φ‖ (McpOptions): measured on the drop sweep's
// failures, 0.1 solved 4 of the 6 steps left without it (0.01 and 1 fewer)
constexpr double kJacobianSmoothing = 0.1;
// a solve whose residual has not halved in this many iterations gives up for the next guess:
// Newton halves it every iteration near a solution, and the slowest recoveries seen (the adaptive
// Levenberg–Marquardt steps out of an impact's near-singular Newton matrix, the stability map's
// 10 m/s case at h = 2e-4 s) went 30 iterations without halving before they converged
constexpr int kStallIterations = 45;
// a hull face whose multiplier exceeds this fraction of the contact's largest one counts as
// active when looking for a degenerate vertex (SolveAtDegenerateVertex): far above round-off,
// far below the multipliers of faces that carry the contact (measured down to 1.9e-6 of it on
// an anchor mesh's five-face vertex)
constexpr double kDegenerateActiveFraction = 1e-9;
// a hull face whose multiplier is below this fraction of the contact's largest carries no
// measurable part of the contact: at a stalled iterate such faces are weakly active (f_i ≈ 0 and
// l_i ≈ 0 together, the degenerate pairs of the Fischer–Burmeister function), measured at
// 1e-9…1e-12 of the largest around a 52 m handle's rolling edge whose carrying faces had 0.43
// and 0.57 (SolveOnCarryingFaces)
constexpr double kCarryingFraction = 1e-6;
// faces left out at most when a degenerate vertex is resolved: enough for six faces at a vertex
// (a fan of triangles, a quad mesh's pole) to come down to three. A vertex with more active
// faces than three plus the drops left is tried one face at a time without going deeper: the
// tree of drops grows as n³ (a 37 m elk mesh's fan took 680,000 iterations in one step)
constexpr int kMaxDegenerateDrops = 3;
// growing the window this many times (each by the faces around the constraints the solution
// violated) before the guess counts as failed: a step never falls back to every hull face, whose
// dense Newton matrix costs in proportion to the hull (11,000 unknowns for a fine UV sphere); one
// growth is what a solution that moved past the window's rim needs, the rest is margin
constexpr int kMaxWindowGrowth = 6;

class BodyStepper {
 public:
  BodyStepper(const Scene& scene, int body_index, std::vector<int> contact_ids)
      : scene_(scene), body_index_(body_index), contact_ids_(std::move(contact_ids)) {}

  // one step of length h from (body, contacts); not solved if every guess failed
  AdvanceResult Advance(double t, double h, BodyState& body, std::vector<ContactState>& contacts) {
    AdvanceResult result;
    const Body& model = scene_.bodies[body_index_];
    BodyProblem problem = MakeProblem(t, h, body);
    const Scales scales = BodyScales(model, body, problem.p_ext, h);
    if (!FreeFlightIsFinite(problem, result.tried)) {
      result.residual = INFINITY;
      return result;
    }

    // windows around the support feature at the predicted pose, in the direction of −n
    const Matrix3d R_predicted = ExpMap(h * body.w_WB) * problem.R;
    for (size_t k = 0; k < contact_ids_.size(); ++k) {
      ContactProblem& cp = problem.contacts[k];
      const Vector3d direction_B = R_predicted.transpose() * -contacts[k].n;
      cp.window = SelectWindow(*cp.hull, direction_B, scene_.solver.window_rings,
                               scene_.solver.use_window);
    }

    // free flight: if every hull ends the step strictly above its half-space obstacle when no
    // contact acts, then p = 0 with ν⁺ = ν + M⁻¹ p_ext *is* the MNCP's solution (p_n = 0 ⊥ s > 0;
    // a1, a2 the closest points), so it is taken in closed form — the reduced system of trap 2,
    // exact, and free of the degenerate σ and of round-off in far-apart coordinates
    {
      const MncpLayout layout = MakeLayout(problem);
      const VectorXd z = MakeGuess(Guess::kSeparated, problem, layout, body, contacts, scales);
      if (AllContactsApart(problem, layout, z)) {
        Commit(problem, layout, z, h, body, contacts);
        result.solved = true;
        return result;
      }
    }

    // a body that starts the step inside an obstacle (allowed at t = 0, or round-off) is pushed
    // out within the step: the contact may give it the energy of that ejection
    const double ejection_energy = EjectionEnergy(problem, contacts);

    // in contact (or about to be): the warm start, then the guesses that fit the body's motion
    const bool have_warm_start =
        contacts.empty() || std::holds_alternative<HullWarmStart>(contacts[0].warm_start);
    const std::vector<Guess> ladder = RestartLadder(have_warm_start, contacts, body, scales);

    McpOptions options;
    options.tolerance = scene_.solver.tolerance;
    options.max_iterations = scene_.solver.max_iterations;
    options.jacobian_smoothing = kJacobianSmoothing;
    options.levenberg_marquardt_rescue = true;
    options.stall_iterations = kStallIterations;

    // the ladder as it is first; only when every guess fails, again with iterates kept in the
    // orthant of the complementarity unknowns (engine/README.md, "Impacts": the merit function
    // has stationary points with σ < 0 — friction pushing along the slip — that capture Newton
    // at hard impacts)
    for (const bool project : {false, true}) {
      options.project_nonnegative = project;
      for (Guess guess : ladder) {
        const auto note = [&](const std::string& what) {
          result.tried += fmt::format("{}{}{} (h = {:g} s): {}", result.tried.empty() ? "" : "; ",
                                      GuessName(guess), project ? " (projected)" : "", h, what);
          ++result.retries;
        };
        for (int growth = 0; growth <= kMaxWindowGrowth; ++growth) {
          const MncpLayout layout = MakeLayout(problem);
          VectorXd z = MakeGuess(guess, problem, layout, body, contacts, scales);
          Attempt attempt = Solve(problem, layout, z, options, scales, ejection_energy, result);
          result.residual = attempt.residual;
          // Newton stalls just above the tolerance where faces are weakly active at the
          // solution, or where four or more hull faces meet at the ECP (a quad mesh's vertex):
          // the faces that carry the contact alone, or one face left out, solve it
          if (attempt.outcome == Outcome::kUnconverged &&
              (SolveOnCarryingFaces(problem, layout, z, options, scales, ejection_energy, h,
                                    body, contacts, result) ||
               SolveAtDegenerateVertex(problem, layout, z, options, scales, ejection_energy,
                                       h, body, contacts, result))) {
            result.solved = true;
            return result;
          }
          if (attempt.outcome != Outcome::kSolved) {
            note(attempt.Describe());
            break;
          }
          // a converged windowed solution must also solve the full-hull problem: else the
          // window grows around the constraints it violates, and the step is solved again
          if (GrowViolatedWindows(problem, layout, z, scales)) {
            if (growth < kMaxWindowGrowth) continue;
            note(fmt::format("the hull window still left out violated faces after {} growths",
                             kMaxWindowGrowth));
            break;
          }
          Commit(problem, layout, z, h, body, contacts);
          result.solved = true;
          return result;
        }
      }
    }
    return result;
  }

 private:
  enum class Outcome { kSolved, kUnconverged, kAliased, kGainsEnergy };

  // one solve of the MNCP of `problem` (laid out as `layout`) from `z`, and whether its root is
  // acceptable
  struct Attempt {
    Outcome outcome = Outcome::kUnconverged;
    double residual = INFINITY;
    int iterations = 0;
    std::string Describe() const {
      const char* what = outcome == Outcome::kAliased       ? "aliased rotation, residual"
                         : outcome == Outcome::kGainsEnergy ? "energy gain, residual"
                                                            : "residual";
      return fmt::format("{} {:.3g} after {} iterations", what, residual, iterations);
    }
  };

  Attempt Solve(const BodyProblem& problem, const MncpLayout& layout, VectorXd& z,
                McpOptions& options, const Scales& scales, double ejection_energy,
                AdvanceResult& result) const {
    const McpFunction f = [&](const VectorXd& zz, VectorXd* F, Eigen::MatrixXd* J) {
      EvaluateMncp(problem, layout, zz, F, J);
    };
    const VectorXd row_scale = RowScales(problem, layout, scales);
    const VectorXd var_scale = VariableScales(problem, layout, scales);
    options.measure = [&](const VectorXd& zz, const VectorXd& F) {
      return MncpResidual(layout, zz, F, row_scale, var_scale,
                          {scales.length, options.tolerance, problem.c.cwiseAbs().maxCoeff()});
    };
    const McpResult solve = SolveMcp(f, layout.num_free, row_scale, var_scale, z, options);
    options.measure = nullptr;
    result.iterations += solve.iterations;
    Attempt attempt;
    attempt.residual = solve.residual;
    attempt.iterations = solve.iterations;
    if (!solve.converged || !z.allFinite()) return attempt;
    // a turn of more than π in one step is an alias: Exp(hω⁺) has the same end pose for a
    // smaller ω⁺, so such a root of the MNCP is a spurious one (it can gain energy); so is one
    // that gains energy the applied loads did not give (engine/README.md, "Roots that gain
    // energy"): the contact can only take energy away
    if (problem.h * z.segment<3>(3).norm() > kMaxStepRotation) {
      attempt.outcome = Outcome::kAliased;
    } else if (StepEnergyGain(problem, z.segment<3>(0), z.segment<3>(3)) >
               kMaxEnergyGainRel * EnergyScale(problem, scales) + ejection_energy) {
      attempt.outcome = Outcome::kGainsEnergy;
    } else {
      attempt.outcome = Outcome::kSolved;
    }
    return attempt;
  }

  // Where four or more hull faces meet at the ECP, their multipliers are not unique and their
  // planes (merged from near-coplanar triangles) meet only up to the merge tolerance: the true
  // support is one of the tiny vertices where three of them meet, and Newton stalls just above
  // the tolerance between them. Re-solves from the stalled `z` with each of those faces left
  // out of the window in turn (the smallest multipliers first; where five or more meet, the
  // reduced problem may stall again at four and leaves out one more, up to `depth` in all); a
  // solution whose window check passes — the faces left out hold, as every face outside the
  // window must — is exact.
  bool SolveAtDegenerateVertex(const BodyProblem& problem, const MncpLayout& layout,
                               const VectorXd& z, McpOptions& options, const Scales& scales,
                               double ejection_energy, double h, BodyState& body,
                               std::vector<ContactState>& contacts, AdvanceResult& result,
                               int depth = kMaxDegenerateDrops) const {
    if (depth == 0 || !z.allFinite()) return false;
    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      const MncpLayout::Contact& L = layout.contacts[k];
      const double largest = z.segment(L.l, L.l_count).maxCoeff();
      std::vector<int> active;  // indices into the window, by increasing multiplier
      for (int i = 0; i < L.l_count; ++i)
        if (z[L.l + i] > kDegenerateActiveFraction * largest) active.push_back(i);
      if (active.size() < 4) continue;
      std::sort(active.begin(), active.end(), [&](int a, int b) { return z[L.l + a] < z[L.l + b]; });
      for (size_t drop = 0; drop + 3 < active.size(); ++drop) {
        BodyProblem reduced = problem;
        std::vector<int>& window = reduced.contacts[k].window;
        window.erase(window.begin() + active[drop]);
        const MncpLayout reduced_layout = MakeLayout(reduced);
        VectorXd rz = RemapWindows(problem, layout, z, reduced, reduced_layout);
        const Attempt attempt =
            Solve(reduced, reduced_layout, rz, options, scales, ejection_energy, result);
        const bool can_reach_three = active.size() <= static_cast<size_t>(3 + depth);
        if (attempt.outcome == Outcome::kUnconverged && can_reach_three &&
            SolveAtDegenerateVertex(reduced, reduced_layout, rz, options, scales, ejection_energy,
                                    h, body, contacts, result, depth - 1)) {
          return true;
        }
        if (AcceptReduced(reduced, reduced_layout, rz, attempt, scales, h, body, contacts,
                          result)) {
          return true;
        }
      }
    }
    return false;
  }

  // Re-solves from the stalled `z` with each window cut to the faces that carry the contact
  // (multiplier above kCarryingFraction of the largest): the weakly active faces left out, the
  // reduced problem's pairs are no longer degenerate. Exact when its window check passes.
  bool SolveOnCarryingFaces(const BodyProblem& problem, const MncpLayout& layout,
                            const VectorXd& z, McpOptions& options, const Scales& scales,
                            double ejection_energy, double h, BodyState& body,
                            std::vector<ContactState>& contacts, AdvanceResult& result) const {
    if (!z.allFinite()) return false;
    BodyProblem reduced = problem;
    bool cut = false;
    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      const MncpLayout::Contact& L = layout.contacts[k];
      const double largest = z.segment(L.l, L.l_count).maxCoeff();
      if (!(largest > 0)) continue;
      std::vector<int> carrying;  // stays sorted, as windows are
      for (int i = 0; i < L.l_count; ++i)
        if (z[L.l + i] > kCarryingFraction * largest) carrying.push_back(problem.contacts[k].window[i]);
      cut |= carrying.size() < problem.contacts[k].window.size();
      reduced.contacts[k].window = std::move(carrying);
    }
    if (!cut) return false;
    const MncpLayout reduced_layout = MakeLayout(reduced);
    VectorXd rz = RemapWindows(problem, layout, z, reduced, reduced_layout);
    const Attempt attempt =
        Solve(reduced, reduced_layout, rz, options, scales, ejection_energy, result);
    return AcceptReduced(reduced, reduced_layout, rz, attempt, scales, h, body, contacts, result);
  }

  // commits a solution of a problem whose windows were cut (faces left out) when it converged
  // and every face outside its windows holds (the window check): then it is exact
  bool AcceptReduced(const BodyProblem& reduced, const MncpLayout& layout, const VectorXd& z,
                     const Attempt& attempt, const Scales& scales, double h, BodyState& body,
                     std::vector<ContactState>& contacts, AdvanceResult& result) const {
    if (attempt.outcome != Outcome::kSolved) return false;
    BodyProblem checked = reduced;
    if (GrowViolatedWindows(checked, layout, z, scales)) return false;
    Commit(reduced, layout, z, h, body, contacts);
    result.residual = attempt.residual;
    return true;
  }

  // `z` of `from` (laid out as `from_layout`) moved to `to`'s layout: the same unknowns, hull
  // multipliers matched by face index (0 for a face new to a window)
  static VectorXd RemapWindows(const BodyProblem& from, const MncpLayout& from_layout,
                               const VectorXd& z, const BodyProblem& to,
                               const MncpLayout& to_layout) {
    VectorXd out = VectorXd::Zero(to_layout.size);
    out.head<6>() = z.head<6>();
    for (size_t k = 0; k < to.contacts.size(); ++k) {
      const MncpLayout::Contact& A = from_layout.contacts[k];
      const MncpLayout::Contact& B = to_layout.contacts[k];
      out.segment<10>(B.a1) = z.segment<10>(A.a1);
      out.segment(B.l_g, B.l_g_count) = z.segment(A.l_g, A.l_g_count);
      out[B.p_n] = z[A.p_n];
      out[B.sigma] = z[A.sigma];
      const std::vector<int>& old_window = from.contacts[k].window;
      for (int i = 0; i < B.l_count; ++i) {
        const auto it = std::find(old_window.begin(), old_window.end(), to.contacts[k].window[i]);
        if (it != old_window.end()) out[B.l + i] = z[A.l + (it - old_window.begin())];
      }
    }
    return out;
  }

  BodyProblem MakeProblem(double t, double h, const BodyState& body) const {
    const Body& model = scene_.bodies[body_index_];
    BodyProblem p = StartOfStep(scene_, body_index_, body, t, h);
    for (int id : contact_ids_) {
      const ContactPair& pair = scene_.contacts[id];
      ContactProblem cp;
      cp.hull = model.hull.get();
      cp.obstacle = scene_.obstacles[pair.obstacle].shape.get();
      cp.friction = pair.friction;
      p.contacts.push_back(cp);
    }
    return p;
  }

  // true if every contact's obstacle is a half-space and the separated guess's a1 (the hull's
  // support point at the free-flight end pose) lies strictly outside it
  static bool AllContactsApart(const BodyProblem& problem, const MncpLayout& layout,
                               const VectorXd& z) {
    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      const geometry::ConvexShape& obstacle = *problem.contacts[k].obstacle;
      if (!obstacle.IsHalfSpace()) return false;
      if (!(obstacle.Value(0, z.segment<3>(layout.contacts[k].a1)) > 0)) return false;
    }
    return true;
  }

  // J: twice the kinetic energy of moving the body out of its deepest start-of-step penetration
  // of any obstacle within one step, plus the applied impulse's work over that depth
  static double EjectionEnergy(const BodyProblem& problem, const std::vector<ContactState>& contacts) {
    double depth = 0;
    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      const ContactProblem& cp = problem.contacts[k];
      const Vector3d lowest = problem.c + problem.R * cp.hull->Support(problem.R.transpose() * -contacts[k].n);
      const double g = cp.obstacle->Value(LargestConstraint(*cp.obstacle, lowest), lowest);
      depth = std::max(depth, -g);
    }
    const double speed = depth / problem.h;
    return problem.mass * speed * speed + problem.p_ext.head<3>().norm() * speed;
  }

  VectorXd MakeGuess(Guess guess, BodyProblem& problem, const MncpLayout& layout,
                     const BodyState& body, const std::vector<ContactState>& contacts,
                     const Scales& scales) const {
    VectorXd z = VectorXd::Zero(layout.size);
    // free-flight velocities as the starting point of a fresh guess; the last ones for warm starts
    const auto& [v_free, w_free] = problem.free;
    z.segment<3>(0) = guess == Guess::kWarm ? body.v_WB : v_free;
    z.segment<3>(3) = guess == Guess::kWarm ? body.w_WB : w_free;

    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      ContactProblem& cp = problem.contacts[k];
      const MncpLayout::Contact& L = layout.contacts[k];
      const ContactState& previous = contacts[k];
      const Friction& fr = cp.friction;
      cp.tangent_reference = TangentReference(previous.n);
      const double sigma0 = kInitialSigmaFraction * scales.velocity;

      const auto* warm = std::get_if<HullWarmStart>(&previous.warm_start);
      if (guess == Guess::kWarm && warm != nullptr) {
        z.segment<3>(L.a1) = previous.a1;
        z.segment<3>(L.a2) = previous.a2;
        z[L.s] = warm->s;
        z[L.p_t] = previous.p_t;
        z[L.p_o] = previous.p_o;
        z[L.p_r] = previous.p_r;
        z[L.p_n] = previous.p_n;
        z[L.sigma] = previous.sigma;
        z.segment(L.l_g, L.l_g_count) = warm->l_g;
        // carry hull multipliers over by face index (the window may have moved); windows are
        // sorted (SelectWindow), so a binary search does it without building a map every step
        const std::vector<int>& window = warm->window;
        for (int i = 0; i < L.l_count; ++i) {
          const auto it = std::lower_bound(window.begin(), window.end(), cp.window[i]);
          if (it != window.end() && *it == cp.window[i]) z[L.l + i] = warm->l[it - window.begin()];
        }
        continue;
      }

      // geometric guess at the free-flight pose: the hull's support point in the direction −n
      const Vector3d n = previous.n;
      const EndPose pose = PoseAfterStep(problem, z.segment<3>(0), z.segment<3>(3));
      const Vector3d support = pose.c + pose.R * cp.hull->Support(pose.R.transpose() * -n);
      // a contact without a warm start (new to the ladder) starts as separated
      const bool separated = guess == Guess::kSeparated || guess == Guess::kWarm;
      Vector3d a1 = support;
      if (!separated) a1 = pose.c - n * n.dot(pose.c - support);  // under the CM
      const auto [a2, active_g] = ProjectOntoObstacle(*cp.obstacle, a1);
      z.segment<3>(L.a1) = a1;
      z.segment<3>(L.a2) = a2;
      z[L.l_g + active_g] = 1;
      const Vector3d N = cp.obstacle->Gradient(active_g, a2);
      z[L.s] = separated ? std::max(0.0, (a1 - a2).dot(N) / N.squaredNorm()) : 0;
      // the window face whose world normal is most opposed to N carries the cone
      const Vector3d y = pose.R.transpose() * (a1 - pose.c);
      const int best = MostOpposedWindowConstraint(cp, pose.R, y, N);
      z[L.l + best] = 1;
      z[L.sigma] = sigma0;
      if (separated) continue;

      // in contact: the normal impulse that cancels gravity and the approach velocity
      const double p_n = std::max(problem.mass * (-n.dot(z.segment<3>(0))), 0.0) +
                         std::max(-problem.mass * scene_.gravity.dot(n) * problem.h, 0.0);
      z[L.p_n] = p_n;
      const Vector3d v_tangent = body.v_WB - n * n.dot(body.v_WB);
      z.segment<3>(0) = v_tangent;
      if (guess == Guess::kSliding) {
        const ContactFrame frame = MakeContactFrame(N, cp.tangent_reference);
        const double v_t = frame.t.dot(v_tangent), v_o = frame.o.dot(v_tangent);
        const double v_r = frame.n.dot(body.w_WB);
        const double sigma = std::sqrt(fr.e_t * fr.e_t * v_t * v_t + fr.e_o * fr.e_o * v_o * v_o +
                                       fr.e_r * fr.e_r * v_r * v_r);
        if (sigma > sigma0) {
          z[L.sigma] = sigma;
          z[L.p_t] = -fr.e_t * fr.e_t * fr.mu * p_n * v_t / sigma;
          z[L.p_o] = -fr.e_o * fr.e_o * fr.mu * p_n * v_o / sigma;
          z[L.p_r] = -fr.e_r * fr.e_r * fr.mu * p_n * v_r / sigma;
        }
      }
    }
    return z;
  }

  static Vector3d SolutionNormal(const BodyProblem& problem, const MncpLayout& layout,
                                 const VectorXd& z, int k) {
    const MncpLayout::Contact& L = layout.contacts[k];
    const ContactProblem& cp = problem.contacts[k];
    Vector3d N = Vector3d::Zero();
    for (int j = 0; j < L.l_g_count; ++j)
      N += z[L.l_g + j] * cp.obstacle->Gradient(j, z.segment<3>(L.a2));
    return N;
  }

  // grows the window of every contact whose windowed solution violates a hull constraint left
  // out (contact_window.h); false when the solution solves the full-hull problem
  bool GrowViolatedWindows(BodyProblem& problem, const MncpLayout& layout, const VectorXd& z,
                           const Scales& scales) const {
    const EndPose end = PoseAfterStep(problem, z.segment<3>(0), z.segment<3>(3));
    bool grown = false;
    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      const MncpLayout::Contact& L = layout.contacts[k];
      ContactProblem& cp = problem.contacts[k];
      int active = 0;
      z.segment(L.l, L.l_count).maxCoeff(&active);
      const Vector3d y = end.R.transpose() * (z.segment<3>(L.a1) - end.c);
      const std::vector<int> violated = WindowViolations(
          *cp.hull, cp.window, cp.window[active], y, kWindowCheckRelTol * scales.length);
      if (violated.empty()) continue;
      cp.window = GrowWindow(*cp.hull, cp.window, violated);
      grown = true;
    }
    return grown;
  }

  void Commit(const BodyProblem& problem, const MncpLayout& layout, const VectorXd& z, double h,
              BodyState& body, std::vector<ContactState>& contacts) const {
    const Vector3d v = z.segment<3>(0);
    const Vector3d w = z.segment<3>(3);
    body.p_WB += h * v;
    body.Q_WB = IntegrateOrientation(body.Q_WB, w, h);
    body.v_WB = v;
    body.w_WB = w;
    for (size_t k = 0; k < problem.contacts.size(); ++k) {
      const MncpLayout::Contact& L = layout.contacts[k];
      const ContactProblem& cp = problem.contacts[k];
      ContactState& c = contacts[k];
      c.a1 = z.segment<3>(L.a1);
      c.a2 = z.segment<3>(L.a2);
      c.p_t = z[L.p_t];
      c.p_o = z[L.p_o];
      c.p_r = z[L.p_r];
      // complementarity unknowns are ≥ 0 up to the tolerance; report them clamped
      c.p_n = std::max(z[L.p_n], 0.0);
      // without a normal impulse any σ ≥ 0 solves the MNCP (trap 2); report the canonical 0
      c.sigma = c.p_n > 0 ? std::max(z[L.sigma], 0.0) : 0.0;
      const ContactFrame frame =
          MakeContactFrame(SolutionNormal(problem, layout, z, static_cast<int>(k)),
                           cp.tangent_reference);
      c.n = frame.n;
      c.t = frame.t;
      c.o = frame.o;
      c.warm_start = HullWarmStart{z[L.s], z.segment(L.l_g, L.l_g_count), cp.window,
                                   z.segment(L.l, L.l_count)};
    }
  }

  const Scene& scene_;
  int body_index_;
  std::vector<int> contact_ids_;
};

}  // namespace

AdvanceResult HullModel::Advance(const Island& island, double t, double h,
                                 IslandState& state) const {
  return AdvanceOneBody<BodyStepper>(scene_, island, t, h, state);
}

}  // namespace ecpsim::engine
