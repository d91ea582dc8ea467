#include "engine/point_contact_model.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <fmt/format.h>

#include "engine/complementarity_solver.h"
#include "engine/lemke_solver.h"
#include "engine/mncp_system.h"
#include "engine/rotation.h"
#include "engine/obstacle_queries.h"
#include "common/errors.h"

namespace ecpsim::engine {
namespace {

using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Vector6d = Eigen::Matrix<double, 6, 1>;

// the activation distance: a hull vertex becomes a contact point when its gap is at most
//   max(kActivationRel × r, kActivationSpeedFactor × h × (|v| + |ω| r))
// with r the largest distance of a hull vertex from the CM. The first term (1 mm on a 1 m body)
// catches vertices that rest on G up to round-off and the slight tilts of a resting body; the
// second is the farthest a vertex can move in one step at the body's speed (start or free-flight
// velocities, whichever is larger), doubled as a margin for the speed that impulses at other
// points add (a box landing on one corner swings its other corners down). Vertices farther away
// are ignored, as in the usual practice: a body faster than that bound, or a thin obstacle, can
// be tunnelled through
constexpr double kActivationRel = 1e-3;
constexpr double kActivationSpeedFactor = 2;
// vertices of a smooth hull (the dumbbell's cylinder) from its display tessellation
constexpr int kSmoothHullSegments = 48;
// Lemke's solution is exact up to round-off in the scaled tableau (entries O(1)); a larger
// complementarity residual means a numerically bad pivot sequence and the step is retried at h/2
constexpr double kLcpResidualTol = 1e-9;  // relative to the velocity and impulse scales
// the fallback Newton solve of an LCP Lemke could not finish: far more than the handful a
// contact LCP needs from z = 0, a bound on the work of a hopeless one
constexpr int kLcpNewtonIterations = 200;
// dimensionless (the scaled LCP's entries are O(1)): the fallback's compliance, 1e-3 of the
// residual bar kLcpResidualTol
constexpr double kLcpNewtonRegularization = 1e-12;

// one contact point: a hull vertex near an obstacle at the start of the step
struct ContactPoint {
  int pair = 0;          // index into the body's contact list
  Vector3d y_B;          // body frame, m
  Vector3d x;            // world, start of the step, m
  Vector3d n;            // unit obstacle normal at x (world)
  double psi = 0;        // gap along n, m (negative: penetration)
  double mu = 0;         // Coulomb coefficient
  Vector3d directions[kPointContactFrictionDirections];  // unit tangents at equal angles
};

std::vector<Vector3d> HullVertices(const geometry::ConvexShape& hull) {
  if (const auto* polyhedron = hull.AsPolyhedron())
    return polyhedron->hull().vertices;
  return hull.Tessellate(kSmoothHullSegments).vertices;
}

// the wrench column (u; r × u) of a unit impulse along u at x, and the velocity row of x along u
Vector6d WrenchColumn(const Vector3d& u, const Vector3d& r) {
  Vector6d column;
  column << u, r.cross(u);
  return column;
}

// w = M z + q, 0 ≤ z ⊥ w ≥ 0 (already scaled to O(1) entries) by SolveMcp from z = 0, on M plus
// a compliance of kLcpNewtonRegularization on the first `m` (impulse) rows: a resting body's
// coplanar points make that block singular and the solutions non-isolated, where semismooth
// Newton stalls; regularized the solution is unique and moves by about the compliance, far below
// the bar. Solved when the residual of the *original* LCP meets the same bar as Lemke's.
// `pivots` counts Newton iterations.
LcpResult SolveLcpNewton(const MatrixXd& M, const VectorXd& q, int m) {
  MatrixXd regularized = M;
  regularized.diagonal().head(m).array() += kLcpNewtonRegularization;
  const McpFunction f = [&](const VectorXd& z, VectorXd* F, MatrixXd* J) {
    *F = regularized * z + q;
    if (J != nullptr) *J = regularized;
  };
  const VectorXd ones = VectorXd::Ones(q.size());
  McpOptions options;
  options.tolerance = kLcpResidualTol;
  options.max_iterations = kLcpNewtonIterations;
  options.project_nonnegative = true;
  LcpResult result;
  result.z = VectorXd::Zero(q.size());
  const McpResult mcp = SolveMcp(f, 0, ones, ones, result.z, options);
  result.w = M * result.z + q;
  result.pivots = mcp.iterations;
  result.residual = 0;
  for (int i = 0; i < q.size(); ++i) {
    result.residual = std::max({result.residual, -result.z[i], -result.w[i],
                                std::abs(std::min(result.z[i], result.w[i]))});
  }
  result.status = mcp.converged && result.residual <= kLcpResidualTol && result.z.allFinite()
                      ? LcpStatus::kSolved
                      : LcpStatus::kRayTermination;
  return result;
}

class PointContactStepper {
 public:
  PointContactStepper(const Scene& scene, int body_index, const std::vector<int>& contact_ids)
      : scene_(scene), body_index_(body_index), contact_ids_(contact_ids) {}

  AdvanceResult Advance(double t, double h, BodyState& body,
                        std::vector<ContactState>& contacts) const {
    AdvanceResult result;
    const Body& model = scene_.bodies[body_index_];
    const BodyProblem problem = StartOfStep(scene_, body_index_, body, t, h);
    const FreeFlight& free = problem.free;

    // contact points: hull vertices within the activation distance of each obstacle
    const std::vector<Vector3d> vertices = HullVertices(*model.hull);
    double radius = 0;
    for (const Vector3d& y : vertices) radius = std::max(radius, y.norm());
    const double speed = std::max(body.v_WB.norm(), free.v.norm()) +
                         std::max(body.w_WB.norm(), free.w.norm()) * radius;
    const double activation =
        std::max(kActivationRel * radius, kActivationSpeedFactor * h * speed);
    std::vector<ContactPoint> points;
    std::vector<Vector3d> lowest(contact_ids_.size(), Vector3d::Zero());
    for (size_t k = 0; k < contact_ids_.size(); ++k) {
      const ContactPair& pair = scene_.contacts[contact_ids_[k]];
      const geometry::ConvexShape& obstacle = *scene_.obstacles[pair.obstacle].shape;
      double lowest_gap = INFINITY;
      for (const Vector3d& y : vertices) {
        const Vector3d x = problem.c + problem.R * y;
        const int j = LargestConstraint(obstacle, x);
        const Vector3d gradient = obstacle.Gradient(j, x);
        const double psi = obstacle.Value(j, x) / gradient.norm();
        if (psi < lowest_gap) {
          lowest_gap = psi;
          lowest[k] = y;
        }
        if (!(psi <= activation)) continue;
        ContactPoint point;
        point.pair = static_cast<int>(k);
        point.y_B = y;
        point.x = x;
        point.n = gradient.normalized();
        point.psi = psi;
        point.mu = pair.friction.mu;
        const ContactFrame frame = MakeContactFrame(point.n, TangentReference(point.n));
        for (int j = 0; j < kPointContactFrictionDirections; ++j) {
          const double angle = 2 * M_PI * j / kPointContactFrictionDirections;
          point.directions[j] = std::cos(angle) * frame.t + std::sin(angle) * frame.o;
        }
        points.push_back(point);
      }
    }

    // no point near an obstacle: free flight in closed form, as the hull model
    const int k = static_cast<int>(points.size());
    constexpr int d = kPointContactFrictionDirections;
    VectorXd impulses = VectorXd::Zero((1 + d) * k);  // (p_n, β), N·s
    VectorXd lambda = VectorXd::Zero(k);               // m/s
    Vector3d v = free.v, w = free.w;
    MatrixXd W(6, (1 + d) * k);  // wrench columns: N (k), then D (d per point)
    double lcp_residual = 0;
    if (k > 0) {
      for (int i = 0; i < k; ++i) {
        const Vector3d r = points[i].x - problem.c;
        W.col(i) = WrenchColumn(points[i].n, r);
        for (int j = 0; j < d; ++j) W.col(k + d * i + j) = WrenchColumn(points[i].directions[j], r);
      }
      // M⁻¹ W with M = diag(m I, R I Rᵀ)
      MatrixXd AW(6, W.cols());
      AW.topRows<3>() = W.topRows<3>() / problem.mass;
      AW.bottomRows<3>() = problem.inertia_world.ldlt().solve(W.bottomRows<3>());
      Vector6d nu_free;
      nu_free << free.v, free.w;

      // the LCP in z = (p_n, β, λ) after eliminating v⁺ = ν_free + M⁻¹ (N p_n + D β):
      //   w_n = Nᵀ M⁻¹ (N p_n + D β) + Nᵀ ν_free + ψ/h
      //   w_β = Dᵀ M⁻¹ (N p_n + D β) + E λ + Dᵀ ν_free
      //   w_λ = U p_n − Eᵀ β           (U = diag μ_i, E = blockdiag of ones)
      const int m = (1 + d) * k, size = m + k;
      MatrixXd M = MatrixXd::Zero(size, size);
      VectorXd q = VectorXd::Zero(size);
      M.topLeftCorner(m, m) = W.transpose() * AW;
      q.head(m) = W.transpose() * nu_free;
      for (int i = 0; i < k; ++i) {
        q[i] += points[i].psi / h;
        for (int j = 0; j < d; ++j) {
          M(k + d * i + j, m + i) = 1;
          M(m + i, k + d * i + j) = -1;
        }
        M(m + i, i) = points[i].mu;
      }

      // scaled so that the tableau's entries are O(1): velocities by V (the largest |q|),
      // impulses by P = m V; the pivot tolerances are relative
      const double V = q.head(m).cwiseAbs().maxCoeff();
      if (q.minCoeff() < 0 && V > 0) {
        const double P = problem.mass * V;
        VectorXd column_scale(size), row_scale(size);
        column_scale.head(m).setConstant(P);
        column_scale.tail(k).setConstant(V);
        row_scale.head(m).setConstant(1 / V);
        row_scale.tail(k).setConstant(1 / P);
        // in place: on a disc of 49 points M is 490 × 490
        M.array().colwise() *= row_scale.array();
        M.array().rowwise() *= column_scale.transpose().array();
        LcpResult lcp = SolveLcpLemke(M, row_scale.cwiseProduct(q));
        result.iterations += lcp.pivots;
        if (lcp.status != LcpStatus::kSolved) {
          // Lemke's pivoting can end on a ray of a degenerate LCP (coplanar resting points, in
          // some orders) although a solution exists; the LCP as a complementarity problem for
          // the semismooth Newton solver finds it
          const LcpResult newton = SolveLcpNewton(M, row_scale.cwiseProduct(q), m);
          result.iterations += newton.pivots;
          if (newton.status == LcpStatus::kSolved) lcp = newton;
        }
        if (lcp.status != LcpStatus::kSolved || !(lcp.residual <= kLcpResidualTol)) {
          result.residual = lcp.status == LcpStatus::kSolved ? lcp.residual : INFINITY;
          result.tried = fmt::format("Lemke at h = {:.3g} s: {} after {} pivots ({} contact "
                                     "points, LCP size {}, scaled residual {:.3g})",
                                     h, LcpStatusName(lcp.status), lcp.pivots, k, size,
                                     lcp.residual);
          return result;
        }
        lcp_residual = lcp.residual;
        const VectorXd z = column_scale.cwiseProduct(lcp.z);
        impulses = z.head(m);
        lambda = z.tail(k);
        const Vector6d dnu = AW * impulses;
        v += dnu.head<3>();
        w += dnu.tail<3>();
      }
    }
    if (!v.allFinite() || !w.allFinite()) {
      result.residual = INFINITY;
      result.tried = fmt::format("Lemke at h = {:.3g} s: non-finite velocities ({} contact points)",
                                 h, k);
      return result;
    }

    // the pose advances with v⁺ as in the hull model
    const EndPose end = PoseAfterStep(problem, v, w);
    body.p_WB += h * v;
    body.Q_WB = IntegrateOrientation(body.Q_WB, w, h);
    body.v_WB = v;
    body.w_WB = w;
    result.residual = lcp_residual;

    // per obstacle: summed impulses at their centre of pressure (points moved with the body)
    for (size_t c = 0; c < contact_ids_.size(); ++c) {
      const geometry::ConvexShape& obstacle =
          *scene_.obstacles[scene_.contacts[contact_ids_[c]].obstacle].shape;
      ContactState& state = contacts[c];
      double p_n = 0, sigma = 0;
      Vector3d centre = Vector3d::Zero(), normal = Vector3d::Zero(), friction = Vector3d::Zero();
      for (int i = 0; i < k; ++i) {
        if (points[i].pair != static_cast<int>(c)) continue;
        const double p_i = impulses[i];
        p_n += p_i;
        centre += p_i * (end.c + end.R * points[i].y_B);
        normal += p_i * points[i].n;
        sigma += p_i * lambda[i];
        for (int j = 0; j < d; ++j) friction += impulses[k + d * i + j] * points[i].directions[j];
      }
      if (p_n > 0) {
        state.a1 = centre / p_n;
        state.sigma = sigma / p_n;
      } else {
        state.a1 = end.c + end.R * lowest[c];
        state.sigma = 0;
      }
      if (!(p_n > 0) || !(normal.norm() > 0)) normal = ObstacleNormalToward(obstacle, state.a1);
      const ContactFrame frame = MakeContactFrame(normal, TangentReference(normal.normalized()));
      // torsion: the moment of the points' friction impulses about a1 along n
      double p_r = 0;
      for (int i = 0; i < k; ++i) {
        if (points[i].pair != static_cast<int>(c)) continue;
        Vector3d f_i = Vector3d::Zero();
        for (int j = 0; j < d; ++j) f_i += impulses[k + d * i + j] * points[i].directions[j];
        p_r += frame.n.dot((end.c + end.R * points[i].y_B - state.a1).cross(f_i));
      }
      state.a2 = ProjectOntoObstacle(obstacle, state.a1).first;
      state.p_n = p_n;
      state.p_t = frame.t.dot(friction);
      state.p_o = frame.o.dot(friction);
      state.p_r = p_r;
      state.n = frame.n;
      state.t = frame.t;
      state.o = frame.o;
      // the model needs no warm start (Lemke starts from its own basis)
      state.warm_start = std::monostate();
    }
    result.solved = true;
    return result;
  }

 private:
  const Scene& scene_;
  int body_index_;
  const std::vector<int>& contact_ids_;
};

}  // namespace

AdvanceResult PointContactModel::Advance(const Island& island, double t, double h,
                                         IslandState& state) const {
  return AdvanceOneBody<PointContactStepper>(scene_, island, t, h, state);
}

}  // namespace ecpsim::engine
