#include "render/scene_frame.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "common/errors.h"

namespace ecpsim::render {
namespace {

// the overlay's model line: the one body's model, or each model with how many bodies it solved
// ("hull 7, free 2"), kinematic bodies left out
std::string ModelLine(const std::vector<engine::StepModel>& models) {
  if (models.size() == 1) return engine::StepModelName(models[0]);
  std::string line;
  for (int m = 0; m < engine::kNumStepModels; ++m) {
    const auto model = static_cast<engine::StepModel>(m);
    if (model == engine::StepModel::kKinematic) continue;
    const long count = std::count(models.begin(), models.end(), model);
    if (count > 0)
      line += fmt::format("{}{} {}", line.empty() ? "" : ", ", engine::StepModelName(model), count);
  }
  return line;
}

// body colours, cycled: warm wood, steel blue, grey, plum, sage
const Eigen::Vector3f kBodyColours[] = {{0.80f, 0.62f, 0.42f},
                                        {0.55f, 0.70f, 0.85f},
                                        {0.62f, 0.62f, 0.66f},
                                        {0.70f, 0.55f, 0.75f},
                                        {0.60f, 0.75f, 0.55f}};
const Eigen::Vector3f kObstacleColour(0.70f, 0.70f, 0.72f);
// kinematic bodies (fingers, pushers: prescribed motion) in one signal orange, none of the above
const Eigen::Vector3f kKinematicColour(0.95f, 0.45f, 0.10f);
// the heaviest body's weight is drawn as an arrow this many of its bounding radii long
constexpr double kWeightArrowRadii = 1.0;
// standard gravity, for the arrow scale of a scene without gravity
constexpr double kStandardGravity = 9.80665;  // m/s²
// tessellation of smooth obstacles and hulls
constexpr int kSegments = 48;

std::optional<geometry::Plane> AsPlane(const geometry::ConvexShape& shape) {
  if (!shape.IsHalfSpace()) return std::nullopt;
  // f(y) = n · y − d with |n| = 1: the gradient is n and f(0) = −d
  geometry::Plane plane;
  plane.normal = shape.Gradient(0, Eigen::Vector3d::Zero()).normalized();
  plane.offset = -shape.Value(0, Eigen::Vector3d::Zero());
  return plane;
}

}  // namespace

SceneFrameBuilder::SceneFrameBuilder(const engine::Scene& scene) : scene_(scene) {
  double max_weight = 0, radius_of_heaviest = 0;
  const double g = scene.gravity.norm() > 0 ? scene.gravity.norm() : kStandardGravity;
  for (const engine::Body& body : scene.bodies) {
    meshes_.push_back(std::make_shared<const geometry::TriangleMesh>(body.mesh));
    hulls_.push_back(
        body.hull ? std::make_shared<const HullGeometry>(MakeHullGeometry(*body.hull, kSegments))
                  : nullptr);
    double radius = 0;
    for (const auto& v : body.mesh.vertices) radius = std::max(radius, v.norm());
    // a kinematic body's mass is nominal: the force scale follows the pushed bodies' weights
    if (!body.IsKinematic() && body.mass * g > max_weight) {
      max_weight = body.mass * g;
      radius_of_heaviest = radius;
    }
  }
  if (max_weight > 0) force_scale_ = kWeightArrowRadii * radius_of_heaviest / max_weight;
  for (const engine::Obstacle& obstacle : scene.obstacles) {
    planes_.push_back(obstacle.shape ? AsPlane(*obstacle.shape) : std::nullopt);
    obstacle_meshes_.push_back(
        obstacle.shape && !planes_.back()
            ? std::make_shared<const geometry::TriangleMesh>(obstacle.shape->Tessellate(kSegments))
            : nullptr);
  }
}

double SceneFrameBuilder::PatchTolerance(int body, const Eigen::Isometry3d& X_WB,
                                         const geometry::Plane& plane) const {
  // a declared hull primitive (the dumbbell's cylinder) touches the plane where the tessellated
  // mesh stays up to its sagitta above it: the features within that gap of the mesh's lowest
  // point carry the contact. For the polyhedral hull of the mesh the gap is 0 (its vertices are
  // mesh vertices) and the tolerance is the plain one.
  const double tolerance = geometry::ContactPatchTolerance(*meshes_[body]);
  const geometry::ConvexShape* hull = scene_.bodies[body].hull.get();
  if (hull == nullptr) return tolerance;
  const Eigen::Matrix3d& R = X_WB.linear();
  const Eigen::Vector3d support = X_WB * hull->Support(R.transpose() * -plane.normal);
  double mesh_lowest = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& v : meshes_[body]->vertices)
    mesh_lowest = std::min(mesh_lowest, plane.normal.dot(X_WB * v));
  const double gap = std::max(0.0, mesh_lowest - plane.normal.dot(support));
  return tolerance + gap;
}

FrameInput SceneFrameBuilder::Build(const engine::State& state, int iterations,
                                    const std::vector<engine::StepModel>& models) const {
  if (state.bodies.size() != scene_.bodies.size() ||
      state.contacts.size() != scene_.contacts.size()) {
    throw InputError(fmt::format("{}: state with {} bodies and {} contacts: expected {} and {}",
                                 scene_.source, state.bodies.size(), state.contacts.size(),
                                 scene_.bodies.size(), scene_.contacts.size()));
  }
  FrameInput frame;
  frame.title = scene_.source;
  frame.time = state.t;
  frame.iterations = iterations;
  frame.model = ModelLine(models);
  frame.force_scale = force_scale_;

  for (size_t i = 0; i < scene_.bodies.size(); ++i) {
    const engine::BodyState& b = state.bodies[i];
    if (!b.p_WB.allFinite() || !b.Q_WB.coeffs().allFinite()) {
      throw InputError(fmt::format("{}: t = {}: body '{}' has a non-finite pose", scene_.source,
                                   state.t, scene_.bodies[i].name));
    }
    BodyVisual body;
    body.mesh = meshes_[i];
    body.hull = hulls_[i];
    body.X_WB = Eigen::Isometry3d::Identity();
    body.X_WB.linear() = b.Q_WB.normalized().toRotationMatrix();
    body.X_WB.translation() = b.p_WB;
    // the gripper's jaws are what the robot drives, like a kinematic body
    body.colour = scene_.bodies[i].IsKinematic() || scene_.bodies[i].IsJaw()
                      ? kKinematicColour
                      : kBodyColours[i % (sizeof(kBodyColours) / sizeof(kBodyColours[0]))];
    frame.bodies.push_back(body);
  }
  for (size_t j = 0; j < scene_.obstacles.size(); ++j) {
    if (planes_[j]) {
      frame.planes.push_back(PlaneVisual{*planes_[j]});
    } else if (obstacle_meshes_[j]) {
      BodyVisual obstacle;
      obstacle.mesh = obstacle_meshes_[j];
      obstacle.colour = kObstacleColour;
      obstacle.fixed = true;
      frame.bodies.push_back(obstacle);
    }
  }

  for (size_t k = 0; k < scene_.contacts.size(); ++k) {
    const engine::ContactPair& pair = scene_.contacts[k];
    // the scene loader checked the indices
    ECPSIM_DEMAND(pair.body >= 0 && pair.body < static_cast<int>(scene_.bodies.size()));
    ECPSIM_DEMAND(pair.WithBody() || (pair.obstacle >= 0 &&
                                      pair.obstacle < static_cast<int>(scene_.obstacles.size())));
    const engine::ContactState& c = state.contacts[k];
    const Eigen::Isometry3d& X_WB = frame.bodies[pair.body].X_WB;
    ContactVisual contact;
    const std::optional<geometry::Plane> plane =
        pair.WithBody() ? std::nullopt : planes_[pair.obstacle];
    if (plane) {
      contact.plane = *plane;
      contact.patch = geometry::ExtractContactPatch(*meshes_[pair.body], X_WB, *plane,
                                                    PatchTolerance(pair.body, X_WB, *plane));
    } else {
      // between two bodies: the contact plane through a2 (G's tangent plane, n out of G), and
      // the features of F on it that lie where G's features on it reach
      contact.plane.normal = c.n.normalized();
      contact.plane.offset = contact.plane.normal.dot(c.a2);
      if (c.p_n > 0) {
        const Eigen::Isometry3d& X_WG = frame.bodies[pair.other_body].X_WB;
        const geometry::Plane below{-contact.plane.normal, -contact.plane.offset};
        const double tolerance = std::max(PatchTolerance(pair.body, X_WB, contact.plane),
                                          PatchTolerance(pair.other_body, X_WG, below));
        contact.patch = geometry::IntersectContactPatches(
            geometry::ExtractContactPatch(*meshes_[pair.body], X_WB, contact.plane, tolerance),
            geometry::ExtractContactPatch(*meshes_[pair.other_body], X_WG, below, tolerance),
            contact.plane, tolerance);
      }
    }
    const Eigen::Vector3d p = X_WB.translation();
    contact.cm_projection =
        p - (contact.plane.normal.dot(p) - contact.plane.offset) * contact.plane.normal;
    if (c.p_n > 0 || contact.patch.mode != geometry::ContactMode::kNone) {
      contact.a1 = c.a1;
      contact.force = (c.p_n * c.n + c.p_t * c.t + c.p_o * c.o) / scene_.h;
    }
    frame.contacts.push_back(contact);
  }
  return frame;
}

}  // namespace ecpsim::render
