#pragma once
// Internal to the scene loader (scene_yaml*.cpp, the only yaml-cpp users): typed readers of YAML
// nodes whose every error names file:line:col (or the --set that made the node), the key, the
// value as written and what was expected; and the readers of the format's parts.

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/errors.h"
#include "engine/kinematic_motion.h"
#include "engine/scene.h"
#include "engine/scene_io/mesh_scale.h"
#include "engine/scene_limits.h"

namespace ecpsim::engine::yaml {

// ---- where a value came from -----------------------------------------------------------------

/// An override applied by --set: its dotted key ("bodies.0.mass") and its text, for messages.
struct Override {
  std::string dotted_key;
  std::string text;
};

struct Context {
  std::string file;              // the scene file as given, or what made the text
  std::filesystem::path folder;  // mesh paths are relative to it
  std::vector<Override> overrides;
  bool has_lines = true;  // false for generated text, whose line:col the user never saw
};

/// "file:line:col" (1-based) of `node`, or "file: --set TEXT" when an override made `key`;
/// "file" alone for generated text (the key names the place).
std::string Where(const Context& ctx, const YAML::Node& node, const std::string& key);

/// The node's text for messages: scalars as written, lists and maps in flow style, cut to 60
/// characters, control characters (NUL, ...) escaped as \xNN.
std::string Show(const YAML::Node& node);

/// Escapes control characters of `text` as \xNN, so that a message is one printable line.
std::string Printable(const std::string& text);

/// Throws InputError "WHERE: KEY = VALUE: expected EXPECTED".
[[noreturn]] void Fail(const Context& ctx, const YAML::Node& node, const std::string& key,
                       const std::string& expected);

/// Runs `f`, re-throwing an InputError (of the mesh, hull or mass properties) with the scene
/// location of `node` and `key` in front.
template <typename F>
auto WithLocation(const Context& ctx, const YAML::Node& node, const std::string& key, F&& f) {
  try {
    return f();
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}: {}", Where(ctx, node, key), key, e.what()));
  }
}

/// "a.b" from ("a", "b"); "b" from ("", "b").
std::string Child(const std::string& key, const std::string& child);
/// "key[i]".
std::string Index(const std::string& key, size_t i);

/// The node at `key` ("bodies[0].shape.box.size[1]") under `root`; an undefined node when the
/// tree has no such key.
YAML::Node FindNode(const YAML::Node& root, const std::string& key);

/// Applies the --set override "dotted.key=value" to the tree `root`, recording it in `applied`.
/// @throws InputError naming the --set when it is not key=value, its value is not YAML, or its
///         key does not fit the tree.
void ApplyOverride(const Context& ctx, YAML::Node& root, const std::string& text,
                   std::vector<Override>& applied);

// ---- typed readers ---------------------------------------------------------------------------

/// A YAML mapping whose keys were checked against the allowed set (unknown and duplicate keys
/// are errors, with the closest valid key suggested).
class MapNode {
 public:
  MapNode(const Context& ctx, const YAML::Node& node, std::string key,
          const std::vector<std::string>& allowed);

  bool Has(const std::string& k) const { return static_cast<bool>(node_[k]); }
  YAML::Node Get(const std::string& k) const { return node_[k]; }
  std::string Key(const std::string& k) const { return Child(key_, k); }
  const std::string& key() const { return key_; }
  const YAML::Node& node() const { return node_; }

  /// The value of a required key, or an error at the mapping naming the key.
  YAML::Node Require(const std::string& k, const std::string& expected) const;

  /// An error about key `k`: at its value when present, else at this mapping as "(missing)".
  [[noreturn]] void FailAt(const std::string& k, const std::string& expected) const;

 private:
  const Context& ctx_;
  YAML::Node node_;
  std::string key_;
};

/// A finite number within ±kMaxMagnitude.
double ReadNumber(const Context& ctx, const YAML::Node& node, const std::string& key,
                  const std::string& expected);
/// A finite number > 0 (`expected` says so), then within `range` (the message names it).
double ReadPositive(const Context& ctx, const YAML::Node& node, const std::string& key,
                    const PositiveRange& range, const std::string& expected);
/// An integer (its range: ValidateScene); `expected` names the range for the message.
int ReadInt(const Context& ctx, const YAML::Node& node, const std::string& key,
            const std::string& expected);
bool ReadBool(const Context& ctx, const YAML::Node& node, const std::string& key);
/// A non-empty string without NUL characters.
std::string ReadString(const Context& ctx, const YAML::Node& node, const std::string& key,
                       const std::string& expected);
/// A body or obstacle name (IsValidName).
std::string ReadName(const Context& ctx, const YAML::Node& node, const std::string& key);
/// A list of `count` numbers as ReadNumber.
Eigen::VectorXd ReadNumbers(const Context& ctx, const YAML::Node& node, const std::string& key,
                            size_t count, const std::string& expected);
/// [x, y, z] as ReadNumbers; `unit` goes into the message.
Eigen::Vector3d ReadVector3(const Context& ctx, const YAML::Node& node, const std::string& key,
                            const std::string& unit);
/// [x, y, z] of lengths > 0 m within kLengthRange (edge lengths, radii).
Eigen::Vector3d ReadLengths3(const Context& ctx, const YAML::Node& node, const std::string& key,
                             const std::string& expected);

// ---- the format's parts (docs/scene_format.md) -----------------------------------------------

ContactModel ReadModel(const Context& ctx, const YAML::Node& node, const std::string& key);

/// What a body's `decomposition` asks for: its hull, its listed parts, or its mesh decomposed.
enum class DecompositionMode { kNone, kParts, kAuto };
/// A body's `decomposition`: `none`, `parts` or `auto`.
DecompositionMode ReadDecomposition(const Context& ctx, const YAML::Node& node,
                                    const std::string& key);

/// `quaternion` [w, x, y, z] (normalized) or `rpy` [deg] of `map`; identity when neither.
Eigen::Quaterniond ReadOrientation(const Context& ctx, const MapNode& map);

/// `friction: {mu, e_t, e_o, e_r}` applied key by key over `friction` (ranges: ValidateScene).
Friction ReadFriction(const Context& ctx, const YAML::Node& node, const std::string& key,
                      Friction friction);

/// A convex primitive centred at the origin with its closed-form volume and inertia per kg.
struct Primitive {
  std::shared_ptr<const geometry::ConvexShape> shape;
  double volume = 0;                                       // m³
  Eigen::Matrix3d unit_inertia = Eigen::Matrix3d::Zero();  // kg·m² per kg, about the centre
};
/// `{box|sphere|cylinder|ellipsoid: ...}`.
Primitive ReadPrimitive(const Context& ctx, const YAML::Node& node, const std::string& key);
/// The one of `box`, `sphere`, `cylinder`, `ellipsoid` that `map` has (it may have other keys).
Primitive ReadPrimitiveIn(const Context& ctx, const MapNode& map);

/// A mesh file as read for a body or a part: where it was found and its triangles in m.
struct MeshFile {
  std::string path;             // as found, relative to the working folder
  geometry::TriangleMesh mesh;  // m, the file's frame
};
/// The mesh file named by `node` (relative to the scene's folder), scaled to m by `scale`
/// (`scale_keys`: the keys that gave it, for messages), its size checked in range; a size
/// outside [1 mm, 10 m] adds a warning.
MeshFile LoadMeshFile(const Context& ctx, const YAML::Node& node, const std::string& key,
                      double scale, const MeshScaleKeys& scale_keys,
                      std::vector<std::string>& warnings);

/// What a body's parts are read against: its frame, its hull and its mesh's scale.
struct PartFrame {
  Eigen::Vector3d center_of_mass = Eigen::Vector3d::Zero();  // m, in the mesh's frame
  const geometry::ConvexShape* hull = nullptr;               // body frame
  double tolerance = 0;      // m: how far a part may reach out of the hull (round-off)
  double mesh_scale = 1;     // the body's mesh units → m, for parts given as meshes
  MeshScaleKeys scale_keys;  // the body's keys that gave it, for messages
  bool touched = true;       // whether contacts touch the parts (Decomposition::kParts)
};
/// `parts: [{box|sphere|cylinder|ellipsoid|mesh: ..., at, rpy | quaternion}]`
/// (docs/scene_format.md, "Parts"): each a primitive or the convex hull of a mesh file, placed
/// in the body's mesh frame and moved to its body frame, inside the body's hull. Where contacts
/// touch them, warns of each two parts that meet face to face (geometry/part_seams.h).
std::vector<std::shared_ptr<const geometry::ConvexShape>> ReadParts(
    const Context& ctx, const YAML::Node& node, const std::string& key, const PartFrame& frame,
    std::vector<std::string>& warnings);
/// A note in `warnings` for each two of `parts` (body frame) that meet face to face, at `key`.
void WarnOfSeams(const std::vector<std::shared_ptr<const geometry::ConvexShape>>& parts,
                 const std::string& key, const PartFrame& frame,
                 std::vector<std::string>& warnings);

/// A box fixture or part: `size` from `box`, its centre from `pose`'s `position_key` (default
/// the origin) minus `shift`, its orientation from `pose`'s `rpy` / `quaternion`.
std::shared_ptr<const geometry::ConvexShape> ReadPosedBox(const Context& ctx, const MapNode& box,
                                                          const MapNode& pose,
                                                          const std::string& position_key,
                                                          const Eigen::Vector3d& shift);

/// `ground: {normal, offset, friction}`.
Obstacle ReadGround(const Context& ctx, const YAML::Node& node, const std::string& key);
/// An entry of `obstacles`: `{name, plane | box, friction}`.
Obstacle ReadObstacle(const Context& ctx, const YAML::Node& node, const std::string& key,
                      const std::string& default_name);

/// What a body adds beyond engine::Body while loading: the mesh-frame shift for `at` points and
/// the friction overrides applied on top of each obstacle's.
struct BodyExtras {
  Eigen::Vector3d center_of_mass = Eigen::Vector3d::Zero();  // m, in the mesh's own frame
  std::optional<YAML::Node> friction;
  std::string friction_key;
};
/// An entry of `bodies`; a mesh of implausible size adds a line to `warnings`.
Body ReadBody(const Context& ctx, const YAML::Node& node, const std::string& key,
              const std::string& default_name, BodyExtras& extras,
              std::vector<std::string>& warnings);

/// The index of the body of `scene` named by the scalar `node`.
int BodyNamed(const Context& ctx, const YAML::Node& node, const std::string& key,
              const Scene& scene);

/// A number or a quoted muparser expression of t (a load component, a motion coordinate).
TimeFunction ReadTimeFunction(const Context& ctx, const YAML::Node& node, const std::string& key);

/// A kinematic body's `motion: {expressions | waypoints | velocity: ...}` (docs/scene_format.md,
/// "Kinematic bodies"); later errors of the motion (PoseAt, StepTwist) name `key`'s location.
KinematicMotion ReadMotion(const Context& ctx, const YAML::Node& node, const std::string& key);

/// An entry of `grippers`: `{name, jaws: [A, B], motion, axis, force}` (docs/scene_format.md,
/// "Grippers"), the jaws bodies of `scene` by name; jaw_in_frame is left to AddGripper.
Gripper ReadGripper(const Context& ctx, const YAML::Node& node, const std::string& key,
                    const Scene& scene);

/// An entry of `loads` / `impulses` (bodies by name or index; `at` in the mesh frame).
Load ReadLoad(const Context& ctx, const YAML::Node& node, const std::string& key,
              const std::vector<Body>& bodies, const std::vector<BodyExtras>& extras);
Impulse ReadImpulse(const Context& ctx, const YAML::Node& node, const std::string& key,
                    const std::vector<Body>& bodies, const std::vector<BodyExtras>& extras);

}  // namespace ecpsim::engine::yaml
