#pragma once
// The multi-patch model's warm start of a contact (ContactState::warm_start).

#include <vector>

#include <Eigen/Core>

namespace ecpsim::engine {

/// The multi-patch model's unknowns of one contact: per convex part of the body its block
/// [a1, p_t, p_o, p_r, l…, p_n, σ] (the plane form, MakeMultiPatchLayout; a block of another
/// size, as the general form's of earlier versions, is not used: the step starts from its
/// guesses).
struct MultiPatchWarmStart {
  std::vector<Eigen::VectorXd> parts;
};

}  // namespace ecpsim::engine
