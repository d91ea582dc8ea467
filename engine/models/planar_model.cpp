#include "engine/models/planar_model.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "common/errors.h"
#include "engine/mncp/contact_window.h"
#include "engine/mncp/mncp_scaling.h"
#include "engine/mncp/mncp_system.h"
#include "engine/obstacle_queries.h"
#include "engine/rotation.h"
#include "engine/solver/complementarity_solver.h"

namespace ecpsim::engine {
namespace {

using Eigen::Vector3d;
using Eigen::VectorXd;

// `model: planar`'s checks: "flat" is the support face's normal within this angle of −N, far below
// any tilt the hull model would resolve, far above round-off
constexpr double kFlatTolerance = 1e-9;  // rad
// the lowest point on the plane, and the ECP on the support face's boundary, up to this fraction
// of the body's length scale: far above the solver's relative 1e-12, far below a face
constexpr double kSupportRelTolerance = 1e-9;

// the face among `faces` whose outward normal (body frame) is closest to `direction_B`
int MostAlignedFace(const geometry::PolyhedralShape& hull, const std::vector<int>& faces,
                    const Vector3d& direction_B) {
  int best = faces.front();
  for (int i : faces)
    if (hull.hull().normals[i].dot(direction_B) > hull.hull().normals[best].dot(direction_B))
      best = i;
  return best;
}

// The plane's frame (t, o, N): world vectors to it and back. The ground's frame is the identity,
// and its vectors go through untouched (no −0 from 0 · x), so a run on the ground is the same to
// the bit as before planes of any orientation.
class PlaneFrame {
 public:
  explicit PlaneFrame(const Vector3d& N) {
    const ContactFrame frame = MakeContactFrame(N, TangentReference(N));
    t_ = frame.t;
    o_ = frame.o;
    n_ = frame.n;
    ground_ = N == Vector3d::UnitZ();
  }
  const Vector3d& t() const { return t_; }
  const Vector3d& o() const { return o_; }
  const Vector3d& n() const { return n_; }
  Vector3d ToLocal(const Vector3d& world) const {
    return ground_ ? world : Vector3d(t_.dot(world), o_.dot(world), n_.dot(world));
  }
  Vector3d ToWorld(const Vector3d& local) const {
    return ground_ ? local : Vector3d(t_ * local.x() + o_ * local.y() + n_ * local.z());
  }

 private:
  Vector3d t_, o_, n_;
  bool ground_ = false;
};

}  // namespace

PlanarStep SolvePlanarStep(const Scene& scene, const Island& island, double t, double h,
                           const PlanarChecks& checks, IslandState& state,
                           StepWorkspace& workspace) {
  ECPSIM_DEMAND(island.bodies.size() == 1);
  PlanarStep step;
  if (island.contacts.size() != 1) {
    step.invalid = "it needs exactly one obstacle (the plane) per body";
    return step;
  }
  const Body& body = scene.bodies[island.bodies[0]];
  const BodyState b = state.bodies[0];
  const ContactPair& pair = scene.contacts[island.contacts[0]];
  const geometry::ConvexShape& plane = ShapeOfOther(scene, pair);

  // the model's assumptions: a plane, the body flat on one hull face of it
  const auto* hull = body.hull->AsPolyhedron();
  if (pair.WithBody() || pair.part >= 0 || !plane.IsHalfSpace() || hull == nullptr) {
    step.invalid = "it needs a polyhedral hull on a fixed plane";
    return step;
  }
  const PlaneFrame frame(plane.Gradient(0, b.p_WB).normalized());
  const Vector3d& N = frame.n();
  const Eigen::Matrix3d R = b.Q_WB.toRotationMatrix();
  const double length = std::sqrt(body.inertia.trace() / body.mass);
  if (checks.in_plane_motion) {
    const double tolerance = *checks.in_plane_motion;
    // the body's velocity scale at the scene's step, at most BodyScales' (so the test is at
    // least as strict as the hull model's measure)
    const double speed =
        std::max(b.v_WB.norm() + b.w_WB.norm() * length, scene.gravity.norm() * scene.h);
    if (std::abs(N.dot(b.v_WB)) > tolerance * speed ||
        b.w_WB.cross(N).norm() * length > tolerance * speed) {
      step.invalid = "it moves off the plane or turns about an axis in it";
      return step;
    }
    // otherwise spinning about N makes a gyroscopic tipping moment the model does not have
    const Vector3d IN = R * (body.inertia * (R.transpose() * N));
    if (IN.cross(N).norm() > tolerance * N.dot(IN)) {
      step.invalid = "the plane's normal is no principal axis of its inertia";
      return step;
    }
  }
  const double support_tolerance = checks.support_length * length;
  // the face most aligned with −N among those at the support vertex in −N: a face flat on the
  // plane is one of them, and the search costs the vertex's degree, not the hull's size
  const Vector3d down_B = R.transpose() * -N;
  const int support_vertex = hull->SupportVertex(down_B);
  const int face = MostAlignedFace(*hull, hull->hull().vertex_faces[support_vertex], down_B);
  // the angle between −N and the face's normal through its sine: a cosine cannot resolve
  // angles below 1e-8 rad (cos 1e-9 rounds to 1)
  const Vector3d support_normal = R * hull->hull().normals[face];
  if (!(support_normal.dot(N) < 0) || support_normal.cross(N).norm() > checks.flat_angle) {
    step.invalid = "the body is not flat on a face";
    return step;
  }
  // CM height above the plane, constant in this model
  const Vector3d lowest = b.p_WB + R * hull->hull().vertices[support_vertex];
  const double height = plane.Value(0, b.p_WB) - plane.Value(0, lowest);
  if (std::abs(plane.Value(0, lowest)) > support_tolerance) {
    step.invalid =
        fmt::format("its lowest point is {:.3g} m off the plane", plane.Value(0, lowest));
    return step;
  }

  // impulses over the step in the plane's frame: gravity, applied loads (at the start of the
  // step, as the hull model)
  const Eigen::Matrix<double, 6, 1> p_app =
      AppliedImpulse(scene.loads, scene.impulses, pair.body, t, h, R);
  const double m = body.mass;
  const Vector3d p_lin = frame.ToLocal(p_app.head<3>());
  const Vector3d p_ang = frame.ToLocal(p_app.tail<3>());
  const Vector3d gravity = frame.ToLocal(scene.gravity);
  const double I = N.dot(R * body.inertia * R.transpose() * N);
  const double p_n = -m * gravity.z() * h - p_lin.z();
  if (!(p_n > 0)) {
    step.invalid = fmt::format("p_n = {:.3g} N·s ≤ 0 (it would lift off)", p_n);
    return step;
  }
  const Friction& fr = island.friction[0];
  const double px = p_lin.x() + m * gravity.x() * h, py = p_lin.y() + m * gravity.y() * h;
  const double ptx = p_ang.x(), pty = p_ang.y(), ptz = p_ang.z();
  const Vector3d v_start = frame.ToLocal(b.v_WB);
  const double w_start = N.dot(b.w_WB);

  // unknowns z = (p_t, p_o, p_r, σ); rows: the three friction equations and the cone
  struct Kinematics {
    double vx, vy, w, rx, ry, vt, vo;
  };
  const auto kinematics = [&](const VectorXd& z) {
    Kinematics k;
    k.vx = v_start.x() + (z[0] + px) / m;
    k.vy = v_start.y() + (z[1] + py) / m;
    // friction at r − q e_N adds (p_τt p_t + p_τo p_o)/p_n about N when tipping torques act
    k.w = w_start + (z[2] + ptz + (ptx * z[0] + pty * z[1]) / p_n) / I;
    k.rx = (pty - height * z[0]) / p_n;
    k.ry = -(height * z[1] + ptx) / p_n;
    k.vt = k.vx - k.w * k.ry;
    k.vo = k.vy + k.w * k.rx;
    return k;
  };
  const double A = fr.e_t * fr.e_t * fr.mu * p_n, B = fr.e_o * fr.e_o * fr.mu * p_n,
               C = fr.e_r * fr.e_r * fr.mu * p_n;
  const auto residual = [&](const VectorXd& z, VectorXd* F, Eigen::MatrixXd* J) {
    const Kinematics k = kinematics(z);
    const double sigma = z[3];
    const double p_hat =
        std::sqrt(z[0] * z[0] / (fr.e_t * fr.e_t) + z[1] * z[1] / (fr.e_o * fr.e_o) +
                  z[2] * z[2] / (fr.e_r * fr.e_r));
    F->resize(4);
    (*F) << A * k.vt + z[0] * sigma, B * k.vo + z[1] * sigma, C * k.w + z[2] * sigma,
        fr.mu * p_n - p_hat;
    if (J == nullptr) return;
    const double dw_dt = ptx / (p_n * I), dw_do = pty / (p_n * I), dw_dr = 1 / I;
    const double drx_dt = -height / p_n, dry_do = -height / p_n;
    J->setZero(4, 4);
    // v_t = v_x − w r_y, v_o = v_y + w r_x
    (*J)(0, 0) = A * (1 / m - k.ry * dw_dt) + sigma;
    (*J)(0, 1) = A * (-k.ry * dw_do - k.w * dry_do);
    (*J)(0, 2) = A * (-k.ry * dw_dr);
    (*J)(0, 3) = z[0];
    (*J)(1, 0) = B * (k.rx * dw_dt + k.w * drx_dt);
    (*J)(1, 1) = B * (1 / m + k.rx * dw_do) + sigma;
    (*J)(1, 2) = B * (k.rx * dw_dr);
    (*J)(1, 3) = z[1];
    (*J)(2, 0) = C * dw_dt;
    (*J)(2, 1) = C * dw_do;
    (*J)(2, 2) = C * dw_dr + sigma;
    (*J)(2, 3) = z[2];
    if (p_hat > 0) {
      (*J)(3, 0) = -z[0] / (fr.e_t * fr.e_t * p_hat);
      (*J)(3, 1) = -z[1] / (fr.e_o * fr.e_o * p_hat);
      (*J)(3, 2) = -z[2] / (fr.e_r * fr.e_r * p_hat);
    }
  };
  // (one reference captured: std::function keeps it in place instead of allocating)
  const McpFunction f = [&residual](const VectorXd& z, VectorXd* F, Eigen::MatrixXd* J) {
    residual(z, F, J);
  };

  // warm start from the last step, else the sliding guess (the vectors kept in the workspace from
  // step to step: the step then allocates nothing for them)
  const ContactState& previous = state.contacts[0];
  struct Unknowns {
    VectorXd z = VectorXd(4), var_scale = VectorXd(4), row_scale = VectorXd(4);
  };
  Unknowns& unknowns = workspace.Part<Unknowns>();
  VectorXd& z = unknowns.z;
  VectorXd& var_scale = unknowns.var_scale;
  VectorXd& row_scale = unknowns.row_scale;
  McpWorkspace& solver_workspace = workspace.Part<McpWorkspace>();
  z << previous.p_t, previous.p_o, previous.p_r, previous.sigma;
  Eigen::Matrix<double, 6, 1> p_ext = p_app;
  p_ext.head<3>() += h * m * scene.gravity;
  const double speed = BodyScales(body, b, p_ext, h).velocity;
  var_scale << p_n, p_n, p_n * fr.e_r, speed;
  row_scale << 1 / (p_n * speed), 1 / (p_n * speed), 1 / (p_n * speed * fr.e_r), 1 / p_n;
  McpOptions options;
  options.tolerance = scene.solver.tolerance;
  options.max_iterations = scene.solver.max_iterations;
  AdvanceResult& result = step.result;
  result.model = StepModel::kPlanar;
  McpResult solve = SolveMcp(f, 3, row_scale, var_scale, z, options, solver_workspace);
  if (!solve.converged) {
    result.tried.push_back(
        {"warm start", h,
         fmt::format("residual {:.3g} after {} iterations", solve.residual, solve.iterations)});
    ++result.retries;
    result.iterations += solve.iterations;
    z << 0, 0, 0, speed;
    solve = SolveMcp(f, 3, row_scale, var_scale, z, options, solver_workspace);
  }
  result.iterations += solve.iterations;
  result.residual = solve.residual;
  if (!solve.converged) {
    result.tried.push_back(
        {"sliding guess", h,
         fmt::format("residual {:.3g} after {} iterations", solve.residual, solve.iterations)});
    return step;
  }

  // the step: motion in the plane and turning about its normal only
  const Kinematics kin = kinematics(z);
  if (!(h * std::abs(kin.w) <= checks.max_rotation)) {
    step.invalid = fmt::format("it turns {:.3g} rad in the step", h * std::abs(kin.w));
    return step;
  }
  BodyState& next = state.bodies[0];
  next.v_WB = frame.ToWorld(Vector3d(kin.vx, kin.vy, 0));
  next.w_WB = frame.ToWorld(Vector3d(0, 0, kin.w));
  next.p_WB = b.p_WB + h * next.v_WB;
  next.Q_WB = IntegrateOrientation(b.Q_WB, next.w_WB, h);

  // the ECP must stay on the support face: otherwise the body tips and the model is invalid
  ContactState& c = state.contacts[0];
  const Vector3d a1 = next.p_WB + frame.ToWorld(Vector3d(kin.rx, kin.ry, -height));
  const Vector3d y = next.Q_WB.toRotationMatrix().transpose() * (a1 - next.p_WB);
  if (!OnFaceFacet(*hull, face, y, support_tolerance)) {
    step.invalid = fmt::format(
        "the ECP ({:.4g}, {:.4g}, {:.4g}) m left the support face (it "
        "would tip)",
        a1.x(), a1.y(), a1.z());
    state.bodies[0] = b;
    return step;
  }
  c.a1 = a1;
  c.a2 = a1;
  c.p_n = p_n;
  c.p_t = z[0];
  c.p_o = z[1];
  c.p_r = z[2];
  c.sigma = std::max(z[3], 0.0);
  c.n = N;
  c.t = frame.t();
  c.o = frame.o();
  step.face = face;
  result.solved = true;
  return step;
}

// (no last resort: every effort is the usual one)
AdvanceResult PlanarModel::Advance(const Island& island, double t, double h, IslandState& state,
                                   Effort) const {
  const PlanarStep step =
      SolvePlanarStep(scene_, island, t, h, {kFlatTolerance, kSupportRelTolerance, INFINITY, {}},
                      state, workspace_);
  if (!step.invalid.empty()) {
    throw ModelInvalid(
        fmt::format("planar model invalid at t = {:.6g} s on body '{}': {}; use "
                    "--model hull",
                    t, scene_.bodies[island.bodies[0]].name, step.invalid));
  }
  return step.result;
}

}  // namespace ecpsim::engine
