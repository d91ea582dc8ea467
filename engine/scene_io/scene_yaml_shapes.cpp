// The geometric parts of the scene format: orientations, primitives, obstacles and friction.

#include <cmath>

#include "engine/rotation.h"
#include "engine/scene_io/scene_yaml_reader.h"
#include "geometry/convex_shape.h"
#include "geometry/posed_shape.h"

namespace ecpsim::engine::yaml {
namespace {

using geometry::ConvexShape;

// a quaternion shorter than this carries no direction to normalize (and is surely a typo)
constexpr double kMinQuaternionNorm = 1e-9;
// a plane normal shorter than this has no direction
constexpr double kMinNormalLength = 1e-12;

int ReadAxis(const Context& ctx, const YAML::Node& node, const std::string& key) {
  const std::string expected = "an axis x, y or z";
  if (!node.IsScalar()) Fail(ctx, node, key, expected);
  const std::string& s = node.Scalar();
  if (s == "x" || s == "X") return 0;
  if (s == "y" || s == "Y") return 1;
  if (s == "z" || s == "Z") return 2;
  Fail(ctx, node, key, expected);
}

double ReadLength(const Context& ctx, const MapNode& map, const std::string& k,
                  const std::string& expected) {
  return ReadPositive(ctx, map.Require(k, expected), map.Key(k), kLengthRange, expected);
}

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
  return WithLocation(ctx, map.node(), map.key(),
                      [&] { return geometry::MakeHalfSpace(normal.normalized(), offset); });
}

}  // namespace

ContactModel ReadModel(const Context& ctx, const YAML::Node& node, const std::string& key) {
  for (ContactModel model : {ContactModel::kAuto, ContactModel::kHull, ContactModel::kPlanar,
                             ContactModel::kMultiPatch, ContactModel::kPoint}) {
    if (node.IsScalar() && node.Scalar() == ContactModelName(model)) return model;
  }
  Fail(ctx, node, key, "one of auto, hull, planar, multipatch, point");
}

DecompositionMode ReadDecomposition(const Context& ctx, const YAML::Node& node,
                                    const std::string& key) {
  if (node.IsScalar()) {
    if (node.Scalar() == "none") return DecompositionMode::kNone;
    if (node.Scalar() == "parts") return DecompositionMode::kParts;
    if (node.Scalar() == "auto") return DecompositionMode::kAuto;
  }
  Fail(ctx, node, key, "one of none, parts, auto");
}

Eigen::Quaterniond ReadOrientation(const Context& ctx, const MapNode& map) {
  if (map.Has("quaternion") && map.Has("rpy")) {
    map.FailAt("rpy", "either `quaternion` or `rpy`, not both");
  }
  if (map.Has("quaternion")) {
    // entries within ±1e150 (ReadNumbers): the norm cannot overflow
    const Eigen::VectorXd q = ReadNumbers(ctx, map.Get("quaternion"), map.Key("quaternion"), 4,
                                          "a list of 4 finite numbers [w, x, y, z], not all zero");
    if (q.norm() < kMinQuaternionNorm) {
      map.FailAt("quaternion", "a non-zero quaternion [w, x, y, z] (it is normalized)");
    }
    return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
  }
  if (map.Has("rpy")) {
    return RpyToQuaternion(ReadVector3(ctx, map.Get("rpy"), map.Key("rpy"), "degrees") *
                           (M_PI / 180));
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
  if (map.Has("e_t")) {
    friction.e_t = ReadPositive(ctx, map.Get("e_t"), map.Key("e_t"), kMagnitudeRange, axis);
  }
  if (map.Has("e_o")) {
    friction.e_o = ReadPositive(ctx, map.Get("e_o"), map.Key("e_o"), kMagnitudeRange, axis);
  }
  if (map.Has("e_r")) {
    // a length, or `patch`: the contact patch's mean distance from the ECP, each step
    const YAML::Node e_r = map.Get("e_r");
    friction.e_r_patch = e_r.IsScalar() && e_r.Scalar() == "patch";
    if (!friction.e_r_patch) {
      friction.e_r = ReadPositive(ctx, e_r, map.Key("e_r"), kLengthRange,
                                  "a torsional ellipsoid semi-axis > 0 m, or `patch`");
    }
  }
  return friction;
}

Primitive ReadPrimitive(const Context& ctx, const YAML::Node& node, const std::string& key) {
  const MapNode map(ctx, node, key, {"box", "sphere", "cylinder", "ellipsoid"});
  if (map.node().size() != 1) {
    Fail(ctx, node, key, "exactly one of box, sphere, cylinder, ellipsoid");
  }
  return ReadPrimitiveIn(ctx, map);
}

Primitive ReadPrimitiveIn(const Context& ctx, const MapNode& map) {
  // lengths within kLengthRange: volume (L³) and inertia per kg (L²) stay normal doubles
  Primitive p;
  if (map.Has("box")) {
    const MapNode box(ctx, map.Get("box"), map.Key("box"), {"size"});
    const Eigen::Vector3d s =
        ReadLengths3(ctx, box.Require("size", "[x, y, z] edge lengths > 0 m"), box.Key("size"),
                     "a list of 3 edge lengths > 0 m [x, y, z]");
    p.shape = WithLocation(ctx, box.node(), box.key(), [&] { return geometry::MakeBox(s / 2); });
    p.volume = s.prod();
    const Eigen::Vector3d sq = s.cwiseProduct(s);
    p.unit_inertia.diagonal() << sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y();
    p.unit_inertia /= 12;
  } else if (map.Has("sphere")) {
    const MapNode sphere(ctx, map.Get("sphere"), map.Key("sphere"), {"radius"});
    const double r = ReadLength(ctx, sphere, "radius", "a radius > 0 m");
    p.shape =
        WithLocation(ctx, sphere.node(), sphere.key(), [&] { return geometry::MakeSphere(r); });
    p.volume = 4.0 / 3.0 * M_PI * r * r * r;
    p.unit_inertia = Eigen::Matrix3d::Identity() * (0.4 * r * r);
  } else if (map.Has("cylinder")) {
    const MapNode cyl(ctx, map.Get("cylinder"), map.Key("cylinder"), {"radius", "length", "axis"});
    const double r = ReadLength(ctx, cyl, "radius", "a radius > 0 m");
    const double l = ReadLength(ctx, cyl, "length", "a length > 0 m");
    const int axis = cyl.Has("axis") ? ReadAxis(ctx, cyl.Get("axis"), cyl.Key("axis")) : 2;
    p.shape = WithLocation(ctx, cyl.node(), cyl.key(),
                           [&] { return geometry::MakeCylinder(r, l, axis); });
    p.volume = M_PI * r * r * l;
    p.unit_inertia = Eigen::Matrix3d::Identity() * ((3 * r * r + l * l) / 12);
    p.unit_inertia(axis, axis) = r * r / 2;
  } else {
    const MapNode ell(ctx, map.Get("ellipsoid"), map.Key("ellipsoid"), {"radii"});
    const Eigen::Vector3d r =
        ReadLengths3(ctx, ell.Require("radii", "[a, b, c] semi-axes > 0 m"), ell.Key("radii"),
                     "a list of 3 semi-axes > 0 m [a, b, c]");
    p.shape = WithLocation(ctx, ell.node(), ell.key(), [&] { return geometry::MakeEllipsoid(r); });
    p.volume = 4.0 / 3.0 * M_PI * r.prod();
    const Eigen::Vector3d sq = r.cwiseProduct(r);
    p.unit_inertia.diagonal() << sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y();
    p.unit_inertia /= 5;
  }
  return p;
}

std::shared_ptr<const ConvexShape> ReadPosedBox(const Context& ctx, const MapNode& box,
                                                const MapNode& pose,
                                                const std::string& position_key,
                                                const Eigen::Vector3d& shift) {
  const Eigen::Vector3d size =
      ReadLengths3(ctx, box.Require("size", "[x, y, z] edge lengths > 0 m"), box.Key("size"),
                   "a list of 3 edge lengths > 0 m [x, y, z]");
  const Eigen::Vector3d position =
      pose.Has(position_key) ? ReadVector3(ctx, pose.Get(position_key), pose.Key(position_key), "m")
                             : Eigen::Vector3d::Zero();
  const Eigen::Quaterniond rotation = ReadOrientation(ctx, pose);
  // a box too thin for its length is flat to the hull's tolerance: an error at the box
  return WithLocation(ctx, pose.node(), pose.key(), [&] {
    return geometry::Posed(geometry::MakeBox(size / 2), rotation.toRotationMatrix(),
                           position - shift);
  });
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
    obstacle.shape = ReadPosedBox(ctx, box, box, "position", Eigen::Vector3d::Zero());
  }
  obstacle.name = map.Has("name") ? ReadName(ctx, map.Get("name"), map.Key("name")) : default_name;
  if (map.Has("friction")) {
    obstacle.friction = ReadFriction(ctx, map.Get("friction"), map.Key("friction"), Friction{});
  }
  return obstacle;
}

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

}  // namespace ecpsim::engine::yaml
