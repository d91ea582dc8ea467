#pragma once
// MuJoCo, Bullet and ODE stepping an ecpsim scene: the same bodies (convex hull vertices, mass,
// inertia about the CM), half-space obstacles, friction, gravity and applied loads, so their
// trajectories can be compared with ecpsim's contact models (issue 6, docs/benchmarks.md).

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/scene.h"
#include "engine/state.h"

namespace ecpsim::baselines {

enum class ExternalEngine { kMujoco, kBullet, kOde };

/// Which settings the engine runs with.
enum class FrictionSetting {
  kDefault,  // the engine's documented defaults (only the time step, geometry, mass and μ set)
  kCoulomb,  // the engine's settings that come closest to Coulomb friction without penetration
             // (documented per engine in baselines/README.md)
};

/// "mujoco", "bullet", "ode".
const char* ExternalEngineName(ExternalEngine engine);

/// Whether this build links the engine (each is optional: ECPSIM_WITH_MUJOCO/BULLET/ODE).
bool IsAvailable(ExternalEngine engine);

/// One external engine's simulation of an ecpsim scene, stepped with the scene's h.
class ExternalSimulation {
 public:
  virtual ~ExternalSimulation() = default;

  /// Advances by scene.h. The scene's loads and impulses enter as a constant wrench over the step,
  /// engine::AppliedImpulse(…, t, h, R_WB) / h at the centre of mass (as ecpsim's models do).
  /// @throws engine::SolverFailure when the engine's state stops being finite (naming t and body).
  virtual void Step() = 0;

  /// The time and every body's CM position, orientation (body → world, with the scene's body
  /// frame: CM origin, the mesh's axes), linear and angular velocity (world), in ecpsim's
  /// conventions. `contacts` is empty.
  virtual const engine::State& state() const = 0;

  /// The mean contact force (N, world) that body `other` exerted on body `body` over the last
  /// step, from the engine's own contact impulses or forces of that step (what a force sensor
  /// between them reads); zero when they did not touch. Indices as in scene.bodies.
  virtual Eigen::Vector3d ContactForce(int body, int other) const = 0;
};

/// Builds `engine`'s model of `scene`: each body's collision geometry is the convex hull of its
/// mesh (or of its primitive hull's tessellation), and where its contact pairs touch its convex
/// parts (ContactPair::part) also those parts, each a convex geometry of its own at its place in
/// the body frame (baselines/README.md, "Bodies made of convex parts"); its mass and full inertia
/// tensor as given, each obstacle a half-space (plane); friction μ of each contact pair.
/// @throws InputError if the engine is not available in this build or the scene holds something
///         the adapter cannot model (an obstacle that is not a half-space), naming it.
std::unique_ptr<ExternalSimulation> MakeExternalSimulation(ExternalEngine engine,
                                                           FrictionSetting setting,
                                                           const engine::Scene& scene);

}  // namespace ecpsim::baselines
