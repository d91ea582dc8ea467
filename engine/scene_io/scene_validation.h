#pragma once
// The checks an assembled Scene must pass before it runs, however it was built: ranges, step
// count, finite masses, inertias and poses, initial overlap. Every route into a Scene ends here
// before it returns — LoadScene (a YAML file), MakeDropScene (`ecpsim drop`), MakeGroundScene
// (code), the Python module's make_scene — and reports the SceneError in its own terms (file
// line, option, dict key); evaluation::MakeStepper checks again the scenes a sweep edits.

#include <optional>
#include <string>
#include <vector>

#include "common/errors.h"
#include "engine/scene.h"
#include "engine/scene_io/loaded_scene.h"
#include "engine/state.h"

namespace ecpsim::engine {

/// A problem of a Scene, named by key paths of the scene format (docs/scene_format.md) so that
/// it reads without a file, and the YAML loader can point at the line behind it. what() is
/// "KEY = VALUE: expected EXPECTED", e.g. `bodies[0].mass = -1: expected a finite mass > 0 kg`.
class SceneError : public InputError {
 public:
  SceneError(std::vector<std::string> keys, std::string value, std::string expected);

  /// The keys the problem is about, the most specific first: a loader reports the first one its
  /// file has, e.g. {"bodies[0].position", "bodies[0].on_ground", "bodies[0]"}. Obstacles are
  /// indexed as in Scene::obstacles.
  const std::vector<std::string>& keys() const { return keys_; }
  /// The value as the Scene holds it, e.g. "(0, 0, -0.35)".
  const std::string& value() const { return value_; }
  /// What was expected, with the body or obstacle by name, e.g. "an initial pose of body \"box\"
  /// whose mesh stays out of obstacle \"ground\" ...".
  const std::string& expected() const { return expected_; }

 private:
  std::vector<std::string> keys_;
  std::string value_;
  std::string expected_;
};

/// Two things of a scene inside each other deeper than kInitialPenetrationTolerance × the
/// size (the body's, or the smaller body's): body `body` in obstacle `obstacle` or in body
/// `other_body` (the other index −1), by `depth` m against `tolerance` m.
struct Overlap {
  int body = -1;
  int other_body = -1;
  int obstacle = -1;
  double depth = 0;
  double tolerance = 0;
  double size = 0;  // m, across the body's mesh (of a pair: the smaller one's)
};

/// The first overlap of `state`'s poses: a dynamic body in an obstacle, then the bodies of a
/// contact pair in each other; bodies with allow_initial_penetration are skipped, as kinematic
/// ones against obstacles (they go where their motion says). None when all are apart.
std::optional<Overlap> FindOverlap(const Scene& scene, const State& state);

/// Checks `scene` as a whole (docs/scene_format.md, "Checks and error messages"):
/// - h and duration finite and in range, h ≤ duration, at most kMaxSteps steps;
/// - at least one body; unique, valid names; every number finite and within its range
///   (scene_limits.h): masses, principal moments of inertia and radii of gyration, mesh sizes,
///   poses and velocities, gravity, friction, loads' windows and points, impulses, solver
///   settings; inertias symmetric positive definite with the triangle inequality;
///   unit-normalizable orientations; every body within kMaxDistanceInSizes of its size from the
///   origin; contacts, loads and impulses naming existing bodies and obstacles;
/// - no body's mesh deeper inside an obstacle at t = 0 than kInitialPenetrationTolerance × its
///   size, nor the bodies of a contact pair inside each other (PenetrationProbe::BodyDepth)
///   deeper than that × the smaller one's, unless Body::allow_initial_penetration (of either).
/// @throws SceneError for the first problem found.
void ValidateScene(const Scene& scene);

/// ValidateScene's checks of body `body`'s mass and inertia alone, for a validated scene whose
/// copy is edited (the Python module's Simulation.set_mass): the mass, principal moments and radii
/// of gyration in range, the inertia symmetric positive definite with the triangle inequality.
/// Precondition: 0 ≤ body < scene.bodies.size().
/// @throws SceneError as ValidateScene (keys bodies[body].*).
void ValidateMassProperties(const Scene& scene, int body);

/// ValidateScene's check of contact `contact`'s friction alone (Simulation.set_friction): μ ≥ 0,
/// e_t, e_o > 0 and e_r a length > 0 unless `patch`, each finite within scene_limits.h's ranges.
/// Precondition: 0 ≤ contact < scene.contacts.size() and the contact's indices valid.
/// @throws SceneError as ValidateScene.
void ValidateContactFriction(const Scene& scene, int contact);

/// ValidateScene of `loaded.scene`, with `loaded.output` checked after the solver settings and
/// before the initial overlap (so a file's first problem is the same whichever it is): `every`
/// ≥ 1, fps in range, width and height in [kMinFramePixels, kMaxFramePixels], a finite camera
/// position apart from its target, a field of view in (0, 180) degrees. Keys `output.*`.
/// @throws SceneError for the first problem found.
void ValidateLoadedScene(const LoadedScene& loaded);

}  // namespace ecpsim::engine
