#include "engine/mncp/mncp_system.h"

#include "engine/mncp/mncp_assembly.h"

namespace ecpsim::engine {
namespace {

// one body and its contacts with fixed obstacles (world frame, all of G's constraints), as
// AssembleMncp walks them
class OneBodyView {
 public:
  OneBodyView(const BodyProblem& problem, const MncpLayout& layout)
      : problem_(problem), layout_(layout) {}

  double h() const { return problem_.h; }
  int NumBodies() const { return 1; }
  const BodyProblem& Body(int) const { return problem_; }
  int Column(int) const { return 0; }  // ν⁺ first (MncpLayout)
  int NumContacts() const { return static_cast<int>(problem_.contacts.size()); }
  const MncpLayout::Contact& Layout(int k) const { return layout_.contacts[k]; }
  ContactLink Link(int k, const PerBody<StepMotion>&) const {
    const ContactProblem& cp = problem_.contacts[k];
    return {
        {cp.hull, &cp.window, cp.obstacle, nullptr, cp.friction, cp.tangent_reference}, 0, nullptr};
  }

 private:
  const BodyProblem& problem_;
  const MncpLayout& layout_;
};

}  // namespace

void EvaluateMncp(const BodyProblem& problem, const MncpLayout& layout, const Eigen::VectorXd& z,
                  Eigen::VectorXd* F, Eigen::MatrixXd* J, bool jacobian_is_zero) {
  DenseMncpRows rows(layout.size, z, *F, J, jacobian_is_zero);
  AssembleMncp(OneBodyView(problem, layout), rows);
}

}  // namespace ecpsim::engine
