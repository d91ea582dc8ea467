#pragma once
// The immutable physics of a simulation: bodies, fixed convex obstacles, contacts, loads and the
// solver's settings (MuJoCo's model/data split: this is the model; state.h is the data). What a
// run writes and the notes from loading a scene travel beside it (scene_io/loaded_scene.h).

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "engine/contact_index.h"
#include "engine/kinematic_motion.h"
#include "engine/loads.h"
#include "geometry/convex_shape.h"
#include "geometry/triangle_mesh.h"

namespace ecpsim::engine {

/// Ellipsoidal friction parameters of one contact (paper eq. for the friction ellipsoid).
struct Friction {
  double mu = 0.22;  // Coulomb coefficient, ≥ 0
  double e_t = 1;    // ellipsoid semi-axes: force axes (dimensionless) ...
  double e_o = 1;
  double e_r = 0.1;  // ... and torsion (m)
  // `e_r: patch`: e_r is the contact patch's mean distance from the ECP, computed for each contact
  // at the start of each step (StepFriction, engine/contact_friction.h); e_r above is then unused
  bool e_r_patch = false;
};

/// Which contact model steps the scene (`model:` in the scene file, `ecpsim run --model`).
enum class ContactModel {
  kAuto,        // per island and step the cheapest model whose answer is the hull model's
  kHull,        // the paper's model: one ECP per body–obstacle pair on the body's convex hull
  kPlanar,      // planar sliding (WAFR 2018): flat on a horizontal plane, no vertical motion
  kMultiPatch,  // multi-convex-patch (IDETC 2018): one ECP per convex part, friction combined
  kPoint,       // usual practice: hull vertices near G as contact points, polyhedral cone, an LCP
};
const char* ContactModelName(ContactModel model);

/// What a body's contacts with other bodies and with bounded obstacles touch: its convex hull,
/// or each of its convex parts (engine/README.md, "Bodies made of convex parts"). A half-space
/// touches a body's hull only where it touches the body, so contacts with one always take the hull.
enum class Decomposition {
  kNone,   // the hull: exact where nothing reaches into a cavity of the body
  kParts,  // each of Body::parts, a contact per part (and per part of the other body)
  kAuto,   // per pair and step the hull where it is exact, else each part (engine/auto_sides.h)
};

/// "none", "parts", "auto" (`decomposition` of a body in the scene file).
const char* DecompositionName(Decomposition decomposition);

/// A rigid body F: its mesh and convex hull in the body frame (origin at the centre of mass).
struct Body {
  std::string name;
  geometry::TriangleMesh mesh;                        // body frame, for patches/penetration/display
  std::shared_ptr<const geometry::ConvexShape> hull;  // body frame: the CGAL hull or a primitive
  // body frame: the convex parts whose union is the body's contact geometry (empty: the hull is
  // the one part). The multi-patch model's patches against half-spaces; under `decomposition`
  // kParts also the body's contacts with bodies and bounded obstacles, one per part
  std::vector<std::shared_ptr<const geometry::ConvexShape>> parts;
  Decomposition decomposition = Decomposition::kNone;
  // body frame, under kAuto: thin slabs under the faces of the hull the parts do not cover, the
  // lids over the body's cavities (geometry::LidSlabs)
  std::vector<std::shared_ptr<const geometry::ConvexShape>> lids;
  double mass = 1;                                        // kg
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Identity();  // kg·m², about the CM, body axes
  // initial state
  Eigen::Vector3d p0 = Eigen::Vector3d::Zero();            // m, CM position in world
  Eigen::Quaterniond q0 = Eigen::Quaterniond::Identity();  // body → world
  Eigen::Vector3d v0 = Eigen::Vector3d::Zero();            // m/s, world
  Eigen::Vector3d w0 = Eigen::Vector3d::Zero();            // rad/s, world (spatial)
  // true: the initial pose may overlap an obstacle deeper than ValidateScene's tolerance (the
  // solver then pushes the body out in the first steps)
  bool allow_initial_penetration = false;
  // the friction of its contacts with other bodies (ContactPair, "the pair rule")
  Friction friction;
  // a kinematic body: its pose is prescribed (mass, inertia and the initial state unused); it
  // pushes and is never pushed. Null: a dynamic body
  std::shared_ptr<const KinematicMotion> motion;
  bool IsKinematic() const { return motion != nullptr; }
  // a jaw of Scene::grippers[gripper] (a dynamic body whose motion the gripper constrains); -1:
  // no jaw
  int gripper = -1;
  bool IsJaw() const { return gripper >= 0; }
};

/// A parallel-jaw gripper (docs/scene_format.md, "Grippers"): a frame whose pose is prescribed
/// like a kinematic body's carries two jaws, dynamic bodies of the scene that slide along the
/// frame's closing axis only, coupled about the frame's centre like the two fingers of one
/// actuator (a rack or a linkage). Across the axis and in orientation each jaw follows the frame
/// exactly (position control); along it the grip is force-controlled: the actuator closes the
/// jaws with `force` on each, and their midpoint follows the frame's centre.
struct Gripper {
  std::string name;
  std::array<int, 2> jaws = {-1, -1};             // scene body indices: jaws[0] closes along +axis
  std::shared_ptr<const KinematicMotion> motion;  // the frame's pose
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // frame coordinates, unit, jaws[0] → jaws[1]
  TimeFunction force;  // N, ≥ 0 at every step: the closing force on each jaw
  // each jaw's pose in the frame, from the jaws' and the frame's poses at t = 0; the part of its
  // position along the axis is where the grip starts, the rest is fixed
  std::array<KinematicPose, 2> jaw_in_frame;
};

/// A fixed convex body G (the ground, a tilted plane, a box fixture) in world coordinates.
struct Obstacle {
  std::string name;
  std::shared_ptr<const geometry::ConvexShape> shape;  // world frame
  Friction friction;                                   // default friction of contacts with it
};

/// Which of the two sets of contacts of a pair with a body under Decomposition::kAuto a contact
/// belongs to: the hulls' (the one contact where neither body has listed parts) or the parts'.
enum class SideChoice {
  kFixed,  // the pair touches with these sides whatever the step
  kHulls,  // taken where the hulls' contact is exact
  kParts,  // taken where something reaches into a cavity
};

/// One potential contact, with its own ECPs and wrench: between the hull of a dynamic body F
/// (`body`) or one of its parts, and G, a fixed obstacle (`obstacle`) or another body
/// (`other_body`: a kinematic one, or a dynamic one of larger index) or one of its parts. F and G
/// are chosen once per pair (warm starts and output columns follow the order). The contacts of
/// one pair of bodies (or of a body and an obstacle) are consecutive in Scene::contacts.
struct ContactPair {
  int body = 0;
  int obstacle = 0;  // -1 when G is a body
  Friction friction;
  int other_body = -1;  // ≥ 0: G is this body (then obstacle = -1)
  int part = -1;        // ≥ 0: F's side is Body::parts[part] of `body`, else its hull
  int other_part = -1;  // ≥ 0: G's side is Body::parts[other_part] of `other_body`, else its hull
  // under decomposition kAuto the pair lists its hulls' contacts and its parts' contacts, and
  // each step takes one of the two (engine/auto_sides.h)
  SideChoice sides = SideChoice::kFixed;
  bool WithBody() const { return other_body >= 0; }
  // whether `other` joins the same body to the same obstacle or body (another part pair of it)
  bool SameBodies(const ContactPair& other) const {
    return body == other.body && obstacle == other.obstacle && other_body == other.other_body;
  }
};

/// The friction of a pair of bodies (docs/scene_format.md, "Contacts between bodies"): the
/// geometric mean of the two bodies' μ and of each ellipsoid semi-axis, so a pair with one
/// frictionless body is frictionless and two equal bodies keep their values; e_r from the patch
/// if either body asks for it (the patch is the pair's, one for both sides).
Friction PairFriction(const Friction& a, const Friction& b);

/// Which of a step's solutions the hull model takes where they form a set: contacts that share
/// a load or a moment statically indeterminately (engine/README.md, "Steps whose solutions form
/// a set").
enum class Selection {
  kCreep,        // the sticking creep's (IslandContact::stick_creep): its viscous law decides
  kLeastEnergy,  // the exact MNCP's solution of least elastic energy of compliant patches
};

/// "creep", "least_energy" (`solver.selection` in the scene file).
const char* SelectionName(Selection selection);

struct SolverSettings {
  double tolerance = 1e-12;  // on the unscaled residual (see engine/README.md)
  int max_iterations = 60;
  int window_rings = 1;    // vertex rings of hull faces around the support vertex
  bool use_window = true;  // false: every hull face enters the MNCP
  Selection selection = Selection::kCreep;
  // islands at rest replay their last step instead of solving it (engine/README.md, "Sleeping
  // islands"): it moves no shipped scene's poses, velocities or impulses by a bit; a replay
  // reports the residual its solution had when solved (re-measured every kSleepCheckSteps)
  bool sleep = true;
};

/// Built by the routes of engine/scene_io/ (a file, `ecpsim drop`, code), each of which checks it
/// with ValidateScene (scene_io/scene_validation.h) before returning it.
struct Scene {
  std::string source;                                     // file the scene came from, for messages
  Eigen::Vector3d gravity = Eigen::Vector3d(0, 0, -9.8);  // m/s²
  double h = 0.01;                                        // s, time step
  double duration = 1;                                    // s
  std::vector<Body> bodies;
  std::vector<Obstacle> obstacles;
  std::vector<ContactPair> contacts;
  std::vector<Load> loads;
  std::vector<Impulse> impulses;
  std::vector<Gripper> grippers;
  SolverSettings solver;
  ContactModel model = ContactModel::kAuto;
  /// where each pair of bodies' contacts lie (IndexContacts, once the contacts are complete); a
  /// step indexes a scene without one itself, every step
  std::shared_ptr<const ContactIndex> contact_index;
};

/// F's side of `pair`: body `pair.body`'s hull or the part it names (body frame).
const geometry::ConvexShape& ShapeOfBody(const Scene& scene, const ContactPair& pair);

/// G's side of `pair`: the obstacle (world frame), or the other body's hull or the part it names
/// (its body frame).
const geometry::ConvexShape& ShapeOfOther(const Scene& scene, const ContactPair& pair);

/// The contact between the hulls of bodies i and j (not both kinematic) with `friction`: F the
/// dynamic one (the lower index when both are), G the other.
ContactPair BodyPair(const Scene& scene, int i, int j, const Friction& friction);

/// Appends the contacts of bodies i ≠ j (not both kinematic) with `friction`: F the dynamic one of
/// lower index (a kinematic body is always G), one contact between their hulls, or, where either
/// body's decomposition is kParts, one per pair of their parts (a body without parts: its hull).
/// Where either is kAuto, both: the contacts as if each kAuto body were kNone (SideChoice::kHulls),
/// then as if it were kParts (kParts).
void AddBodyContacts(Scene& scene, int i, int j, const Friction& friction);

/// Appends the contacts of dynamic body b with obstacle o with `friction`: one with its hull, or
/// one per part where its decomposition is kParts and the obstacle is bounded (not a half-space);
/// under kAuto, against a bounded obstacle, both as AddBodyContacts.
void AddObstacleContacts(Scene& scene, int b, int o, const Friction& friction);

/// Adds `gripper` to `scene`: its jaws' poses in the frame (jaw_in_frame) from the jaws' initial
/// poses (Body::p0, q0) and the frame's pose at t = 0, the axis normalized (a zero or non-finite
/// one is left for ValidateScene to report), and each jaw marked as its (Body::gripper).
/// Gives `scene` compiled expressions of its own (TimeFunction::Recompiled): its loads', its
/// kinematic bodies' and grippers' motions and its grippers' forces, which a copy of a scene
/// shares with the original. For a copy that a thread steps beside other copies.
void RecompileExpressions(Scene& scene);

/// ECPSIM_DEMAND: a motion and jaws that are bodies of the scene.
void AddGripper(Scene& scene, Gripper gripper);

/// Jaw `jaw` (0 or 1) of `gripper` at its place on the frame when the frame is at `frame`: the
/// frame's pose composed with the jaw's pose in it (along the axis, where the grip started).
KinematicPose JawOnFrame(const Gripper& gripper, int jaw, const KinematicPose& frame);

/// The closing axis in world coordinates when the frame is at `frame` (unit).
Eigen::Vector3d ClosingAxis(const Gripper& gripper, const KinematicPose& frame);

}  // namespace ecpsim::engine
