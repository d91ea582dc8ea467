#include "engine/mncp/mncp_assembly.h"

#include "common/errors.h"

namespace ecpsim::engine {
namespace {

constexpr int kBodyUnknowns = 6;  // ν⁺ = (v⁺, ω⁺)

// A contact's block of unknowns for SparseMncpRows: F's ν⁺ (6), a dynamic G's ν⁺ (6), then its
// free block (a1, a2, s, p_t, p_o, p_r; on a plane a1, p_t, p_o, p_r) and its complementarity
// block (l, l_G, p_n, σ), each contiguous in the whole layout too
struct LocalContact {
  MncpLayout::Contact L;              // the contact's layout in local indices
  int other_column = -1;              // local column of a dynamic G's ν⁺
  int num_body_rows = kBodyUnknowns;  // the Newton–Euler rows first: 6, or 12 with a dynamic G
};

// the block of contact L between F's ν⁺ at `body_column` and a dynamic G's at `other_column`
// (−1: G is not a body); `global` becomes its local index → index in z
LocalContact MakeLocalContact(const MncpLayout::Contact& L, int body_column, int other_column,
                              std::vector<int>& global) {
  LocalContact local;
  global.clear();
  for (int i = 0; i < kBodyUnknowns; ++i) global.push_back(body_column + i);
  if (other_column >= 0) {
    local.other_column = kBodyUnknowns;
    local.num_body_rows = 2 * kBodyUnknowns;
    for (int i = 0; i < kBodyUnknowns; ++i) global.push_back(other_column + i);
  }
  const int free = static_cast<int>(global.size());
  for (int i = L.a1; i <= L.p_r; ++i) global.push_back(i);
  const int complementarity = static_cast<int>(global.size());
  const int count = L.l_count + L.l_g_count + 2;
  for (int i = 0; i < count; ++i) global.push_back(L.l + i);
  local.L = L;
  const int shift_free = free - L.a1, shift_complementarity = complementarity - L.l;
  for (int* index : {&local.L.a1, &local.L.p_t, &local.L.p_o, &local.L.p_r}) *index += shift_free;
  if (!L.on_plane())
    for (int* index : {&local.L.a2, &local.L.s}) *index += shift_free;
  for (int* index : {&local.L.l, &local.L.l_g, &local.L.p_n, &local.L.sigma})
    *index += shift_complementarity;
  return local;
}

// the non-zero entries of a dense local block as triplets of the whole matrix
void ScatterNonZeros(const Eigen::MatrixXd& block, const std::vector<int>& global,
                     std::vector<Eigen::Triplet<double>>& triplets) {
  for (Eigen::Index j = 0; j < block.cols(); ++j)
    for (Eigen::Index i = 0; i < block.rows(); ++i)
      if (block(i, j) != 0) triplets.emplace_back(global[i], global[j], block(i, j));
}

}  // namespace

DenseMncpRows::DenseMncpRows(int size, const Eigen::VectorXd& z, Eigen::VectorXd& F,
                             Eigen::MatrixXd* J, bool jacobian_is_zero)
    : z_(z), F_(F), J_(J) {
  F.setZero(size);
  if (J && jacobian_is_zero) {
    ECPSIM_DEMAND(J->rows() == size && J->cols() == size);
  } else if (J) {
    J->setZero(size, size);
  }
}

SparseMncpRows::SparseMncpRows(int size, const Eigen::VectorXd& z, Eigen::VectorXd& F,
                               std::vector<Eigen::Triplet<double>>* triplets)
    : z_(z), F_(F), triplets_(triplets) {
  F.setZero(size);
  if (!triplets) return;
  for (int i = 0; i < size; ++i) triplets->emplace_back(i, i, 0.0);
}

StepMotion SparseMncpRows::AddBody(const BodyProblem& problem, int column) {
  // the body's rows on its own ν⁺
  z_local_ = z_.segment<kBodyUnknowns>(column);
  F_local_.setZero(kBodyUnknowns);
  if (triplets_) J_local_.setZero(kBodyUnknowns, kBodyUnknowns);
  StepMotion motion = AddBodyRows(problem, 0, z_local_, F_local_, triplets_ ? &J_local_ : nullptr);
  motion.column = column;
  F_.segment<kBodyUnknowns>(column) = F_local_;
  if (!triplets_) return motion;
  global_.resize(kBodyUnknowns);
  for (int i = 0; i < kBodyUnknowns; ++i) global_[i] = column + i;
  ScatterNonZeros(J_local_, global_, *triplets_);
  return motion;
}

void SparseMncpRows::AddContact(const ContactLink& link, const MncpLayout::Contact& L,
                                const StepMotion& body, double h) {
  // the contact's rows and impulses on its compact block
  const bool dynamic_other = link.other && link.other->column >= 0;
  const LocalContact local =
      MakeLocalContact(L, body.column, dynamic_other ? link.other->column : -1, global_);
  const int m = static_cast<int>(global_.size());
  z_local_.resize(m);
  for (int i = 0; i < m; ++i) z_local_[i] = z_[global_[i]];
  F_local_.setZero(m);
  if (triplets_) J_local_.setZero(m, m);
  StepMotion local_body = body;
  local_body.column = 0;
  StepMotion local_other;
  if (link.other) {
    local_other = *link.other;
    local_other.column = local.other_column;
  }
  AddContactRows(link.sides, local.L, local_body, link.other ? &local_other : nullptr, h, z_local_,
                 F_local_, triplets_ ? &J_local_ : nullptr);
  // the impulses add to the bodies' Newton–Euler rows; the contact's own rows are its alone
  for (int i = 0; i < m; ++i) {
    if (i < local.num_body_rows) {
      F_[global_[i]] += F_local_[i];
    } else {
      F_[global_[i]] = F_local_[i];
    }
  }
  if (triplets_) ScatterNonZeros(J_local_, global_, *triplets_);
}

}  // namespace ecpsim::engine
