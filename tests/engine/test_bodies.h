#pragma once
// Small scenes built in code for the engine tests: boxes and meshes on a ground plane.

#include <memory>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "engine/scene.h"
#include "engine/scene_io/scene_builders.h"
#include "engine/state.h"
#include "geometry/convex_hull.h"
#include "geometry/convex_shape.h"
#include "geometry/mass_properties.h"
#include "geometry/paper_bodies.h"
#include "geometry/triangle_mesh.h"

namespace ecpsim::engine::testing {

/// The paper's friction: μ = 0.22, e_t = e_o = 1, e_r = 0.1 m.
inline Friction PaperFriction() { return Friction{0.22, 1, 1, 0.1}; }

using engine::MakeBoxBody;
using engine::MakeMeshBody;

/// A scene with the ground z ≤ 0 and the given bodies, each in contact with the ground.
inline Scene MakeGroundScene(std::vector<Body> bodies, double h = 0.01,
                             Friction friction = PaperFriction()) {
  Scene scene = engine::MakeGroundScene(std::move(bodies), h, friction);
  scene.source = "test";
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

/// A UV sphere of `radius` (m) centred at the origin: `segments` meridians and `rings` bands, two
/// poles where `segments` thin triangles meet, quads in between; coordinates rounded to nine
/// decimals as in a mesh file (the quads are planar up to that rounding: they merge into one hull
/// face each, whose plane can differ from its corners by up to the merge tolerance).
inline geometry::TriangleMesh MakeUvSphereMesh(int segments, int rings, double radius) {
  geometry::TriangleMesh mesh;
  mesh.vertices.emplace_back(0, 0, radius);
  for (int j = 1; j < rings; ++j) {
    const double theta = M_PI * j / rings;
    for (int i = 0; i < segments; ++i) {
      const double phi = 2 * M_PI * i / segments;
      // nine decimals, as a mesh file stores it
      const auto rounded = [](double x) { return std::round(x * 1e9) / 1e9; };
      mesh.vertices.emplace_back(rounded(radius * std::sin(theta) * std::cos(phi)),
                                 rounded(radius * std::sin(theta) * std::sin(phi)),
                                 rounded(radius * std::cos(theta)));
    }
  }
  mesh.vertices.emplace_back(0, 0, -radius);
  const int south = static_cast<int>(mesh.vertices.size()) - 1;
  const auto at = [segments](int ring, int i) { return 1 + (ring - 1) * segments + i % segments; };
  for (int i = 0; i < segments; ++i) {
    mesh.triangles.emplace_back(0, at(1, i), at(1, i + 1));
    for (int j = 1; j + 1 < rings; ++j) {
      mesh.triangles.emplace_back(at(j, i), at(j + 1, i), at(j + 1, i + 1));
      mesh.triangles.emplace_back(at(j, i), at(j + 1, i + 1), at(j, i + 1));
    }
    mesh.triangles.emplace_back(south, at(rings - 1, i + 1), at(rings - 1, i));
  }
  return mesh;
}

/// Signed distance of the lowest mesh vertex above the plane z = 0 (negative: penetration).
inline double LowestVertexHeight(const Body& body, const BodyState& state) {
  const Eigen::Matrix3d R = state.Q_WB.toRotationMatrix();
  double lowest = INFINITY;
  for (const auto& v : body.mesh.vertices) lowest = std::min(lowest, (state.p_WB + R * v).z());
  return lowest;
}

}  // namespace ecpsim::engine::testing
