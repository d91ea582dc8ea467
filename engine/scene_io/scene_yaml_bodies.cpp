// The bodies of the scene format: mesh or primitive, mass properties, hull, parts, initial state.

#include <cmath>
#include <optional>

#include "engine/scene_io/mesh_scale.h"
#include "engine/scene_io/parts_cache.h"
#include "engine/scene_io/scene_yaml_reader.h"
#include "geometry/convex_decomposition.h"
#include "geometry/convex_hull.h"
#include "geometry/convex_shape.h"
#include "geometry/hull_lids.h"
#include "geometry/mass_properties.h"

namespace ecpsim::engine::yaml {
namespace {

namespace fs = std::filesystem;
using geometry::ConvexShape;
using geometry::TriangleMesh;

// mesh vertices may poke out of a declared hull primitive by this fraction of the mesh's
// bounding-box diagonal: tessellation round-off, far below any modelled feature
constexpr double kHullContainmentTolerance = 1e-6;  // × bounding-box diagonal

// `units` and/or `scale` of a body with a mesh: mesh units → m
double ReadMeshScale(const Context& ctx, const MapNode& map) {
  std::optional<double> scale;
  if (map.Has("scale")) {
    scale = ReadPositive(ctx, map.Get("scale"), map.Key("scale"), kMeshScaleRange,
                         "a scale > 0 (mesh units to m)");
  }
  if (!map.Has("units")) return scale.value_or(1.0);
  const std::string units = ReadString(ctx, map.Get("units"), map.Key("units"), "a unit");
  const std::optional<double> metres = MetresPerUnit(units);
  if (!metres) map.FailAt("units", fmt::format("one of {}", KnownUnits()));
  if (scale && !ScalesAgree(*scale, *metres)) {
    map.FailAt("units", fmt::format("a unit agreeing with {} = {} ({} is {} m); give one of them",
                                    map.Key("scale"), *scale, units, *metres));
  }
  return *metres;
}

// the mesh file of `mesh`, scaled to m by the body's `scale` or `units`
MeshFile ReadMesh(const Context& ctx, const MapNode& map, std::vector<std::string>& warnings) {
  return LoadMeshFile(ctx, map.Get("mesh"), map.Key("mesh"), ReadMeshScale(ctx, map),
                      {map.Key("scale"), map.Key("units")}, warnings);
}

// 3 (diagonal) or 9 (row-major) numbers; symmetric, positive definite etc.: ValidateScene
Eigen::Matrix3d ReadInertia(const Context& ctx, const YAML::Node& node, const std::string& key) {
  const std::string expected =
      "3 (diagonal) or 9 (row-major) values in kg·m² about the CM in body axes";
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
  return inertia;
}

// relative: a mesh whose volume is within this of its hull's is convex (its hull exact): the
// hull merges coplanar triangles within 1e-6 of the diagonal (kCoplanarTolerance), which moves
// its volume by up to about that, relative
constexpr double kConvexVolumeRel = 1e-5;
// the most parts `decomposition: auto` gives a body: a pair of bodies of n and m parts is n × m
// contacts, each tested by the broad phase every step
constexpr std::size_t kMaxDecomposedParts = 64;

// `decomposition_tolerance` unless given: exact parts only. A tolerance lets a part reach out of
// the body by up to that much, which moves where it touches: a modelling choice the scene makes
// (a curved mesh's exact pieces exceed kMaxDecomposedParts, and the error says to raise it), and
// with 0 the shipped polyhedral meshes keep their exact parts (a mug's 12; any tolerance lets
// pieces merge whose hull covers a third piece, giving 8)
constexpr double kDefaultDecompositionTolerance = 0;  // × the mesh's bounding-box diagonal

// `decomposition: auto`: the convex parts of the body's mesh (body frame) within `tolerance` ×
// its diagonal, cached beside its file `mesh_file`, or none where the mesh is convex, whose hull
// is exact
std::vector<std::shared_ptr<const ConvexShape>> DecomposedParts(
    const Body& body, const std::string& mesh_file, double mesh_volume, double tolerance,
    std::vector<std::string>& warnings) {
  if (!(mesh_volume > 0)) return {};
  // the body's hull is its mesh's unless a primitive was declared for it
  const auto* polyhedron = body.hull->AsPolyhedron();
  const double hull_volume = geometry::HullVolume(
      polyhedron ? polyhedron->hull() : geometry::ComputeConvexHull(body.mesh.vertices, mesh_file));
  if (mesh_volume >= (1 - kConvexVolumeRel) * hull_volume) return {};
  std::vector<std::shared_ptr<const ConvexShape>> parts;
  for (geometry::ConvexHull& part : CachedDecomposition(
           mesh_file, body.mesh, tolerance,
           [&] {
             return geometry::DecomposeSolid(body.mesh, mesh_file, kMaxDecomposedParts, tolerance);
           },
           warnings))
    parts.push_back(std::make_shared<geometry::PolyhedralShape>(std::move(part)));
  return parts;
}

// an explicit hull primitive, centred at the CM, must contain the mesh
std::shared_ptr<const ConvexShape> ReadDeclaredHull(const Context& ctx, const MapNode& map,
                                                    const TriangleMesh& mesh) {
  const Primitive hull = ReadPrimitive(ctx, map.Get("hull"), map.Key("hull"));
  const double tolerance = kHullContainmentTolerance * MeshAcross(mesh);
  for (const Eigen::Vector3d& v : mesh.vertices) {
    for (int i = 0; i < hull.shape->NumConstraints(); ++i) {
      const double outside = hull.shape->Value(i, v);
      if (outside > tolerance) {
        map.FailAt("hull",
                   fmt::format("a convex primitive centred at the CM that contains the mesh; mesh "
                               "vertex ({:.6g}, {:.6g}, {:.6g}) m (CM frame) lies {:.3g} m outside",
                               v.x(), v.y(), v.z(), outside));
      }
    }
  }
  return hull.shape;
}

// `position`, or `on_ground` / `lowest_point_height` with an optional [x, y]: where the CM starts
Eigen::Vector3d ReadPosition(const Context& ctx, const MapNode& map, const Body& body) {
  const bool on_ground =
      map.Has("on_ground") && ReadBool(ctx, map.Get("on_ground"), map.Key("on_ground"));
  if (map.Has("on_ground") && !on_ground) {
    map.FailAt("on_ground", "true (or leave it out and give `position` [x, y, z])");
  }
  if (on_ground && map.Has("lowest_point_height")) {
    map.FailAt("lowest_point_height", "either `on_ground` or `lowest_point_height`, not both");
  }
  if (!on_ground && !map.Has("lowest_point_height")) {
    return ReadVector3(ctx, map.Require("position", "[x, y, z] (m), the CM's initial position"),
                       map.Key("position"), "m, the CM's initial position");
  }
  const double height =
      on_ground ? 0.0
                : ReadNumber(ctx, map.Get("lowest_point_height"), map.Key("lowest_point_height"),
                             "a finite height (m) of the hull's lowest point");
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();
  if (map.Has("position")) {
    xy = ReadNumbers(ctx, map.Get("position"), map.Key("position"), 2,
                     "[x, y] (m): the height comes from on_ground / lowest_point_height");
  }
  // the lowest point of the hull (what touches the ground) at the initial orientation
  const Eigen::Matrix3d R = body.q0.toRotationMatrix();
  const Eigen::Vector3d lowest_B = body.hull->Support(R.transpose() * -Eigen::Vector3d::UnitZ());
  return Eigen::Vector3d(xy.x(), xy.y(), height - (R * lowest_B).z());
}

}  // namespace

MeshFile LoadMeshFile(const Context& ctx, const YAML::Node& node, const std::string& key,
                      double scale, const MeshScaleKeys& scale_keys,
                      std::vector<std::string>& warnings) {
  const std::string file =
      ReadString(ctx, node, key, "a mesh file path (relative to the scene file)");
  const fs::path path = (ctx.folder / file).lexically_normal();
  std::error_code error;
  if (!fs::is_regular_file(path, error)) {
    Fail(ctx, node, key, fmt::format("an existing mesh file (looked for {})", path.string()));
  }
  ScaledMesh scaled = WithLocation(ctx, node, key, [&] {
    return LoadScaledMesh(path.string(), scale, std::nullopt, scale_keys);
  });
  if (!scaled.warning.empty()) {
    warnings.push_back(fmt::format("{}: {}: {}", Where(ctx, node, key), key, scaled.warning));
  }
  return {path.string(), std::move(scaled.mesh)};
}

// kg/m³: a kinematic body's mass properties are unused (it is never pushed); its body frame is
// the centroid of its volume, as a dynamic body's is its centre of mass at uniform density
constexpr double kKinematicDensity = 1000;

Body ReadBody(const Context& ctx, const YAML::Node& node, const std::string& key,
              const std::string& default_name, BodyExtras& extras,
              std::vector<std::string>& warnings) {
  const MapNode map(ctx, node, key,
                    {"name",
                     "mesh",
                     "scale",
                     "units",
                     "shape",
                     "hull",
                     "mass",
                     "density",
                     "inertia",
                     "position",
                     "quaternion",
                     "rpy",
                     "lowest_point_height",
                     "on_ground",
                     "allow_initial_penetration",
                     "velocity",
                     "angular_velocity",
                     "friction",
                     "parts",
                     "decomposition",
                     "decomposition_tolerance",
                     "kinematic",
                     "motion"});
  Body body;
  body.name = map.Has("name") ? ReadName(ctx, map.Get("name"), map.Key("name")) : default_name;

  // a kinematic body: its motion instead of mass and initial state (docs/scene_format.md)
  const bool kinematic =
      map.Has("kinematic") && ReadBool(ctx, map.Get("kinematic"), map.Key("kinematic"));
  if (kinematic) {
    for (const char* k :
         {"mass", "density", "inertia", "position", "quaternion", "rpy", "lowest_point_height",
          "on_ground", "allow_initial_penetration", "velocity", "angular_velocity"}) {
      if (map.Has(k)) {
        map.FailAt(k, fmt::format("no `{}` on a kinematic body (its `motion` gives its pose)", k));
      }
    }
    body.motion = std::make_shared<KinematicMotion>(
        ReadMotion(ctx, map.Require("motion", "a motion: {expressions | waypoints | velocity}"),
                   map.Key("motion")));
  } else if (map.Has("motion")) {
    map.FailAt("motion", "`motion` only on a body with `kinematic: true`");
  }

  // mass: `mass`, `density`, or `mass` + `inertia`
  if (map.Has("mass") && map.Has("density")) {
    map.FailAt("density", "either `mass` or `density`, not both");
  }
  if (!map.Has("mass") && !map.Has("density") && !kinematic) {
    map.FailAt("mass", "a mass > 0 kg (or a `density` in kg/m³)");
  }
  if (map.Has("inertia") && !map.Has("mass")) {
    map.FailAt("inertia", "`inertia` together with `mass`");
  }
  std::optional<double> mass, density;
  if (kinematic) {
    density = kKinematicDensity;
  } else if (map.Has("mass")) {
    mass = ReadPositive(ctx, map.Get("mass"), map.Key("mass"), kMassRange, "a finite mass > 0 kg");
  } else {
    density = ReadPositive(ctx, map.Get("density"), map.Key("density"), kDensityRange,
                           "a finite density > 0 kg/m³");
  }

  // geometry: a mesh file or a primitive; the body frame is the CM with the mesh's axes
  if (map.Has("mesh") == map.Has("shape")) {
    map.FailAt("mesh",
               "exactly one of `mesh: FILE` or `shape: {box|sphere|cylinder|ellipsoid: ...}`");
  }
  for (const char* k : {"scale", "units"}) {
    if (map.Has(k) && !map.Has("mesh")) {
      map.FailAt(k, fmt::format("`{}` only together with `mesh`", k));
    }
  }
  Eigen::Matrix3d inertia;
  double mesh_volume = 0;  // m³; 0: a primitive, which is convex
  std::string mesh_file;
  if (map.Has("mesh")) {
    const YAML::Node mesh_node = map.Get("mesh");
    const MeshFile file = ReadMesh(ctx, map, warnings);
    const TriangleMesh& mesh = file.mesh;
    const std::string& source = file.path;
    const geometry::MassProperties props = WithLocation(ctx, mesh_node, map.Key("mesh"), [&] {
      return mass ? geometry::ComputeMassPropertiesForMass(mesh, *mass, source)
                  : geometry::ComputeMassProperties(mesh, *density, source);
    });
    body.mass = props.mass;
    inertia = props.inertia;
    mesh_volume = props.volume;
    mesh_file = source;
    extras.center_of_mass = props.center_of_mass;
    body.mesh = mesh;
    for (Eigen::Vector3d& v : body.mesh.vertices) v -= props.center_of_mass;
    if (!map.Has("hull")) {
      const geometry::ConvexHull hull = WithLocation(ctx, mesh_node, map.Key("mesh"), [&] {
        return geometry::ComputeConvexHull(mesh.vertices, source);
      });
      body.hull = std::make_shared<geometry::PolyhedralShape>(
          geometry::TranslateHull(hull, -props.center_of_mass));
    }
  } else {
    const Primitive primitive = ReadPrimitive(ctx, map.Get("shape"), map.Key("shape"));
    // a mass or inertia that overflows is ValidateScene's to report
    body.mass = mass ? *mass : *density * primitive.volume;
    inertia = body.mass * primitive.unit_inertia;
    body.mesh = primitive.shape->Tessellate();
    body.hull = primitive.shape;
  }
  body.inertia =
      map.Has("inertia") ? ReadInertia(ctx, map.Get("inertia"), map.Key("inertia")) : inertia;
  if (map.Has("hull")) body.hull = ReadDeclaredHull(ctx, map, body.mesh);
  // a body whose parts are listed has said what its shape is: its hull would fill its cavities
  DecompositionMode mode = map.Has("parts") ? DecompositionMode::kParts : DecompositionMode::kNone;
  if (map.Has("decomposition")) {
    mode = ReadDecomposition(ctx, map.Get("decomposition"), map.Key("decomposition"));
    if (mode == DecompositionMode::kParts && !map.Has("parts")) {
      map.FailAt("decomposition", "`decomposition: parts` on a body with `parts` to touch with");
    }
  }
  double tolerance = kDefaultDecompositionTolerance;
  // (read whatever the decomposition, used by `auto`: `--set bodies.0.decomposition=none` then
  // needs no other change)
  if (map.Has("decomposition_tolerance")) {
    if (!map.Has("mesh")) {
      map.FailAt("decomposition_tolerance",
                 "`decomposition_tolerance` only on a body with a `mesh` (which `decomposition: "
                 "auto` decomposes)");
    }
    const std::string expected =
        "a tolerance >= 0 and < 1 (a fraction of the mesh's bounding-box diagonal; 0: exact "
        "parts)";
    tolerance = ReadNumber(ctx, map.Get("decomposition_tolerance"),
                           map.Key("decomposition_tolerance"), expected);
    if (!(tolerance >= 0 && tolerance < 1)) map.FailAt("decomposition_tolerance", expected);
    // listed parts are the body's: nothing is decomposed
    if (map.Has("parts")) {
      warnings.push_back(fmt::format(
          "{}: {}: unused, the body lists its `parts` (only `decomposition: auto` without `parts` "
          "decomposes the mesh)",
          Where(ctx, map.Get("decomposition_tolerance"), map.Key("decomposition_tolerance")),
          map.Key("decomposition_tolerance")));
    }
  }
  body.decomposition = mode == DecompositionMode::kNone    ? Decomposition::kNone
                       : mode == DecompositionMode::kParts ? Decomposition::kParts
                                                           : Decomposition::kAuto;
  // (only a body with parts or a decomposition reads them)
  const auto part_frame = [&] {
    return PartFrame{extras.center_of_mass,
                     body.hull.get(),
                     kHullContainmentTolerance * MeshAcross(body.mesh),
                     map.Has("mesh") ? ReadMeshScale(ctx, map) : 1.0,
                     {map.Key("scale"), map.Key("units")},
                     body.decomposition != Decomposition::kNone};
  };
  if (map.Has("parts")) {
    body.parts = ReadParts(ctx, map.Get("parts"), map.Key("parts"), part_frame(), warnings);
  }
  if (mode == DecompositionMode::kAuto && !map.Has("parts")) {
    body.parts = WithLocation(ctx, map.Get("decomposition"), map.Key("decomposition"), [&] {
      return DecomposedParts(body, mesh_file, mesh_volume, tolerance, warnings);
    });
    WarnOfSeams(body.parts, map.Key("decomposition"), part_frame(), warnings);
  }
  // under auto, the hull's faces the parts leave open; with none the hull is the body's surface
  // and always exact
  if (body.decomposition == Decomposition::kAuto && !body.parts.empty())
    body.lids = geometry::LidSlabs(body.hull, body.parts);
  if (body.decomposition == Decomposition::kAuto && body.lids.empty())
    body.decomposition = Decomposition::kNone;

  // initial state: `position` is where the CM starts; a kinematic body's motion at t = 0
  if (kinematic) {
    const KinematicPose start = WithLocation(ctx, map.Get("motion"), map.Key("motion"),
                                             [&] { return body.motion->PoseAt(0); });
    body.p0 = start.p;
    body.q0 = start.q;
  } else {
    body.q0 = ReadOrientation(ctx, map);
    body.p0 = ReadPosition(ctx, map, body);
  }
  if (map.Has("allow_initial_penetration")) {
    body.allow_initial_penetration =
        ReadBool(ctx, map.Get("allow_initial_penetration"), map.Key("allow_initial_penetration"));
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

int BodyNamed(const Context& ctx, const YAML::Node& node, const std::string& key,
              const Scene& scene) {
  std::string names;
  for (size_t i = 0; i < scene.bodies.size(); ++i) {
    if (node.IsScalar() && node.Scalar() == scene.bodies[i].name) return static_cast<int>(i);
    names += (names.empty() ? "" : ", ") + scene.bodies[i].name;
  }
  Fail(ctx, node, key, fmt::format("the name of a body of the scene ({})", names));
}

}  // namespace ecpsim::engine::yaml
