#include "engine/scene_io/drop_scene.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>

#include "common/errors.h"
#include "engine/scene_io/mesh_scale.h"
#include "engine/scene_io/scene_validation.h"
#include "engine/scene_limits.h"
#include "geometry/convex_hull.h"
#include "geometry/convex_shape.h"
#include "geometry/mass_properties.h"

namespace ecpsim::engine {
namespace {

namespace fs = std::filesystem;

constexpr double kDefaultDensity = 1000;  // kg/m³, water: `ecpsim drop` without --mass

[[noreturn]] void Fail(const char* option, double value, const std::string& expected) {
  throw InputError(fmt::format("{} = {}: expected {}", option, value, expected));
}

// `value` > 0 and within `range`, else an error naming `option`
void CheckPositive(const char* option, double value, const PositiveRange& range,
                   const char* expected) {
  if (!(value > 0)) Fail(option, value, expected);
  const std::string in_range = OutOfRange(value, range);
  if (!in_range.empty()) Fail(option, value, in_range);
}

// finite and within ±kMaxMagnitude, else an error naming `option`
void CheckBounded(const char* option, double value, const char* expected) {
  if (!OutOfMagnitude(value).empty()) Fail(option, value, expected);
}

void CheckOptions(const DropOptions& options) {
  CheckBounded("--height", options.height, "a finite height >= 0 m");
  if (!(options.height >= 0)) Fail("--height", options.height, "a height >= 0 m");
  CheckBounded("--tilt", options.tilt_deg, "a finite angle in degrees");
  CheckBounded("--spin", options.spin, "a finite angular velocity in rad/s");
  CheckPositive("--duration", options.duration, kTimeRange, "a duration > 0 s");
  CheckPositive("--dt", options.h, kTimeRange, "a time step > 0 s");
  if (options.h > options.duration) {
    Fail("--dt", options.h, fmt::format("a time step <= the duration {} s", options.duration));
  }
  const std::string steps = StepCountProblem(options.duration, options.h);
  if (!steps.empty()) Fail("--dt", options.h, steps);
  if (options.mass) CheckPositive("--mass", *options.mass, kMassRange, "a mass > 0 kg");
}

}  // namespace

LoadedScene MakeDropScene(const DropOptions& options) {
  CheckOptions(options);
  std::error_code error;
  if (!fs::is_regular_file(options.mesh, error)) {
    throw InputError(
        fmt::format("mesh {}: no such file; expected an existing mesh file", options.mesh));
  }

  LoadedScene loaded;
  Scene& scene = loaded.scene;
  scene.source = options.mesh;
  scene.h = options.h;
  scene.duration = options.duration;

  Body body;
  body.name = fs::path(options.mesh).stem().string();
  if (!IsValidName(body.name)) body.name = "body";
  const ScaledMesh scaled =
      LoadScaledMesh(options.mesh, options.scale, options.units, {"--scale", "--units"});
  if (!scaled.warning.empty()) loaded.warnings.push_back(scaled.warning);
  const geometry::TriangleMesh& mesh = scaled.mesh;

  const geometry::MassProperties props =
      options.mass ? geometry::ComputeMassPropertiesForMass(mesh, *options.mass, options.mesh)
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
  try {
    ValidateScene(scene);
  } catch (const SceneError& e) {
    throw InputError(fmt::format("ecpsim drop {}: {}", options.mesh, e.what()));
  }
  IndexContacts(scene);
  return loaded;
}

}  // namespace ecpsim::engine
