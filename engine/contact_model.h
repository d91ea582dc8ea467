#pragma once
// The interface every contact model implements (hull, planar, multi-patch, point): advance one
// contact island — bodies whose contacts couple them within the step, with those contacts — by
// one step or sub-step. The driver (step_driver.h) forms the islands (islands.h), runs the
// split spans and commits; a model only solves.

#include <string>
#include <vector>

#include "common/errors.h"
#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"

namespace ecpsim::engine {

/// Bodies solved together and their contacts (indices into Scene::bodies and Scene::contacts,
/// ascending), with each contact's friction for the step (StepFriction, contact_friction.h: the
/// pair's, e_r from the patch at the step's start where it asks for it), which every model reads
/// instead of the pair's.
struct Island {
  std::vector<int> bodies;
  std::vector<int> contacts;
  std::vector<Friction> friction;  // one per contact, in their order
};

/// The part of the State an island's step reads and writes, in the island's orders.
struct IslandState {
  std::vector<BodyState> bodies;
  std::vector<ContactState> contacts;
};

/// What one attempt to advance an island reports.
struct AdvanceResult {
  StepModel model = StepModel::kHull;  // what solved it
  bool solved = false;
  double residual = 0;  // the accepted solution's convergence measure (failed: the last one)
  int iterations = 0;   // solver iterations (Lemke pivots for the point model), all attempts
  int retries = 0;      // guesses that failed before the accepted one
  std::vector<FailedAttempt> tried;  // what failed, in order, for SolverFailure
};

/// How hard the driver asks a model to try: its usual attempt, or the dearer last resort that the
/// driver asks for only on a span where the usual one failed and so did every split of the span
/// into halves, so that every step the usual attempt solves is solved as without it.
enum class Effort { kUsual, kLastResort };

class ContactModelStepper {
 public:
  virtual ~ContactModelStepper() = default;
  /// Advances `state` from time t by h with `effort`. When the result is not solved, `state`
  /// holds no meaningful values (the driver discards it).
  /// @throws ModelInvalid where the model does not apply.
  virtual AdvanceResult Advance(const Island& island, double t, double h, IslandState& state,
                                Effort effort) const = 0;
  /// Whether Effort::kLastResort tries more than Effort::kUsual (false: the driver never asks).
  virtual bool HasLastResort() const { return false; }
};

}  // namespace ecpsim::engine
