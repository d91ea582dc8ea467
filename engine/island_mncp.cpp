#include "engine/island_mncp.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "common/errors.h"
#include "engine/rotation.h"

namespace ecpsim::engine {
namespace {

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using RowVector3d = Eigen::Matrix<double, 1, 3>;
using Other = IslandContact::Other;

// A body's motion over the step as a contact sees it: its end pose and velocities and, when the
// velocities are unknowns (a dynamic body), where they are in z and the derivatives of the end
// pose in ω⁺ (left Jacobians of Exp at ±hω⁺)
struct StepMotion {
  EndPose end;
  Vector3d v, w;          // ν⁺, or a kinematic body's prescribed twist
  int column = -1;        // z index of v⁺ (ω⁺ at + 3); −1: prescribed
  Matrix3d Jl_plus;       // J_l(hω⁺): ∂(R⁺ x_B)/∂ω⁺ = −h [R⁺ x_B]× J_l(hω⁺)
  Matrix3d Rt_Jl_minus;   // Rᵀ J_l(−hω⁺): ∂y/∂ω⁺ = h [y]× Rᵀ J_l(−hω⁺), y = R⁺ᵀ(x − c⁺)
};

// G's side of a contact at a2: its window's world gradients, N = Σ_j l_G,j ∇g_j and the
// derivatives of N (a fixed G in world coordinates; a moving one in its frame at the end pose)
class OtherSide {
 public:
  OtherSide(const IslandContact& cp, const MncpLayout::Contact& L, const VectorXd& z,
            const StepMotion* motion, double h, bool with_derivatives)
      : cp_(cp), motion_(motion) {
    const Vector3d a2 = z.segment<3>(L.a2);
    y_ = motion ? Vector3d(motion->end.R.transpose() * (a2 - motion->end.c)) : a2;
    const bool dynamic = motion && motion->column >= 0;
    if (dynamic && with_derivatives) dy_dw_ = h * Skew(y_) * motion->Rt_Jl_minus;
    // the normal-cone combination normalized by Σ l_G = 1
    for (int j = 0; j < L.l_g_count; ++j) {
      const double l_g = z[L.l_g + j];
      const Vector3d gradient = Gradient(j);
      N_ += l_g * gradient;
      if (!cp.other_shape->IsLinear(cp.other_window[j])) dN_da2_ += l_g * Hessian(j);
      if (dynamic && with_derivatives) {
        dN_dw_ += l_g * (-h * Skew(gradient) * motion->Jl_plus);
        if (!cp.other_shape->IsLinear(cp.other_window[j]))
          dN_dw_ += l_g * motion->end.R * cp.other_shape->Hessian(cp.other_window[j], y_) * dy_dw_;
      }
      l_g_sum_ += l_g;
    }
    dN_dv_ = -h * dN_da2_;  // y_G depends on a2 − c_G − h v_G
  }

  // constraint j of the window at a2: g_j, its gradient in G's frame and in the world, and the
  // world gradient's derivative in a2
  double Value(int j) const { return cp_.other_shape->Value(cp_.other_window[j], y_); }
  Vector3d FrameGradient(int j) const {
    return cp_.other_shape->Gradient(cp_.other_window[j], y_);
  }
  Vector3d Gradient(int j) const {
    const Vector3d gradient = FrameGradient(j);
    return motion_ ? Vector3d(motion_->end.R * gradient) : gradient;
  }
  Matrix3d Hessian(int j) const {
    const Matrix3d H = cp_.other_shape->Hessian(cp_.other_window[j], y_);
    return motion_ ? Matrix3d(motion_->end.R * H * motion_->end.R.transpose()) : H;
  }

  const Vector3d& N() const { return N_; }
  double l_g_sum() const { return l_g_sum_; }
  const Matrix3d& dN_da2() const { return dN_da2_; }
  const Matrix3d& dN_dv() const { return dN_dv_; }  // in G's v⁺ (a dynamic G)
  const Matrix3d& dN_dw() const { return dN_dw_; }  // in G's ω⁺ (a dynamic G)
  const Matrix3d& dy_dw() const { return dy_dw_; }  // y_G in G's ω⁺ (a dynamic G)

 private:
  const IslandContact& cp_;
  const StepMotion* motion_;  // null: fixed, world frame
  Vector3d y_;
  Vector3d N_ = Vector3d::Zero();
  double l_g_sum_ = 0;
  Matrix3d dN_da2_ = Matrix3d::Zero(), dN_dv_ = Matrix3d::Zero(), dN_dw_ = Matrix3d::Zero();
  Matrix3d dy_dw_ = Matrix3d::Zero();
};

// G's motion for contact `cp`: null for a fixed G
const StepMotion* OtherMotion(const IslandContact& cp, const std::vector<StepMotion>& bodies,
                              const std::vector<StepMotion>& kinematic) {
  if (cp.other_kind == Other::kBody) return &bodies[cp.other];
  if (cp.other_kind == Other::kKinematic) return &kinematic[cp.other];
  return nullptr;
}

std::vector<StepMotion> KinematicMotions(const IslandProblem& problem) {
  std::vector<StepMotion> motions;
  for (const KinematicBody& k : problem.kinematic)
    motions.push_back({PoseAfterStep(k.c, k.R, problem.h, k.v, k.w), k.v, k.w, -1, {}, {}});
  return motions;
}

// The residual and Jacobian of one island (EvaluateIslandMncp): per body the contact-free
// Newton–Euler rows, then per contact its rows and its wrenches on its bodies
class IslandEvaluation {
 public:
  IslandEvaluation(const IslandProblem& problem, const IslandLayout& layout, const VectorXd& z,
                   VectorXd& F, MatrixXd* J)
      : problem_(problem), layout_(layout), z_(z), F_(F), J_(J ? *J : dummy_),
        with_jacobian_(J != nullptr), kinematic_(KinematicMotions(problem)) {}

  void Run() {
    F_.setZero(layout_.size);
    if (with_jacobian_) J_.setZero(layout_.size, layout_.size);
    for (int b = 0; b < layout_.num_bodies; ++b) AddBody(b);
    for (size_t k = 0; k < problem_.contacts.size(); ++k) AddContact(static_cast<int>(k));
  }

 private:
  // Newton–Euler with impulses (paper eq. discrete_NE), contact terms added per contact
  void AddBody(int b) {
    const BodyProblem& body = problem_.bodies[b];
    const int col = IslandLayout::Velocity(b);
    StepMotion m;
    m.v = z_.segment<3>(col);
    m.w = z_.segment<3>(col + 3);
    m.column = col;
    m.end = PoseAfterStep(body, m.v, m.w);
    F_.segment<3>(col) = body.mass * (m.v - body.v) - body.p_ext.head<3>();
    F_.segment<3>(col + 3) = GyroscopicResidual(body, m.w) - body.p_ext.tail<3>();
    if (with_jacobian_) {
      J_.block<3, 3>(col, col) = body.mass * Matrix3d::Identity();
      J_.block<3, 3>(col + 3, col + 3) = GyroscopicJacobian(body, m.w);
      m.Jl_plus = LeftJacobian(body.h * m.w);
      m.Rt_Jl_minus = Matrix3d(body.R.transpose() * LeftJacobian(-body.h * m.w));
    }
    bodies_.push_back(m);
  }

  void AddContact(int k) {
    const IslandContact& cp = problem_.contacts[k];
    const MncpLayout::Contact& L = layout_.contacts[k];
    const StepMotion& body = bodies_[cp.body];
    const StepMotion* other = OtherMotion(cp, bodies_, kinematic_);
    const OtherSide G(cp, L, z_, other, problem_.h, with_jacobian_);
    const double h = problem_.h;
    const int col = body.column;
    const Vector3d& v = body.v;
    const Vector3d& w = body.w;
    const EndPose& end = body.end;
    const Matrix3d& R_end = end.R;
    const Vector3d a1 = z_.segment<3>(L.a1);
    const Vector3d a2 = z_.segment<3>(L.a2);
    const double s = z_[L.s];
    const double p_t = z_[L.p_t], p_o = z_[L.p_o], p_r = z_[L.p_r];
    const double p_n = z_[L.p_n], sigma = z_[L.sigma];
    const Friction& fr = cp.friction;
    const Vector3d& N = G.N();
    const ContactFrame frame = MakeContactFrame(N, cp.tangent_reference);
    const Vector3d& n = frame.n;
    const Vector3d& t = frame.t;
    const Vector3d& o = frame.o;

    // F's ECP lever arm at the end of the step and the contact impulse on F
    const Vector3d r = a1 - end.c;
    const Vector3d force = n * p_n + t * p_t + o * p_o;
    F_.segment<3>(col) -= force;
    F_.segment<3>(col + 3) -= r.cross(force) + n * p_r;
    // the opposite impulse on a dynamic G, at a2
    const bool dynamic_other = other && other->column >= 0;
    const Vector3d r_other = other ? Vector3d(a2 - other->end.c) : Vector3d::Zero();
    if (dynamic_other) {
      F_.segment<3>(other->column) += force;
      F_.segment<3>(other->column + 3) += r_other.cross(force) + n * p_r;
    }

    // contact constraints (paper eqs. re_contact_multiple_1..4, normalized on G's side)
    const Vector3d y = R_end.transpose() * r;  // a1 in F's body frame at q⁺
    Vector3d cone = N;                          // N + Σ l_i ∇f_i(a1)
    for (int i = 0; i < L.l_count; ++i) {
      const int face = cp.window[i];
      const Vector3d grad_world = R_end * cp.hull->Gradient(face, y);
      cone += z_[L.l + i] * grad_world;
      F_[L.l + i] = -cp.hull->Value(face, y);
    }
    F_.segment<3>(L.a1) = a1 - a2 - s * N;
    F_.segment<3>(L.a2) = cone;
    F_[L.s] = G.l_g_sum() - 1;
    for (int j = 0; j < L.l_g_count; ++j) F_[L.l_g + j] = -G.Value(j);
    // gap: a1 = a2 + s N with N in G's normal cone, so s has the sign of max_j g_j(a1)
    F_[L.p_n] = s;

    // friction on the relative velocity at the ECP (paper eq. friction)
    Vector3d v_contact = v + w.cross(r);
    Vector3d w_relative = w;
    if (other) {
      v_contact -= other->v + other->w.cross(r_other);
      w_relative -= other->w;
    }
    const double v_t = t.dot(v_contact), v_o = o.dot(v_contact), v_r = n.dot(w_relative);
    const double et2 = fr.e_t * fr.e_t, eo2 = fr.e_o * fr.e_o, er2 = fr.e_r * fr.e_r;
    F_[L.p_t] = et2 * fr.mu * p_n * v_t + p_t * sigma;
    F_[L.p_o] = eo2 * fr.mu * p_n * v_o + p_o * sigma;
    F_[L.p_r] = er2 * fr.mu * p_n * v_r + p_r * sigma;
    // the friction cone as μ p_n − ‖p̂‖ (see MncpResidual's note and engine/README.md)
    const double p_hat = std::sqrt(p_t * p_t / et2 + p_o * p_o / eo2 + p_r * p_r / er2);
    F_[L.sigma] = fr.mu * p_n - p_hat;

    if (!with_jacobian_) return;

    // --- analytic Jacobian ---
    const FrameDerivatives d = ContactFrameDerivatives(N, frame, cp.tangent_reference);
    // X_N (1×3 or 3×3): the derivative of some rows with respect to N, chained to (a2, l_G) and
    // to a dynamic G's ν⁺
    auto add_through_N = [&](int row, const auto& X_N) {
      constexpr int kRows = std::decay_t<decltype(X_N)>::RowsAtCompileTime;
      J_.block<kRows, 3>(row, L.a2) += X_N * G.dN_da2();
      for (int j = 0; j < L.l_g_count; ++j)
        J_.block<kRows, 1>(row, L.l_g + j) += X_N * G.Gradient(j);
      if (dynamic_other) {
        J_.block<kRows, 3>(row, other->column) += X_N * G.dN_dv();
        J_.block<kRows, 3>(row, other->column + 3) += X_N * G.dN_dw();
      }
    };
    const Matrix3d dforce_dN = p_n * d.dn_dN + p_t * d.dt_dN + p_o * d.do_dN;

    // F's Newton–Euler linear rows
    J_.block<3, 1>(col, L.p_n) -= n;
    J_.block<3, 1>(col, L.p_t) -= t;
    J_.block<3, 1>(col, L.p_o) -= o;
    add_through_N(col, Matrix3d(-dforce_dN));

    // F's Newton–Euler angular rows: −(r × force + n p_r), r = a1 − c − h v
    J_.block<3, 3>(col + 3, L.a1) += Skew(force);
    J_.block<3, 3>(col + 3, col) += -h * Skew(force);
    J_.block<3, 1>(col + 3, L.p_n) -= r.cross(n);
    J_.block<3, 1>(col + 3, L.p_t) -= r.cross(t);
    J_.block<3, 1>(col + 3, L.p_o) -= r.cross(o);
    J_.block<3, 1>(col + 3, L.p_r) -= n;
    add_through_N(col + 3, Matrix3d(-(Skew(r) * dforce_dN + p_r * d.dn_dN)));

    // a dynamic G's Newton–Euler rows: + force and + (r_G × force + n p_r), r_G = a2 − c_G − h v_G
    if (dynamic_other) {
      const int other_col = other->column;
      J_.block<3, 1>(other_col, L.p_n) += n;
      J_.block<3, 1>(other_col, L.p_t) += t;
      J_.block<3, 1>(other_col, L.p_o) += o;
      add_through_N(other_col, dforce_dN);
      J_.block<3, 3>(other_col + 3, L.a2) -= Skew(force);
      J_.block<3, 3>(other_col + 3, other_col) += h * Skew(force);
      J_.block<3, 1>(other_col + 3, L.p_n) += r_other.cross(n);
      J_.block<3, 1>(other_col + 3, L.p_t) += r_other.cross(t);
      J_.block<3, 1>(other_col + 3, L.p_o) += r_other.cross(o);
      J_.block<3, 1>(other_col + 3, L.p_r) += n;
      add_through_N(other_col + 3, Matrix3d(Skew(r_other) * dforce_dN + p_r * d.dn_dN));
    }

    // F's hull constraints at the end pose: y = R⁺ᵀ(a1 − c − h v), R⁺ = Exp(hω) R
    const Matrix3d dy_da1 = R_end.transpose();
    const Matrix3d dy_dw = h * Skew(y) * body.Rt_Jl_minus;
    Matrix3d dcone_da1 = Matrix3d::Zero();
    Matrix3d dcone_dw = Matrix3d::Zero();
    for (int i = 0; i < L.l_count; ++i) {
      const int face = cp.window[i];
      const double l = z_[L.l + i];
      const Vector3d grad_body = cp.hull->Gradient(face, y);
      const Vector3d grad_world = R_end * grad_body;
      // complementarity row −f_i(a1; q⁺)
      const RowVector3d df_dy = grad_body.transpose();
      J_.block<1, 3>(L.l + i, L.a1) = -df_dy * dy_da1;
      J_.block<1, 3>(L.l + i, col) = h * df_dy * dy_da1;
      J_.block<1, 3>(L.l + i, col + 3) = -df_dy * dy_dw;
      // the normal-cone row: ∂(l R⁺ ∇f(y))
      J_.block<3, 1>(L.a2, L.l + i) = grad_world;
      dcone_dw += l * (-h * Skew(grad_world) * body.Jl_plus);
      if (!cp.hull->IsLinear(face)) {
        const Matrix3d H_world = R_end * cp.hull->Hessian(face, y);
        dcone_da1 += l * H_world * dy_da1;
        dcone_dw += l * H_world * dy_dw;
      }
    }
    J_.block<3, 3>(L.a2, L.a1) += dcone_da1;
    J_.block<3, 3>(L.a2, col) += -h * dcone_da1;
    J_.block<3, 3>(L.a2, col + 3) += dcone_dw;
    add_through_N(L.a2, Matrix3d(Matrix3d::Identity()));

    // a1 − a2 − s N
    J_.block<3, 3>(L.a1, L.a1) += Matrix3d::Identity();
    J_.block<3, 3>(L.a1, L.a2) -= Matrix3d::Identity();
    J_.block<3, 1>(L.a1, L.s) = -N;
    add_through_N(L.a1, Matrix3d(-s * Matrix3d::Identity()));

    // Σ l_G = 1, G's complementarity rows −g_j(y_G), and the gap s
    for (int j = 0; j < L.l_g_count; ++j) {
      J_(L.s, L.l_g + j) = 1;
      const RowVector3d dg_da2 = G.Gradient(j).transpose();
      J_.block<1, 3>(L.l_g + j, L.a2) = -dg_da2;
      if (dynamic_other) {
        J_.block<1, 3>(L.l_g + j, other->column) = h * dg_da2;
        J_.block<1, 3>(L.l_g + j, other->column + 3) = -G.FrameGradient(j).transpose() * G.dy_dw();
      }
    }
    J_(L.p_n, L.s) = 1;

    // friction rows: v_c = v + ω × r − (v_G + ω_G × r_G), v_t = t·v_c, v_o = o·v_c,
    // v_r = n·(ω − ω_G)
    const Matrix3d dvc_da1 = Skew(w);
    const Matrix3d dvc_dv = Matrix3d::Identity() - h * Skew(w);
    const Matrix3d dvc_dw = -Skew(r);
    struct Row {
      int index;
      double e2;
      double p;
      double speed;
      const Vector3d* axis;
      const Matrix3d* daxis_dN;
    };
    const Row rows[2] = {{L.p_t, et2, p_t, v_t, &t, &d.dt_dN},
                         {L.p_o, eo2, p_o, v_o, &o, &d.do_dN}};
    for (const Row& row : rows) {
      const double scale = row.e2 * fr.mu * p_n;
      const RowVector3d axis_t = row.axis->transpose();
      J_.block<1, 3>(row.index, col) += scale * axis_t * dvc_dv;
      J_.block<1, 3>(row.index, col + 3) += scale * axis_t * dvc_dw;
      J_.block<1, 3>(row.index, L.a1) += scale * axis_t * dvc_da1;
      add_through_N(row.index, RowVector3d(scale * v_contact.transpose() * *row.daxis_dN));
      J_(row.index, L.p_n) += row.e2 * fr.mu * row.speed;
      J_(row.index, row.index) += sigma;  // ∂/∂p_t (or p_o): the row index equals the unknown's
      J_(row.index, L.sigma) += row.p;
      // G's point velocity v_G + ω_G × (a2 − c_G − h v_G)
      if (other) J_.block<1, 3>(row.index, L.a2) -= scale * axis_t * Skew(other->w);
      if (dynamic_other) {
        J_.block<1, 3>(row.index, other->column) -=
            scale * axis_t * (Matrix3d::Identity() - h * Skew(other->w));
        J_.block<1, 3>(row.index, other->column + 3) += scale * axis_t * Skew(r_other);
      }
    }
    const double scale_r = er2 * fr.mu * p_n;
    J_.block<1, 3>(L.p_r, col + 3) += scale_r * n.transpose();
    add_through_N(L.p_r, RowVector3d(scale_r * w_relative.transpose() * d.dn_dN));
    J_(L.p_r, L.p_n) += er2 * fr.mu * v_r;
    J_(L.p_r, L.p_r) += sigma;
    J_(L.p_r, L.sigma) += p_r;
    if (dynamic_other) J_.block<1, 3>(L.p_r, other->column + 3) -= scale_r * n.transpose();

    // μ p_n − ‖p̂‖; at p̂ = 0 the norm's generalized gradient contains 0, which is used
    J_(L.sigma, L.p_n) = fr.mu;
    if (p_hat > 0) {
      J_(L.sigma, L.p_t) = -p_t / (et2 * p_hat);
      J_(L.sigma, L.p_o) = -p_o / (eo2 * p_hat);
      J_(L.sigma, L.p_r) = -p_r / (er2 * p_hat);
    }
  }

  const IslandProblem& problem_;
  const IslandLayout& layout_;
  const VectorXd& z_;
  VectorXd& F_;
  MatrixXd dummy_;
  MatrixXd& J_;
  const bool with_jacobian_;
  std::vector<StepMotion> bodies_;
  const std::vector<StepMotion> kinematic_;
};

}  // namespace

IslandLayout MakeIslandLayout(const IslandProblem& problem) {
  const int num_bodies = static_cast<int>(problem.bodies.size());
  ECPSIM_DEMAND(num_bodies > 0);
  for (const BodyProblem& body : problem.bodies)
    ECPSIM_DEMAND(body.h == problem.h && body.contacts.empty());
  IslandLayout layout;
  layout.num_bodies = num_bodies;
  int next = IslandLayout::Velocity(num_bodies);
  layout.contacts.resize(problem.contacts.size());
  for (auto& c : layout.contacts) {
    c.a1 = next;
    c.a2 = next + 3;
    c.s = next + 6;
    c.p_t = next + 7;
    c.p_o = next + 8;
    c.p_r = next + 9;
    next += 10;
  }
  layout.num_free = next;
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const IslandContact& cp = problem.contacts[k];
    ECPSIM_DEMAND(cp.body >= 0 && cp.body < num_bodies && cp.hull && cp.other_shape);
    switch (cp.other_kind) {
      case Other::kFixed:
        break;
      case Other::kKinematic:
        ECPSIM_DEMAND(cp.other >= 0 && cp.other < static_cast<int>(problem.kinematic.size()));
        break;
      case Other::kBody:
        ECPSIM_DEMAND(cp.other >= 0 && cp.other < num_bodies && cp.other != cp.body);
        break;
    }
    for (int i : cp.window) ECPSIM_DEMAND(i >= 0 && i < cp.hull->NumConstraints());
    for (int j : cp.other_window) ECPSIM_DEMAND(j >= 0 && j < cp.other_shape->NumConstraints());
    auto& c = layout.contacts[k];
    c.l = next;
    c.l_count = static_cast<int>(cp.window.size());
    next += c.l_count;
    c.l_g = next;
    c.l_g_count = static_cast<int>(cp.other_window.size());
    next += c.l_g_count;
    c.p_n = next++;
    c.sigma = next++;
  }
  layout.size = next;
  return layout;
}

void EvaluateIslandMncp(const IslandProblem& problem, const IslandLayout& layout,
                        const VectorXd& z, VectorXd* F, MatrixXd* J) {
  IslandEvaluation evaluation(problem, layout, z, *F, J);
  evaluation.Run();
}

double IslandMncpResidual(const IslandProblem& problem, const IslandLayout& layout,
                          const VectorXd& z, const VectorXd& F, const VectorXd& row_scale,
                          const VectorXd& var_scale, const IslandResidualUnits& units) {
  // row by row, as MncpResidual: each contact's rows in its own length, floored by round-off
  ScaledRowResidual r(layout.num_free, z, F, row_scale, var_scale);
  std::vector<double> moment_factor(layout.num_bodies, 1.0);
  for (size_t k = 0; k < layout.contacts.size(); ++k) {
    const IslandContact& cp = problem.contacts[k];
    const MncpLayout::Contact& L = layout.contacts[k];
    const double round_off =
        ContactRoundOffLength(L, z, units.contact_coordinates[k], units.tolerance);
    r.AddContact(L, std::max(1.0, round_off / units.contact_length[k]));
    // each body's moment rows carry r × p of its contacts, in its own length
    for (int b : {cp.body, cp.other_kind == Other::kBody ? cp.other : -1}) {
      if (b < 0) continue;
      moment_factor[b] =
          std::max(moment_factor[b], std::max(1.0, round_off / units.body_length[b]));
    }
  }
  for (int b = 0; b < layout.num_bodies; ++b) {
    const int col = IslandLayout::Velocity(b);
    for (int i = 0; i < 3; ++i) {
      r.AddRow(col + i, 1);
      r.AddRow(col + 3 + i, moment_factor[b]);
    }
  }
  return r.value();
}

double IslandStepEnergyGain(const IslandProblem& problem, const IslandLayout& layout,
                            const VectorXd& z) {
  const auto body_gain = [&](int b) {
    const int col = IslandLayout::Velocity(b);
    return StepEnergyGain(problem.bodies[b], z.segment<3>(col), z.segment<3>(col + 3));
  };
  double gain = body_gain(0);
  for (int b = 1; b < layout.num_bodies; ++b) gain += body_gain(b);
  // the kinematic bodies' work: their contact impulse times their prescribed velocities
  const std::vector<StepMotion> kinematic = KinematicMotions(problem);
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const IslandContact& cp = problem.contacts[k];
    if (cp.other_kind != Other::kKinematic) continue;
    const MncpLayout::Contact& L = layout.contacts[k];
    const StepMotion& other = kinematic[cp.other];
    const OtherSide G(cp, L, z, &other, problem.h, false);
    const ContactFrame frame = MakeContactFrame(G.N(), cp.tangent_reference);
    const Vector3d force = frame.n * z[L.p_n] + frame.t * z[L.p_t] + frame.o * z[L.p_o];
    const Vector3d r_other = z.segment<3>(L.a2) - other.end.c;
    gain -= force.dot(other.v + other.w.cross(r_other)) + z[L.p_r] * frame.n.dot(other.w);
  }
  return gain;
}

}  // namespace ecpsim::engine
