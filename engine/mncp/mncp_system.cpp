#include "engine/mncp/mncp_system.h"

#include "common/errors.h"

namespace ecpsim::engine {

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
