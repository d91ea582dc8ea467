#pragma once
// The one assembly of an MNCP's residual F and Jacobian J, for one body's MNCP (EvaluateMncp,
// mncp_system.h) and an island's (EvaluateIslandMncp and EvaluateIslandMncpSparse,
// island_mncp.h): per body its contact-free Newton–Euler rows (AddBodyRows), then per contact,
// in order, its rows and its impulse on the bodies it joins (AddContactRows). Two things vary,
// both template arguments resolved at compile time: where the bodies and contacts come from
// (`Problem`, a view of one body's problem or of an island's) and how J is stored (`Rows`: dense
// in place, or per block scattered as sparse triplets).

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "engine/mncp/body_step.h"
#include "engine/mncp/contact_rows.h"
#include "engine/mncp/mncp_layout.h"

namespace ecpsim::engine {

/// Values per body of an MNCP: in place for one body (the usual island, whose MNCP is evaluated
/// and measured every Newton iteration: no heap allocation), in a vector for several.
template <typename T>
class PerBody {
 public:
  explicit PerBody(int count) {
    if (count > 1) several_.resize(count);
  }
  PerBody(int count, const T& value) : single_(value) {
    if (count > 1) several_.assign(count, value);
  }
  T& operator[](int b) { return several_.empty() ? single_ : several_[b]; }
  const T& operator[](int b) const { return several_.empty() ? single_ : several_[b]; }

 private:
  T single_{};
  std::vector<T> several_;
};

/// One contact as the assembly walks it: its sides, the index of F's body and G's motion.
struct ContactLink {
  ContactSides sides;
  int body;                 // F's body, an index of the problem's bodies
  const StepMotion* other;  // G's motion over the step (its column ≥ 0: a body); null: fixed
};

/// Assembles F and J in place, J dense.
class DenseMncpRows {
 public:
  /// F becomes `size` zeros, J (if not null) size × size zeros — unless `jacobian_is_zero`: the
  /// caller promises J is already that (as SolveMcp hands it to its callback) and it is not
  /// cleared again. The references must outlive the object.
  DenseMncpRows(int size, const Eigen::VectorXd& z, Eigen::VectorXd& F, Eigen::MatrixXd* J,
                bool jacobian_is_zero);

  StepMotion AddBody(const BodyProblem& problem, int column) {
    return AddBodyRows(problem, column, z_, F_, J_);
  }
  void AddContact(const ContactLink& link, const MncpLayout::Contact& L, const StepMotion& body,
                  double h) {
    AddContactRows(link.sides, L, body, link.other, h, z_, F_, J_);
  }

 private:
  const Eigen::VectorXd& z_;
  Eigen::VectorXd& F_;
  Eigen::MatrixXd* J_;
};

/// Assembles F in place and J as triplets: each body's Newton–Euler rows and each contact's rows
/// are evaluated on the compact block of unknowns they touch (a body: its ν⁺; a contact: F's ν⁺,
/// a dynamic G's ν⁺ and its own block), their F added (a contact's impulse on the Newton–Euler
/// rows) or set (its own rows), their J's non-zero entries appended as triplets. Cost and storage
/// grow with the bodies and contacts, not with the square of the unknowns.
class SparseMncpRows {
 public:
  /// F becomes `size` zeros; `triplets` (null: no J) gets every diagonal entry, zero where J has
  /// none, so that a Newton matrix J + D keeps J's pattern. The references must outlive the
  /// object.
  SparseMncpRows(int size, const Eigen::VectorXd& z, Eigen::VectorXd& F,
                 std::vector<Eigen::Triplet<double>>* triplets);

  StepMotion AddBody(const BodyProblem& problem, int column);
  void AddContact(const ContactLink& link, const MncpLayout::Contact& L, const StepMotion& body,
                  double h);

 private:
  const Eigen::VectorXd& z_;
  Eigen::VectorXd& F_;
  std::vector<Eigen::Triplet<double>>* triplets_;
  // the block being evaluated: its local index → index in z, its unknowns, F and J
  std::vector<int> global_;
  Eigen::VectorXd z_local_, F_local_;
  Eigen::MatrixXd J_local_;
};

/// Assembles `problem`'s MNCP into `rows`: per body b its Newton–Euler rows, ν⁺ at
/// problem.Column(b), then per contact k its rows (layout problem.Layout(k)) and its impulse on
/// F's body and a dynamic G. `Problem` provides h(), NumBodies(), Body(b) (a BodyProblem),
/// Column(b), NumContacts(), Layout(k) and Link(k, motions) (a ContactLink, G's motion taken from
/// `motions`, the bodies' PerBody<StepMotion>, where G is a body).
template <typename Problem, typename Rows>
void AssembleMncp(const Problem& problem, Rows& rows) {
  PerBody<StepMotion> motions(problem.NumBodies());
  for (int b = 0; b < problem.NumBodies(); ++b)
    motions[b] = rows.AddBody(problem.Body(b), problem.Column(b));
  for (int k = 0; k < problem.NumContacts(); ++k) {
    const ContactLink link = problem.Link(k, motions);
    rows.AddContact(link, problem.Layout(k), motions[link.body], problem.h());
  }
}

}  // namespace ecpsim::engine
