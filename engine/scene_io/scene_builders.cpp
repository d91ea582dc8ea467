#include "engine/scene_io/scene_builders.h"

#include <algorithm>

#include <memory>

#include "engine/scene_io/scene_validation.h"
#include "geometry/convex_hull.h"
#include "geometry/convex_shape.h"
#include "geometry/mass_properties.h"

namespace ecpsim::engine {

Body MakeBoxBody(const Eigen::Vector3d& size, double mass, const std::string& name) {
  Body body;
  body.name = name;
  auto hull = geometry::MakeBox(size / 2);
  body.hull = hull;
  body.mesh = hull->Tessellate();
  body.mass = mass;
  const Eigen::Vector3d s2 = size.cwiseProduct(size);
  body.inertia =
      (mass / 12 * Eigen::Vector3d(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y())).asDiagonal();
  return body;
}

Body MakeMeshBody(const geometry::TriangleMesh& mesh_any_frame, double mass,
                  const std::string& name) {
  const geometry::MassProperties mp = geometry::ComputeMassPropertiesForMass(mesh_any_frame, mass);
  Body body;
  body.name = name;
  body.mesh = mesh_any_frame;
  for (auto& v : body.mesh.vertices) v -= mp.center_of_mass;
  body.hull = std::make_shared<geometry::PolyhedralShape>(
      geometry::ComputeConvexHull(body.mesh.vertices, name));
  body.mass = mass;
  body.inertia = mp.inertia;
  return body;
}

Scene MakeGroundScene(std::vector<Body> bodies, double h, const Friction& friction,
                      const Eigen::Vector3d& up) {
  Scene scene;
  scene.source = "code";
  scene.h = h;
  Obstacle ground;
  ground.name = "ground";
  ground.shape = geometry::MakeHalfSpace(up, 0);
  ground.friction = friction;
  scene.obstacles.push_back(ground);
  for (size_t b = 0; b < bodies.size(); ++b) {
    // a kinematic body is never pushed: no contact with the ground
    if (!bodies[b].IsKinematic())
      scene.contacts.push_back(ContactPair{static_cast<int>(b), 0, friction});
  }
  scene.bodies = std::move(bodies);
  ValidateScene(scene);
  IndexContacts(scene);
  return scene;
}

void AddBodyPairs(Scene& scene) {
  const int n = static_cast<int>(scene.bodies.size());
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (scene.bodies[i].IsKinematic() && scene.bodies[j].IsKinematic()) continue;
      AddBodyContacts(scene, i, j,
                      PairFriction(scene.bodies[i].friction, scene.bodies[j].friction));
    }
  }
  IndexContacts(scene);
}

}  // namespace ecpsim::engine
