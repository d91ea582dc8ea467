#pragma once
// The canonical frames of the golden tests and the render benchmark: the paper's bodies in
// characteristic contacts with poses given directly (no engine), ECPs at chosen points.

#include <cmath>
#include <memory>

#include <Eigen/Geometry>

#include "geometry/contact_patch.h"
#include "geometry/convex_hull.h"
#include "geometry/mass_properties.h"
#include "geometry/paper_bodies.h"
#include "render/frame_input.h"

namespace ecpsim::render::testing {

/// The ground plane z = 0.
inline geometry::Plane Ground() { return geometry::Plane{Eigen::Vector3d::UnitZ(), 0.0}; }

/// A body with its CGAL hull.
inline BodyVisual MakeBody(geometry::TriangleMesh mesh, const Eigen::Isometry3d& X_WB,
                           const Eigen::Vector3f& colour = Eigen::Vector3f(0.80f, 0.62f, 0.42f)) {
  BodyVisual body;
  body.hull = std::make_shared<HullGeometry>(
      MakeHullGeometry(geometry::ComputeConvexHull(mesh.vertices, "test mesh")));
  body.mesh = std::make_shared<geometry::TriangleMesh>(std::move(mesh));
  body.X_WB = X_WB;
  body.colour = colour;
  return body;
}

/// The centroid of a patch's hull vertices (on the plane).
inline Eigen::Vector3d HullCentre(const geometry::ContactPatch& patch) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : patch.hull) sum += p;
  return patch.hull.empty() ? sum : Eigen::Vector3d(sum / static_cast<double>(patch.hull.size()));
}

/// The contact of `body` with the ground: its actual patch, the CM projection, and the ECP at
/// `a1` (the patch hull's centre if not given).
inline ContactVisual GroundContact(const BodyVisual& body,
                                   const std::optional<Eigen::Vector3d>& a1 = std::nullopt) {
  ContactVisual contact;
  contact.plane = Ground();
  contact.patch = geometry::ExtractContactPatch(*body.mesh, body.X_WB, contact.plane);
  const Eigen::Vector3d cm =
      body.X_WB * geometry::ComputeMassProperties(*body.mesh, 1000.0).center_of_mass;
  contact.cm_projection = Eigen::Vector3d(cm.x(), cm.y(), 0.0);
  contact.a1 = a1 ? *a1 : HullCentre(contact.patch);
  return contact;
}

inline FrameInput GroundFrame() {
  FrameInput frame;
  frame.planes.push_back(PlaneVisual{Ground()});
  return frame;
}

/// The desk resting flat: four square feet, their hull a square, the ECP at its centre.
inline FrameInput DeskRestingFlat() {
  FrameInput frame = GroundFrame();
  frame.title = "desk resting flat";
  frame.time = 0.5;
  frame.iterations = 4;
  frame.bodies.push_back(MakeBody(geometry::MakeDeskMesh(), Eigen::Isometry3d::Identity()));
  frame.contacts.push_back(GroundContact(frame.bodies[0]));
  return frame;
}

/// The T-bar tilted 12° about the line through a bar corner and a stem corner (a hull edge of
/// its footprint that is not a mesh edge): two separate contact points, the ECP 40% along the
/// segment between them.
inline FrameInput TBarTwoPoint() {
  FrameInput frame = GroundFrame();
  frame.title = "T-bar in two-point contact";
  frame.time = 1.25;
  frame.iterations = 9;
  geometry::TriangleMesh mesh = geometry::MakeTBarMesh();

  // the bar's corner at max x (min y among those) and the stem's corner at min y (max x); m, the
  // mesh's coordinates tie exactly, far below its 0.05 m features
  constexpr double kTie = 1e-9;
  double z_min = 1e30;
  for (const auto& v : mesh.vertices) z_min = std::min(z_min, v.z());
  Eigen::Vector3d a(-1e30, 1e30, 0), b(-1e30, 1e30, 0);
  for (const auto& v : mesh.vertices) {
    if (v.z() > z_min + kTie) continue;
    if (v.x() > a.x() + kTie || (std::abs(v.x() - a.x()) < kTie && v.y() < a.y())) a = v;
    if (v.y() < b.y() - kTie || (std::abs(v.y() - b.y()) < kTie && v.x() > b.x())) b = v;
  }
  // tilt about a→b so that the rest of the body rises
  const Eigen::Vector3d axis = (b - a).normalized();
  const Eigen::Vector3d centre = geometry::ComputeMassProperties(mesh, 1000.0).center_of_mass;
  double angle = 12 * M_PI / 180;
  const auto pose = [&](double theta) {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translate(a);
    X.rotate(Eigen::AngleAxisd(theta, axis));
    X.translate(-a);
    Eigen::Isometry3d lift = Eigen::Isometry3d::Identity();
    lift.translation().z() = -z_min;
    return lift * X;
  };
  if ((pose(angle) * centre).z() < (pose(-angle) * centre).z()) angle = -angle;
  frame.bodies.push_back(MakeBody(std::move(mesh), pose(angle), {0.55f, 0.70f, 0.85f}));
  const Eigen::Vector3d a_W = pose(angle) * a, b_W = pose(angle) * b;
  frame.contacts.push_back(GroundContact(frame.bodies[0], a_W + 0.4 * (b_W - a_W)));
  return frame;
}

/// The dumbbell lying on its side, turned 30° about z: its two end discs touch the ground along
/// two segments whose hull is one segment; the ECP at the middle of the hull.
inline FrameInput DumbbellOnItsSide() {
  FrameInput frame = GroundFrame();
  frame.title = "dumbbell on its side";
  frame.time = 2.0;
  frame.iterations = 6;
  geometry::TriangleMesh mesh = geometry::MakeDumbbellMesh();
  double z_min = 1e30;
  for (const auto& v : mesh.vertices) z_min = std::min(z_min, v.z());
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation().z() = -z_min;
  X.rotate(Eigen::AngleAxisd(30 * M_PI / 180, Eigen::Vector3d::UnitZ()));
  frame.bodies.push_back(MakeBody(std::move(mesh), X, {0.62f, 0.62f, 0.66f}));
  frame.contacts.push_back(GroundContact(frame.bodies[0]));
  return frame;
}

/// An L-shaped block (two boxes side by side, not the paper's) turned 20° about z: a non-convex
/// footprint, a hull that is not a box, and the ECP off the centre of mass.
inline geometry::TriangleMesh MakeLBlockMesh() {
  geometry::TriangleMesh mesh;
  const auto box = [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    const int base = static_cast<int>(mesh.vertices.size());
    for (int k = 0; k < 8; ++k) {
      mesh.vertices.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(),
                                 k & 4 ? hi.z() : lo.z());
    }
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
      mesh.triangles.emplace_back(base + q[0], base + q[1], base + q[2]);
      mesh.triangles.emplace_back(base + q[0], base + q[2], base + q[3]);
    }
  };
  box({-0.2, -0.15, 0.0}, {0.2, -0.03, 0.12});
  box({-0.2, -0.03, 0.0}, {-0.08, 0.25, 0.12});
  return mesh;
}

inline FrameInput HullOfNonConvexBlock() {
  FrameInput frame = GroundFrame();
  frame.title = "hull of an L-shaped block";
  frame.time = 0.0;
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.rotate(Eigen::AngleAxisd(20 * M_PI / 180, Eigen::Vector3d::UnitZ()));
  frame.bodies.push_back(MakeBody(MakeLBlockMesh(), X, {0.70f, 0.55f, 0.75f}));
  frame.contacts.push_back(GroundContact(frame.bodies[0], X * Eigen::Vector3d(-0.05, -0.05, 0)));
  return frame;
}

/// The T-bar lying flat (its T-shaped footprint is a non-convex patch) with a force arrow and the
/// ECP off the CM projection; for the inset.
inline FrameInput TBarFlatWithForce() {
  FrameInput frame = GroundFrame();
  frame.title = "T-bar flat";
  frame.time = 3.5;
  frame.iterations = 12;
  geometry::TriangleMesh mesh = geometry::MakeTBarMesh();
  double z_min = 1e30;
  for (const auto& v : mesh.vertices) z_min = std::min(z_min, v.z());
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation().z() = -z_min;
  X.rotate(Eigen::AngleAxisd(-15 * M_PI / 180, Eigen::Vector3d::UnitZ()));
  frame.bodies.push_back(MakeBody(std::move(mesh), X, {0.55f, 0.70f, 0.85f}));
  ContactVisual contact = GroundContact(frame.bodies[0]);
  contact.a1 = *contact.cm_projection + X.linear() * Eigen::Vector3d(0.04, 0.03, 0);
  contact.force = Eigen::Vector3d(4.0, -2.0, 29.4);  // N: weight of 3 kg plus friction
  frame.contacts.push_back(contact);
  frame.force_scale = 0.25 / 29.4;  // m/N: the weight is a 25 cm arrow
  frame.show.hull = false;
  return frame;
}

}  // namespace ecpsim::render::testing
