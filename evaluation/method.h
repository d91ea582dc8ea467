#pragma once
// The simulation methods a benchmark compares: ecpsim's contact models (with a solver tolerance)
// and the external engines (with a settings choice), behind one stepping interface.

#include <memory>
#include <string>
#include <vector>

#include "baselines/external_simulation.h"
#include "common/cancel_flag.h"
#include "engine/scene.h"
#include "engine/state.h"

namespace ecpsim::evaluation {

struct Method {
  std::string name;  // e.g. "hull", "hull-tol1e-06", "point", "mujoco-coulomb" (CSV key)
  bool external = false;
  engine::ContactModel model = engine::ContactModel::kHull;  // ecpsim's model (external = false)
  double tolerance = 1e-12;                                  // ecpsim's residual tolerance
  // ecpsim's choice where a step's solutions form a set (solver.selection)
  engine::Selection selection = engine::Selection::kCreep;
  // run when no --methods are named (the least-energy selection only where named: its dense
  // factorizations make the many-body scenarios and the scaling grid take hours)
  bool in_default_set = true;
  baselines::ExternalEngine engine = baselines::ExternalEngine::kMujoco;  // (external = true)
  baselines::FrictionSetting setting = baselines::FrictionSetting::kDefault;
};

/// Every method this build can run: hull at tolerances 1e-12 (the default), 1e-8 and 1e-5; auto,
/// and auto with the least-energy selection (auto-least-energy); planar; multipatch; point; and
/// each available external engine with its default and its Coulomb-matched settings.
std::vector<Method> AllMethods();

/// AllMethods() that are in_default_set: what a sweep runs when no methods are named.
std::vector<Method> DefaultMethods();

/// The method called `name` among AllMethods().
/// @throws InputError naming the name and the choices.
Method FindMethod(const std::string& name);

/// A method stepping one scene.
class Stepper {
 public:
  virtual ~Stepper() = default;
  /// Advances by the scene's h. @throws engine::SolverFailure or engine::ModelInvalid; Cancelled
  /// (the state unchanged) once the flag of StopOn is raised.
  virtual void Step() = 0;
  /// Steps stop within a solver iteration once `flag` is raised (ecpsim's; an external engine's
  /// step, a few milliseconds at most, runs to its end).
  virtual void StopOn(const CancelFlag* flag) = 0;
  virtual const engine::State& state() const = 0;
  /// Iterations of the last step (Newton iterations, Lemke pivots; 0 for external engines).
  virtual int iterations() const = 0;
  /// The mean contact force (N, world) body `other` exerted on body `body` over the last step.
  virtual Eigen::Vector3d ContactForce(int body, int other) const = 0;
};

/// A stepper of `scene` from its initial state; ecpsim's methods step it with `method`'s model and
/// tolerance.
/// @throws engine::SceneError if `scene` fails engine::ValidateScene (e.g. `h = 0: expected a
///         finite time step > 0 s: ...`), InputError if an external engine cannot model it.
std::unique_ptr<Stepper> MakeStepper(const Method& method, const engine::Scene& scene);

}  // namespace ecpsim::evaluation
