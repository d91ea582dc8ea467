#include "engine/models/multipatch_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numeric>
#include <string>

#include <fmt/format.h>

#include "common/errors.h"
#include "engine/mncp/mncp_scaling.h"
#include "engine/models/balanced_start.h"
#include "engine/models/multipatch_balance.h"
#include "engine/obstacle_queries.h"
#include "engine/rotation.h"
#include "engine/solver/complementarity_solver.h"

namespace ecpsim::engine {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;
using RowVector3d = Eigen::Matrix<double, 1, 3>;

// a guess's slip multiplier starts slightly positive: (σ, ζ) = (0, 0) is the kink of φ_FB
constexpr double kInitialSigmaFraction = 1e-3;  // of the velocity scale
// a part whose lowest point at the predicted pose is within this fraction of the body's length
// scale of the lowest part's is taken as touching in the in-contact guesses (the feet of a flat
// desk: exactly level; a tilted body: only its lowest part)
constexpr double kTouchingRelTol = 1e-6;
// vertices this close to the support plane belong to the support feature (a face or an edge):
// far above the hull's round-off, far below any part's size
constexpr double kFeatureRelTol = 1e-9;  // of the part's width along the direction, or its offset
// the combined ECP's weight floor relative to the body's impulse scale: far below the solver
// tolerance's effect on the ECP (it moves a1 by ≈ 1e-12 of the part spacing), far above 0 so
// that a1 stays defined when no part carries load
constexpr double kWeightFloorRel = 1e-12;
// the proximal terms of the Newton matrix (AddProximalTerms), in the scaled problem's units (an
// ECP's offset in L against the dimensionless normal-cone rows, a normal impulse in P against the
// gap row in L): far above the round-off of the matrix's O(1) entries (1e-16), so the directions
// along which the solutions are not unique get a well-defined Newton step, and far below 1, so
// that the others keep it. On the desk (iterations_mean of `ecpsim run scenes/desk.yaml --model
// multipatch` with these two changed) the mean Newton iterations per step are flat at 3.0–3.2
// for ECP terms of 1e-6 … 1e-4 and load terms of 1e-9 … 1e-6 (9.2 at 1e-10 / 1e-13, one step
// 522; 3.7 at 1e-4 / 1e-4, 4.0 at 1e-2 / 1e-6, 10 at 1e-2 / 1e-2); these sit in the middle
constexpr double kEcpDampingRel = 1e-5;   // of 1/L
constexpr double kLoadDampingRel = 1e-7;  // of L/P

// a part's hull face carries it where its multiplier exceeds this fraction of the part's largest
// (the balanced warm start applies to parts flat on one face): the hull model's
// kDegenerateActiveFraction, far above round-off, far below the multipliers of faces that carry
constexpr double kCarryingFaceFraction = 1e-9;

// the centroid of the part's support feature in `direction` (body frame): a face's vertex centroid,
// an edge's midpoint, or the support point. A guess at a corner of a flat foot leaves the side
// faces' pairs (f_i = 0, l_i = 0) degenerate at the solution, and since a1_i is free on the face
// (the multi-patch MNCP has non-isolated solutions) Newton keeps it there and converges slowly
Vector3d SupportFeatureCentroid(const geometry::ConvexShape& part, const Vector3d& direction) {
  const auto* polyhedron = part.AsPolyhedron();
  const Vector3d support = part.Support(direction);
  if (polyhedron == nullptr) return support;
  const Vector3d d = direction.normalized();
  const double top = support.dot(d);
  const double width = top - part.Support(-d).dot(d);
  const double tolerance = kFeatureRelTol * std::max(std::abs(top), width);
  Vector3d sum = Vector3d::Zero();
  int count = 0;
  for (const Vector3d& v : polyhedron->hull().vertices) {
    if (v.dot(d) >= top - tolerance) {
      sum += v;
      ++count;
    }
  }
  return count > 0 ? Vector3d(sum / count) : support;
}

// a block's unknowns, each part contiguous in the layout: the free ones [a1, p_t, p_o, p_r] (on a
// plane; in the general form [a1, a2, s, p_t, p_o, p_r]) and the complementarity ones
// [l…, l_G…, p_n, σ]
int FreeSize(const MncpLayout::Contact& L) { return L.p_r + 1 - L.a1; }
int ComplementaritySize(const MncpLayout::Contact& L) { return L.sigma + 1 - L.l; }
int BlockSize(const MncpLayout::Contact& L) { return FreeSize(L) + ComplementaritySize(L); }

// a block's unknowns in the order [free…, complementarity…] (its slice of a warm start)
VectorXd PackBlock(const MncpLayout::Contact& L, const VectorXd& z) {
  VectorXd block(BlockSize(L));
  block << z.segment(L.a1, FreeSize(L)), z.segment(L.l, ComplementaritySize(L));
  return block;
}

void UnpackBlock(const MncpLayout::Contact& L, const VectorXd& block, VectorXd& z) {
  z.segment(L.a1, FreeSize(L)) = block.head(FreeSize(L));
  z.segment(L.l, ComplementaritySize(L)) = block.tail(ComplementaritySize(L));
}

// the dense LU's elimination order (McpOptions::elimination_order): the parts' complementarity
// unknowns, then their free ones, then the body's velocities, which every part's rows share;
// eliminated first they would fill the parts' blocks into one dense matrix (the desk's 62 × 62:
// 10 thousand multiply-adds a factorization in this order, 38 thousand in the layout's)
std::vector<int> PartsFirstOrder(const MncpLayout& layout) {
  const int complementarity = layout.size - layout.num_free;
  std::vector<int> order(layout.size);
  std::iota(order.begin(), order.begin() + complementarity, layout.num_free);
  std::iota(order.begin() + complementarity, order.end() - 6, 6);
  std::iota(order.end() - 6, order.end(), 0);
  return order;
}

class MultiPatchStepper {
 public:
  // `friction`: the contacts' friction for the step (Island::friction), in their order
  MultiPatchStepper(const Scene& scene, int body_index, std::vector<int> contact_ids,
                    const std::vector<Friction>& friction, McpWorkspace& solver_workspace)
      : scene_(scene),
        body_index_(body_index),
        contact_ids_(std::move(contact_ids)),
        friction_(friction),
        solver_workspace_(solver_workspace) {
    const Body& body = scene.bodies[body_index];
    if (body.parts.empty()) {
      parts_.push_back(body.hull.get());
    } else {
      for (const auto& part : body.parts) parts_.push_back(part.get());
    }
    for (int id : contact_ids_) {
      const geometry::ConvexShape& shape = *scene.obstacles[scene.contacts[id].obstacle].shape;
      if (!shape.IsHalfSpace()) {
        throw ModelInvalid(fmt::format(
            "multipatch model: body '{}' touches obstacle '{}', which is not a half-space; the "
            "model combines the parts' ECPs on one plane; use --model hull",
            body.name, scene.obstacles[scene.contacts[id].obstacle].name));
      }
    }
  }

  // one step of length h; not solved if every guess failed
  AdvanceResult Advance(double t, double h, BodyState& body,
                        std::vector<ContactState>& contacts) const {
    AdvanceResult result;
    result.model = StepModel::kMultiPatch;
    const Body& model = scene_.bodies[body_index_];
    const BodyProblem start = StartOfStep(scene_, body_index_, body, t, h);
    const Scales scales = BodyScales(model, body, start.p_ext, h);
    const MultiPatchProblem problem = MakeProblem(start, scales);
    const MncpLayout layout = MakeMultiPatchLayout(problem.body);
    if (!FreeFlightIsFinite(problem.body, result.tried)) {
      result.residual = INFINITY;
      return result;
    }

    // free flight: every part ends the step strictly above its plane when no contact acts, so
    // p = 0 with ν⁺ = ν + M⁻¹ p_ext is the MNCP's solution (as in the hull model)
    {
      const VectorXd z = MakeGuess(Guess::kSeparated, problem, layout, body, contacts, scales);
      bool apart = true;
      for (size_t i = 0; i < problem.body.contacts.size(); ++i) {
        const auto& cp = problem.body.contacts[i];
        if (!(cp.obstacle->Value(0, z.segment<3>(layout.contacts[i].a1)) > 0)) apart = false;
      }
      if (apart) {
        Commit(problem, layout, z, h, body, contacts);
        result.model = StepModel::kFree;
        result.solved = true;
        return result;
      }
    }

    // in contact: the warm start, then the guesses that fit the body's motion
    bool have_warm_start = true;
    for (int g = 0; g < problem.num_groups; ++g)
      have_warm_start &= FitsWarmStart(layout, problem, g, contacts[g].warm_start);
    const GuessLadder ladder = RestartLadder(have_warm_start, contacts, body, scales);

    McpOptions options;
    options.tolerance = scene_.solver.tolerance;
    options.max_iterations = scene_.solver.max_iterations;
    options.elimination_order = PartsFirstOrder(layout);
    // no pivot replay (pattern_lu.h): the replay depends on the patterns recorded by earlier
    // solves, so a run resumed from a saved state (a checkpoint, a pickled State) left the
    // uninterrupted one by an ulp (tests/python/test_state_pickle.py, dumbbell under
    // multipatch); it once cost the desk's 82-unknown Newton matrix 3.5 × fewer instructions, but
    // with the proximal terms the desk's median step takes twice as long with it (234 against
    // 114 µs, `options.replay_pivots = true` here)

    // SolveMcp hands J over zero (complementarity_solver.h)
    const McpFunction f = [&](const VectorXd& zz, VectorXd* F, Eigen::MatrixXd* J) {
      EvaluateMultiPatch(problem, layout, zz, F, J, /*jacobian_is_zero=*/true);
      if (J != nullptr) AddProximalTerms(problem, layout, *J);
    };
    const VectorXd row_scale = RowScales(problem.body, layout, scales);
    const VectorXd var_scale = VariableScales(problem.body, layout, scales);
    options.measure = [&](const VectorXd& zz, const VectorXd& F) {
      return MncpResidual(layout, zz, F, row_scale, var_scale,
                          {scales.length, options.tolerance, problem.body.c.cwiseAbs().maxCoeff()});
    };
    // the ladder as it is, then once more with iterates kept in the orthant of the
    // complementarity unknowns, as the hull model (engine/README.md, "Impacts")
    for (const bool project : {false, true}) {
      options.project_nonnegative = project;
      for (Guess guess : ladder) {
        VectorXd z = MakeGuess(guess, problem, layout, body, contacts, scales);
        // a warm start balanced where the body slides flat takes one Newton step to round-off,
        // where a polished one usually is already: it is verified on its residual alone
        // (engine/README.md, "A balanced warm start")
        const StartBalance balance =
            guess == Guess::kWarm
                ? BalanceMultiPatchSlidingStart(problem, layout, kCarryingFaceFraction, z)
                : StartBalance::kUnbalanced;
        options.start_tolerance = BalancedStartTolerance(balance, options.tolerance);
        options.verify_start_first = balance == StartBalance::kPolished;
        const McpResult solve =
            SolveMcp(f, layout.num_free, row_scale, var_scale, z, options, solver_workspace_);
        result.iterations += solve.iterations;
        result.residual = solve.residual;
        if (solve.converged && z.allFinite()) {
          Commit(problem, layout, z, h, body, contacts);
          result.solved = true;
          return result;
        }
        result.tried.push_back(
            {std::string(GuessName(guess)) + (project ? " (projected)" : ""), h,
             fmt::format("residual {:.3g} after {} iterations", solve.residual, solve.iterations)});
        ++result.retries;
      }
    }
    return result;
  }

 private:
  // the body's problem at the start of the step (StartOfStep) with one block per part and plane
  MultiPatchProblem MakeProblem(const BodyProblem& start, const Scales& scales) const {
    MultiPatchProblem problem;
    problem.weight_floor = kWeightFloorRel * scales.impulse;
    problem.ecp_damping = kEcpDampingRel / scales.length;
    problem.load_damping = kLoadDampingRel * scales.length / scales.impulse;
    BodyProblem& p = problem.body;
    p = start;
    for (size_t g = 0; g < contact_ids_.size(); ++g) {
      const ContactPair& pair = scene_.contacts[contact_ids_[g]];
      const geometry::ConvexShape* plane = scene_.obstacles[pair.obstacle].shape.get();
      for (const geometry::ConvexShape* part : parts_) {
        ContactProblem cp;
        cp.hull = part;
        cp.obstacle = plane;
        cp.friction = friction_[g];
        cp.tangent_reference = TangentReference(plane->Gradient(0, Vector3d::Zero()));
        cp.window.resize(part->NumConstraints());
        std::iota(cp.window.begin(), cp.window.end(), 0);
        p.contacts.push_back(cp);
        problem.group.push_back(static_cast<int>(g));
      }
    }
    problem.num_groups = static_cast<int>(contact_ids_.size());
    return problem;
  }

  // whether `warm` holds a block of the right size for every part of group g
  static bool FitsWarmStart(const MncpLayout& layout, const MultiPatchProblem& problem, int g,
                            const WarmStart& warm) {
    const auto* parts = warm.Get<MultiPatchWarmStart>();
    if (parts == nullptr) return false;
    size_t part = 0;
    for (size_t i = 0; i < problem.group.size(); ++i) {
      if (problem.group[i] != g) continue;
      if (part >= parts->parts.size() || parts->parts[part].size() != BlockSize(layout.contacts[i]))
        return false;
      ++part;
    }
    return part == parts->parts.size();
  }

  VectorXd MakeGuess(Guess guess, const MultiPatchProblem& problem, const MncpLayout& layout,
                     const BodyState& body, const std::vector<ContactState>& contacts,
                     const Scales& scales) const {
    const BodyProblem& bp = problem.body;
    VectorXd z = VectorXd::Zero(layout.size);
    const auto& [v_free, w_free] = bp.free;

    // warm start: the last step's velocities and every block's unknowns
    if (guess == Guess::kWarm) {
      z.segment<3>(0) = body.v_WB;
      z.segment<3>(3) = body.w_WB;
      std::vector<int> part(problem.num_groups, 0);
      for (size_t i = 0; i < bp.contacts.size(); ++i) {
        const int g = problem.group[i];
        UnpackBlock(layout.contacts[i],
                    (*contacts[g].warm_start.Get<MultiPatchWarmStart>()).parts[part[g]++], z);
      }
      return z;
    }

    // each part's lowest point on its plane at the free-flight pose
    z.segment<3>(0) = v_free;
    z.segment<3>(3) = w_free;
    const EndPose pose = PoseAfterStep(bp, v_free, w_free);
    const int blocks = static_cast<int>(bp.contacts.size());
    std::vector<Vector3d> support(blocks);
    std::vector<double> gap(blocks);
    std::vector<double> lowest(problem.num_groups, INFINITY);
    for (int i = 0; i < blocks; ++i) {
      const ContactProblem& cp = bp.contacts[i];
      const Vector3d n = MultiPatchFrame(cp).n;
      support[i] = pose.c + pose.R * SupportFeatureCentroid(*cp.hull, pose.R.transpose() * -n);
      gap[i] = cp.obstacle->Value(0, support[i]) / cp.obstacle->Gradient(0, support[i]).norm();
      lowest[problem.group[i]] = std::min(lowest[problem.group[i]], gap[i]);
    }
    const bool separated = guess == Guess::kSeparated;
    std::vector<int> touching(problem.num_groups, 0);
    for (int i = 0; i < blocks; ++i)
      if (gap[i] <= lowest[problem.group[i]] + kTouchingRelTol * scales.length)
        ++touching[problem.group[i]];

    const double sigma0 = kInitialSigmaFraction * scales.velocity;
    Vector3d v_guess = v_free;
    for (int i = 0; i < blocks; ++i) {
      const ContactProblem& cp = bp.contacts[i];
      const MncpLayout::Contact& L = layout.contacts[i];
      const int g = problem.group[i];
      const ContactFrame frame = MultiPatchFrame(cp);
      const Vector3d& n = frame.n;
      z.segment<3>(L.a1) = support[i];
      const Vector3d N = cp.obstacle->Gradient(0, support[i]);
      if (!L.on_plane()) {
        z.segment<3>(L.a2) = support[i] - gap[i] * n;
        z[L.l_g] = 1;
        z[L.s] = separated ? std::max(0.0, gap[i] / N.norm()) : gap[i] / N.norm();
      }
      // the part's constraint whose world normal is most opposed to N carries the cone
      const Vector3d y = pose.R.transpose() * (support[i] - pose.c);
      const int best = MostOpposedWindowConstraint(cp, pose.R, y, N);
      z[L.l + best] = 1;
      z[L.sigma] = sigma0;
      const bool touches = gap[i] <= lowest[g] + kTouchingRelTol * scales.length;
      if (separated || !touches) continue;

      // in contact: the group's normal impulse cancels gravity and the approach, shared evenly
      const double p_n_total = std::max(bp.mass * (-n.dot(v_free)), 0.0) +
                               std::max(-bp.mass * scene_.gravity.dot(n) * bp.h, 0.0);
      const double p_n = p_n_total / touching[g];
      z[L.p_n] = p_n;
      v_guess = body.v_WB - n * n.dot(body.v_WB);
      if (guess == Guess::kSliding) {
        const Friction& fr = cp.friction;
        const double v_t = frame.t.dot(v_guess), v_o = frame.o.dot(v_guess);
        const double v_r = n.dot(body.w_WB);
        SetSlidingFriction(fr, p_n, v_t, v_o, v_r, sigma0, L, z);
      }
    }
    z.segment<3>(0) = v_guess;
    return z;
  }

  void Commit(const MultiPatchProblem& problem, const MncpLayout& layout, const VectorXd& z,
              double h, BodyState& body, std::vector<ContactState>& contacts) const {
    const Vector3d v = z.segment<3>(0);
    const Vector3d w = z.segment<3>(3);
    body.p_WB += h * v;
    body.Q_WB = IntegrateOrientation(body.Q_WB, w, h);
    body.v_WB = v;
    body.w_WB = w;
    for (int g = 0; g < problem.num_groups; ++g) {
      ContactState& c = contacts[g];
      c.a1 = CombinedEcp(problem, layout, z, g);
      c.a2 = CombinedEcp(problem, layout, z, g, true);
      c.p_n = c.p_t = c.p_o = c.p_r = c.sigma = 0;
      MultiPatchWarmStart warm;
      double weighted_sigma = 0;
      for (size_t i = 0; i < problem.group.size(); ++i) {
        if (problem.group[i] != g) continue;
        const MncpLayout::Contact& L = layout.contacts[i];
        const ContactFrame frame = MultiPatchFrame(problem.body.contacts[i]);
        c.n = frame.n;
        c.t = frame.t;
        c.o = frame.o;
        // complementarity unknowns are ≥ 0 up to the tolerance; reported clamped
        const double p_n = std::max(z[L.p_n], 0.0);
        c.p_n += p_n;
        c.p_t += z[L.p_t];
        c.p_o += z[L.p_o];
        c.p_r += EquivalentMoment(frame, z.segment<3>(L.a1) - c.a1, z[L.p_t], z[L.p_o], z[L.p_r]);
        weighted_sigma += p_n * std::max(z[L.sigma], 0.0);
        warm.parts.push_back(PackBlock(L, z));
      }
      c.warm_start.Set(std::move(warm));
      // without a normal impulse any σ ≥ 0 solves the MNCP (trap 2); report the canonical 0
      c.sigma = c.p_n > 0 ? weighted_sigma / c.p_n : 0.0;
    }
  }

  const Scene& scene_;
  int body_index_;
  std::vector<int> contact_ids_;
  const std::vector<Friction>& friction_;
  std::vector<const geometry::ConvexShape*> parts_;
  McpWorkspace& solver_workspace_;
};

}  // namespace

ContactFrame MultiPatchFrame(const ContactProblem& cp) {
  const Vector3d normal = cp.obstacle->Gradient(0, Vector3d::Zero());
  return MakeContactFrame(normal, cp.tangent_reference);
}

double EquivalentMoment(const ContactFrame& f, const Vector3d& d, double p_t, double p_o,
                        double p_r) {
  return p_r - p_t * f.o.dot(d) + p_o * f.t.dot(d);
}

MncpLayout MakeMultiPatchLayout(const BodyProblem& problem) {
  std::vector<std::array<int, 2>> counts;
  for (const ContactProblem& cp : problem.contacts) {
    const int l_g_count = cp.obstacle->IsHalfSpace() ? 0 : cp.obstacle->NumConstraints();
    counts.push_back({static_cast<int>(cp.window.size()), l_g_count});
  }
  return LayOutContacts(6, counts);  // ν⁺ = (v⁺, ω⁺) first
}

Vector3d CombinedEcp(const MultiPatchProblem& problem, const MncpLayout& layout, const VectorXd& z,
                     int g, bool which_a2) {
  Vector3d sum = Vector3d::Zero();
  double weight = 0;
  for (size_t i = 0; i < problem.group.size(); ++i) {
    if (problem.group[i] != g) continue;
    const MncpLayout::Contact& L = layout.contacts[i];
    const double w = std::max(z[L.p_n], 0.0) + problem.weight_floor;
    sum += w * (which_a2 ? ContactGapAt(L, problem.body.contacts[i].obstacle, z).a2
                         : Vector3d(z.segment<3>(L.a1)));
    weight += w;
  }
  return sum / weight;
}

void EvaluateMultiPatch(const MultiPatchProblem& problem, const MncpLayout& layout,
                        const VectorXd& z, VectorXd* F_out, Eigen::MatrixXd* J_out,
                        bool jacobian_is_zero) {
  ECPSIM_DEMAND(problem.weight_floor > 0);
  ECPSIM_DEMAND(problem.group.size() == problem.body.contacts.size());
  // the geometry, Newton–Euler and the per-block friction rows of the hull model's MNCP; the
  // friction rows are replaced below
  EvaluateMncp(problem.body, layout, z, F_out, J_out, jacobian_is_zero);
  VectorXd& F = *F_out;
  const bool with_jacobian = J_out != nullptr;
  const double h = problem.body.h;
  const Vector3d v = z.segment<3>(0);
  const Vector3d w = z.segment<3>(3);
  const EndPose end = PoseAfterStep(problem.body, v, w);

  for (int g = 0; g < problem.num_groups; ++g) {
    std::vector<int> blocks;
    double weight = 0;
    for (size_t i = 0; i < problem.group.size(); ++i) {
      if (problem.group[i] != g) continue;
      blocks.push_back(static_cast<int>(i));
      weight += std::max(z[layout.contacts[i].p_n], 0.0) + problem.weight_floor;
    }
    if (blocks.empty()) continue;
    const Vector3d a1 = CombinedEcp(problem, layout, z, g);
    // ∂a1/∂a1_j = (w_j / W) I and ∂a1/∂p_n,j = (a1_j − a1) / W while p_n,j > 0
    std::vector<double> da1_da1j(blocks.size());
    std::vector<Vector3d> da1_dpnj(blocks.size());
    for (size_t j = 0; j < blocks.size(); ++j) {
      const MncpLayout::Contact& Lj = layout.contacts[blocks[j]];
      da1_da1j[j] = (std::max(z[Lj.p_n], 0.0) + problem.weight_floor) / weight;
      da1_dpnj[j] =
          z[Lj.p_n] > 0 ? Vector3d((z.segment<3>(Lj.a1) - a1) / weight) : Vector3d::Zero();
    }

    // the sliding velocity at the combined ECP at the end of the step
    const ContactFrame frame = MultiPatchFrame(problem.body.contacts[blocks[0]]);
    const Vector3d& n = frame.n;
    const Vector3d& t = frame.t;
    const Vector3d& o = frame.o;
    const Vector3d r = a1 - end.c;
    const Vector3d v_contact = v + w.cross(r);
    const double v_t = t.dot(v_contact), v_o = o.dot(v_contact), v_r = n.dot(w);

    for (size_t bi = 0; bi < blocks.size(); ++bi) {
      const int i = blocks[bi];
      const MncpLayout::Contact& L = layout.contacts[i];
      const Friction& fr = problem.body.contacts[i].friction;
      const double p_t = z[L.p_t], p_o = z[L.p_o], p_r = z[L.p_r];
      const double p_n = z[L.p_n], sigma = z[L.sigma];
      const Vector3d d = z.segment<3>(L.a1) - a1;
      const double p_rE = EquivalentMoment(frame, d, p_t, p_o, p_r);
      const double et2 = fr.e_t * fr.e_t, eo2 = fr.e_o * fr.e_o, er2 = fr.e_r * fr.e_r;

      // maximum dissipation of patch i in (p_t, p_o, p_rE) at the combined ECP's velocity
      const double p_hat = SetFrictionRows(fr, p_n, v_t, v_o, v_r, p_t, p_o, p_rE, sigma, L, F);

      if (!with_jacobian) continue;
      Eigen::MatrixXd& J = *J_out;
      for (int row : {L.p_t, L.p_o, L.p_r, L.sigma}) J.row(row).setZero();

      // ∂p_rE/∂d, and d = a1_i − a1 depends on every a1_j and p_n,j of the group
      const RowVector3d drE_dd = (-p_t * o + p_o * t).transpose();
      const auto add_through_d = [&](int row, double factor) {
        for (size_t j = 0; j < blocks.size(); ++j) {
          const MncpLayout::Contact& Lj = layout.contacts[blocks[j]];
          const double dd_da1j = (j == bi ? 1.0 : 0.0) - da1_da1j[j];
          J.block<1, 3>(row, Lj.a1) += factor * dd_da1j * drE_dd;
          J(row, Lj.p_n) -= factor * drE_dd.dot(da1_dpnj[j]);
        }
      };
      // v_c = v + ω × (a1 − c − h v): ∂/∂v = I − h[ω]×, ∂/∂ω = −[r]×, ∂/∂a1 = [ω]×
      const Matrix3d dvc_dv = Matrix3d::Identity() - h * Skew(w);
      const Matrix3d dvc_dw = -Skew(r);
      const Matrix3d dvc_da1 = Skew(w);
      const auto add_speed = [&](int row, const Vector3d& axis, double scale) {
        const RowVector3d axis_t = axis.transpose();
        J.block<1, 3>(row, 0) += scale * axis_t * dvc_dv;
        J.block<1, 3>(row, 3) += scale * axis_t * dvc_dw;
        const RowVector3d through_a1 = scale * axis_t * dvc_da1;
        for (size_t j = 0; j < blocks.size(); ++j) {
          const MncpLayout::Contact& Lj = layout.contacts[blocks[j]];
          J.block<1, 3>(row, Lj.a1) += da1_da1j[j] * through_a1;
          J(row, Lj.p_n) += through_a1.dot(da1_dpnj[j]);
        }
      };

      add_speed(L.p_t, t, et2 * fr.mu * p_n);
      J(L.p_t, L.p_n) += et2 * fr.mu * v_t;
      J(L.p_t, L.p_t) += sigma;
      J(L.p_t, L.sigma) += p_t;

      add_speed(L.p_o, o, eo2 * fr.mu * p_n);
      J(L.p_o, L.p_n) += eo2 * fr.mu * v_o;
      J(L.p_o, L.p_o) += sigma;
      J(L.p_o, L.sigma) += p_o;

      J.block<1, 3>(L.p_r, 3) += er2 * fr.mu * p_n * n.transpose();
      J(L.p_r, L.p_n) += er2 * fr.mu * v_r;
      J(L.p_r, L.p_r) += sigma;
      J(L.p_r, L.p_t) += -sigma * o.dot(d);
      J(L.p_r, L.p_o) += sigma * t.dot(d);
      J(L.p_r, L.sigma) += p_rE;
      add_through_d(L.p_r, sigma);

      // μ p_n − ‖p̂‖; at p̂ = 0 the norm's generalized gradient contains 0, which is used
      J(L.sigma, L.p_n) = fr.mu;
      if (p_hat > 0) {
        const double c_r = p_rE / (er2 * p_hat);
        J(L.sigma, L.p_t) += -(p_t / (et2 * p_hat) - c_r * o.dot(d));
        J(L.sigma, L.p_o) += -(p_o / (eo2 * p_hat) + c_r * t.dot(d));
        J(L.sigma, L.p_r) += -c_r;
        add_through_d(L.sigma, -c_r);
      }
    }
  }
}

void AddProximalTerms(const MultiPatchProblem& problem, const MncpLayout& layout,
                      Eigen::MatrixXd& J) {
  // a group of one part is the hull model's contact, whose solutions are isolated: there the
  // terms would only perturb the Newton step (scenes/slide.yaml under multipatch took 1.64
  // iterations per step on average with them, 0.66 without)
  std::vector<int> parts(problem.num_groups, 0);
  for (int g : problem.group) ++parts[g];
  for (size_t i = 0; i < problem.body.contacts.size(); ++i) {
    if (parts[problem.group[i]] < 2) continue;
    const MncpLayout::Contact& L = layout.contacts[i];
    // a1 along the plane: where a flat part's ECP lies on its face is not determined (the cone
    // rows are a1's on a plane, a2's in the general form)
    const Vector3d n = MultiPatchFrame(problem.body.contacts[i]).n;
    const int cone_rows = L.on_plane() ? L.a1 : L.a2;
    J.block<3, 3>(cone_rows, L.a1) +=
        problem.ecp_damping * (Matrix3d::Identity() - n * n.transpose());
    // p_n: how coplanar parts share the normal load is not determined
    J(L.p_n, L.p_n) += problem.load_damping;
  }
}

// (no last resort: every effort is the usual one)
AdvanceResult MultiPatchModel::Advance(const Island& island, double t, double h, IslandState& state,
                                       Effort) const {
  ECPSIM_DEMAND(island.bodies.size() == 1);
  return MultiPatchStepper(scene_, island.bodies[0], island.contacts, island.friction,
                           workspace_.Part<McpWorkspace>())
      .Advance(t, h, state.bodies[0], state.contacts);
}

}  // namespace ecpsim::engine
