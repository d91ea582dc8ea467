#include "engine/mncp/contact_rows.h"

#include <cmath>
#include <type_traits>

#include "common/errors.h"
#include "engine/rotation.h"

namespace ecpsim::engine {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using RowVector3d = Eigen::Matrix<double, 1, 3>;

// Adds X_N ∂N/∂(a2, l_G, a dynamic G's ν⁺) to `row`: the chain rule through N for the rows that
// depend on it, X_N = ∂row/∂N (1 × 3 or 3 × 3) made by `make_X_N`, which is called only where N
// is not constant (not on a plane)
template <typename MakeXN>
void AddThroughN(const ContactAtZ& c, int row, const MakeXN& make_X_N, Eigen::MatrixXd& J) {
  if (c.plane) return;
  const auto X_N = make_X_N();
  constexpr int kRows = std::decay_t<decltype(X_N)>::RowsAtCompileTime;
  J.block<kRows, 3>(row, c.L.a2) += X_N * c.G.dN_da2();
  for (int j = 0; j < c.L.l_g_count; ++j)
    J.block<kRows, 1>(row, c.L.l_g + j) += X_N * c.G.Gradient(j);
  if (c.dynamic_other) {
    J.block<kRows, 3>(row, c.other->column) += X_N * c.G.dN_dv();
    J.block<kRows, 3>(row, c.other->column + 3) += X_N * c.G.dN_dw();
  }
}

// One body's share of the contact impulse in its Newton–Euler rows at `column` (which are
// M Δν − impulses): kSign = −1 for F, which receives (force, lever × force + n p_r) with lever
// r = a1 − c_F⁺; kSign = +1 for G, which receives the opposite at a2 with lever r_G. `point` is
// the z index of that body's ECP; c_⁺ = c + h v⁺ puts −h [lever]× … in the body's own v⁺.
// (±1 times x is exact, so either side does the operations of a plain += or −=.)
template <int kSign>
void AddImpulseOnBody(const ContactAtZ& c, int column, int point, const Vector3d& lever,
                      const Matrix3d& dforce_dN, Eigen::VectorXd& F, Eigen::MatrixXd* J_out) {
  constexpr double sign = kSign;
  const MncpLayout::Contact& L = c.L;
  const Vector3d& n = c.frame.n;
  F.segment<3>(column) += sign * c.force;
  F.segment<3>(column + 3) += sign * (lever.cross(c.force) + n * c.p_r);
  if (!J_out) return;
  Eigen::MatrixXd& J = *J_out;
  // force rows
  J.block<3, 1>(column, L.p_n) += sign * n;
  J.block<3, 1>(column, L.p_t) += sign * c.frame.t;
  J.block<3, 1>(column, L.p_o) += sign * c.frame.o;
  AddThroughN(
      c, column, [&] { return Matrix3d(sign * dforce_dN); }, J);
  // moment rows, lever = point − c − h v
  J.block<3, 3>(column + 3, point) -= sign * Skew(c.force);
  J.block<3, 3>(column + 3, column) += sign * c.h * Skew(c.force);
  J.block<3, 1>(column + 3, L.p_n) += sign * lever.cross(n);
  J.block<3, 1>(column + 3, L.p_t) += sign * lever.cross(c.frame.t);
  J.block<3, 1>(column + 3, L.p_o) += sign * lever.cross(c.frame.o);
  J.block<3, 1>(column + 3, L.p_r) += sign * n;
  AddThroughN(
      c, column + 3, [&] { return Matrix3d(sign * (Skew(lever) * dforce_dN + c.p_r * c.d.dn_dN)); },
      J);
}

// One sliding-friction row (p_t with axis t, or p_o with axis o):
// e² μ p_n (axis · v_c) + p slip, v_c = v + ω × (a1 − c − h v) − (v_G + ω_G × (a2 − c_G − h v_G))
struct SlidingRow {
  int index;             // the row, also the z index of its impulse p
  double e2;             // e_t² or e_o²
  double p;              // p_t or p_o
  double speed;          // v_t or v_o
  const Vector3d* axis;  // t or o
  const Matrix3d* daxis_dN;
};

// F's part of v_c in F's unknowns: ∂/∂v = I − h[ω]×, ∂/∂ω = −[r]×, ∂/∂a1 = [ω]×
struct SlipDerivatives {
  Matrix3d dvc_dv, dvc_dw, dvc_da1;
};

void AddSlidingFrictionJacobian(const ContactAtZ& c, const SlidingRow& row,
                                const SlipDerivatives& slip, Eigen::MatrixXd& J) {
  const MncpLayout::Contact& L = c.L;
  const Friction& fr = c.sides.friction;
  const int col = c.body.column;
  const double scale = row.e2 * fr.mu * c.p_n;
  const RowVector3d axis_t = row.axis->transpose();
  J.block<1, 3>(row.index, col) += scale * axis_t * slip.dvc_dv;
  J.block<1, 3>(row.index, col + 3) += scale * axis_t * slip.dvc_dw;
  J.block<1, 3>(row.index, L.a1) += scale * axis_t * slip.dvc_da1;
  AddThroughN(
      c, row.index, [&] { return RowVector3d(scale * c.v_contact.transpose() * *row.daxis_dN); },
      J);
  J(row.index, L.p_n) += row.e2 * fr.mu * row.speed;
  J(row.index, row.index) += c.slip;  // ∂/∂p_t (or p_o): the row index equals the unknown's
  J(row.index, L.sigma) += row.p;
  // G's point velocity v_G + ω_G × (a2 − c_G − h v_G)
  if (c.other) J.block<1, 3>(row.index, L.a2) -= scale * axis_t * Skew(c.other->w);
  if (c.dynamic_other) {
    J.block<1, 3>(row.index, c.other->column) -=
        scale * axis_t * (Matrix3d::Identity() - c.h * Skew(c.other->w));
    J.block<1, 3>(row.index, c.other->column + 3) += scale * axis_t * Skew(c.r_other);
  }
}

}  // namespace

OtherSide::OtherSide(const ContactSides& sides, const MncpLayout::Contact& L,
                     const Eigen::VectorXd& z, const StepMotion* motion, double h,
                     bool with_derivatives)
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
      if (!linear) dN_dw_ += l_g * motion->end.R * sides.other->Hessian(Constraint(j), y_) * dy_dw_;
    }
    l_g_sum_ += l_g;
  }
  dN_dv_ = -h * dN_da2_;  // y_G depends on a2 − c_G − h v_G
}

ContactAtZ::ContactAtZ(const ContactSides& sides_in, const MncpLayout::Contact& L_in,
                       const StepMotion& body_in, const StepMotion* other_in, double h_in,
                       const Eigen::VectorXd& z_in, bool with_jacobian)
    : sides(sides_in),
      L(L_in),
      body(body_in),
      other(other_in),
      h(h_in),
      z(z_in),
      plane(L_in.on_plane()),
      dynamic_other(other_in && other_in->column >= 0),
      G(sides_in, L_in, z_in, other_in, h_in, with_jacobian) {
  ECPSIM_DEMAND(!plane || other == nullptr);
  a1 = z.segment<3>(L.a1);
  const ContactGap gap = ContactGapAt(L, sides.other, z);
  a2 = gap.a2;
  s = gap.s;
  p_t = z[L.p_t];
  p_o = z[L.p_o];
  p_r = z[L.p_r];
  p_n = z[L.p_n];
  sigma = z[L.sigma];
  // G's side: N = Σ l_G ∇g(a2), the normal-cone combination normalized by Σ l_G = 1
  frame = MakeContactFrame(G.N(), sides.tangent_reference);
  // the ECP's lever arms at the end of the step and the contact impulse on F
  r = a1 - body.end.c;
  r_other = other ? Vector3d(a2 - other->end.c) : Vector3d::Zero();
  y = body.end.R.transpose() * r;
  force = frame.n * p_n + frame.t * p_t + frame.o * p_o;
  // the velocity relative to G at the ECP
  v_contact = body.v + body.w.cross(r);
  w_relative = body.w;
  if (other) {
    v_contact -= other->v + other->w.cross(r_other);
    w_relative -= other->w;
  }
  v_t = frame.t.dot(v_contact);
  v_o = frame.o.dot(v_contact);
  v_r = frame.n.dot(w_relative);
  // σ + ε for a creeping contact; σ itself (not σ + 0) otherwise, to the bit
  slip = sides.stick_creep > 0 ? sigma + sides.stick_creep : sigma;
  if (!with_jacobian) return;
  // (a plane's N is constant: nothing goes through it)
  d = plane ? FrameDerivatives{Matrix3d::Zero(), Matrix3d::Zero(), Matrix3d::Zero()}
            : ContactFrameDerivatives(G.N(), frame, sides.tangent_reference);
  // y = R⁺ᵀ(a1 − c − h v), R⁺ = Exp(hω) R
  dy_da1 = body.end.R.transpose();
  dy_dw = h * Skew(y) * body.Rt_Jl_minus;
}

void AddContactImpulse(const ContactAtZ& c, Eigen::VectorXd& F, Eigen::MatrixXd* J) {
  const Matrix3d dforce_dN =
      J ? Matrix3d(c.p_n * c.d.dn_dN + c.p_t * c.d.dt_dN + c.p_o * c.d.do_dN) : Matrix3d();
  AddImpulseOnBody<-1>(c, c.body.column, c.L.a1, c.r, dforce_dN, F, J);
  if (c.dynamic_other) AddImpulseOnBody<+1>(c, c.other->column, c.L.a2, c.r_other, dforce_dN, F, J);
}

void SetSeparationRows(const ContactAtZ& c, Eigen::VectorXd& F, Eigen::MatrixXd* J) {
  if (c.plane) return;
  const MncpLayout::Contact& L = c.L;
  const Vector3d& N = c.G.N();
  F.segment<3>(L.a1) = c.a1 - c.a2 - c.s * N;
  if (!J) return;
  J->block<3, 3>(L.a1, L.a1) += Matrix3d::Identity();
  J->block<3, 3>(L.a1, L.a2) -= Matrix3d::Identity();
  J->block<3, 1>(L.a1, L.s) = -N;
  AddThroughN(
      c, L.a1, [&] { return Matrix3d(-c.s * Matrix3d::Identity()); }, *J);
}

void SetNormalConeRows(const ContactAtZ& c, Eigen::VectorXd& F, Eigen::MatrixXd* J) {
  const MncpLayout::Contact& L = c.L;
  const int row = c.ConeRow();
  const int col = c.body.column;
  const Matrix3d& R_end = c.body.end.R;
  // N + Σ l_i R⁺ ∇f_i(y), with R⁺ = Exp(hω) R and y = R⁺ᵀ(a1 − c − h v)
  Vector3d cone = c.G.N();
  Matrix3d dcone_da1 = Matrix3d::Zero();
  Matrix3d dcone_dw = Matrix3d::Zero();
  for (int i = 0; i < L.l_count; ++i) {
    const int face = (*c.sides.window)[i];
    const double l = c.z[L.l + i];
    const Vector3d grad_world = R_end * c.sides.hull->Gradient(face, c.y);
    cone += l * grad_world;
    if (!J) continue;
    J->block<3, 1>(row, L.l + i) = grad_world;
    dcone_dw += l * (-c.h * Skew(grad_world) * c.body.Jl_plus);
    if (!c.sides.hull->IsLinear(face)) {
      const Matrix3d H_world = R_end * c.sides.hull->Hessian(face, c.y);
      dcone_da1 += l * H_world * c.dy_da1;
      dcone_dw += l * H_world * c.dy_dw;
    }
  }
  F.segment<3>(row) = cone;
  if (!J) return;
  J->block<3, 3>(row, L.a1) += dcone_da1;
  J->block<3, 3>(row, col) += -c.h * dcone_da1;
  J->block<3, 3>(row, col + 3) += dcone_dw;
  AddThroughN(
      c, row, [] { return Matrix3d(Matrix3d::Identity()); }, *J);
}

void SetHullConstraintRows(const ContactAtZ& c, Eigen::VectorXd& F, Eigen::MatrixXd* J) {
  const MncpLayout::Contact& L = c.L;
  const int col = c.body.column;
  for (int i = 0; i < L.l_count; ++i) {
    const int face = (*c.sides.window)[i];
    F[L.l + i] = -c.sides.hull->Value(face, c.y);
    if (!J) continue;
    // y = R⁺ᵀ(a1 − c − h v): ∂y/∂v = −h ∂y/∂a1
    const RowVector3d df_dy = c.sides.hull->Gradient(face, c.y).transpose();
    J->block<1, 3>(L.l + i, L.a1) = -df_dy * c.dy_da1;
    J->block<1, 3>(L.l + i, col) = c.h * df_dy * c.dy_da1;
    J->block<1, 3>(L.l + i, col + 3) = -df_dy * c.dy_dw;
  }
}

void SetObstacleConstraintRows(const ContactAtZ& c, Eigen::VectorXd& F, Eigen::MatrixXd* J) {
  if (c.plane) return;
  const MncpLayout::Contact& L = c.L;
  F[L.s] = c.G.l_g_sum() - 1;
  for (int j = 0; j < L.l_g_count; ++j) F[L.l_g + j] = -c.G.Value(j);
  if (!J) return;
  for (int j = 0; j < L.l_g_count; ++j) {
    (*J)(L.s, L.l_g + j) = 1;
    // y_G = R_G⁺ᵀ(a2 − c_G − h v_G)
    const RowVector3d dg_da2 = c.G.Gradient(j).transpose();
    J->block<1, 3>(L.l_g + j, L.a2) = -dg_da2;
    if (c.dynamic_other) {
      J->block<1, 3>(L.l_g + j, c.other->column) = c.h * dg_da2;
      J->block<1, 3>(L.l_g + j, c.other->column + 3) =
          -c.G.FrameGradient(j).transpose() * c.G.dy_dw();
    }
  }
}

void SetGapRow(const ContactAtZ& c, Eigen::VectorXd& F, Eigen::MatrixXd* J) {
  const MncpLayout::Contact& L = c.L;
  // a1 = a2 + s N with N in G's normal cone, so s has the sign of max_j g_j(a1)
  F[L.p_n] = c.s;
  if (!J) return;
  if (c.plane) {
    // s = g(a1)/|N|² = N·a1/|N|² + const
    const Vector3d& N = c.G.N();
    J->block<1, 3>(L.p_n, L.a1) = N.transpose() / N.squaredNorm();
  } else {
    (*J)(L.p_n, L.s) = 1;
  }
}

void SetMaximumDissipationRows(const ContactAtZ& c, Eigen::VectorXd& F, Eigen::MatrixXd* J_out) {
  const MncpLayout::Contact& L = c.L;
  const Friction& fr = c.sides.friction;
  const double p_hat =
      SetFrictionRows(fr, c.p_n, c.v_t, c.v_o, c.v_r, c.p_t, c.p_o, c.p_r, c.slip, L, F);
  if (!J_out) return;
  Eigen::MatrixXd& J = *J_out;
  const double et2 = fr.e_t * fr.e_t, eo2 = fr.e_o * fr.e_o, er2 = fr.e_r * fr.e_r;
  // sliding: v_t = t · v_c, v_o = o · v_c
  const SlipDerivatives slip{Matrix3d::Identity() - c.h * Skew(c.body.w), -Skew(c.r),
                             Skew(c.body.w)};
  AddSlidingFrictionJacobian(c, {L.p_t, et2, c.p_t, c.v_t, &c.frame.t, &c.d.dt_dN}, slip, J);
  AddSlidingFrictionJacobian(c, {L.p_o, eo2, c.p_o, c.v_o, &c.frame.o, &c.d.do_dN}, slip, J);
  // spin: v_r = n · (ω − ω_G)
  const double scale_r = er2 * fr.mu * c.p_n;
  J.block<1, 3>(L.p_r, c.body.column + 3) += scale_r * c.frame.n.transpose();
  AddThroughN(
      c, L.p_r, [&] { return RowVector3d(scale_r * c.w_relative.transpose() * c.d.dn_dN); }, J);
  J(L.p_r, L.p_n) += er2 * fr.mu * c.v_r;
  J(L.p_r, L.p_r) += c.slip;
  J(L.p_r, L.sigma) += c.p_r;
  if (c.dynamic_other) J.block<1, 3>(L.p_r, c.other->column + 3) -= scale_r * c.frame.n.transpose();
  // the cone μ p_n − ‖p̂‖; at p̂ = 0 the norm's generalized gradient contains 0, which is used
  J(L.sigma, L.p_n) = fr.mu;
  if (p_hat > 0) {
    J(L.sigma, L.p_t) = -c.p_t / (et2 * p_hat);
    J(L.sigma, L.p_o) = -c.p_o / (eo2 * p_hat);
    J(L.sigma, L.p_r) = -c.p_r / (er2 * p_hat);
  }
}

double SetFrictionRows(const Friction& fr, double p_n, double v_t, double v_o, double v_r,
                       double p_t, double p_o, double p_r, double slip,
                       const MncpLayout::Contact& L, Eigen::VectorXd& F) {
  const double et2 = fr.e_t * fr.e_t, eo2 = fr.e_o * fr.e_o, er2 = fr.e_r * fr.e_r;
  F[L.p_t] = et2 * fr.mu * p_n * v_t + p_t * slip;
  F[L.p_o] = eo2 * fr.mu * p_n * v_o + p_o * slip;
  F[L.p_r] = er2 * fr.mu * p_n * v_r + p_r * slip;
  // the friction cone as μ p_n − ‖p̂‖ (see EvaluateMncp's note and engine/README.md)
  const double p_hat = std::sqrt(p_t * p_t / et2 + p_o * p_o / eo2 + p_r * p_r / er2);
  F[L.sigma] = fr.mu * p_n - p_hat;
  return p_hat;
}

// flatten: the row groups compiled as one function; called one by one they cost 12 % more
// instructions per contact evaluation on the desk (callgrind), in calls and in reloading c
[[gnu::flatten]] void AddContactRows(const ContactSides& sides, const MncpLayout::Contact& L,
                                     const StepMotion& body, const StepMotion* other, double h,
                                     const Eigen::VectorXd& z, Eigen::VectorXd& F,
                                     Eigen::MatrixXd* J) {
  const ContactAtZ c(sides, L, body, other, h, z, J != nullptr);
  AddContactImpulse(c, F, J);
  SetSeparationRows(c, F, J);
  SetNormalConeRows(c, F, J);
  SetHullConstraintRows(c, F, J);
  SetObstacleConstraintRows(c, F, J);
  SetGapRow(c, F, J);
  SetMaximumDissipationRows(c, F, J);
}

Vector3d ContactNormalCombination(const ContactSides& sides, const MncpLayout::Contact& L,
                                  const StepMotion* other, const Eigen::VectorXd& z) {
  return OtherSide(sides, L, z, other, 0, false).N();
}

}  // namespace ecpsim::engine
