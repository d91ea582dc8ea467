#pragma once
// Small scenes built in code for the engine tests: boxes and meshes on a ground plane.

#include <memory>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "engine/scene.h"
#include "engine/state.h"
#include "geometry/convex_hull.h"
#include "geometry/convex_shape.h"
#include "geometry/mass_properties.h"
#include "geometry/paper_bodies.h"
#include "geometry/triangle_mesh.h"

namespace ecpsim::engine::testing {

/// The paper's friction: μ = 0.22, e_t = e_o = 1, e_r = 0.1 m.
inline Friction PaperFriction() { return Friction{0.22, 1, 1, 0.1}; }

/// A solid box body with closed-form inertia; its mesh is the hull's triangulation.
inline Body MakeBoxBody(const Eigen::Vector3d& size, double mass, const std::string& name = "box") {
  Body body;
  body.name = name;
  auto hull = geometry::MakeBox(size / 2);
  body.hull = hull;
  body.mesh = hull->Tessellate();
  body.mass = mass;
  const Eigen::Vector3d s2 = size.cwiseProduct(size);
  body.inertia = (mass / 12 * Eigen::Vector3d(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y()))
                     .asDiagonal();
  return body;
}

/// A body from a closed mesh (any frame): moved into its CM frame, hull from CGAL, given mass.
inline Body MakeMeshBody(const geometry::TriangleMesh& mesh_any_frame, double mass,
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

/// A scene with the ground z ≤ 0 and the given bodies, each in contact with the ground.
inline Scene MakeGroundScene(std::vector<Body> bodies, double h = 0.01,
                             Friction friction = PaperFriction()) {
  Scene scene;
  scene.source = "test";
  scene.h = h;
  Obstacle ground;
  ground.name = "ground";
  ground.shape = geometry::MakeHalfSpace(Eigen::Vector3d::UnitZ(), 0);
  ground.friction = friction;
  scene.obstacles.push_back(ground);
  for (size_t b = 0; b < bodies.size(); ++b) {
    scene.contacts.push_back(ContactPair{static_cast<int>(b), 0, friction});
  }
  scene.bodies = std::move(bodies);
  return scene;
}

/// The paper's desk (section 5): 15 kg, CM 0.45 m above its feet on z = 0, v0 = (0.3, 0.2, 0) m/s,
/// ω_z = 0.5 rad/s, pushed by f_x = 22.5 sin(2πt) + 22.5 N, f_y = 22.5 cos(2πt) + 22.5 N and
/// τ_z = 2.1 cos(2πt) N·m for 4 s, stepped with `model`.
inline Scene PaperDeskScene(ContactModel model) {
  Body desk = MakeMeshBody(geometry::MakeDeskMesh(), 15, "desk");
  desk.p0 = Eigen::Vector3d(0, 0, 0.45);
  desk.v0 = Eigen::Vector3d(0.3, 0.2, 0);
  desk.w0 = Eigen::Vector3d(0, 0, 0.5);
  Scene scene = MakeGroundScene({desk});
  Load force;
  force.x = TimeFunction("22.5*sin(2*pi*t)+22.5", "paper desk");
  force.y = TimeFunction("22.5*cos(2*pi*t)+22.5", "paper desk");
  Load torque;
  torque.kind = Load::Kind::kTorque;
  torque.z = TimeFunction("2.1*cos(2*pi*t)", "paper desk");
  scene.loads = {force, torque};
  scene.model = model;
  scene.duration = 4;
  return scene;
}

/// Signed distance of the lowest mesh vertex above the plane z = 0 (negative: penetration).
inline double LowestVertexHeight(const Body& body, const BodyState& state) {
  const Eigen::Matrix3d R = state.Q_WB.toRotationMatrix();
  double lowest = INFINITY;
  for (const auto& v : body.mesh.vertices) lowest = std::min(lowest, (state.p_WB + R * v).z());
  return lowest;
}

}  // namespace ecpsim::engine::testing
