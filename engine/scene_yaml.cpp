#include "engine/scene_yaml.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <set>
#include <utility>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "geometry/convex_hull.h"
#include "common/errors.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_io.h"

namespace ecpsim::engine {
namespace {

namespace fs = std::filesystem;
using geometry::ConvexShape;
using geometry::TriangleMesh;

constexpr double kDefaultDensity = 1000;  // kg/m³, water: `ecpsim drop` without --mass
// a quaternion shorter than this carries no direction to normalize (and is surely a typo)
constexpr double kMinQuaternionNorm = 1e-9;
// a plane normal shorter than this has no direction
constexpr double kMinNormalLength = 1e-12;
// mesh vertices may poke out of a declared hull primitive by this fraction of the mesh's
// bounding-box diagonal: tessellation round-off, far below any modelled feature
constexpr double kHullContainmentTolerance = 1e-6;  // × bounding-box diagonal
// symmetry and triangle inequality of a user inertia, relative to its largest entry: values
// typed with ~10 significant digits pass, a transposition typo does not
constexpr double kInertiaTolerance = 1e-9;  // × max |I_ij|
// a constant force/torque component whose end is not given
constexpr double kForever = 1e300;  // s, as Load::end's default
// values shown in messages are cut to this many characters
constexpr size_t kMaxShownValue = 60;
// body and obstacle names become CSV column prefixes
constexpr const char* kNameCharacters =
    "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-";

// ---- messages --------------------------------------------------------------------------------

// an override applied by --set: its dotted key and its text, for naming it in messages
struct Override {
  std::string dotted_key;
  std::string text;
};

struct Context {
  std::string file;
  fs::path folder;
  std::vector<Override> overrides;
};

// "bodies[0].mass" → "bodies.0.mass", the spelling of --set keys
std::string Dotted(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '[') {
      out += '.';
    } else if (c != ']') {
      out += c;
    }
  }
  return out;
}

// "file:line:col" (1-based), or the --set that produced the node
std::string Where(const Context& ctx, const YAML::Node& node, const std::string& key) {
  const std::string dotted = Dotted(key);
  for (const Override& o : ctx.overrides) {
    if (dotted == o.dotted_key || dotted.rfind(o.dotted_key + ".", 0) == 0) {
      return fmt::format("{}: --set {}", ctx.file, o.text);
    }
  }
  const YAML::Mark mark = node.IsDefined() ? node.Mark() : YAML::Mark::null_mark();
  if (mark.is_null()) {
    return ctx.file;
  }
  return fmt::format("{}:{}:{}", ctx.file, mark.line + 1, mark.column + 1);
}

std::string Show(const YAML::Node& node) {
  if (!node.IsDefined()) {
    return "(missing)";
  }
  std::string text;
  if (node.IsNull()) {
    text = "null";
  } else if (node.IsScalar()) {
    text = node.Scalar();
  } else {
    YAML::Emitter out;
    out.SetSeqFormat(YAML::Flow);
    out.SetMapFormat(YAML::Flow);
    out << node;
    text = out.c_str();
  }
  if (text.size() > kMaxShownValue) {
    text = text.substr(0, kMaxShownValue - 3) + "...";
  }
  return text;
}

[[noreturn]] void Fail(const Context& ctx, const YAML::Node& node, const std::string& key,
                       const std::string& expected) {
  throw InputError(
      fmt::format("{}: {} = {}: expected {}", Where(ctx, node, key), key, Show(node), expected));
}

// re-throws a geometry error (mesh, hull, mass) with the scene location in front
template <typename F>
auto WithLocation(const Context& ctx, const YAML::Node& node, const std::string& key, F&& f) {
  try {
    return f();
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}: {}", Where(ctx, node, key), key, e.what()));
  }
}

int EditDistance(const std::string& a, const std::string& b) {
  std::vector<int> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    int diagonal = row[0];
    row[0] = static_cast<int>(i);
    for (size_t j = 1; j <= b.size(); ++j) {
      const int substitute = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitute});
    }
  }
  return row[b.size()];
}

std::string JoinKeys(const std::vector<std::string>& keys) {
  std::string out;
  for (const std::string& k : keys) {
    out += (out.empty() ? "" : ", ") + k;
  }
  return out;
}

std::string Child(const std::string& key, const std::string& child) {
  return key.empty() ? child : key + "." + child;
}

std::string Index(const std::string& key, size_t i) { return fmt::format("{}[{}]", key, i); }

// ---- typed readers ---------------------------------------------------------------------------

// A YAML mapping whose keys were checked against the allowed set (unknown and duplicate keys are
// errors, with the closest valid key suggested).
class MapNode {
 public:
  MapNode(const Context& ctx, const YAML::Node& node, std::string key,
          const std::vector<std::string>& allowed)
      : ctx_(ctx), node_(node), key_(std::move(key)) {
    if (!node.IsMap()) {
      Fail(ctx, node, key_.empty() ? "(scene)" : key_,
           fmt::format("a mapping with keys {}", JoinKeys(allowed)));
    }
    std::set<std::string> seen;
    for (auto it = node.begin(); it != node.end(); ++it) {
      const YAML::Node& k = it->first;
      const std::string name = k.IsScalar() ? k.Scalar() : Show(k);
      const std::string full = Child(key_, name);
      if (std::find(allowed.begin(), allowed.end(), name) == allowed.end()) {
        std::string best;
        int best_distance = 3;  // suggest only near misses (up to two edits)
        for (const std::string& a : allowed) {
          const int d = EditDistance(name, a);
          if (d < best_distance) {
            best_distance = d;
            best = a;
          }
        }
        const std::string hint = best.empty() ? "" : fmt::format(" (did you mean \"{}\"?)", best);
        throw InputError(fmt::format("{}: {}: unknown key{}; expected one of {}",
                                     Where(ctx, k, full), full, hint, JoinKeys(allowed)));
      }
      if (!seen.insert(name).second) {
        throw InputError(fmt::format("{}: {}: duplicate key; expected each key once",
                                     Where(ctx, k, full), full));
      }
    }
  }

  bool Has(const std::string& k) const { return static_cast<bool>(node_[k]); }
  YAML::Node Get(const std::string& k) const { return node_[k]; }
  std::string Key(const std::string& k) const { return Child(key_, k); }
  const std::string& key() const { return key_; }
  const YAML::Node& node() const { return node_; }

  // the value of a required key, or an error at the mapping naming the key
  YAML::Node Require(const std::string& k, const std::string& expected) const {
    const YAML::Node value = node_[k];
    if (!value) {
      throw InputError(fmt::format("{}: {} = (missing): expected {}", Where(ctx_, node_, key_),
                                   Key(k), expected));
    }
    return value;
  }

  // an error about key `k`: at its value when present, else at this mapping as "(missing)"
  [[noreturn]] void FailAt(const std::string& k, const std::string& expected) const {
    if (Has(k)) {
      Fail(ctx_, Get(k), Key(k), expected);
    }
    throw InputError(
        fmt::format("{}: {} = (missing): expected {}", Where(ctx_, node_, key_), Key(k), expected));
  }

 private:
  const Context& ctx_;
  YAML::Node node_;
  std::string key_;
};

double ReadNumber(const Context& ctx, const YAML::Node& node, const std::string& key,
                  const std::string& expected) {
  double value = 0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, value) || !std::isfinite(value)) {
    Fail(ctx, node, key, expected);
  }
  return value;
}

double ReadPositive(const Context& ctx, const YAML::Node& node, const std::string& key,
                    const std::string& expected) {
  const double value = ReadNumber(ctx, node, key, expected);
  if (!(value > 0)) {
    Fail(ctx, node, key, expected);
  }
  return value;
}

int ReadInt(const Context& ctx, const YAML::Node& node, const std::string& key, int min,
            const std::string& expected) {
  int value = 0;
  if (!node.IsScalar() || !YAML::convert<int>::decode(node, value) || value < min) {
    Fail(ctx, node, key, expected);
  }
  return value;
}

bool ReadBool(const Context& ctx, const YAML::Node& node, const std::string& key) {
  bool value = false;
  if (!node.IsScalar() || !YAML::convert<bool>::decode(node, value)) {
    Fail(ctx, node, key, "true or false");
  }
  return value;
}

ContactModel ReadModel(const Context& ctx, const YAML::Node& node, const std::string& key) {
  for (ContactModel model :
       {ContactModel::kHull, ContactModel::kPlanar, ContactModel::kMultiPatch,
        ContactModel::kPointLcp}) {
    if (node.IsScalar() && node.Scalar() == ContactModelName(model)) return model;
  }
  Fail(ctx, node, key, "one of hull, planar, multipatch, point");
}

std::string ReadName(const Context& ctx, const YAML::Node& node, const std::string& key) {
  const std::string expected = "a name of letters, digits, '_' and '-' (it prefixes CSV columns)";
  if (!node.IsScalar() || node.Scalar().empty() ||
      node.Scalar().find_first_not_of(kNameCharacters) != std::string::npos) {
    Fail(ctx, node, key, expected);
  }
  return node.Scalar();
}

Eigen::VectorXd ReadNumbers(const Context& ctx, const YAML::Node& node, const std::string& key,
                            size_t count, const std::string& expected) {
  if (!node.IsSequence() || node.size() != count) {
    Fail(ctx, node, key, expected);
  }
  Eigen::VectorXd values(count);
  for (size_t i = 0; i < count; ++i) {
    values[i] = ReadNumber(ctx, node[i], Index(key, i), expected);
  }
  return values;
}

Eigen::Vector3d ReadVector3(const Context& ctx, const YAML::Node& node, const std::string& key,
                            const std::string& unit) {
  return ReadNumbers(ctx, node, key, 3,
                     fmt::format("a list of 3 finite numbers [x, y, z] ({})", unit));
}

Eigen::Vector3d ReadPositive3(const Context& ctx, const YAML::Node& node, const std::string& key,
                              const std::string& expected) {
  const Eigen::Vector3d v = ReadNumbers(ctx, node, key, 3, expected);
  if (!(v.array() > 0).all()) {
    Fail(ctx, node, key, expected);
  }
  return v;
}

// R = Rz(yaw) · Ry(pitch) · Rx(roll) from [roll, pitch, yaw] in degrees
Eigen::Quaterniond FromRpyDegrees(const Eigen::Vector3d& rpy_deg) {
  const Eigen::Vector3d rpy = rpy_deg * (M_PI / 180);
  return Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX());
}

// `quaternion` [w, x, y, z] (normalized) or `rpy` [deg]; identity when neither is given
Eigen::Quaterniond ReadOrientation(const Context& ctx, const MapNode& map) {
  if (map.Has("quaternion") && map.Has("rpy")) {
    map.FailAt("rpy", "either `quaternion` or `rpy`, not both");
  }
  if (map.Has("quaternion")) {
    const Eigen::VectorXd q = ReadNumbers(ctx, map.Get("quaternion"), map.Key("quaternion"), 4,
                                          "a list of 4 finite numbers [w, x, y, z], not all zero");
    if (q.norm() < kMinQuaternionNorm) {
      map.FailAt("quaternion", "a non-zero quaternion [w, x, y, z] (it is normalized)");
    }
    return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
  }
  if (map.Has("rpy")) {
    return FromRpyDegrees(ReadVector3(ctx, map.Get("rpy"), map.Key("rpy"), "degrees"));
  }
  return Eigen::Quaterniond::Identity();
}

Friction ReadFriction(const Context& ctx, const YAML::Node& node, const std::string& key,
                      Friction friction) {
  const MapNode map(ctx, node, key, {"mu", "e_t", "e_o", "e_r"});
  if (map.Has("mu")) {
    friction.mu = ReadNumber(ctx, map.Get("mu"), map.Key("mu"), "a friction coefficient >= 0");
    if (friction.mu < 0) {
      map.FailAt("mu", "a friction coefficient >= 0");
    }
  }
  const std::string axis = "an ellipsoid semi-axis > 0 (dimensionless for e_t, e_o)";
  if (map.Has("e_t")) friction.e_t = ReadPositive(ctx, map.Get("e_t"), map.Key("e_t"), axis);
  if (map.Has("e_o")) friction.e_o = ReadPositive(ctx, map.Get("e_o"), map.Key("e_o"), axis);
  if (map.Has("e_r")) {
    friction.e_r =
        ReadPositive(ctx, map.Get("e_r"), map.Key("e_r"), "a torsional ellipsoid semi-axis > 0 m");
  }
  return friction;
}

// ---- shapes ----------------------------------------------------------------------------------

// A convex primitive centred at the origin with its closed-form volume and inertia per kg.
struct Primitive {
  std::shared_ptr<const ConvexShape> shape;
  double volume = 0;                                       // m³
  Eigen::Matrix3d unit_inertia = Eigen::Matrix3d::Zero();  // m², I / m about the centre
};

int ReadAxis(const Context& ctx, const YAML::Node& node, const std::string& key) {
  const std::string expected = "an axis x, y or z";
  if (!node.IsScalar()) Fail(ctx, node, key, expected);
  const std::string& s = node.Scalar();
  if (s == "x" || s == "X") return 0;
  if (s == "y" || s == "Y") return 1;
  if (s == "z" || s == "Z") return 2;
  Fail(ctx, node, key, expected);
}

Primitive ReadPrimitive(const Context& ctx, const YAML::Node& node, const std::string& key) {
  const MapNode map(ctx, node, key, {"box", "sphere", "cylinder", "ellipsoid"});
  if (map.node().size() != 1) {
    Fail(ctx, node, key, "exactly one of box, sphere, cylinder, ellipsoid");
  }
  Primitive p;
  if (map.Has("box")) {
    const MapNode box(ctx, map.Get("box"), map.Key("box"), {"size"});
    const Eigen::Vector3d s =
        ReadPositive3(ctx, box.Require("size", "[x, y, z] edge lengths > 0 m"), box.Key("size"),
                      "a list of 3 edge lengths > 0 m [x, y, z]");
    p.shape = geometry::MakeBox(s / 2);
    p.volume = s.prod();
    const Eigen::Vector3d sq = s.cwiseProduct(s);
    p.unit_inertia.diagonal() << sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y();
    p.unit_inertia /= 12;
  } else if (map.Has("sphere")) {
    const MapNode sphere(ctx, map.Get("sphere"), map.Key("sphere"), {"radius"});
    const double r = ReadPositive(ctx, sphere.Require("radius", "a radius > 0 m"),
                                  sphere.Key("radius"), "a radius > 0 m");
    p.shape = geometry::MakeSphere(r);
    p.volume = 4.0 / 3.0 * M_PI * r * r * r;
    p.unit_inertia = Eigen::Matrix3d::Identity() * (0.4 * r * r);
  } else if (map.Has("cylinder")) {
    const MapNode cyl(ctx, map.Get("cylinder"), map.Key("cylinder"), {"radius", "length", "axis"});
    const double r = ReadPositive(ctx, cyl.Require("radius", "a radius > 0 m"), cyl.Key("radius"),
                                  "a radius > 0 m");
    const double l = ReadPositive(ctx, cyl.Require("length", "a length > 0 m"), cyl.Key("length"),
                                  "a length > 0 m");
    const int axis = cyl.Has("axis") ? ReadAxis(ctx, cyl.Get("axis"), cyl.Key("axis")) : 2;
    p.shape = geometry::MakeCylinder(r, l, axis);
    p.volume = M_PI * r * r * l;
    p.unit_inertia = Eigen::Matrix3d::Identity() * ((3 * r * r + l * l) / 12);
    p.unit_inertia(axis, axis) = r * r / 2;
  } else {
    const MapNode ell(ctx, map.Get("ellipsoid"), map.Key("ellipsoid"), {"radii"});
    const Eigen::Vector3d r =
        ReadPositive3(ctx, ell.Require("radii", "[a, b, c] semi-axes > 0 m"), ell.Key("radii"),
                      "a list of 3 semi-axes > 0 m [a, b, c]");
    p.shape = geometry::MakeEllipsoid(r);
    p.volume = 4.0 / 3.0 * M_PI * r.prod();
    const Eigen::Vector3d sq = r.cwiseProduct(r);
    p.unit_inertia.diagonal() << sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y();
    p.unit_inertia /= 5;
  }
  return p;
}

// the box's hull moved to the pose (R, p): n' = R n, d' = d + n' · p
std::shared_ptr<const ConvexShape> PosedBox(const Eigen::Vector3d& size,
                                            const Eigen::Quaterniond& rotation,
                                            const Eigen::Vector3d& position) {
  geometry::ConvexHull hull = geometry::MakeBox(size / 2)->hull();
  const Eigen::Matrix3d R = rotation.toRotationMatrix();
  for (Eigen::Vector3d& v : hull.vertices) v = R * v + position;
  for (size_t i = 0; i < hull.normals.size(); ++i) {
    hull.normals[i] = R * hull.normals[i];
    hull.offsets[i] += hull.normals[i].dot(position);
  }
  return std::make_shared<geometry::PolyhedralShape>(std::move(hull));
}

// ---- obstacles -------------------------------------------------------------------------------

// the half-space n̂ · x <= offset of a mapping with optional `normal` (default +z) and `offset`
std::shared_ptr<const ConvexShape> ReadPlaneShape(const Context& ctx, const MapNode& map) {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  if (map.Has("normal")) {
    normal = ReadVector3(ctx, map.Get("normal"), map.Key("normal"), "unit-free direction");
    if (normal.norm() < kMinNormalLength) {
      map.FailAt("normal", "a non-zero normal pointing out of the obstacle (it is normalized)");
    }
  }
  const double offset = map.Has("offset") ? ReadNumber(ctx, map.Get("offset"), map.Key("offset"),
                                                       "a finite offset (m)")
                                          : 0.0;
  return geometry::MakeHalfSpace(normal.normalized(), offset);
}

Obstacle ReadObstacle(const Context& ctx, const YAML::Node& node, const std::string& key,
                      const std::string& default_name) {
  const MapNode map(ctx, node, key, {"name", "plane", "box", "friction"});
  if (map.Has("plane") == map.Has("box")) {
    Fail(ctx, node, key,
         "exactly one of `plane: {normal, offset}` or `box: {size, position, rpy}`");
  }
  Obstacle obstacle;
  if (map.Has("plane")) {
    const MapNode plane(ctx, map.Get("plane"), map.Key("plane"), {"normal", "offset"});
    obstacle.shape = ReadPlaneShape(ctx, plane);
  } else {
    const MapNode box(ctx, map.Get("box"), map.Key("box"),
                      {"size", "position", "rpy", "quaternion"});
    const Eigen::Vector3d size =
        ReadPositive3(ctx, box.Require("size", "[x, y, z] edge lengths > 0 m"), box.Key("size"),
                      "a list of 3 edge lengths > 0 m [x, y, z]");
    const Eigen::Vector3d position =
        box.Has("position") ? ReadVector3(ctx, box.Get("position"), box.Key("position"), "m")
                            : Eigen::Vector3d::Zero();
    obstacle.shape = PosedBox(size, ReadOrientation(ctx, box), position);
  }
  obstacle.name = map.Has("name") ? ReadName(ctx, map.Get("name"), map.Key("name")) : default_name;
  if (map.Has("friction")) {
    obstacle.friction = ReadFriction(ctx, map.Get("friction"), map.Key("friction"), Friction{});
  }
  return obstacle;
}

// `ground: {normal, offset, friction}`: the plane z = 0 unless told otherwise
Obstacle ReadGround(const Context& ctx, const YAML::Node& node, const std::string& key) {
  const MapNode map(ctx, node, key, {"normal", "offset", "friction"});
  Obstacle ground;
  ground.shape = ReadPlaneShape(ctx, map);
  ground.name = "ground";
  if (map.Has("friction")) {
    ground.friction = ReadFriction(ctx, map.Get("friction"), map.Key("friction"), Friction{});
  }
  return ground;
}

// ---- bodies ----------------------------------------------------------------------------------

// what a body adds beyond engine::Body: the frame shift for `at` points and friction overrides
struct BodyExtras {
  Eigen::Vector3d center_of_mass = Eigen::Vector3d::Zero();  // m, in the mesh's own frame
  std::optional<YAML::Node> friction;
  std::string friction_key;
};

double BoundingBoxDiagonal(const TriangleMesh& mesh) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const Eigen::Vector3d& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  return mesh.vertices.empty() ? 0.0 : (hi - lo).norm();
}

Eigen::Matrix3d ReadInertia(const Context& ctx, const YAML::Node& node, const std::string& key) {
  const std::string expected =
      "3 (diagonal) or 9 (row-major) values in kg·m² about the CM in body axes, symmetric, "
      "positive definite, each principal moment <= the sum of the other two";
  if (!node.IsSequence() || (node.size() != 3 && node.size() != 9)) {
    Fail(ctx, node, key, expected);
  }
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  if (node.size() == 3) {
    inertia.diagonal() = ReadNumbers(ctx, node, key, 3, expected);
  } else {
    const Eigen::VectorXd v = ReadNumbers(ctx, node, key, 9, expected);
    for (int i = 0; i < 9; ++i) inertia(i / 3, i % 3) = v[i];
  }
  const double scale = inertia.cwiseAbs().maxCoeff();
  if (!(scale > 0) ||
      (inertia - inertia.transpose()).cwiseAbs().maxCoeff() > kInertiaTolerance * scale) {
    Fail(ctx, node, key, expected);
  }
  const Eigen::Vector3d moments =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(inertia, Eigen::EigenvaluesOnly).eigenvalues();
  // ascending: positive definite, and the largest no more than the sum of the other two
  if (!(moments[0] > 0) || moments[2] > moments[0] + moments[1] + kInertiaTolerance * scale) {
    Fail(ctx, node, key, expected);
  }
  return inertia;
}

// `parts: [{box: {size}, at, rpy | quaternion}]`: the convex pieces of the multipatch model, each
// a box whose centre `at` is in the mesh's frame (like loads' `at`), moved to the CM frame; every
// part must lie inside the body's hull (its vertices within `tolerance` m), since the parts
// stand for pieces of the body
std::vector<std::shared_ptr<const ConvexShape>> ReadParts(const Context& ctx,
                                                          const YAML::Node& node,
                                                          const std::string& key,
                                                          const Eigen::Vector3d& center_of_mass,
                                                          const ConvexShape& hull,
                                                          double tolerance) {
  if (!node.IsSequence() || node.size() == 0) {
    Fail(ctx, node, key, "a list of at least one part {box: {size: [x, y, z]}, at: [x, y, z]}");
  }
  std::vector<std::shared_ptr<const ConvexShape>> parts;
  for (size_t i = 0; i < node.size(); ++i) {
    const MapNode part(ctx, node[i], Index(key, i), {"box", "at", "rpy", "quaternion"});
    const MapNode box(ctx, part.Require("box", "a box part {size: [x, y, z]}"), part.Key("box"),
                      {"size"});
    const Eigen::Vector3d size =
        ReadPositive3(ctx, box.Require("size", "[x, y, z] edge lengths > 0 m"), box.Key("size"),
                      "a list of 3 edge lengths > 0 m [x, y, z]");
    const Eigen::Vector3d at =
        part.Has("at") ? ReadVector3(ctx, part.Get("at"), part.Key("at"), "m, mesh frame")
                       : Eigen::Vector3d::Zero();
    auto shape = PosedBox(size, ReadOrientation(ctx, part), at - center_of_mass);
    const auto& polyhedron = static_cast<const geometry::PolyhedralShape&>(*shape);
    for (const Eigen::Vector3d& v : polyhedron.hull().vertices) {
      for (int c = 0; c < hull.NumConstraints(); ++c) {
        const double outside = hull.Value(c, v);
        if (outside > tolerance) {
          const Eigen::Vector3d v_mesh = v + center_of_mass;
          Fail(ctx, node[i], Index(key, i),
               fmt::format("a part inside the body; its corner ({:.6g}, {:.6g}, {:.6g}) m (mesh "
                           "frame) lies {:.3g} m outside the body's hull",
                           v_mesh.x(), v_mesh.y(), v_mesh.z(), outside));
        }
      }
    }
    parts.push_back(std::move(shape));
  }
  return parts;
}

Body ReadBody(const Context& ctx, const YAML::Node& node, const std::string& key,
              const std::string& default_name, BodyExtras& extras) {
  const MapNode map(ctx, node, key,
                    {"name", "mesh", "scale", "shape", "hull", "mass", "density", "inertia",
                     "position", "quaternion", "rpy", "lowest_point_height", "on_ground",
                     "velocity", "angular_velocity", "friction", "parts"});
  Body body;
  body.name = map.Has("name") ? ReadName(ctx, map.Get("name"), map.Key("name")) : default_name;

  // mass: `mass`, `density`, or `mass` + `inertia`
  if (map.Has("mass") && map.Has("density")) {
    map.FailAt("density", "either `mass` or `density`, not both");
  }
  if (!map.Has("mass") && !map.Has("density")) {
    map.FailAt("mass", "a mass > 0 kg (or a `density` in kg/m³)");
  }
  if (map.Has("inertia") && !map.Has("mass")) {
    map.FailAt("inertia", "`inertia` together with `mass`");
  }
  std::optional<double> mass, density;
  if (map.Has("mass")) {
    mass = ReadPositive(ctx, map.Get("mass"), map.Key("mass"), "a finite mass > 0 kg");
  } else {
    density =
        ReadPositive(ctx, map.Get("density"), map.Key("density"), "a finite density > 0 kg/m³");
  }

  // geometry: a mesh file or a primitive; the body frame is the CM with the mesh's axes
  if (map.Has("mesh") == map.Has("shape")) {
    map.FailAt("mesh",
               "exactly one of `mesh: FILE` or `shape: {box|sphere|cylinder|ellipsoid: ...}`");
  }
  if (map.Has("scale") && !map.Has("mesh")) {
    map.FailAt("scale", "`scale` only together with `mesh`");
  }
  Eigen::Matrix3d inertia;
  if (map.Has("mesh")) {
    const YAML::Node mesh_node = map.Get("mesh");
    if (!mesh_node.IsScalar() || mesh_node.Scalar().empty()) {
      Fail(ctx, mesh_node, map.Key("mesh"), "a mesh file path (relative to the scene file)");
    }
    const double scale = map.Has("scale") ? ReadPositive(ctx, map.Get("scale"), map.Key("scale"),
                                                         "a scale > 0 (mesh units to m)")
                                          : 1.0;
    const fs::path path = (ctx.folder / mesh_node.Scalar()).lexically_normal();
    std::error_code error;
    if (!fs::is_regular_file(path, error)) {
      Fail(ctx, mesh_node, map.Key("mesh"),
           fmt::format("an existing mesh file (looked for {})", path.string()));
    }
    const TriangleMesh mesh = WithLocation(
        ctx, mesh_node, map.Key("mesh"), [&] { return geometry::LoadMesh(path.string(), scale); });
    const geometry::MassProperties props = WithLocation(ctx, mesh_node, map.Key("mesh"), [&] {
      return mass ? geometry::ComputeMassPropertiesForMass(mesh, *mass, path.string())
                  : geometry::ComputeMassProperties(mesh, *density, path.string());
    });
    body.mass = props.mass;
    inertia = props.inertia;
    extras.center_of_mass = props.center_of_mass;
    body.mesh = mesh;
    for (Eigen::Vector3d& v : body.mesh.vertices) v -= props.center_of_mass;
    if (!map.Has("hull")) {
      const geometry::ConvexHull hull = WithLocation(ctx, mesh_node, map.Key("mesh"), [&] {
        return geometry::ComputeConvexHull(mesh.vertices, path.string());
      });
      body.hull = std::make_shared<geometry::PolyhedralShape>(
          geometry::TranslateHull(hull, -props.center_of_mass));
    }
  } else {
    const Primitive primitive = ReadPrimitive(ctx, map.Get("shape"), map.Key("shape"));
    body.mass = mass ? *mass : *density * primitive.volume;
    inertia = body.mass * primitive.unit_inertia;
    body.mesh = primitive.shape->Tessellate();
    body.hull = primitive.shape;
  }
  body.inertia =
      map.Has("inertia") ? ReadInertia(ctx, map.Get("inertia"), map.Key("inertia")) : inertia;

  // an explicit hull primitive, centred at the CM, must contain the mesh
  if (map.Has("hull")) {
    const Primitive hull = ReadPrimitive(ctx, map.Get("hull"), map.Key("hull"));
    const double tolerance = kHullContainmentTolerance * BoundingBoxDiagonal(body.mesh);
    for (const Eigen::Vector3d& v : body.mesh.vertices) {
      for (int i = 0; i < hull.shape->NumConstraints(); ++i) {
        const double outside = hull.shape->Value(i, v);
        if (outside > tolerance) {
          map.FailAt(
              "hull",
              fmt::format("a convex primitive centred at the CM that contains the mesh; mesh "
                          "vertex ({:.6g}, {:.6g}, {:.6g}) m (CM frame) lies {:.3g} m outside",
                          v.x(), v.y(), v.z(), outside));
        }
      }
    }
    body.hull = hull.shape;
  }

  if (map.Has("parts")) {
    body.parts = ReadParts(ctx, map.Get("parts"), map.Key("parts"), extras.center_of_mass,
                           *body.hull, kHullContainmentTolerance * BoundingBoxDiagonal(body.mesh));
  }

  // initial pose: `position` is where the CM starts
  body.q0 = ReadOrientation(ctx, map);
  const bool on_ground =
      map.Has("on_ground") && ReadBool(ctx, map.Get("on_ground"), map.Key("on_ground"));
  if (map.Has("on_ground") && !on_ground) {
    map.FailAt("on_ground", "true (or leave it out and give `position` [x, y, z])");
  }
  if (on_ground && map.Has("lowest_point_height")) {
    map.FailAt("lowest_point_height", "either `on_ground` or `lowest_point_height`, not both");
  }
  if (on_ground || map.Has("lowest_point_height")) {
    const double height =
        on_ground ? 0.0
                  : ReadNumber(ctx, map.Get("lowest_point_height"), map.Key("lowest_point_height"),
                               "a finite height (m) of the hull's lowest point");
    Eigen::Vector2d xy = Eigen::Vector2d::Zero();
    if (map.Has("position")) {
      const YAML::Node pos = map.Get("position");
      xy = ReadNumbers(ctx, pos, map.Key("position"), 2,
                       "[x, y] (m): the height comes from on_ground / lowest_point_height");
    }
    // the lowest point of the hull (what touches the ground) at the initial orientation
    const Eigen::Matrix3d R = body.q0.toRotationMatrix();
    const Eigen::Vector3d lowest_B = body.hull->Support(R.transpose() * -Eigen::Vector3d::UnitZ());
    body.p0 = Eigen::Vector3d(xy.x(), xy.y(), height - (R * lowest_B).z());
  } else {
    body.p0 = ReadVector3(ctx, map.Require("position", "[x, y, z] (m), the CM's initial position"),
                          map.Key("position"), "m, the CM's initial position");
  }
  if (map.Has("velocity")) {
    body.v0 = ReadVector3(ctx, map.Get("velocity"), map.Key("velocity"), "m/s, world frame");
  }
  if (map.Has("angular_velocity")) {
    body.w0 = ReadVector3(ctx, map.Get("angular_velocity"), map.Key("angular_velocity"),
                          "rad/s, world frame");
  }
  if (map.Has("friction")) {
    // checked now against default friction; applied on top of each obstacle's later
    ReadFriction(ctx, map.Get("friction"), map.Key("friction"), Friction{});
    extras.friction = map.Get("friction");
    extras.friction_key = map.Key("friction");
  }
  return body;
}

// a body by name, or by index into `bodies`
int ReadBodyReference(const Context& ctx, const MapNode& map, const std::vector<Body>& bodies) {
  if (!map.Has("body")) {
    if (bodies.size() == 1) return 0;
    map.FailAt("body", "a body name (required: the scene has several)");
  }
  const YAML::Node node = map.Get("body");
  std::string names;
  for (const Body& b : bodies) names += (names.empty() ? "" : ", ") + b.name;
  const std::string expected =
      fmt::format("a body name ({}) or index 0..{}", names, bodies.size() - 1);
  if (!node.IsScalar()) Fail(ctx, node, map.Key("body"), expected);
  for (size_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i].name == node.Scalar()) return static_cast<int>(i);
  }
  int index = -1;
  if (!YAML::convert<int>::decode(node, index) || index < 0 ||
      index >= static_cast<int>(bodies.size())) {
    Fail(ctx, node, map.Key("body"), expected);
  }
  return index;
}

// ---- loads -----------------------------------------------------------------------------------

TimeFunction ReadComponent(const Context& ctx, const YAML::Node& node, const std::string& key) {
  if (!node.IsScalar()) {
    Fail(ctx, node, key, "a number or an expression of t in quotes");
  }
  double value = 0;
  if (YAML::convert<double>::decode(node, value)) {
    if (!std::isfinite(value)) Fail(ctx, node, key, "a finite number or an expression of t");
    return TimeFunction(value);
  }
  return TimeFunction(node.Scalar(), fmt::format("{}: {}", Where(ctx, node, key), key));
}

void ReadWindow(const Context& ctx, const MapNode& map, double& start, double& end) {
  start = map.Has("start")
              ? ReadNumber(ctx, map.Get("start"), map.Key("start"), "a finite start time (s)")
              : 0.0;
  end = kForever;
  if (map.Has("end")) {
    end = ReadNumber(ctx, map.Get("end"), map.Key("end"), "a finite end time (s) > start");
    if (!(end > start)) {
      map.FailAt("end", fmt::format("an end time (s) > start = {}", start));
    }
  }
}

Load ReadLoad(const Context& ctx, const YAML::Node& node, const std::string& key,
              const std::vector<Body>& bodies, const std::vector<BodyExtras>& extras) {
  const MapNode map(ctx, node, key, {"body", "force", "torque", "at", "start", "end"});
  Load load;
  load.body = ReadBodyReference(ctx, map, bodies);
  if (map.Has("force") == map.Has("torque")) {
    Fail(ctx, node, key, "exactly one of `force` [N] or `torque` [N·m] (world frame)");
  }
  load.kind = map.Has("force") ? Load::Kind::kForce : Load::Kind::kTorque;
  const std::string name = map.Has("force") ? "force" : "torque";
  const YAML::Node components = map.Get(name);
  if (!components.IsSequence() || components.size() != 3) {
    Fail(ctx, components, map.Key(name),
         "a list of 3 components [x, y, z] (world frame), each a number or an expression of t");
  }
  load.x = ReadComponent(ctx, components[0], Index(map.Key(name), 0));
  load.y = ReadComponent(ctx, components[1], Index(map.Key(name), 1));
  load.z = ReadComponent(ctx, components[2], Index(map.Key(name), 2));
  if (map.Has("at")) {
    if (load.kind == Load::Kind::kTorque) {
      map.FailAt("at", "`at` only with a force (a torque has no point)");
    }
    load.at_point = true;
    load.point_B = ReadVector3(ctx, map.Get("at"), map.Key("at"), "m, mesh frame") -
                   extras[load.body].center_of_mass;
  }
  ReadWindow(ctx, map, load.start, load.end);
  return load;
}

Impulse ReadImpulse(const Context& ctx, const YAML::Node& node, const std::string& key,
                    const std::vector<Body>& bodies, const std::vector<BodyExtras>& extras) {
  const MapNode map(ctx, node, key, {"body", "time", "linear", "angular", "at"});
  Impulse impulse;
  impulse.body = ReadBodyReference(ctx, map, bodies);
  impulse.time = ReadNumber(ctx, map.Require("time", "a time >= 0 s"), map.Key("time"),
                            "a finite time >= 0 s");
  if (impulse.time < 0) map.FailAt("time", "a finite time >= 0 s");
  if (!map.Has("linear") && !map.Has("angular")) {
    map.FailAt("linear", "`linear` [N·s] and/or `angular` [N·m·s] (world frame)");
  }
  if (map.Has("linear")) {
    impulse.linear = ReadVector3(ctx, map.Get("linear"), map.Key("linear"), "N·s, world frame");
  }
  if (map.Has("angular")) {
    impulse.angular = ReadVector3(ctx, map.Get("angular"), map.Key("angular"),
                                  "N·m·s, world frame, about the CM");
  }
  if (map.Has("at")) {
    if (!map.Has("linear")) {
      map.FailAt("at", "`at` only together with `linear`");
    }
    impulse.at_point = true;
    impulse.point_B = ReadVector3(ctx, map.Get("at"), map.Key("at"), "m, mesh frame") -
                      extras[impulse.body].center_of_mass;
  }
  return impulse;
}

// ---- settings --------------------------------------------------------------------------------

SolverSettings ReadSolver(const Context& ctx, const YAML::Node& node, const std::string& key) {
  const MapNode map(ctx, node, key, {"tolerance", "max_iterations", "window_rings", "use_window"});
  SolverSettings solver;
  if (map.Has("tolerance")) {
    solver.tolerance =
        ReadPositive(ctx, map.Get("tolerance"), map.Key("tolerance"), "a residual tolerance > 0");
  }
  if (map.Has("max_iterations")) {
    solver.max_iterations =
        ReadInt(ctx, map.Get("max_iterations"), map.Key("max_iterations"), 1, "an integer >= 1");
  }
  if (map.Has("window_rings")) {
    solver.window_rings =
        ReadInt(ctx, map.Get("window_rings"), map.Key("window_rings"), 0, "an integer >= 0");
  }
  if (map.Has("use_window")) {
    solver.use_window = ReadBool(ctx, map.Get("use_window"), map.Key("use_window"));
  }
  return solver;
}

// ---- overrides -------------------------------------------------------------------------------

void ApplyOverride(const Context& ctx, YAML::Node& root, const std::string& text,
                   std::vector<Override>& applied) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw InputError(
        fmt::format("{}: --set {}: expected key=value, e.g. h=0.005 or "
                    "bodies.0.mass=3",
                    ctx.file, text));
  }
  const std::string dotted = text.substr(0, eq);
  YAML::Node value;
  try {
    value = YAML::Load(text.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    throw InputError(
        fmt::format("{}: --set {}: the value is not valid YAML ({})", ctx.file, text, e.msg));
  }
  std::vector<std::string> parts;
  for (size_t start = 0;;) {
    const size_t dot = dotted.find('.', start);
    parts.push_back(dotted.substr(start, dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  YAML::Node node;
  node.reset(root);
  std::string prefix;
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string& part = parts[i];
    const bool last = i + 1 == parts.size();
    if (part.empty()) {
      throw InputError(
          fmt::format("{}: --set {}: empty key component in \"{}\"", ctx.file, text, dotted));
    }
    if (node.IsSequence()) {
      int index = -1;
      if (!YAML::convert<int>::decode(YAML::Node(part), index) || index < 0 ||
          index >= static_cast<int>(node.size())) {
        throw InputError(fmt::format(
            "{}: --set {}: {} is a list of {} entries; expected an "
            "index 0..{} instead of \"{}\"",
            ctx.file, text, prefix, node.size(), static_cast<int>(node.size()) - 1, part));
      }
      if (last) {
        node[index] = value;
      } else {
        YAML::Node child = node[index];
        node.reset(child);
      }
    } else if (node.IsMap() || node.IsNull()) {
      if (last) {
        node[part] = value;
      } else {
        if (!node[part]) node[part] = YAML::Node(YAML::NodeType::Map);
        YAML::Node child = node[part];
        node.reset(child);
      }
    } else {
      throw InputError(
          fmt::format("{}: --set {}: {} = {} is a value, not a mapping or list; "
                      "key \"{}\" cannot go inside it",
                      ctx.file, text, prefix, Show(node), part));
    }
    prefix = prefix.empty() ? part : prefix + "." + part;
  }
  applied.push_back({dotted, text});
}

}  // namespace

Scene LoadScene(const std::string& path, const std::vector<std::string>& overrides) {
  Context ctx;
  ctx.file = path;
  ctx.folder = fs::path(path).parent_path();

  YAML::Node root;
  std::error_code error;
  if (!fs::is_regular_file(path, error)) {
    throw InputError(
        fmt::format("scene file {}: cannot open it; expected an existing YAML file", path));
  }
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throw InputError(fmt::format("{}:{}:{}: YAML syntax error: {}", path, e.mark.line + 1,
                                 e.mark.column + 1, e.msg));
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("scene file {}: cannot read it: {}", path, e.msg));
  }
  if (root.IsNull() && overrides.empty()) {
    throw InputError(
        fmt::format("{}: the scene file is empty; expected a mapping with at least "
                    "`duration` and `bodies`",
                    path));
  }
  std::vector<Override> applied;
  for (const std::string& o : overrides) ApplyOverride(ctx, root, o, applied);
  ctx.overrides = applied;

  const MapNode map(ctx, root, "",
                    {"gravity", "h", "duration", "ground", "obstacles", "bodies", "loads",
                     "impulses", "solver", "output", "model"});
  Scene scene;
  scene.source = path;
  if (map.Has("model")) scene.model = ReadModel(ctx, map.Get("model"), "model");
  if (map.Has("gravity")) {
    scene.gravity = ReadVector3(ctx, map.Get("gravity"), "gravity", "m/s², world frame");
  }
  scene.duration = ReadPositive(ctx, map.Require("duration", "a duration > 0 s"), "duration",
                                "a finite duration > 0 s");
  if (map.Has("h")) {
    scene.h = ReadPositive(ctx, map.Get("h"), "h", "a finite time step > 0 s");
  }
  if (scene.h > scene.duration) {
    if (map.Has("h")) {
      Fail(ctx, map.Get("h"), "h", fmt::format("a time step <= duration = {} s", scene.duration));
    }
    Fail(ctx, map.Get("duration"), "duration",
         fmt::format("a duration >= the default time step h = {} s", scene.h));
  }

  // obstacles: the ground first, then the list
  if (map.Has("ground")) {
    scene.obstacles.push_back(ReadGround(ctx, map.Get("ground"), "ground"));
  }
  if (map.Has("obstacles")) {
    const YAML::Node list = map.Get("obstacles");
    if (!list.IsSequence()) {
      Fail(ctx, list, "obstacles", "a list of obstacles (`- plane: ...` or `- box: ...`)");
    }
    for (size_t i = 0; i < list.size(); ++i) {
      scene.obstacles.push_back(
          ReadObstacle(ctx, list[i], Index("obstacles", i), fmt::format("obstacle{}", i)));
      for (size_t j = 0; j + 1 < scene.obstacles.size(); ++j) {
        if (scene.obstacles[j].name == scene.obstacles.back().name) {
          const YAML::Node name = list[i]["name"];
          Fail(ctx, name ? name : list[i], Index("obstacles", i) + ".name",
               "a name no other obstacle has");
        }
      }
    }
  }

  // bodies
  const YAML::Node bodies = map.Require("bodies", "a list of at least one body");
  if (!bodies.IsSequence() || bodies.size() == 0) {
    Fail(ctx, bodies, "bodies", "a list of at least one body");
  }
  std::vector<BodyExtras> extras(bodies.size());
  for (size_t i = 0; i < bodies.size(); ++i) {
    scene.bodies.push_back(
        ReadBody(ctx, bodies[i], Index("bodies", i), fmt::format("body{}", i), extras[i]));
    for (size_t j = 0; j < i; ++j) {
      if (scene.bodies[j].name == scene.bodies[i].name) {
        const YAML::Node name = bodies[i]["name"];
        Fail(ctx, name ? name : bodies[i], Index("bodies", i) + ".name",
             "a name no other body has");
      }
    }
  }

  // one contact per (body, obstacle), with the obstacle's friction under the body's overrides
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    for (size_t o = 0; o < scene.obstacles.size(); ++o) {
      ContactPair pair;
      pair.body = static_cast<int>(b);
      pair.obstacle = static_cast<int>(o);
      pair.friction = scene.obstacles[o].friction;
      if (extras[b].friction) {
        pair.friction =
            ReadFriction(ctx, *extras[b].friction, extras[b].friction_key, pair.friction);
      }
      scene.contacts.push_back(pair);
    }
  }

  if (map.Has("loads")) {
    const YAML::Node list = map.Get("loads");
    if (!list.IsSequence()) Fail(ctx, list, "loads", "a list of loads");
    for (size_t i = 0; i < list.size(); ++i) {
      scene.loads.push_back(ReadLoad(ctx, list[i], Index("loads", i), scene.bodies, extras));
    }
  }
  if (map.Has("impulses")) {
    const YAML::Node list = map.Get("impulses");
    if (!list.IsSequence()) Fail(ctx, list, "impulses", "a list of impulses");
    for (size_t i = 0; i < list.size(); ++i) {
      scene.impulses.push_back(
          ReadImpulse(ctx, list[i], Index("impulses", i), scene.bodies, extras));
    }
  }
  if (map.Has("solver")) {
    scene.solver = ReadSolver(ctx, map.Get("solver"), "solver");
  }
  if (map.Has("output")) {
    const MapNode output(ctx, map.Get("output"), "output",
                         {"every", "fps", "width", "height", "camera"});
    if (output.Has("every")) {
      scene.output.every = ReadInt(ctx, output.Get("every"), "output.every", 1,
                                   "an integer >= 1 (write every N-th step)");
    }
    if (output.Has("fps")) {
      scene.output.fps = ReadPositive(ctx, output.Get("fps"), "output.fps",
                                      "a finite frame rate > 0 frames per simulated second");
    }
    if (output.Has("width")) {
      scene.output.width = ReadInt(ctx, output.Get("width"), "output.width", 16,
                                   "an integer width >= 16 pixels");
    }
    if (output.Has("height")) {
      scene.output.height = ReadInt(ctx, output.Get("height"), "output.height", 16,
                                    "an integer height >= 16 pixels");
    }
    if (output.Has("camera")) {
      const MapNode camera(ctx, output.Get("camera"), "output.camera",
                           {"position", "target", "fov"});
      scene.output.camera_fixed = true;
      scene.output.camera_position =
          ReadVector3(ctx, camera.Require("position", "[x, y, z] m, world"),
                      "output.camera.position", "m, world");
      if (camera.Has("target")) {
        scene.output.camera_target = ReadVector3(ctx, camera.Get("target"),
                                                 "output.camera.target", "m, world");
      }
      if (camera.Has("fov")) {
        scene.output.camera_fov_deg = ReadPositive(ctx, camera.Get("fov"), "output.camera.fov",
                                                   "a vertical field of view in (0, 180) degrees");
        if (scene.output.camera_fov_deg >= 180) {
          Fail(ctx, camera.Get("fov"), "output.camera.fov",
               "a vertical field of view in (0, 180) degrees");
        }
      }
      if ((scene.output.camera_position - scene.output.camera_target).norm() == 0) {
        Fail(ctx, camera.Get("position"), "output.camera.position",
             "a camera position different from its target");
      }
    }
  }
  return scene;
}

Scene MakeDropScene(const DropOptions& options) {
  const auto check = [](const char* option, double value, bool ok, const char* expected) {
    if (!std::isfinite(value) || !ok) {
      throw InputError(fmt::format("{} = {}: expected {}", option, value, expected));
    }
  };
  check("--height", options.height, options.height >= 0, "a height >= 0 m");
  check("--tilt", options.tilt_deg, true, "a finite angle in degrees");
  check("--spin", options.spin, true, "a finite angular velocity in rad/s");
  check("--duration", options.duration, options.duration > 0, "a duration > 0 s");
  check("--dt", options.h, options.h > 0 && options.h <= options.duration,
        "a time step > 0 s and <= the duration");
  check("--scale", options.scale, options.scale > 0, "a scale > 0");
  check("--mass", options.mass, true, "a mass > 0 kg (or 0 for density 1000 kg/m³)");
  std::error_code error;
  if (!fs::is_regular_file(options.mesh, error)) {
    throw InputError(
        fmt::format("mesh {}: no such file; expected an existing mesh file", options.mesh));
  }

  Scene scene;
  scene.source = options.mesh;
  scene.h = options.h;
  scene.duration = options.duration;

  Body body;
  body.name = fs::path(options.mesh).stem().string();
  if (body.name.empty() || body.name.find_first_not_of(kNameCharacters) != std::string::npos) {
    body.name = "body";
  }
  const TriangleMesh mesh = geometry::LoadMesh(options.mesh, options.scale);
  const geometry::MassProperties props =
      options.mass > 0 ? geometry::ComputeMassPropertiesForMass(mesh, options.mass, options.mesh)
                       : geometry::ComputeMassProperties(mesh, kDefaultDensity, options.mesh);
  body.mass = props.mass;
  body.inertia = props.inertia;
  body.mesh = mesh;
  for (Eigen::Vector3d& v : body.mesh.vertices) v -= props.center_of_mass;
  body.hull = std::make_shared<geometry::PolyhedralShape>(geometry::TranslateHull(
      geometry::ComputeConvexHull(mesh.vertices, options.mesh), -props.center_of_mass));

  // tilted about x, lowest hull point `height` above the ground, spinning about z
  body.q0 = Eigen::Quaterniond(
      Eigen::AngleAxisd(options.tilt_deg * M_PI / 180, Eigen::Vector3d::UnitX()));
  const Eigen::Matrix3d R = body.q0.toRotationMatrix();
  const Eigen::Vector3d lowest_B = body.hull->Support(R.transpose() * -Eigen::Vector3d::UnitZ());
  body.p0 = Eigen::Vector3d(0, 0, options.height - (R * lowest_B).z());
  body.w0 = Eigen::Vector3d(0, 0, options.spin);
  scene.bodies.push_back(body);

  Obstacle ground;
  ground.name = "ground";
  ground.shape = geometry::MakeHalfSpace(Eigen::Vector3d::UnitZ(), 0);
  ground.friction = Friction{0.22, 1, 1, 0.1};
  scene.obstacles.push_back(ground);
  scene.contacts.push_back(ContactPair{0, 0, ground.friction});
  return scene;
}

}  // namespace ecpsim::engine
