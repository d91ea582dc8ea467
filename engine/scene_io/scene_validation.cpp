#include "engine/scene_io/scene_validation.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <optional>
#include <set>
#include <tuple>
#include <utility>

#include "engine/report/penetration.h"
#include "engine/scene_io/mesh_scale.h"
#include "engine/scene_limits.h"
#include "engine/state.h"
#include "geometry/convex_shape.h"

namespace ecpsim::engine {
namespace {

// a quaternion shorter than this carries no direction to normalize
constexpr double kMinQuaternionNorm = 1e-9;
// symmetry and triangle inequality of an inertia, relative to its largest entry: values typed
// with ~10 significant digits and mesh integrals pass, a transposition typo does not
constexpr double kInertiaTolerance = 1e-9;  // × max |I_ij|

std::string Index(const std::string& key, size_t i) { return fmt::format("{}[{}]", key, i); }

std::string Show(const Eigen::Vector3d& v) {
  return fmt::format("[{}, {}, {}]", v.x(), v.y(), v.z());
}

std::string Show(const Eigen::Matrix3d& m) {
  return fmt::format("[{}, {}, {}, {}, {}, {}, {}, {}, {}]", m(0, 0), m(0, 1), m(0, 2), m(1, 0),
                     m(1, 1), m(1, 2), m(2, 0), m(2, 1), m(2, 2));
}

[[noreturn]] void Fail(std::vector<std::string> keys, std::string value, std::string expected) {
  throw SceneError(std::move(keys), std::move(value), std::move(expected));
}

// every component finite and within ±kMaxMagnitude
bool Bounded(const Eigen::Vector3d& v) {
  return v.allFinite() && v.cwiseAbs().maxCoeff() <= kMaxMagnitude;
}

void CheckRange(const std::vector<std::string>& keys, double value, const PositiveRange& range,
                const std::string& what) {
  const std::string expected = OutOfRange(value, range);
  if (!expected.empty()) Fail(keys, fmt::format("{}", value), fmt::format("{}{}", what, expected));
}

// a quantity derived from the keys' values: the message shows it, since the keys' values differ
void CheckDerived(const std::vector<std::string>& keys, const std::string& shown, double value,
                  const PositiveRange& range, const std::string& what) {
  const std::string expected = OutOfRange(value, range);
  if (!expected.empty()) {
    Fail(keys, shown,
         fmt::format("{} {}; it is {:.3g}{}{}", what, expected, value, *range.unit ? " " : "",
                     range.unit));
  }
}

void CheckVector(const std::vector<std::string>& keys, const Eigen::Vector3d& v,
                 const std::string& expected) {
  if (!Bounded(v)) {
    Fail(keys, Show(v),
         fmt::format("{}, each a finite number within ±{:g}", expected, kMaxMagnitude));
  }
}

void CheckInt(const std::string& key, int value, int min, int max, const std::string& what) {
  if (value < min || value > max) {
    Fail({key}, fmt::format("{}", value),
         fmt::format("an integer in [{}, {}]: {}", min, max, what));
  }
}

void CheckName(const std::string& key, const std::string& name) {
  if (!IsValidName(name)) Fail({key}, fmt::format("\"{}\"", name), kNameExpected);
}

// ---- time ------------------------------------------------------------------------------------

void CheckTime(const Scene& scene) {
  CheckRange({"duration"}, scene.duration, kTimeRange, "a finite duration > 0 s: ");
  CheckRange({"h"}, scene.h, kTimeRange, "a finite time step > 0 s: ");
  if (scene.h > scene.duration) {
    Fail({"h", "duration"}, fmt::format("{}", scene.h),
         fmt::format("a time step h <= duration = {} s", scene.duration));
  }
  const std::string steps = StepCountProblem(scene.duration, scene.h);
  if (!steps.empty()) Fail({"h", "duration"}, fmt::format("{}", scene.h), steps);
  CheckVector({"gravity"}, scene.gravity, "a gravity [x, y, z] in m/s²");
}

// ---- friction --------------------------------------------------------------------------------

// `keys` are the friction mappings that may have set it, most specific first
void CheckFriction(const std::vector<std::string>& mappings, const Friction& friction,
                   const std::string& who) {
  const auto keys = [&](const char* name) {
    std::vector<std::string> out;
    for (const std::string& m : mappings) out.push_back(m + "." + name);
    return out;
  };
  if (!(friction.mu >= 0 && friction.mu <= kMaxMagnitude)) {
    Fail(keys("mu"), fmt::format("{}", friction.mu),
         fmt::format("a friction coefficient >= 0 (within {:g}) for {}", kMaxMagnitude, who));
  }
  const std::string axis = fmt::format("an ellipsoid semi-axis > 0 (dimensionless) for {}: ", who);
  CheckRange(keys("e_t"), friction.e_t, kMagnitudeRange, axis);
  CheckRange(keys("e_o"), friction.e_o, kMagnitudeRange, axis);
  // `e_r: patch` leaves the number unused (StepFriction computes it each step)
  if (!friction.e_r_patch) {
    CheckRange(keys("e_r"), friction.e_r, kLengthRange,
               fmt::format("a torsional ellipsoid semi-axis > 0 m, or `patch`, for {}: ", who));
  }
}

// ---- obstacles -------------------------------------------------------------------------------

// a bounded fixture (a box) within kMaxDistanceInSizes of its size from the origin: farther, its
// vertices round to fewer digits than its size has, and it can even collapse to a point
void CheckFixturePosition(const Obstacle& obstacle, const std::string& at) {
  const auto* polyhedron = obstacle.shape->AsPolyhedron();
  if (polyhedron == nullptr || polyhedron->hull().vertices.empty()) return;
  geometry::TriangleMesh corners;
  corners.vertices = polyhedron->hull().vertices;
  const double size = MeshAcross(corners);
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& v : corners.vertices) center += v / corners.vertices.size();
  if (!(size > 0 && center.norm() <= kMaxDistanceInSizes * size)) {
    Fail({at + ".box.position", at + ".box.size", at}, Show(center),
         fmt::format("obstacle \"{}\" within {:g} × its size {:.3g} m of the origin (doubles "
                     "resolve a position |p| only to 2.2e-16 |p|)",
                     obstacle.name, kMaxDistanceInSizes, size));
  }
}

void CheckObstacles(const Scene& scene) {
  for (size_t o = 0; o < scene.obstacles.size(); ++o) {
    const Obstacle& obstacle = scene.obstacles[o];
    const std::string at = Index("obstacles", o);
    CheckName(at + ".name", obstacle.name);
    for (size_t other = 0; other < o; ++other) {
      if (scene.obstacles[other].name == obstacle.name) {
        Fail({at + ".name"}, fmt::format("\"{}\"", obstacle.name), "a name no other obstacle has");
      }
    }
    if (!obstacle.shape) Fail({at}, "(no shape)", "an obstacle with a convex shape");
    CheckFixturePosition(obstacle, at);
    CheckFriction({at + ".friction"}, obstacle.friction,
                  fmt::format("obstacle \"{}\"", obstacle.name));
  }
}

// ---- bodies ----------------------------------------------------------------------------------

// what a body's problem may trace back to in a scene file, the most specific first
std::vector<std::string> Keys(const std::string& at, std::initializer_list<const char*> names) {
  std::vector<std::string> keys;
  for (const char* name : names) keys.push_back(at + "." + name);
  keys.push_back(at);
  return keys;
}

// m: the body's size (bounding-box diagonal of its mesh), checked to be a length in range
double CheckGeometry(const Body& body, const std::string& at, const std::string& who) {
  if (!body.hull) Fail(Keys(at, {"hull"}), "(none)", fmt::format("a convex hull for {}", who));
  for (const auto& part : body.parts) {
    if (!part) Fail(Keys(at, {"parts"}), "(none)", fmt::format("convex parts for {}", who));
  }
  bool finite = !body.mesh.vertices.empty();
  for (const Eigen::Vector3d& v : body.mesh.vertices) finite = finite && v.allFinite();
  const double size = finite ? MeshAcross(body.mesh) : NAN;
  CheckDerived(Keys(at, {"mesh", "shape", "scale", "units"}), fmt::format("{} m across", size),
               size, kLengthRange,
               fmt::format("a mesh of {} with finite vertices and a size (bounding-box diagonal, "
                           "L⁵ enters its inertia) that is",
                           who));
  return size;
}

void CheckMassAndInertia(const Body& body, const std::string& at, const std::string& who) {
  CheckDerived(Keys(at, {"mass", "density"}), fmt::format("{}", body.mass), body.mass, kMassRange,
               fmt::format("a mass of {} that is", who));
  const Eigen::Matrix3d& I = body.inertia;
  const std::vector<std::string> keys = Keys(at, {"inertia", "mass", "density", "shape", "mesh"});
  const std::string expected = fmt::format(
      "an inertia of {} (kg·m², about the CM in body axes) that is symmetric, positive definite, "
      "each principal moment <= the sum of the other two",
      who);
  const double scale = I.allFinite() ? I.cwiseAbs().maxCoeff() : NAN;
  if (!(scale > 0) || (I - I.transpose()).cwiseAbs().maxCoeff() > kInertiaTolerance * scale) {
    Fail(keys, Show(I), expected);
  }
  const Eigen::Vector3d moments =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I, Eigen::EigenvaluesOnly).eigenvalues();
  // ascending: positive definite, and the largest no more than the sum of the other two
  if (!(moments[0] > 0) || moments[2] > moments[0] + moments[1] + kInertiaTolerance * scale) {
    Fail(keys, Show(I), expected);
  }
  for (int k = 0; k < 3; ++k) {
    CheckDerived(keys, Show(I), moments[k], kInertiaRange,
                 fmt::format("principal moments of {} that are each", who));
  }
  // the radii of gyration sqrt(I/m) are the body's rotational length scales
  for (int k = 0; k < 3; ++k) {
    CheckDerived(keys, Show(I), std::sqrt(moments[k] / body.mass), kLengthRange,
                 fmt::format("radii of gyration sqrt(I/m) of {} that are each", who));
  }
}

void CheckInitialState(const Body& body, const std::string& at, const std::string& who,
                       double size) {
  const std::vector<std::string> position = Keys(at, {"position", "lowest_point_height"});
  CheckVector(position, body.p0, fmt::format("a position of {} in m", who));
  if (body.p0.norm() > kMaxDistanceInSizes * size) {
    Fail(position, Show(body.p0),
         fmt::format("{} within {:g} × its size {:.3g} m of the origin (doubles resolve a position "
                     "|p| only to 2.2e-16 |p|); move the scene's origin near the bodies",
                     who, kMaxDistanceInSizes, size));
  }
  const Eigen::Vector4d q = body.q0.coeffs();
  if (!q.allFinite() || !(q.cwiseAbs().maxCoeff() <= kMaxMagnitude) ||
      !(q.norm() >= kMinQuaternionNorm)) {
    Fail(Keys(at, {"quaternion", "rpy"}),
         fmt::format("[{}, {}, {}, {}]", body.q0.w(), body.q0.x(), body.q0.y(), body.q0.z()),
         fmt::format("a non-zero, finite orientation quaternion [w, x, y, z] of {}", who));
  }
  CheckVector(Keys(at, {"velocity"}), body.v0, fmt::format("a velocity of {} in m/s", who));
  CheckVector(Keys(at, {"angular_velocity"}), body.w0,
              fmt::format("an angular velocity of {} in rad/s", who));
}

void CheckBodies(const Scene& scene) {
  if (scene.bodies.empty()) Fail({"bodies"}, "[]", "a list of at least one body");
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    const std::string at = Index("bodies", b);
    CheckName(at + ".name", body.name);
    for (size_t other = 0; other < b; ++other) {
      if (scene.bodies[other].name == body.name) {
        Fail({at + ".name"}, fmt::format("\"{}\"", body.name), "a name no other body has");
      }
    }
    const std::string who = fmt::format("body \"{}\"", body.name);
    const double size = CheckGeometry(body, at, who);
    CheckMassAndInertia(body, at, who);
    CheckInitialState(body, at, who, size);
  }
}

// ---- contacts, loads, impulses ---------------------------------------------------------------

void CheckBodyIndex(const Scene& scene, const std::string& key, int body) {
  if (body < 0 || body >= static_cast<int>(scene.bodies.size())) {
    Fail({key}, fmt::format("{}", body),
         fmt::format("a body index 0..{}", static_cast<int>(scene.bodies.size()) - 1));
  }
}

// loads and impulses act on dynamic bodies: a kinematic body's motion is prescribed
void CheckDynamic(const Scene& scene, const std::string& key, int body) {
  if (scene.bodies[body].IsKinematic()) {
    Fail({key}, fmt::format("\"{}\"", scene.bodies[body].name),
         "a dynamic body (a kinematic body's motion is prescribed; no load moves it)");
  }
}

// contact k's friction (its body and its other body or obstacle checked before)
void CheckContactFriction(const Scene& scene, size_t k) {
  const ContactPair& pair = scene.contacts[k];
  const std::string at = Index("contacts", k);
  if (pair.WithBody()) {
    CheckFriction({"pairs", at + ".friction"}, pair.friction,
                  fmt::format("the contact of body \"{}\" with body \"{}\"",
                              scene.bodies[pair.body].name, scene.bodies[pair.other_body].name));
    return;
  }
  CheckFriction({Index("bodies", pair.body) + ".friction",
                 Index("obstacles", pair.obstacle) + ".friction", at + ".friction"},
                pair.friction,
                fmt::format("the contact of body \"{}\" with obstacle \"{}\"",
                            scene.bodies[pair.body].name, scene.obstacles[pair.obstacle].name));
}

// contact k's parts name parts of its bodies
void CheckContactParts(const Scene& scene, size_t k) {
  const ContactPair& pair = scene.contacts[k];
  const std::string at = Index("contacts", k);
  const auto check = [&](const std::string& key, int part, const Body* body) {
    const int parts = body != nullptr ? static_cast<int>(body->parts.size()) : 0;
    if (part < -1 || part >= parts) {
      Fail({at + key}, fmt::format("{}", part),
           parts == 0 ? std::string("-1 (the hull: it has no parts)")
                      : fmt::format("-1 (the hull) or a part index 0..{}", parts - 1));
    }
  };
  check(".part", pair.part, &scene.bodies[pair.body]);
  check(".other_part", pair.other_part, pair.WithBody() ? &scene.bodies[pair.other_body] : nullptr);
}

// the contacts of one pair of bodies (or of a body and an obstacle) are consecutive (a
// ContactGroup), with each pair of their parts once
void CheckContactGroups(const Scene& scene) {
  std::set<std::tuple<int, int, int>> closed;
  std::set<std::pair<int, int>> parts_of_group;
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const ContactPair& pair = scene.contacts[k];
    const std::string at = Index("contacts", k);
    if (k == 0 || !scene.contacts[k - 1].SameBodies(pair)) {
      if (k > 0) {
        const ContactPair& last = scene.contacts[k - 1];
        closed.emplace(last.body, last.obstacle, last.other_body);
      }
      if (closed.count({pair.body, pair.obstacle, pair.other_body}) > 0) {
        Fail({at}, "a contact of an earlier pair",
             "the contacts of one pair of bodies (or of a body and an obstacle) one after "
             "another");
      }
      parts_of_group.clear();
    }
    if (!parts_of_group.emplace(pair.part, pair.other_part).second) {
      Fail({at}, fmt::format("parts {} and {} again", pair.part, pair.other_part),
           "each pair of parts (or hulls) of two bodies once");
    }
  }
}

void CheckContacts(const Scene& scene) {
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const ContactPair& pair = scene.contacts[k];
    const std::string at = Index("contacts", k);
    CheckBodyIndex(scene, at + ".body", pair.body);
    if (scene.bodies[pair.body].IsKinematic()) {
      Fail({at + ".body"}, fmt::format("{}", pair.body),
           "a dynamic body on the F side of a contact (a kinematic body is never pushed)");
    }
    if (pair.WithBody()) {
      CheckBodyIndex(scene, at + ".other_body", pair.other_body);
      if (pair.other_body == pair.body ||
          (!scene.bodies[pair.other_body].IsKinematic() && pair.other_body < pair.body)) {
        Fail({at + ".other_body"}, fmt::format("{}", pair.other_body),
             "another body: a kinematic one, or a dynamic one of larger index than `body`");
      }
    } else if (pair.obstacle < 0 || pair.obstacle >= static_cast<int>(scene.obstacles.size())) {
      Fail({at + ".obstacle"}, fmt::format("{}", pair.obstacle),
           fmt::format("an obstacle index 0..{}", static_cast<int>(scene.obstacles.size()) - 1));
    }
    CheckContactParts(scene, k);
    CheckContactFriction(scene, k);
  }
  CheckContactGroups(scene);
}

void CheckLoads(const Scene& scene) {
  for (size_t i = 0; i < scene.loads.size(); ++i) {
    const Load& load = scene.loads[i];
    const std::string at = Index("loads", i);
    CheckBodyIndex(scene, at + ".body", load.body);
    CheckDynamic(scene, at + ".body", load.body);
    if (!(std::abs(load.start) <= kMaxMagnitude)) {
      Fail({at + ".start"}, fmt::format("{}", load.start),
           fmt::format("a start time (s) within ±{:g}", kMaxMagnitude));
    }
    if (!(load.end > load.start)) {
      Fail({at + ".end"}, fmt::format("{}", load.end),
           fmt::format("an end time (s) > start = {}", load.start));
    }
    if (load.at_point) CheckVector({at + ".at"}, load.point_B, "a point [x, y, z] in m");
  }
  for (size_t i = 0; i < scene.impulses.size(); ++i) {
    const Impulse& impulse = scene.impulses[i];
    const std::string at = Index("impulses", i);
    CheckBodyIndex(scene, at + ".body", impulse.body);
    CheckDynamic(scene, at + ".body", impulse.body);
    if (!(impulse.time >= 0 && impulse.time <= kMaxMagnitude)) {
      Fail({at + ".time"}, fmt::format("{}", impulse.time), "a finite time >= 0 s");
    }
    CheckVector({at + ".linear"}, impulse.linear, "a linear impulse [x, y, z] in N·s");
    CheckVector({at + ".angular"}, impulse.angular, "an angular impulse [x, y, z] in N·m·s");
    if (impulse.at_point) CheckVector({at + ".at"}, impulse.point_B, "a point [x, y, z] in m");
  }
}

// ---- grippers --------------------------------------------------------------------------------

void CheckGrippers(const Scene& scene) {
  std::vector<int> jaw_of(scene.bodies.size(), -1);
  for (size_t g = 0; g < scene.grippers.size(); ++g) {
    const Gripper& gripper = scene.grippers[g];
    const std::string at = Index("grippers", g);
    CheckName(at + ".name", gripper.name);
    for (size_t other = 0; other < g; ++other) {
      if (scene.grippers[other].name == gripper.name) {
        Fail({at + ".name"}, fmt::format("\"{}\"", gripper.name), "a name no other gripper has");
      }
    }
    ECPSIM_DEMAND(gripper.motion != nullptr);
    for (int j = 0; j < 2; ++j) {
      const std::string key = fmt::format("{}.jaws[{}]", at, j);
      const int b = gripper.jaws[j];
      CheckBodyIndex(scene, key, b);
      const Body& jaw = scene.bodies[b];
      if (jaw.IsKinematic()) {
        Fail(
            {key}, fmt::format("\"{}\"", jaw.name),
            "a dynamic body (a kinematic body's motion is prescribed; the gripper moves its jaws)");
      }
      if (jaw_of[b] >= 0) {
        Fail({key}, fmt::format("\"{}\"", jaw.name),
             fmt::format("a body that is no other jaw (it is one of {})",
                         jaw_of[b] == static_cast<int>(g) ? "this gripper's already"
                                                          : scene.grippers[jaw_of[b]].name));
      }
      jaw_of[b] = static_cast<int>(g);
      // the loader and scene builders set the back reference; a mismatch is their bug
      ECPSIM_DEMAND(jaw.gripper == static_cast<int>(g));
      if (jaw.v0.norm() != 0 || jaw.w0.norm() != 0) {
        Fail(Keys(Index("bodies", b), {"velocity", "angular_velocity"}),
             fmt::format("({}, {})", Show(jaw.v0), Show(jaw.w0)),
             fmt::format("no initial velocity for jaw \"{}\" of gripper \"{}\" (the gripper "
                         "moves it)",
                         jaw.name, gripper.name));
      }
    }
    if (!(gripper.axis.allFinite() && std::abs(gripper.axis.norm() - 1) < 1e-12)) {
      Fail({at + ".axis"}, Show(gripper.axis), "a unit closing axis (frame coordinates)");
    }
    const double spread = gripper.axis.dot(gripper.jaw_in_frame[1].p - gripper.jaw_in_frame[0].p);
    if (!(spread > 0)) {
      Fail({at + ".axis", at + ".jaws"}, Show(gripper.axis),
           fmt::format("an axis from jaw \"{}\" towards jaw \"{}\" (their centres are {:.3g} m "
                       "apart along it at t = 0; swap the jaws or flip the axis)",
                       scene.bodies[gripper.jaws[0]].name, scene.bodies[gripper.jaws[1]].name,
                       spread));
    }
    const double force = gripper.force(0);
    if (!(force >= 0 && force <= kMaxMagnitude)) {
      Fail({at + ".force"}, fmt::format("{}", force),
           "a closing force ≥ 0 N at t = 0 (the jaws open only as far as what they hold pushes "
           "them)");
    }
  }
  for (size_t b = 0; b < scene.bodies.size(); ++b)
    ECPSIM_DEMAND(scene.bodies[b].gripper == jaw_of[b]);
}

// ---- settings --------------------------------------------------------------------------------

void CheckSettings(const Scene& scene) {
  CheckRange({"solver.tolerance"}, scene.solver.tolerance, kMagnitudeRange,
             "a residual tolerance > 0: ");
  CheckInt("solver.max_iterations", scene.solver.max_iterations, 1, kMaxSolverIterations,
           "Newton iterations per attempt");
  CheckInt("solver.window_rings", scene.solver.window_rings, 0, kMaxWindowRings,
           "vertex rings around the support vertex (use_window: false takes every face)");
}

void CheckOutput(const OutputSettings& out) {
  if (out.every < 1) {
    Fail({"output.every"}, fmt::format("{}", out.every), "an integer >= 1 (write every N-th step)");
  }
  CheckRange({"output.fps"}, out.fps, kMagnitudeRange,
             "a finite frame rate > 0 frames per simulated second: ");
  CheckInt("output.width", out.width, kMinFramePixels, kMaxFramePixels, "frame width in pixels");
  CheckInt("output.height", out.height, kMinFramePixels, kMaxFramePixels, "frame height in pixels");
  CheckVector({"output.camera.position"}, out.camera_position, "a camera position in m");
  CheckVector({"output.camera.target"}, out.camera_target, "a camera target in m");
  if ((out.camera_position - out.camera_target).norm() == 0) {
    Fail({"output.camera.position"}, Show(out.camera_position),
         "a camera position different from its target");
  }
  if (!(out.camera_fov_deg > 0 && out.camera_fov_deg < 180)) {
    Fail({"output.camera.fov"}, fmt::format("{}", out.camera_fov_deg),
         "a vertical field of view in (0, 180) degrees");
  }
}

// ---- initial overlap -------------------------------------------------------------------------

void CheckInitialPenetration(const Scene& scene) {
  const std::optional<Overlap> overlap = FindOverlap(scene, InitialState(scene));
  if (!overlap) return;
  const Body& body = scene.bodies[overlap->body];
  const std::string at = Index("bodies", overlap->body);
  if (overlap->obstacle >= 0) {
    Fail(Keys(at, {"position", "lowest_point_height", "on_ground"}), Show(body.p0),
         fmt::format("an initial pose of body \"{}\" whose mesh stays out of obstacle \"{}\": "
                     "a vertex is {:.3g} m inside, more than {:.3g} m ({:g} × the body's "
                     "size {:.3g} m); move the body, or allow it with "
                     "{}.allow_initial_penetration: true",
                     body.name, scene.obstacles[overlap->obstacle].name, overlap->depth,
                     overlap->tolerance, kInitialPenetrationTolerance, overlap->size, at));
  }
  const Body& other = scene.bodies[overlap->other_body];
  Fail(Keys(at, {"position"}), Show(body.p0),
       fmt::format("an initial pose of body \"{}\" apart from body \"{}\": they overlap by "
                   "{:.3g} m, more than {:.3g} m ({:g} × the "
                   "smaller body's size {:.3g} m); move one of them, exclude the pair "
                   "(pairs: [{{bodies: [{}, {}], exclude: true}}]), or allow it with "
                   "{}.allow_initial_penetration: true",
                   body.name, other.name, overlap->depth, overlap->tolerance,
                   kInitialPenetrationTolerance, overlap->size, body.name, other.name, at));
}

// the checks in the order of the docs; `output` (may be null) among the settings
void Validate(const Scene& scene, const OutputSettings* output) {
  CheckTime(scene);
  CheckObstacles(scene);
  CheckBodies(scene);
  CheckContacts(scene);
  CheckLoads(scene);
  CheckGrippers(scene);
  CheckSettings(scene);
  if (output != nullptr) CheckOutput(*output);
  CheckInitialPenetration(scene);
}

}  // namespace

SceneError::SceneError(std::vector<std::string> keys, std::string value, std::string expected)
    : InputError(fmt::format("{} = {}: expected {}", keys.at(0), value, expected)),
      keys_(std::move(keys)),
      value_(std::move(value)),
      expected_(std::move(expected)) {}

void ValidateMassProperties(const Scene& scene, int body) {
  ECPSIM_DEMAND(body >= 0 && static_cast<size_t>(body) < scene.bodies.size());
  const Body& b = scene.bodies[static_cast<size_t>(body)];
  CheckMassAndInertia(b, Index("bodies", static_cast<size_t>(body)),
                      fmt::format("body \"{}\"", b.name));
}

void ValidateContactFriction(const Scene& scene, int contact) {
  ECPSIM_DEMAND(contact >= 0 && static_cast<size_t>(contact) < scene.contacts.size());
  CheckContactFriction(scene, static_cast<size_t>(contact));
}

std::optional<Overlap> FindOverlap(const Scene& scene, const State& state) {
  const PenetrationProbe probe(scene);
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    // a kinematic body goes where its motion says, through the ground too
    if (body.allow_initial_penetration || body.IsKinematic()) continue;
    const double size = MeshAcross(body.mesh);
    const double tolerance = kInitialPenetrationTolerance * size;
    for (size_t o = 0; o < scene.obstacles.size(); ++o) {
      const double depth = probe.Depth(scene, state, static_cast<int>(b), static_cast<int>(o));
      if (depth > tolerance) {
        return Overlap{static_cast<int>(b), -1, static_cast<int>(o), depth, tolerance, size};
      }
    }
  }
  // bodies that can touch must be apart too (a kinematic body included: it would shoot the
  // other out at the first step); excluded pairs are not contact pairs and may overlap
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const ContactPair& pair = scene.contacts[k];
    // (a hull spans the body's cavities: its parts' contacts measure the body itself)
    if (!pair.WithBody() || pair.sides == SideChoice::kHulls) continue;
    const Body& a = scene.bodies[pair.body];
    const Body& b = scene.bodies[pair.other_body];
    if (a.allow_initial_penetration || b.allow_initial_penetration) continue;
    const double size = std::min(MeshAcross(a.mesh), MeshAcross(b.mesh));
    const double tolerance = kInitialPenetrationTolerance * size;
    const double depth = probe.ContactDepth(scene, state, static_cast<int>(k));
    if (depth > tolerance) return Overlap{pair.body, pair.other_body, -1, depth, tolerance, size};
  }
  return std::nullopt;
}

void ValidateScene(const Scene& scene) { Validate(scene, nullptr); }

void ValidateLoadedScene(const LoadedScene& loaded) { Validate(loaded.scene, &loaded.output); }

}  // namespace ecpsim::engine
