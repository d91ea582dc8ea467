#include "engine/mncp/mncp_system.h"

#include <algorithm>
#include <cmath>

#include "common/errors.h"
#include "engine/rotation.h"

namespace ecpsim::engine {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using RowVector3d = Eigen::Matrix<double, 1, 3>;

// G's side of a contact at a2: its window's world gradients, N = Σ_j l_G,j ∇g_j and the
// derivatives of N (a fixed G in world coordinates; a moving one in its frame at its end pose)
class OtherSide {
 public:
  OtherSide(const ContactSides& sides, const MncpLayout::Contact& L, const Eigen::VectorXd& z,
            const StepMotion* motion, double h, bool with_derivatives)
      : sides_(sides), motion_(motion) {
    if (L.on_plane()) {
      // a fixed half-space: l_G = 1, N its constant gradient, no derivatives
      y_ = z.segment<3>(L.a1);
      N_ = Gradient(0);
      l_g_sum_ = 1;
      return;
    }
    const Vector3d a2 = z.segment<3>(L.a2);
    y_ = motion ? Vector3d(motion->end.R.transpose() * (a2 - motion->end.c)) : a2;
    const bool dynamic = motion && motion->column >= 0 && with_derivatives;
    if (dynamic) dy_dw_ = h * Skew(y_) * motion->Rt_Jl_minus;
    // the normal-cone combination normalized by Σ l_G = 1
    for (int j = 0; j < L.l_g_count; ++j) {
      const double l_g = z[L.l_g + j];
      const bool linear = sides.other->IsLinear(Constraint(j));
      const Vector3d gradient = Gradient(j);
      N_ += l_g * gradient;
      if (!linear) dN_da2_ += l_g * Hessian(j);
      if (dynamic) {
        dN_dw_ += l_g * (-h * Skew(gradient) * motion->Jl_plus);
        if (!linear) {
          dN_dw_ += l_g * motion->end.R * sides.other->Hessian(Constraint(j), y_) * dy_dw_;
        }
      }
      l_g_sum_ += l_g;
    }
    dN_dv_ = -h * dN_da2_;  // y_G depends on a2 − c_G − h v_G
  }

  // constraint j of the window at a2: g_j, its gradient in G's frame and in the world, and the
  // world gradient's derivative in a2
  double Value(int j) const { return sides_.other->Value(Constraint(j), y_); }
  Vector3d FrameGradient(int j) const { return sides_.other->Gradient(Constraint(j), y_); }
  Vector3d Gradient(int j) const {
    const Vector3d gradient = FrameGradient(j);
    return motion_ ? Vector3d(motion_->end.R * gradient) : gradient;
  }
  Matrix3d Hessian(int j) const {
    const Matrix3d H = sides_.other->Hessian(Constraint(j), y_);
    return motion_ ? Matrix3d(motion_->end.R * H * motion_->end.R.transpose()) : H;
  }

  const Vector3d& N() const { return N_; }
  double l_g_sum() const { return l_g_sum_; }
  const Matrix3d& dN_da2() const { return dN_da2_; }
  const Matrix3d& dN_dv() const { return dN_dv_; }  // in G's v⁺ (a dynamic G)
  const Matrix3d& dN_dw() const { return dN_dw_; }  // in G's ω⁺ (a dynamic G)
  const Matrix3d& dy_dw() const { return dy_dw_; }  // y_G in G's ω⁺ (a dynamic G)

 private:
  int Constraint(int j) const { return sides_.other_window ? (*sides_.other_window)[j] : j; }

  const ContactSides& sides_;
  const StepMotion* motion_;  // null: fixed, world frame
  Vector3d y_;
  Vector3d N_ = Vector3d::Zero();
  double l_g_sum_ = 0;
  Matrix3d dN_da2_ = Matrix3d::Zero(), dN_dv_ = Matrix3d::Zero(), dN_dw_ = Matrix3d::Zero();
  Matrix3d dy_dw_ = Matrix3d::Zero();
};

}  // namespace

StepMotion AddBodyRows(const BodyProblem& problem, int column, const Eigen::VectorXd& z,
                       Eigen::VectorXd& F, Eigen::MatrixXd* J) {
  StepMotion m;
  m.v = z.segment<3>(column);
  m.w = z.segment<3>(column + 3);
  m.column = column;
  m.end = PoseAfterStep(problem, m.v, m.w);
  // Newton–Euler with impulses (paper eq. discrete_NE), contact terms added per contact
  F.segment<3>(column) = problem.mass * (m.v - problem.v) - problem.p_ext.head<3>();
  F.segment<3>(column + 3) = GyroscopicResidual(problem, m.w) - problem.p_ext.tail<3>();
  if (J) {
    J->block<3, 3>(column, column) = problem.mass * Matrix3d::Identity();
    J->block<3, 3>(column + 3, column + 3) = GyroscopicJacobian(problem, m.w);
    // rotation-rate derivatives of the end pose (left Jacobians of Exp at ±hω)
    m.Jl_plus = LeftJacobian(problem.h * m.w);
    m.Rt_Jl_minus = Matrix3d(problem.R.transpose() * LeftJacobian(-problem.h * m.w));
  }
  return m;
}

double SetFrictionRows(const Friction& fr, double p_n, double v_t, double v_o, double v_r,
                       double p_t, double p_o, double p_r, double slip,
                       const MncpLayout::Contact& L, Eigen::VectorXd& F) {
  const double et2 = fr.e_t * fr.e_t, eo2 = fr.e_o * fr.e_o, er2 = fr.e_r * fr.e_r;
  F[L.p_t] = et2 * fr.mu * p_n * v_t + p_t * slip;
  F[L.p_o] = eo2 * fr.mu * p_n * v_o + p_o * slip;
  F[L.p_r] = er2 * fr.mu * p_n * v_r + p_r * slip;
  // the friction cone as μ p_n − ‖p̂‖ (see MncpResidual's note and engine/README.md)
  const double p_hat = std::sqrt(p_t * p_t / et2 + p_o * p_o / eo2 + p_r * p_r / er2);
  F[L.sigma] = fr.mu * p_n - p_hat;
  return p_hat;
}

void AddContactRows(const ContactSides& sides, const MncpLayout::Contact& L, const StepMotion& body,
                    const StepMotion* other, double h, const Eigen::VectorXd& z, Eigen::VectorXd& F,
                    Eigen::MatrixXd* J_out) {
  const bool with_jacobian = J_out != nullptr;
  // on a plane a2, s and l_G are left out (MncpLayout): a2 and s follow from a1, N is constant
  const bool plane = L.on_plane();
  ECPSIM_DEMAND(!plane || other == nullptr);
  const OtherSide G(sides, L, z, other, h, with_jacobian);
  const int col = body.column;
  const Vector3d& v = body.v;
  const Vector3d& w = body.w;
  const EndPose& end = body.end;
  const Matrix3d& R_end = end.R;
  const Vector3d a1 = z.segment<3>(L.a1);
  const auto [a2, s] = ContactGapAt(L, sides.other, z);
  const double p_t = z[L.p_t], p_o = z[L.p_o], p_r = z[L.p_r];
  const double p_n = z[L.p_n], sigma = z[L.sigma];
  const Friction& fr = sides.friction;

  // G's side: N = Σ l_G ∇g(a2), the normal-cone combination normalized by Σ l_G = 1
  const Vector3d& N = G.N();
  const ContactFrame frame = MakeContactFrame(N, sides.tangent_reference);
  const Vector3d& n = frame.n;
  const Vector3d& t = frame.t;
  const Vector3d& o = frame.o;

  // the ECP's lever arm at the end of the step and the contact impulse on F
  const Vector3d r = a1 - end.c;
  const Vector3d force = n * p_n + t * p_t + o * p_o;
  F.segment<3>(col) -= force;
  F.segment<3>(col + 3) -= r.cross(force) + n * p_r;
  // the opposite impulse on a dynamic G, at a2
  const bool dynamic_other = other && other->column >= 0;
  const Vector3d r_other = other ? Vector3d(a2 - other->end.c) : Vector3d::Zero();
  if (dynamic_other) {
    F.segment<3>(other->column) += force;
    F.segment<3>(other->column + 3) += r_other.cross(force) + n * p_r;
  }

  // contact constraints (paper eqs. re_contact_multiple_1..4, normalized on G's side)
  const Vector3d y = R_end.transpose() * r;  // a1 in the body frame at q⁺
  Vector3d cone = N;                         // N + Σ l_i ∇f_i(a1)
  for (int i = 0; i < L.l_count; ++i) {
    const int face = (*sides.window)[i];
    const Vector3d grad_world = R_end * sides.hull->Gradient(face, y);
    cone += z[L.l + i] * grad_world;
    F[L.l + i] = -sides.hull->Value(face, y);
  }
  // the normal-cone rows: a2's, or a1's on a plane (where a1 − a2 − s N = 0 holds by a2's
  // definition and Σ l_G = 1 by l_G's)
  const int cone_row = plane ? L.a1 : L.a2;
  F.segment<3>(cone_row) = cone;
  if (!plane) {
    F.segment<3>(L.a1) = a1 - a2 - s * N;
    F[L.s] = G.l_g_sum() - 1;
  }
  for (int j = 0; j < L.l_g_count; ++j) F[L.l_g + j] = -G.Value(j);
  // gap: a1 = a2 + s N with N in G's normal cone, so s has the sign of max_j g_j(a1)
  F[L.p_n] = s;

  // friction: Fritz-John conditions of maximum dissipation on the ellipsoid (paper eq. friction),
  // on the velocity relative to G at the ECP
  Vector3d v_contact = v + w.cross(r);
  Vector3d w_relative = w;
  if (other) {
    v_contact -= other->v + other->w.cross(r_other);
    w_relative -= other->w;
  }
  const double v_t = t.dot(v_contact), v_o = o.dot(v_contact), v_r = n.dot(w_relative);
  const double et2 = fr.e_t * fr.e_t, eo2 = fr.e_o * fr.e_o, er2 = fr.e_r * fr.e_r;
  // σ + ε for a creeping contact; σ itself (not σ + 0) otherwise, to the bit
  const double slip = sides.stick_creep > 0 ? sigma + sides.stick_creep : sigma;
  const double p_hat = SetFrictionRows(fr, p_n, v_t, v_o, v_r, p_t, p_o, p_r, slip, L, F);

  if (!with_jacobian) return;

  // --- analytic Jacobian ---
  Eigen::MatrixXd& J = *J_out;
  // (a plane's N is constant: nothing goes through it)
  const FrameDerivatives d =
      plane ? FrameDerivatives{Matrix3d::Zero(), Matrix3d::Zero(), Matrix3d::Zero()}
            : ContactFrameDerivatives(N, frame, sides.tangent_reference);
  // X_N (1×3 or 3×3): the derivative of some rows with respect to N, chained to (a2, l_G) and
  // to a dynamic G's ν⁺; given by `make_X_N`, called only where N is not constant (no plane)
  auto add_through_N = [&](int row, const auto& make_X_N) {
    if (plane) return;
    const auto X_N = make_X_N();
    constexpr int kRows = std::decay_t<decltype(X_N)>::RowsAtCompileTime;
    J.block<kRows, 3>(row, L.a2) += X_N * G.dN_da2();
    for (int j = 0; j < L.l_g_count; ++j) J.block<kRows, 1>(row, L.l_g + j) += X_N * G.Gradient(j);
    if (dynamic_other) {
      J.block<kRows, 3>(row, other->column) += X_N * G.dN_dv();
      J.block<kRows, 3>(row, other->column + 3) += X_N * G.dN_dw();
    }
  };
  const Matrix3d dforce_dN = p_n * d.dn_dN + p_t * d.dt_dN + p_o * d.do_dN;

  // Newton–Euler linear rows
  J.block<3, 1>(col, L.p_n) -= n;
  J.block<3, 1>(col, L.p_t) -= t;
  J.block<3, 1>(col, L.p_o) -= o;
  add_through_N(col, [&] { return Matrix3d(-dforce_dN); });

  // Newton–Euler angular rows: −(r × force + n p_r), r = a1 − c − h v
  J.block<3, 3>(col + 3, L.a1) += Skew(force);
  J.block<3, 3>(col + 3, col) += -h * Skew(force);
  J.block<3, 1>(col + 3, L.p_n) -= r.cross(n);
  J.block<3, 1>(col + 3, L.p_t) -= r.cross(t);
  J.block<3, 1>(col + 3, L.p_o) -= r.cross(o);
  J.block<3, 1>(col + 3, L.p_r) -= n;
  add_through_N(col + 3, [&] { return Matrix3d(-(Skew(r) * dforce_dN + p_r * d.dn_dN)); });

  // a dynamic G's Newton–Euler rows: + force and + (r_G × force + n p_r), r_G = a2 − c_G − h v_G
  if (dynamic_other) {
    const int other_col = other->column;
    J.block<3, 1>(other_col, L.p_n) += n;
    J.block<3, 1>(other_col, L.p_t) += t;
    J.block<3, 1>(other_col, L.p_o) += o;
    add_through_N(other_col, [&] { return dforce_dN; });
    J.block<3, 3>(other_col + 3, L.a2) -= Skew(force);
    J.block<3, 3>(other_col + 3, other_col) += h * Skew(force);
    J.block<3, 1>(other_col + 3, L.p_n) += r_other.cross(n);
    J.block<3, 1>(other_col + 3, L.p_t) += r_other.cross(t);
    J.block<3, 1>(other_col + 3, L.p_o) += r_other.cross(o);
    J.block<3, 1>(other_col + 3, L.p_r) += n;
    add_through_N(other_col + 3,
                  [&] { return Matrix3d(Skew(r_other) * dforce_dN + p_r * d.dn_dN); });
  }

  // hull constraints at the end pose: y = R⁺ᵀ(a1 − c − h v), R⁺ = Exp(hω) R
  const Matrix3d dy_da1 = R_end.transpose();
  const Matrix3d dy_dw = h * Skew(y) * body.Rt_Jl_minus;
  Matrix3d dcone_da1 = Matrix3d::Zero();
  Matrix3d dcone_dw = Matrix3d::Zero();
  for (int i = 0; i < L.l_count; ++i) {
    const int face = (*sides.window)[i];
    const double l = z[L.l + i];
    const Vector3d grad_body = sides.hull->Gradient(face, y);
    const Vector3d grad_world = R_end * grad_body;
    // complementarity row −f_i(a1; q⁺)
    const RowVector3d df_dy = grad_body.transpose();
    J.block<1, 3>(L.l + i, L.a1) = -df_dy * dy_da1;
    J.block<1, 3>(L.l + i, col) = h * df_dy * dy_da1;
    J.block<1, 3>(L.l + i, col + 3) = -df_dy * dy_dw;
    // the normal-cone row: ∂(l R⁺ ∇f(y))
    J.block<3, 1>(cone_row, L.l + i) = grad_world;
    dcone_dw += l * (-h * Skew(grad_world) * body.Jl_plus);
    if (!sides.hull->IsLinear(face)) {
      const Matrix3d H_world = R_end * sides.hull->Hessian(face, y);
      dcone_da1 += l * H_world * dy_da1;
      dcone_dw += l * H_world * dy_dw;
    }
  }
  J.block<3, 3>(cone_row, L.a1) += dcone_da1;
  J.block<3, 3>(cone_row, col) += -h * dcone_da1;
  J.block<3, 3>(cone_row, col + 3) += dcone_dw;
  if (plane) {
    // the gap s = g(a1)/|N|² = N·a1/|N|² + const
    J.block<1, 3>(L.p_n, L.a1) = N.transpose() / N.squaredNorm();
  } else {
    add_through_N(L.a2, [] { return Matrix3d(Matrix3d::Identity()); });
    // a1 − a2 − s N
    J.block<3, 3>(L.a1, L.a1) += Matrix3d::Identity();
    J.block<3, 3>(L.a1, L.a2) -= Matrix3d::Identity();
    J.block<3, 1>(L.a1, L.s) = -N;
    add_through_N(L.a1, [&] { return Matrix3d(-s * Matrix3d::Identity()); });
    J(L.p_n, L.s) = 1;
  }

  // Σ l_G = 1, G's complementarity rows −g_j(y_G)
  for (int j = 0; j < L.l_g_count; ++j) {
    J(L.s, L.l_g + j) = 1;
    const RowVector3d dg_da2 = G.Gradient(j).transpose();
    J.block<1, 3>(L.l_g + j, L.a2) = -dg_da2;
    if (dynamic_other) {
      J.block<1, 3>(L.l_g + j, other->column) = h * dg_da2;
      J.block<1, 3>(L.l_g + j, other->column + 3) = -G.FrameGradient(j).transpose() * G.dy_dw();
    }
  }

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
  const Row rows[2] = {{L.p_t, et2, p_t, v_t, &t, &d.dt_dN}, {L.p_o, eo2, p_o, v_o, &o, &d.do_dN}};
  for (const Row& row : rows) {
    const double scale = row.e2 * fr.mu * p_n;
    const RowVector3d axis_t = row.axis->transpose();
    J.block<1, 3>(row.index, col) += scale * axis_t * dvc_dv;
    J.block<1, 3>(row.index, col + 3) += scale * axis_t * dvc_dw;
    J.block<1, 3>(row.index, L.a1) += scale * axis_t * dvc_da1;
    add_through_N(row.index,
                  [&] { return RowVector3d(scale * v_contact.transpose() * *row.daxis_dN); });
    J(row.index, L.p_n) += row.e2 * fr.mu * row.speed;
    J(row.index, row.index) += slip;  // ∂/∂p_t (or p_o): the row index equals the unknown's
    J(row.index, L.sigma) += row.p;
    // G's point velocity v_G + ω_G × (a2 − c_G − h v_G)
    if (other) J.block<1, 3>(row.index, L.a2) -= scale * axis_t * Skew(other->w);
    if (dynamic_other) {
      J.block<1, 3>(row.index, other->column) -=
          scale * axis_t * (Matrix3d::Identity() - h * Skew(other->w));
      J.block<1, 3>(row.index, other->column + 3) += scale * axis_t * Skew(r_other);
    }
  }
  const double scale_r = er2 * fr.mu * p_n;
  J.block<1, 3>(L.p_r, col + 3) += scale_r * n.transpose();
  add_through_N(L.p_r, [&] { return RowVector3d(scale_r * w_relative.transpose() * d.dn_dN); });
  J(L.p_r, L.p_n) += er2 * fr.mu * v_r;
  J(L.p_r, L.p_r) += slip;
  J(L.p_r, L.sigma) += p_r;
  if (dynamic_other) J.block<1, 3>(L.p_r, other->column + 3) -= scale_r * n.transpose();

  // μ p_n − ‖p̂‖; at p̂ = 0 the norm's generalized gradient contains 0, which is used
  J(L.sigma, L.p_n) = fr.mu;
  if (p_hat > 0) {
    J(L.sigma, L.p_t) = -p_t / (et2 * p_hat);
    J(L.sigma, L.p_o) = -p_o / (eo2 * p_hat);
    J(L.sigma, L.p_r) = -p_r / (er2 * p_hat);
  }
}

Vector3d ContactNormalCombination(const ContactSides& sides, const MncpLayout::Contact& L,
                                  const StepMotion* other, const Eigen::VectorXd& z) {
  return OtherSide(sides, L, z, other, 0, false).N();
}

void EvaluateMncp(const BodyProblem& problem, const MncpLayout& layout, const Eigen::VectorXd& z,
                  Eigen::VectorXd* F_out, Eigen::MatrixXd* J_out, bool jacobian_is_zero) {
  F_out->setZero(layout.size);
  if (J_out && jacobian_is_zero) {
    ECPSIM_DEMAND(J_out->rows() == layout.size && J_out->cols() == layout.size);
  } else if (J_out) {
    J_out->setZero(layout.size, layout.size);
  }
  const StepMotion body = AddBodyRows(problem, 0, z, *F_out, J_out);
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const ContactProblem& cp = problem.contacts[k];
    const ContactSides sides{cp.hull, &cp.window,  cp.obstacle,
                             nullptr, cp.friction, cp.tangent_reference};
    AddContactRows(sides, layout.contacts[k], body, nullptr, problem.h, z, *F_out, J_out);
  }
}

}  // namespace ecpsim::engine
