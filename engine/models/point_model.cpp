#include "engine/models/point_model.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <Eigen/Cholesky>

#include "common/errors.h"
#include "engine/mncp/mncp_system.h"
#include "engine/obstacle_queries.h"
#include "engine/rotation.h"
#include "engine/solver/complementarity_solver.h"
#include "engine/solver/lemke_solver.h"

namespace ecpsim::engine {
namespace {

using Eigen::Matrix3d;
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
// be tunnelled through. Between two bodies r is the larger body's and the speed the sum of both
constexpr double kActivationRel = 1e-3;
constexpr double kActivationSpeedFactor = 2;
// relative to the size r of the body whose face a vertex is tested against: a vertex within this
// of two of its face planes lies on their common edge (a pusher's corner level with a box's side,
// stacked boxes' corners), where either face's plane is the body's boundary up to round-off; the
// face is then chosen by the direction between the two bodies (FaceGap)
constexpr double kFaceTieRel = 1e-6;
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

constexpr int kDirections = kPointContactFrictionDirections;

std::vector<Vector3d> HullVertices(const geometry::ConvexShape& hull) {
  if (const auto* polyhedron = hull.AsPolyhedron()) return polyhedron->hull().vertices;
  return hull.Tessellate(kSmoothHullSegments).vertices;
}

double Radius(const std::vector<Vector3d>& vertices) {
  double radius = 0;
  for (const Vector3d& y : vertices) radius = std::max(radius, y.norm());
  return radius;
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
LcpResult SolveLcpNewton(const MatrixXd& M, const VectorXd& q, int m, McpWorkspace& workspace) {
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
  const McpResult mcp = SolveMcp(f, 0, ones, ones, result.z, options, workspace);
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

// One end of a contact pair: a dynamic body of the island (velocities unknown), a kinematic body
// (its prescribed twist) or a fixed obstacle (world-frame shape, at rest).
struct Side {
  int island_body = -1;                                 // ≥ 0: index into the island's bodies
  const geometry::ConvexShape* shape = nullptr;         // in the frame (c, R)
  const std::vector<Vector3d>* vertices = nullptr;      // hull vertices (bodies only)
  Vector3d c = Vector3d::Zero();                        // m, world: frame origin (a body's CM)
  Matrix3d R = Matrix3d::Identity();                    // frame → world at the start of the step
  Vector3d v = Vector3d::Zero(), w = Vector3d::Zero();  // known twist (kinematic), else 0
  double radius = 0;                                    // m, largest vertex distance from c
  double speed = 0;                                     // m/s, bound on a point's speed in the step
  EndPose end;                                          // the pose at the end of the step

  bool Dynamic() const { return island_body >= 0; }
  // the world velocity of the side's material point at x with its known twist
  Vector3d KnownVelocity(const Vector3d& x) const { return v + w.cross(x - c); }
};

// one contact point: a hull vertex of F near G, or of G near F, at the start of the step
struct ContactPoint {
  int pair = 0;                      // index into the island's contact list
  bool on_f = true;                  // the vertex is F's (else G's)
  Vector3d y;                        // the vertex in its body's frame, m
  Vector3d x;                        // world, start of the step, m
  Vector3d n;                        // unit normal from G into F (world)
  double psi = 0;                    // gap along n, m (negative: penetration)
  double mu = 0;                     // Coulomb coefficient
  double mass = 0;                   // kg, the impulse scale's mass: the lighter dynamic body's
  Vector3d directions[kDirections];  // unit tangents at equal angles
};

// the gap of world point x to the convex shape of `side` and the shape's unit outward normal
// there: its largest constraint (normalized), or — for a moving G, when several lie within
// kFaceTieRel r of the largest — the one of those whose normal points most along `toward` (from
// the shape's body to the vertex's body: the face they meet across)
struct FaceGap {
  double psi = INFINITY;
  Vector3d normal = Vector3d::UnitZ();
};

FaceGap GapToObstacle(const geometry::ConvexShape& obstacle, const Vector3d& x) {
  const int j = LargestConstraint(obstacle, x);
  const Vector3d gradient = obstacle.Gradient(j, x);
  return {obstacle.Value(j, x) / gradient.norm(), gradient.normalized()};
}

FaceGap GapToBody(const Side& side, const Vector3d& x, const Vector3d& toward) {
  const Vector3d y = side.R.transpose() * (x - side.c);
  const geometry::ConvexShape& shape = *side.shape;
  const int count = shape.NumConstraints();
  std::vector<double> values(count);
  double largest = -INFINITY;
  for (int j = 0; j < count; ++j) {
    values[j] = shape.Value(j, y) / shape.Gradient(j, y).norm();
    largest = std::max(largest, values[j]);
  }
  const double tie = kFaceTieRel * side.radius;
  FaceGap best;
  double best_alignment = -INFINITY;
  for (int j = 0; j < count; ++j) {
    if (!(values[j] >= largest - tie)) continue;
    const Vector3d normal = side.R * shape.Gradient(j, y).normalized();
    const double alignment = normal.dot(toward);
    if (alignment > best_alignment) {
      best_alignment = alignment;
      best = {values[j], normal};
    }
  }
  return best;
}

class PointIslandStepper {
 public:
  PointIslandStepper(const Scene& scene, const PointModel::SideVertices& vertices,
                     const Island& island, McpWorkspace& solver_workspace)
      : scene_(scene), vertices_(vertices), island_(island), solver_workspace_(solver_workspace) {}

  AdvanceResult Advance(double t, double h, IslandState& state) const {
    AdvanceResult result;
    result.model = StepModel::kPoint;
    const int num_bodies = static_cast<int>(island_.bodies.size());
    std::vector<BodyProblem> problems;
    for (int i = 0; i < num_bodies; ++i)
      problems.push_back(StartOfStep(scene_, island_.bodies[i], state.bodies[i], t, h));

    // both ends of every contact at the start of the step
    std::vector<Side> f_sides, g_sides;
    for (int id : island_.contacts) {
      const ContactPair& pair = scene_.contacts[id];
      f_sides.push_back(BodySide(pair.body, pair.part, problems, state, t, h));
      if (pair.WithBody()) {
        g_sides.push_back(BodySide(pair.other_body, pair.other_part, problems, state, t, h));
      } else {
        Side obstacle;
        obstacle.shape = scene_.obstacles[pair.obstacle].shape.get();
        obstacle.end = {Vector3d::Zero(), Matrix3d::Identity()};
        g_sides.push_back(obstacle);
      }
    }

    // contact points: F's vertices within the activation distance of G, and G's of F (bodies)
    std::vector<ContactPoint> points;
    std::vector<Vector3d> lowest(island_.contacts.size(), Vector3d::Zero());
    for (size_t k = 0; k < island_.contacts.size(); ++k) {
      const ContactPair& pair = scene_.contacts[island_.contacts[k]];
      const Side& f = f_sides[k];
      const Side& g = g_sides[k];
      const double mass = g.Dynamic()
                              ? std::min(problems[f.island_body].mass, problems[g.island_body].mass)
                              : problems[f.island_body].mass;
      const double activation =
          pair.WithBody()
              ? std::max(kActivationRel * std::max(f.radius, g.radius),
                         kActivationSpeedFactor * h * (f.speed + g.speed))
              : std::max(kActivationRel * f.radius, kActivationSpeedFactor * h * f.speed);
      double lowest_gap = INFINITY;
      for (const Vector3d& y : *f.vertices) {
        const Vector3d x = f.c + f.R * y;
        const FaceGap gap =
            pair.WithBody() ? GapToBody(g, x, f.c - g.c) : GapToObstacle(*g.shape, x);
        if (gap.psi < lowest_gap) {
          lowest_gap = gap.psi;
          lowest[k] = y;
        }
        if (gap.psi <= activation)
          points.push_back(MakePoint(static_cast<int>(k), true, y, x, gap.normal, gap.psi,
                                     island_.friction[k].mu, mass));
      }
      if (!pair.WithBody()) continue;
      for (const Vector3d& y : *g.vertices) {
        const Vector3d x = g.c + g.R * y;
        const FaceGap gap = GapToBody(f, x, g.c - f.c);
        // F's outward normal points from F into G: the pair's normal is its opposite
        if (gap.psi <= activation)
          points.push_back(MakePoint(static_cast<int>(k), false, y, x, -gap.normal, gap.psi,
                                     island_.friction[k].mu, mass));
      }
    }

    // no point near anything: free flight in closed form, as the hull model
    const int k = static_cast<int>(points.size());
    constexpr int d = kDirections;
    VectorXd impulses = VectorXd::Zero((1 + d) * k);  // (p_n, β), N·s
    VectorXd lambda = VectorXd::Zero(k);              // m/s
    VectorXd nu(6 * num_bodies);                      // (v⁺, ω⁺) per island body
    for (int i = 0; i < num_bodies; ++i)
      nu.segment<6>(6 * i) << problems[i].free.v, problems[i].free.w;
    double lcp_residual = 0;
    if (k > 0) {
      // wrench columns: N (k), then D (d per point); the impulse acts on F at x and its opposite
      // on G when G is a dynamic body of the island
      const int m = (1 + d) * k, size = m + k;
      MatrixXd W = MatrixXd::Zero(6 * num_bodies, m);
      VectorXd known = VectorXd::Zero(m);  // G's prescribed velocity at x along each direction
      for (int i = 0; i < k; ++i) {
        const ContactPoint& point = points[i];
        const Side& f = f_sides[point.pair];
        const Side& g = g_sides[point.pair];
        const auto add = [&](int column, const Vector3d& u) {
          W.block<6, 1>(6 * f.island_body, column) = WrenchColumn(u, point.x - f.c);
          if (g.Dynamic()) {
            W.block<6, 1>(6 * g.island_body, column) = -WrenchColumn(u, point.x - g.c);
          } else {
            known[column] = u.dot(g.KnownVelocity(point.x));
          }
        };
        add(i, point.n);
        for (int j = 0; j < d; ++j) add(k + d * i + j, point.directions[j]);
      }
      // M⁻¹ W with M = blockdiag(m I, R I Rᵀ) per body
      MatrixXd AW(6 * num_bodies, m);
      for (int b = 0; b < num_bodies; ++b) {
        AW.middleRows<3>(6 * b) = W.middleRows<3>(6 * b) / problems[b].mass;
        AW.middleRows<3>(6 * b + 3) =
            problems[b].inertia_world.ldlt().solve(W.middleRows<3>(6 * b + 3));
      }

      // the LCP in z = (p_n, β, λ) after eliminating ν⁺ = ν_free + M⁻¹ (N p_n + D β):
      //   w_n = Nᵀ M⁻¹ (N p_n + D β) + Nᵀ ν_free − n·v_G(x) + ψ/h
      //   w_β = Dᵀ M⁻¹ (N p_n + D β) + E λ + Dᵀ ν_free − D·v_G(x)
      //   w_λ = U p_n − Eᵀ β           (U = diag μ_i, E = blockdiag of ones)
      // (v_G the prescribed velocity of a kinematic G, 0 for a fixed one; a dynamic G's
      // velocity is in ν and its block of N and D)
      MatrixXd M = MatrixXd::Zero(size, size);
      VectorXd q = VectorXd::Zero(size);
      M.topLeftCorner(m, m) = W.transpose() * AW;
      q.head(m) = W.transpose() * nu - known;
      for (int i = 0; i < k; ++i) {
        q[i] += points[i].psi / h;
        for (int j = 0; j < d; ++j) {
          M(k + d * i + j, m + i) = 1;
          M(m + i, k + d * i + j) = -1;
        }
        M(m + i, i) = points[i].mu;
      }

      // scaled so that the tableau's entries are O(1): velocities by V (the largest |q|),
      // a point's impulses by P = m V (m its lighter body's mass); the pivot tolerances are
      // relative
      const double V = q.head(m).cwiseAbs().maxCoeff();
      if (q.minCoeff() < 0 && V > 0) {
        VectorXd column_scale(size), row_scale(size);
        for (int i = 0; i < k; ++i) {
          const double P = points[i].mass * V;
          column_scale[i] = P;
          column_scale.segment(k + d * i, d).setConstant(P);
          row_scale[m + i] = 1 / P;
        }
        column_scale.tail(k).setConstant(V);
        row_scale.head(m).setConstant(1 / V);
        // in place: on a disc of 49 points M is 490 × 490
        M.array().colwise() *= row_scale.array();
        M.array().rowwise() *= column_scale.transpose().array();
        LemkeOptions lemke;
        lemke.cancel = solver_workspace_.cancel();
        LcpResult lcp = SolveLcpLemke(M, row_scale.cwiseProduct(q), lemke);
        result.iterations += lcp.pivots;
        if (lcp.status != LcpStatus::kSolved) {
          // Lemke's pivoting can end on a ray of a degenerate LCP (coplanar resting points, in
          // some orders) although a solution exists; the LCP as a complementarity problem for
          // the semismooth Newton solver finds it
          const LcpResult newton =
              SolveLcpNewton(M, row_scale.cwiseProduct(q), m, solver_workspace_);
          result.iterations += newton.pivots;
          if (newton.status == LcpStatus::kSolved) lcp = newton;
        }
        if (lcp.status != LcpStatus::kSolved || !(lcp.residual <= kLcpResidualTol)) {
          result.residual = lcp.status == LcpStatus::kSolved ? lcp.residual : INFINITY;
          result.tried.push_back(
              {"Lemke", h,
               fmt::format("{} after {} pivots ({} contact points, LCP size {}, scaled residual "
                           "{:.3g})",
                           LcpStatusName(lcp.status), lcp.pivots, k, size, lcp.residual)});
          return result;
        }
        lcp_residual = lcp.residual;
        const VectorXd z = column_scale.cwiseProduct(lcp.z);
        impulses = z.head(m);
        lambda = z.tail(k);
        nu += AW * impulses;
      }
    }
    if (!nu.allFinite()) {
      result.residual = INFINITY;
      result.tried.push_back(
          {"Lemke", h, fmt::format("non-finite velocities ({} contact points)", k)});
      return result;
    }

    // the poses advance with ν⁺ as in the hull model
    std::vector<EndPose> ends(num_bodies);
    for (int b = 0; b < num_bodies; ++b) {
      const Vector3d v = nu.segment<3>(6 * b), w = nu.segment<3>(6 * b + 3);
      BodyState& body = state.bodies[b];
      ends[b] = PoseAfterStep(problems[b], v, w);
      body.p_WB += h * v;
      body.Q_WB = IntegrateOrientation(body.Q_WB, w, h);
      body.v_WB = v;
      body.w_WB = w;
    }
    for (std::vector<Side>* sides : {&f_sides, &g_sides})
      for (Side& side : *sides)
        if (side.Dynamic()) side.end = ends[side.island_body];
    result.residual = lcp_residual;

    for (size_t c = 0; c < island_.contacts.size(); ++c)
      Report(static_cast<int>(c), f_sides[c], g_sides[c], points, impulses, lambda, lowest[c],
             state.contacts[c]);
    result.solved = true;
    return result;
  }

 private:
  // body `b` of the scene (its hull, or part `part` of it) at the start of the step: an island
  // body (its StartOfStep problem) or a kinematic one at its prescribed pose and twist over
  // [t, t + h]
  Side BodySide(int b, int part, const std::vector<BodyProblem>& problems, const IslandState& state,
                double t, double h) const {
    const Body& body = scene_.bodies[b];
    Side side;
    side.shape = part < 0 ? body.hull.get() : body.parts[part].get();
    side.vertices = &vertices_[b][part + 1];
    side.radius = Radius(*side.vertices);
    if (body.IsKinematic()) {
      const KinematicPose pose = body.motion->PoseAt(t);
      const KinematicMotion::Twist twist = body.motion->StepTwist(t, h);
      side.c = pose.p;
      side.R = pose.q.toRotationMatrix();
      side.v = twist.v;
      side.w = twist.w;
      side.speed = twist.v.norm() + twist.w.norm() * side.radius;
      side.end = PoseAfterStep(side.c, side.R, h, side.v, side.w);
      return side;
    }
    const auto it = std::find(island_.bodies.begin(), island_.bodies.end(), b);
    ECPSIM_DEMAND(it != island_.bodies.end());
    side.island_body = static_cast<int>(it - island_.bodies.begin());
    const BodyProblem& problem = problems[side.island_body];
    const BodyState& s = state.bodies[side.island_body];
    side.c = problem.c;
    side.R = problem.R;
    side.speed = std::max(s.v_WB.norm(), problem.free.v.norm()) +
                 std::max(s.w_WB.norm(), problem.free.w.norm()) * side.radius;
    return side;
  }

  static ContactPoint MakePoint(int pair, bool on_f, const Vector3d& y, const Vector3d& x,
                                const Vector3d& n, double psi, double mu, double mass) {
    ContactPoint point;
    point.pair = pair;
    point.on_f = on_f;
    point.y = y;
    point.x = x;
    point.n = n;
    point.psi = psi;
    point.mu = mu;
    point.mass = mass;
    const ContactFrame frame = MakeContactFrame(n, TangentReference(n));
    for (int j = 0; j < kDirections; ++j) {
      const double angle = 2 * M_PI * j / kDirections;
      point.directions[j] = std::cos(angle) * frame.t + std::sin(angle) * frame.o;
    }
    return point;
  }

  // contact c's state: the summed impulses on F at their centre of pressure (the points moved
  // with their bodies to the end pose), a2 its projection on G at G's end pose
  void Report(int c, const Side& f, const Side& g, const std::vector<ContactPoint>& points,
              const VectorXd& impulses, const VectorXd& lambda, const Vector3d& lowest,
              ContactState& state) const {
    const int k = static_cast<int>(points.size());
    constexpr int d = kDirections;
    const auto end_position = [&](const ContactPoint& point) {
      const EndPose& end = point.on_f ? f.end : g.end;
      return Vector3d(end.c + end.R * point.y);
    };
    double p_n = 0, sigma = 0;
    Vector3d centre = Vector3d::Zero(), normal = Vector3d::Zero(), friction = Vector3d::Zero();
    for (int i = 0; i < k; ++i) {
      if (points[i].pair != c) continue;
      const double p_i = impulses[i];
      p_n += p_i;
      centre += p_i * end_position(points[i]);
      normal += p_i * points[i].n;
      sigma += p_i * lambda[i];
      for (int j = 0; j < d; ++j) friction += impulses[k + d * i + j] * points[i].directions[j];
    }
    if (p_n > 0) {
      state.a1 = centre / p_n;
      state.sigma = sigma / p_n;
    } else {
      state.a1 = f.end.c + f.end.R * lowest;
      state.sigma = 0;
    }
    // G's shape in its own frame at its end pose (a fixed obstacle's frame is the world's)
    const Vector3d a1_G = g.end.R.transpose() * (state.a1 - g.end.c);
    if (!(p_n > 0) || !(normal.norm() > 0)) normal = g.end.R * ObstacleNormalToward(*g.shape, a1_G);
    const ContactFrame frame = MakeContactFrame(normal, TangentReference(normal.normalized()));
    // torsion: the moment of the points' friction impulses about a1 along n
    double p_r = 0;
    for (int i = 0; i < k; ++i) {
      if (points[i].pair != c) continue;
      Vector3d f_i = Vector3d::Zero();
      for (int j = 0; j < d; ++j) f_i += impulses[k + d * i + j] * points[i].directions[j];
      p_r += frame.n.dot((end_position(points[i]) - state.a1).cross(f_i));
    }
    state.a2 = g.end.c + g.end.R * ProjectOntoObstacle(*g.shape, a1_G).first;
    state.p_n = p_n;
    state.p_t = frame.t.dot(friction);
    state.p_o = frame.o.dot(friction);
    state.p_r = p_r;
    state.n = frame.n;
    state.t = frame.t;
    state.o = frame.o;
    // the model needs no warm start (Lemke starts from its own basis)
    state.warm_start.Reset();
  }

  const Scene& scene_;
  const PointModel::SideVertices& vertices_;
  const Island& island_;
  McpWorkspace& solver_workspace_;
};

}  // namespace

PointModel::PointModel(const Scene& scene, StepWorkspace& workspace)
    : scene_(scene), workspace_(workspace) {
  for (const Body& body : scene.bodies) {
    vertices_.emplace_back().push_back(HullVertices(*body.hull));
    for (const auto& part : body.parts) vertices_.back().push_back(HullVertices(*part));
  }
}

// (no last resort: every effort is the usual one)
AdvanceResult PointModel::Advance(const Island& island, double t, double h, IslandState& state,
                                  Effort) const {
  return PointIslandStepper(scene_, vertices_, island, workspace_.Part<McpWorkspace>())
      .Advance(t, h, state);
}

}  // namespace ecpsim::engine
